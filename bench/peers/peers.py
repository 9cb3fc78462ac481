"""Runs qdmeta, pyribs and QDax side by side on the same tasks and budget, interleaved
(qdmeta, pyribs, qdax, qdmeta-py, ...), writes results.csv and prints qdmeta/peer ratios and each
Python library's overhead (its loop's wall time less the numpy task's own time).

Each run is a separate process (a peer's runner or `qdmeta run`), so imports, thread pools and
memory never carry over from one run to the next. Started by run.sh with the venv's python.
"""
import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import common

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
PEERS = {"pyribs": ("ribs", "peer_pyribs.py"), "qdax": ("qdax", "peer_qdax.py"),
         "qdmeta-py": ("qdmeta", "peer_qdmeta_python.py")}
# The qdmeta module that `make build` puts in build/python (the qdmeta-py runner adds it itself).
PYTHON_MODULE_DIR = ROOT / "build" / "python"
# Apart from the runs' seeds 1..R: with seed 1 for both, a peer's k-means samples and repeat 1's
# initial random solutions came from the same stream (the same points), which slowed that run's
# filling of the CVT archive by a quarter (bench/README.md).
CENTROID_SEED = 1_000_003
COLUMNS = ["library", "version", "algorithm", "evals", "wall_s", "evals_per_s", "num_elites", "qd_score", "obj_max",
           "task_s", "repeat", "note"]
# The arm as a qdmeta command line: examples/own-task built against an install of this build
# (run.sh makes it).
ARM_QD = ROOT / "build/peers-arm/arm-qd"

QDMETA_CVT_CONFIG = """# Written by bench/peers/peers.py: configs/rastrigin/cvt-map-elites.toml with the peers'
# centroid construction (k-means over {samples} uniform points, random seeding, {iterations} Lloyd passes).
algorithm = "cvt-map-elites"
seed = {seed}
[budget]
evaluations = {evals}
counts = "bottom"
[log]
every = 0
[task]
name = "rastrigin"
dimensions = 20
score_m = 2000.0
[mutation]
kind = "gaussian"
rate = 0.10
sigma = 0.05
[map_elites]
batch_size = 400
initial_population = 2000
{cvt}"""


QDMETA_ARM_CONFIG = """# Written by bench/peers/peers.py: the 100-joint planar arm (examples/own-task), the peers'
# batches, {algorithm} with the {operator} operator.
algorithm = "{algorithm}"
seed = {seed}
[budget]
evaluations = {evals}
counts = "bottom"
[log]
every = 0
[task]
name = "arm"
joints = {joints}
[mutation]
{mutation}
[map_elites]
batch_size = 400
initial_population = 2000
{layout}
"""
ARM_GRID = """[archive]
bins = [100, 100]
measures = [0, 1]"""
# The peers' centroid construction, the same for both tasks.
CVT_TABLE = """[cvt]
centroids = {centroids}
samples = {samples}
init = "random"
init_samples = {samples}
method = "lloyd"
iterations = {iterations}
seed = 1
cache = true
cache_dir = "{cache}"
"""


def variant(task, algorithm, operator="gaussian"):
    """A row's `algorithm` field: Rastrigin's rows keep their names (map-elites, cvt), the arm's
    are arm-map-elites, arm-cvt, arm-map-elites-iso-line, ..."""
    prefix = "" if task == "rastrigin" else f"{task}-"
    return prefix + algorithm + ("" if operator == "gaussian" else f"-{operator}")


def log(message):
    print(message, file=sys.stderr, flush=True)


def peer_available(python, module):
    """None when `module` imports in the venv, else a one-line reason."""
    r = subprocess.run([python, "-c", f"import sys; sys.path.insert(0, {str(PYTHON_MODULE_DIR)!r}); import {module}"],
                       capture_output=True, text=True)
    if r.returncode == 0:
        return None
    lines = (r.stderr or r.stdout).strip().splitlines()
    return lines[-1] if lines else f"import {module} failed"


def run_peer(python, script, args, timeout):
    """One runner process; its JSON line, or a failure reason."""
    try:
        r = subprocess.run([python, str(HERE / script), *args], capture_output=True, text=True, timeout=timeout,
                           cwd=HERE)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {timeout} s"
    if r.returncode != 0:
        tail = (r.stderr or r.stdout).strip().splitlines()
        return None, tail[-1] if tail else f"exit status {r.returncode}"
    return json.loads(r.stdout.strip().splitlines()[-1]), None


class Qdmeta:
    """`qdmeta run` (or the arm's `arm-qd run`) as a peer: its summary.json gives the loop's wall
    time (centroids excluded)."""

    def __init__(self, binary, arm_binary, work, threads, cvt_samples, kmeans_iterations, centroids):
        self.binary = binary
        self.arm_binary = arm_binary
        self.work = work
        self.threads = threads
        self.cache = work / "centroid-cache"  # one folder per task, as the qdmeta-py runner reads it
        self.cvt_samples = cvt_samples
        self.kmeans_iterations = kmeans_iterations
        self.centroids = centroids
        version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.split()
        self.version = version[-1] if version else "?"

    def _cvt_table(self, task):
        return CVT_TABLE.format(centroids=self.centroids, samples=self.cvt_samples, iterations=self.kmeans_iterations,
                                cache=self.cache / task)

    def _config(self, task, algorithm, operator, evals, seed):
        if task == "rastrigin" and algorithm == "map-elites":
            return ROOT / "configs/rastrigin/map-elites.toml"
        path = self.work / f"qdmeta-{variant(task, algorithm, operator)}-{seed}.toml"
        if task == "rastrigin":
            text = QDMETA_CVT_CONFIG.format(seed=seed, evals=evals, samples=self.cvt_samples,
                                            iterations=self.kmeans_iterations, cvt=self._cvt_table(task))
        else:
            mutation = (f'kind = "gaussian"\nrate = {common.MUTATION_RATE}\nsigma = {common.MUTATION_SD}'
                        if operator == "gaussian" else
                        f'kind = "iso-line"\niso_sigma = {common.ISO_SIGMA}\nline_sigma = {common.LINE_SIGMA}')
            layout = ARM_GRID if algorithm == "map-elites" else self._cvt_table(task)
            text = QDMETA_ARM_CONFIG.format(algorithm="map-elites" if algorithm == "map-elites" else "cvt-map-elites",
                                            operator=operator, seed=seed, evals=evals, joints=common.ARM_JOINTS,
                                            mutation=mutation, layout=layout)
        path.write_text(text)
        return path

    def _run(self, task, algorithm, operator, evals, seed, timeout):
        out = self.work / f"run-{variant(task, algorithm, operator)}-{seed}"
        binary = self.binary if task == "rastrigin" else self.arm_binary
        command = [str(binary), "run", "--config", str(self._config(task, algorithm, operator, evals, seed)),
                   "--out", str(out), "--evals", str(evals), "--seed", str(seed), "--threads", str(self.threads),
                   "--overwrite", "--quiet"]
        start = time.perf_counter()
        try:
            r = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, None, f"timed out after {timeout} s"
        process_s = time.perf_counter() - start
        if r.returncode != 0:
            return None, None, (r.stderr.strip().splitlines() or ["qdmeta failed"])[-1]
        return json.loads((out / "summary.json").read_text()), process_s, None

    def centroids_row(self, task, timeout):
        # Time k-means itself, not a cache hit (the arm's 2-D centroids have their own cache file).
        shutil.rmtree(self.cache / task, ignore_errors=True)
        _, process_s, error = self._run(task, "cvt", "gaussian", 2000, 1, timeout)
        if error:
            return None, error
        # qdmeta makes the centroids in the run's first step, so this is the whole process: k-means
        # plus a 2,000-evaluation run (a few ms). Later runs load them from the cache.
        return dict(library="qdmeta", version=self.version, algorithm=variant(task, "cvt-centroids"), evals=0,
                    wall_s=process_s,
                    note=f"k-means over {self.cvt_samples} uniform points, random seeding, {self.kmeans_iterations} "
                         "Lloyd passes (wall of a 2,000-evaluation run with an empty cache)"), None

    def run(self, task, algorithm, operator, evals, seed, timeout):
        summary, _, error = self._run(task, algorithm, operator, evals, seed, timeout)
        if error:
            return None, error
        note = f"{summary['threads']} threads"
        if task != "rastrigin":
            note += "; the C++ arm of examples/own-task"
        if algorithm == "cvt":
            note += ("; exact parent-bound nearest-centroid search" if task == "rastrigin"
                     else "; exact bucket-grid nearest-centroid search")
        return dict(library="qdmeta", version=self.version, algorithm=variant(task, algorithm, operator),
                    evals=summary["evals"], wall_s=summary["wall_seconds"], num_elites=summary["num_elites"],
                    qd_score=summary["qd_score"], obj_max=summary["obj_max"], note=note), None


def ratios(rows, algorithm, peer, field, mine="qdmeta"):
    """mine/peer of `field`, pairing runs of the same repeat."""
    by = {(r["library"], int(r["repeat"])): float(r[field]) for r in rows if r["algorithm"] == algorithm
          and r.get(field) not in (None, "")}
    return [by[(mine, k)] / by[(peer, k)] for (lib, k) in by if lib == peer and (mine, k) in by
            and by[(peer, k)] != 0]


def overhead(row):
    """A Python library's loop time less its numpy task's, in seconds per 1M evaluations."""
    return (float(row["wall_s"]) - float(row["task_s"])) / float(row["evals"]) * 1e6


def print_table(rows, variants, peers):
    def median(values):
        values = list(values)
        return statistics.median(values) if values else float("nan")

    fmt = lambda v, d: f"{min(v):.{d}f} / {statistics.median(v):.{d}f} / {max(v):.{d}f}"  # noqa: E731
    print()
    print(f"{'algorithm':<24} {'library':<9} {'evals/s (median)':>17} {'QD-score (median)':>18} {'elites':>7} "
          f"{'task s/1M':>10} {'overhead s/1M':>14}")
    for algorithm in variants:
        for lib in ["qdmeta", *peers]:
            mine = [r for r in rows if r["algorithm"] == algorithm and r["library"] == lib]
            if not mine:
                continue
            timed = [r for r in mine if r.get("task_s") not in (None, "")]
            task = f"{median(float(r['task_s']) / float(r['evals']) * 1e6 for r in timed):10.3f}" if timed else " " * 10
            over = f"{median(overhead(r) for r in timed):14.3f}" if timed else " " * 14
            print(f"{algorithm:<24} {lib:<9} {median(float(r['evals_per_s']) for r in mine):>17,.0f} "
                  f"{median(float(r['qd_score']) for r in mine):>18,.0f} "
                  f"{median(int(r['num_elites']) for r in mine):>7,.0f} {task} {over}")
    for r in rows:
        if r["library"] == "numpy-task":
            print(f"{r['algorithm']:<24} numpy task alone, repeat {r['repeat']}: "
                  f"{float(r['wall_s']) / float(r['evals']) * 1e6:.3f} s per 1M evaluations")
    print()
    print("ratios, min / median / max over repeats (qdmeta: the CLI; qdmeta-py: the Python module's ask/tell loop;")
    print("overhead: the peer's loop less its numpy task over qdmeta-py's, so > 1 means qdmeta-py spends less)")
    print(f"{'algorithm':<24} {'ratio':<22} {'throughput':>22} {'QD-score':>26} {'overhead':>24}")
    pairs = [("qdmeta", p) for p in peers] + [("qdmeta-py", p) for p in peers if p != "qdmeta-py" and "qdmeta-py" in peers]
    for algorithm in variants:
        for mine, peer in pairs:
            t = ratios(rows, algorithm, peer, "evals_per_s", mine)
            q = ratios(rows, algorithm, peer, "qd_score", mine)
            if not t:
                continue
            o = ""
            if mine == "qdmeta-py":
                by = {(r["library"], int(r["repeat"])): overhead(r) for r in rows
                      if r["algorithm"] == algorithm and r.get("task_s") not in (None, "")}
                v = [by[(peer, k)] / by[(mine, k)] for (lib, k) in by
                     if lib == peer and (mine, k) in by and by[(mine, k)] > 0]
                o = fmt(v, 2) if v else ""
            print(f"{algorithm:<24} {mine + ' / ' + peer:<22} {fmt(t, 2):>22} {fmt(q, 4):>26} {o:>24}")
    for r in rows:
        if r["algorithm"].endswith("cvt-centroids"):
            print(f"{r['algorithm']}: {r['library']:<9} {float(r['wall_s']):8.1f} s  ({r['note']})")


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--evals", type=int, default=1_000_000, help="evaluations per run (2000 + 400 k)")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--tasks", default="rastrigin,arm", help="rastrigin (20-D), arm (100 joints, 2-D measures)")
    p.add_argument("--algorithms", default="map-elites,cvt")
    p.add_argument("--arm-operators", default="gaussian,iso-line",
                   help="operators of the arm's rows (Rastrigin's are Gaussian)")
    p.add_argument("--peers", default="pyribs,qdax,qdmeta-py")
    p.add_argument("--threads", type=int, default=2, help="qdmeta's worker threads")
    p.add_argument("--centroids", type=int, default=10_000)
    p.add_argument("--cvt-samples", type=int, default=100_000, help="uniform points clustered into centroids")
    p.add_argument("--kmeans-iterations", type=int, default=10)
    p.add_argument("--timeout", type=int, default=3600, help="seconds allowed to one run")
    p.add_argument("--qdmeta", default=str(ROOT / "build/qdmeta"))
    p.add_argument("--arm-qd", default=str(ARM_QD), help="the arm's qdmeta command line (run.sh builds it)")
    p.add_argument("--out", default=str(HERE / "results.csv"))
    args = p.parse_args()
    if args.evals < 2000 or (args.evals - 2000) % 400:
        raise SystemExit("--evals must be 2000 + 400 k (the initial solutions, then whole batches)")
    tasks = [t for t in args.tasks.split(",") if t]
    algorithms = [a for a in args.algorithms.split(",") if a]
    arm_operators = [o for o in args.arm_operators.split(",") if o]
    for t in tasks:
        if t not in common.TASKS:
            raise SystemExit(f"unknown task {t!r}: use {', '.join(common.TASKS)}")
    python = sys.executable

    peers = []
    for name in [n for n in args.peers.split(",") if n]:
        reason = peer_available(python, PEERS[name][0])
        if reason:
            print(f"skipping {name}: {reason}")
        else:
            peers.append(name)
    arm_cli = Path(args.arm_qd).is_file()
    if "arm" in tasks and not arm_cli:
        print(f"skipping qdmeta's CLI on the arm: no {args.arm_qd} (run.sh builds it from examples/own-task)")
    work = Path(tempfile.mkdtemp(prefix="qdmeta-peers-"))
    qdmeta = Qdmeta(args.qdmeta, args.arm_qd, work, args.threads, args.cvt_samples, args.kmeans_iterations,
                    args.centroids)
    rows = []

    def record(row, repeat):
        row["repeat"] = repeat
        if row.get("evals"):
            row["evals_per_s"] = row["evals"] / row["wall_s"]
        rows.append(row)
        log(f"  {row['library']:<10} {row['algorithm']:<24} repeat {repeat}: {row['wall_s']:.2f} s"
            + (f", {row['evals_per_s']:,.0f} evals/s, {row['num_elites']} elites, QD-score {row['qd_score']:,.0f}"
               if row.get("num_elites") is not None else ""))

    def peers_of(task, operator):
        # QDax's runner has Rastrigin with the Gaussian operator only.
        return [n for n in peers if n != "qdax" or (task == "rastrigin" and operator == "gaussian")]

    def centroids_file(name, task):
        return work / f"centroids-{name}-{task}.npy"

    def cli_runs(task):
        return task == "rastrigin" or arm_cli

    if "cvt" in algorithms:
        for task in tasks:
            log(f"{task}: {args.centroids} centroids by each library's own k-means")
            if cli_runs(task):
                row, error = qdmeta.centroids_row(task, args.timeout)
                if error:
                    raise SystemExit(f"qdmeta's centroids failed: {error}")
                record(row, 0)
            for name in peers_of(task, "gaussian"):
                if name == "qdmeta-py" and not cli_runs(task):
                    continue  # it reads the CLI's centroids
                row, error = run_peer(python, PEERS[name][1],
                                      ["--algorithm", "cvt-centroids", "--centroids", str(args.centroids), "--samples",
                                       str(args.cvt_samples), "--centroids-file", str(centroids_file(name, task)),
                                       "--seed", str(CENTROID_SEED), "--task", task]
                                      + (["--kmeans-iterations", str(args.kmeans_iterations)]
                                         if name in ("pyribs", "qdmeta-py") else []),
                                      args.timeout)
                if error:
                    print(f"{name}: {task} centroids failed ({error}); its {task} CVT runs are skipped")
                else:
                    row["algorithm"] = variant(task, "cvt-centroids")
                    record(row, 0)

    variants = []
    for repeat in range(1, args.repeats + 1):
        for task in tasks:
            row, error = run_peer(python, "task_cost.py", ["--task", task, "--evals", str(args.evals), "--seed",
                                                           str(repeat)], args.timeout)
            if error:
                print(f"the {task} task's own timing failed: {error}")
            else:
                record(row, repeat)
            for algorithm in algorithms:
                for operator in (["gaussian"] if task == "rastrigin" else arm_operators):
                    name_of_row = variant(task, algorithm, operator)
                    if name_of_row not in variants:
                        variants.append(name_of_row)
                    log(f"repeat {repeat}/{args.repeats}, {name_of_row}")
                    if cli_runs(task):
                        row, error = qdmeta.run(task, algorithm, operator, args.evals, repeat, args.timeout)
                        if error:
                            raise SystemExit(f"qdmeta failed: {error}")
                        record(row, repeat)
                    for name in peers_of(task, operator):
                        if algorithm == "cvt" and not centroids_file(name, task).exists():
                            continue
                        row, error = run_peer(python, PEERS[name][1],
                                              ["--algorithm", algorithm, "--evals", str(args.evals), "--seed",
                                               str(repeat), "--centroids-file", str(centroids_file(name, task)),
                                               "--task", task, "--operator", operator]
                                              + (["--centroids", str(args.centroids), "--samples", str(args.cvt_samples),
                                                  "--kmeans-iterations", str(args.kmeans_iterations)]
                                                 if name == "qdmeta-py" else []), args.timeout)
                        if error:
                            print(f"{name} {name_of_row} repeat {repeat} failed: {error}")
                        else:
                            row["algorithm"] = name_of_row
                            record(row, repeat)

    with open(args.out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    shutil.rmtree(work, ignore_errors=True)
    print(f"{os.cpu_count()} cores; {args.evals} evaluations per run; {args.repeats} repeats; results: {args.out}")
    print_table(rows, variants, peers)


if __name__ == "__main__":
    main()
