"""The CMA-MAE paper's comparison (bench/peers/README.md, "CMA-ME and CMA-MAE"): qdmeta's C++
emitters (build/bench/cma_peer) and pyribs (peer_pyribs_cma.py) on the linear-projection sphere
and the planar arm, per seed and library in separate processes, each finished run appended at
once as a row of results-cma.csv. A run whose (library, algorithm, domain, iterations, seed) is
already in the file is skipped, so an interrupted sweep continues where it stopped.

    bench/peers/run.sh --cma [--iterations 10000] [--seeds 1-10] [--domains sphere,arm]
                       [--algorithms cma-mae,cma-me] [--libraries qdmeta,pyribs] [--jobs 1]

--jobs N runs N processes at once (their wall times then share the cores; throughput figures
come from overhead_split-style timed runs, cma_timing.py, not from these rows).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CMA_PEER = ROOT / "build/bench/cma_peer"
COLUMNS = ["library", "version", "algorithm", "domain", "iterations", "evals", "wall_s", "task_s", "num_elites",
           "qd_score", "coverage", "obj_max", "seed", "load", "note"]
KEY = ("library", "algorithm", "domain", "iterations", "seed")


def seeds(text):
    """'1-10' or '1,3,5' -> [1, ..., 10] or [1, 3, 5]."""
    if "-" in text:
        first, last = text.split("-")
        return list(range(int(first), int(last) + 1))
    return [int(s) for s in text.split(",")]


def command(library, algorithm, domain, iterations, seed):
    args = ["--domain", domain, "--algorithm", algorithm, "--iterations", str(iterations), "--seed", str(seed)]
    if library == "qdmeta":
        return [str(CMA_PEER)] + args
    return [sys.executable, str(HERE / "peer_pyribs_cma.py")] + args


def done_keys(path):
    if not path.exists():
        return set()
    with path.open() as f:
        return {tuple(row[k] for k in KEY) for row in csv.DictReader(f)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--iterations", type=int, default=10_000)
    p.add_argument("--seeds", type=seeds, default=seeds("1-10"))
    p.add_argument("--domains", default="sphere,arm")
    p.add_argument("--algorithms", default="cma-mae,cma-me")
    p.add_argument("--libraries", default="qdmeta,pyribs")
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--out", type=Path, default=HERE / "results-cma.csv")
    args = p.parse_args()
    # Seed-major, so that a sweep cut short has the same seeds for every configuration it reached.
    runs = [(lib, alg, dom, args.iterations, seed) for seed in args.seeds for alg in args.algorithms.split(",")
            for dom in args.domains.split(",") for lib in args.libraries.split(",")]
    done = done_keys(args.out)
    runs = [r for r in runs if tuple(str(v) for v in r) not in done]
    lock = threading.Lock()
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")

    def run(r):
        load = os.getloadavg()[0]
        out = subprocess.run(command(*r), capture_output=True, text=True, env=env, cwd=HERE)
        if out.returncode != 0:
            print(f"{r}: exit {out.returncode}: {out.stderr.strip().splitlines()[-1:]}", flush=True)
            return
        row = json.loads(out.stdout.strip().splitlines()[-1])
        row["load"] = round(load, 2)
        with lock:
            new = not args.out.exists()
            with args.out.open("a", newline="") as f:
                w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
                if new:
                    w.writeheader()
                w.writerow(row)
            print(f"{r}: qd {row['qd_score']:.2f} cov {row['coverage']:.2f} wall {row['wall_s']:.0f} s", flush=True)

    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        list(pool.map(run, runs))


if __name__ == "__main__":
    main()
