#!/usr/bin/env python3
"""What the paper's RHex study costs per engine and leg model (docs/scaling.md, "Both engines"):
core-hours of Table 2 (24 runs) and Figs S3-S5 (32 runs), and the wall time of Table 2 on 32, 400
and 4,000 cores, from the throughput model (scaling_model.py) at each measured CPU time per 5 s
episode. A study on P cores takes the shorter of its runs one after another, each on all P cores,
and its runs side by side, each on P // runs cores.
Usage: study_cost.py NAME=SECONDS... [c_msg_s=20e-6]   e.g. study_cost.py "DART rigid=0.23"
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scaling_model import run_hours  # noqa: E402

STUDIES = [("Table 2", 24), ("Figs S3-S5", 32)]
CORES = [32, 400, 4000]


def study_hours(P, runs, t_ep, c_msg):
    one_by_one = runs * run_hours(P, t_ep, c_msg)
    return min(one_by_one, run_hours(P // runs, t_ep, c_msg)) if P >= runs else one_by_one


def table(models, c_msg=20e-6):
    out = ["| engine, legs | s / episode | " + " | ".join(f"{name}: core-hours ({runs} runs)" for name, runs in STUDIES)
           + " | " + " | ".join(f"Table 2 on {p:,} cores" for p in CORES) + " |",
           "|---|---|" + "---|" * (len(STUDIES) + len(CORES))]
    for name, t_ep in models:
        serial = run_hours(1, t_ep, c_msg)
        out.append(f"| {name} | {t_ep:g} | " + " | ".join(f"{runs * serial:,.0f}" for _, runs in STUDIES) + " | "
                   + " | ".join(f"{study_hours(p, STUDIES[0][1], t_ep, c_msg):,.1f} h" for p in CORES) + " |")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    models = [(a.split("=")[0], float(a.split("=")[1])) for a in sys.argv[1:] if not a.startswith("c_msg=")]
    c_msg = next((float(a.split("=")[1]) for a in sys.argv[1:] if a.startswith("c_msg=")), 20e-6)
    sys.stdout.write(table(models, c_msg))
