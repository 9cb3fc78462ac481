"""Runs qdmeta, pyribs and QDax side by side on the same task and budget, interleaved
(qdmeta, pyribs, qdax, qdmeta, ...), writes results.csv and prints qdmeta/peer ratios.

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
           "repeat", "note"]

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
[cvt]
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
    """`qdmeta run` as a peer: its summary.json gives the loop's wall time (centroids excluded)."""

    def __init__(self, binary, work, threads, cvt_samples, kmeans_iterations, centroids):
        self.binary = binary
        self.work = work
        self.threads = threads
        self.cache = work / "centroid-cache"
        self.cvt_samples = cvt_samples
        self.kmeans_iterations = kmeans_iterations
        self.centroids = centroids
        version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.split()
        self.version = version[-1] if version else "?"

    def _config(self, algorithm, evals, seed):
        if algorithm == "map-elites":
            return ROOT / "configs/rastrigin/map-elites.toml"
        path = self.work / f"qdmeta-cvt-{seed}.toml"
        path.write_text(QDMETA_CVT_CONFIG.format(seed=seed, evals=evals, centroids=self.centroids,
                                                 samples=self.cvt_samples, iterations=self.kmeans_iterations,
                                                 cache=self.cache))
        return path

    def _run(self, algorithm, evals, seed, timeout):
        out = self.work / f"run-{algorithm}-{seed}"
        command = [str(self.binary), "run", "--config", str(self._config(algorithm, evals, seed)), "--out", str(out),
                   "--evals", str(evals), "--seed", str(seed), "--threads", str(self.threads), "--overwrite", "--quiet"]
        start = time.perf_counter()
        try:
            r = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, None, f"timed out after {timeout} s"
        process_s = time.perf_counter() - start
        if r.returncode != 0:
            return None, None, (r.stderr.strip().splitlines() or ["qdmeta failed"])[-1]
        return json.loads((out / "summary.json").read_text()), process_s, None

    def centroids_row(self, timeout):
        shutil.rmtree(self.cache, ignore_errors=True)  # time k-means itself, not a cache hit
        _, process_s, error = self._run("cvt", 2000, 1, timeout)
        if error:
            return None, error
        # qdmeta makes the centroids in the run's first step, so this is the whole process: k-means
        # plus a 2,000-evaluation run (a few ms). Later runs load them from the cache.
        return dict(library="qdmeta", version=self.version, algorithm="cvt-centroids", evals=0, wall_s=process_s,
                    note=f"k-means over {self.cvt_samples} uniform points, random seeding, {self.kmeans_iterations} "
                         "Lloyd passes (wall of a 2,000-evaluation run with an empty cache)"), None

    def run(self, algorithm, evals, seed, timeout):
        summary, _, error = self._run(algorithm, evals, seed, timeout)
        if error:
            return None, error
        return dict(library="qdmeta", version=self.version, algorithm=algorithm, evals=summary["evals"],
                    wall_s=summary["wall_seconds"], num_elites=summary["num_elites"], qd_score=summary["qd_score"],
                    obj_max=summary["obj_max"],
                    note=f"{summary['threads']} threads" + ("; exact parent-bound nearest-centroid search"
                                                             if algorithm == "cvt" else "")), None


def ratios(rows, algorithm, peer, field, mine="qdmeta"):
    """mine/peer of `field`, pairing runs of the same repeat."""
    by = {(r["library"], int(r["repeat"])): float(r[field]) for r in rows if r["algorithm"] == algorithm}
    return [by[(mine, k)] / by[(peer, k)] for (lib, k) in by if lib == peer and (mine, k) in by
            and by[(peer, k)] != 0]


def print_table(rows, algorithms, peers):
    print()
    print(f"{'algorithm':<12} {'library':<9} {'evals/s (median)':>17} {'QD-score (median)':>18} {'elites':>7}")
    for algorithm in algorithms:
        for lib in ["qdmeta", *peers]:
            mine = [r for r in rows if r["algorithm"] == algorithm and r["library"] == lib]
            if mine:
                print(f"{algorithm:<12} {lib:<9} {statistics.median(float(r['evals_per_s']) for r in mine):>17,.0f} "
                      f"{statistics.median(float(r['qd_score']) for r in mine):>18,.0f} "
                      f"{statistics.median(int(r['num_elites']) for r in mine):>7,.0f}")
    print()
    print("ratios, min / median / max over repeats (qdmeta: the CLI; qdmeta-py: the Python module's ask/tell loop)")
    print(f"{'algorithm':<12} {'ratio':<22} {'throughput':>22} {'QD-score':>26}")
    pairs = [("qdmeta", p) for p in peers] + [("qdmeta-py", p) for p in peers if p != "qdmeta-py" and "qdmeta-py" in peers]
    for algorithm in algorithms:
        for mine, peer in pairs:
            t = ratios(rows, algorithm, peer, "evals_per_s", mine)
            q = ratios(rows, algorithm, peer, "qd_score", mine)
            if not t:
                continue
            fmt = lambda v, d: f"{min(v):.{d}f} / {statistics.median(v):.{d}f} / {max(v):.{d}f}"  # noqa: E731
            print(f"{algorithm:<12} {mine + ' / ' + peer:<22} {fmt(t, 2):>22} {fmt(q, 4):>26}")
    for r in rows:
        if r["algorithm"] == "cvt-centroids":
            print(f"centroids: {r['library']:<8} {float(r['wall_s']):8.1f} s  ({r['note']})")


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--evals", type=int, default=1_000_000, help="evaluations per run (2000 + 400 k)")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--algorithms", default="map-elites,cvt")
    p.add_argument("--peers", default="pyribs,qdax,qdmeta-py")
    p.add_argument("--threads", type=int, default=2, help="qdmeta's worker threads")
    p.add_argument("--centroids", type=int, default=10_000)
    p.add_argument("--cvt-samples", type=int, default=100_000, help="uniform points clustered into centroids")
    p.add_argument("--kmeans-iterations", type=int, default=10)
    p.add_argument("--timeout", type=int, default=3600, help="seconds allowed to one run")
    p.add_argument("--qdmeta", default=str(ROOT / "build/qdmeta"))
    p.add_argument("--out", default=str(HERE / "results.csv"))
    args = p.parse_args()
    if args.evals < 2000 or (args.evals - 2000) % 400:
        raise SystemExit("--evals must be 2000 + 400 k (the initial solutions, then whole batches)")
    algorithms = [a for a in args.algorithms.split(",") if a]
    python = sys.executable

    peers = []
    for name in [n for n in args.peers.split(",") if n]:
        reason = peer_available(python, PEERS[name][0])
        if reason:
            print(f"skipping {name}: {reason}")
        else:
            peers.append(name)
    work = Path(tempfile.mkdtemp(prefix="qdmeta-peers-"))
    qdmeta = Qdmeta(args.qdmeta, work, args.threads, args.cvt_samples, args.kmeans_iterations, args.centroids)
    rows = []

    def record(row, repeat):
        row["repeat"] = repeat
        if row.get("evals"):
            row["evals_per_s"] = row["evals"] / row["wall_s"]
        rows.append(row)
        log(f"  {row['library']:<7} {row['algorithm']:<13} repeat {repeat}: {row['wall_s']:.2f} s"
            + (f", {row['evals_per_s']:,.0f} evals/s, {row['num_elites']} elites, QD-score {row['qd_score']:,.0f}"
               if row.get("evals") else ""))

    if "cvt" in algorithms:
        log(f"centroids: {args.centroids} by each library's own k-means")
        row, error = qdmeta.centroids_row(args.timeout)
        if error:
            raise SystemExit(f"qdmeta's centroids failed: {error}")
        record(row, 0)
        for name in list(peers):
            row, error = run_peer(python, PEERS[name][1],
                                  ["--algorithm", "cvt-centroids", "--centroids", str(args.centroids), "--samples",
                                   str(args.cvt_samples), "--centroids-file", str(work / f"centroids-{name}.npy"),
                                   "--seed", str(CENTROID_SEED)]
                                  + (["--kmeans-iterations", str(args.kmeans_iterations)]
                                     if name in ("pyribs", "qdmeta-py") else []),
                                  args.timeout)
            if error:
                print(f"{name}: centroids failed ({error}); its CVT runs are skipped")
            else:
                record(row, 0)

    for repeat in range(1, args.repeats + 1):
        for algorithm in algorithms:
            log(f"repeat {repeat}/{args.repeats}, {algorithm}")
            row, error = qdmeta.run(algorithm, args.evals, repeat, args.timeout)
            if error:
                raise SystemExit(f"qdmeta failed: {error}")
            record(row, repeat)
            for name in peers:
                centroids_file = work / f"centroids-{name}.npy"
                if algorithm == "cvt" and not centroids_file.exists():
                    continue
                row, error = run_peer(python, PEERS[name][1],
                                      ["--algorithm", algorithm, "--evals", str(args.evals), "--seed", str(repeat),
                                       "--centroids-file", str(centroids_file)]
                                      + (["--centroids", str(args.centroids), "--samples", str(args.cvt_samples),
                                          "--kmeans-iterations", str(args.kmeans_iterations)]
                                         if name == "qdmeta-py" else []), args.timeout)
                if error:
                    print(f"{name} {algorithm} repeat {repeat} failed: {error}")
                else:
                    record(row, repeat)

    with open(args.out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    shutil.rmtree(work, ignore_errors=True)
    print(f"{os.cpu_count()} cores; {args.evals} evaluations per run; {args.repeats} repeats; results: {args.out}")
    print_table(rows, algorithms, peers)


if __name__ == "__main__":
    main()
