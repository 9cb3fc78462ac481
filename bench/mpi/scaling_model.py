#!/usr/bin/env python3
"""Throughput model of an MPI QD-Meta RHex run (docs/scaling.md): time of the paper's 12M-evaluation
budget on P cores, from the measured per-episode cost and per-piece message cost.

One meta-generation (configs/rhex/qdmeta-*.toml): lambda maps evolve in turn, each G generations of
B offspring (one evaluate request of B rows each), then its meta-fitness (one request of A x E
episodes: archive size x environments). A request of R rows on P ranks takes the longer of
  compute:  ceil-ish(R / P) episodes, plus half an episode of tail (guided pieces end at 1 row),
  rank 0:   one message round per piece (pieces ~ 2 P ln(R / 2P) + min(R, 2P)), c_msg each,
plus rank 0's serial work per meta-generation (S: map rebuilds, insertion, CMA-ES).
Usage: scaling_model.py [t_episode_s] [c_msg_s] [CORES...]   (cores: 1 2 40 400 4000 by default)
"""
import math
import sys

lam, G, B = 10, 5, 400            # meta-population, generations per meta-generation, batch size
E = 12                            # Damage: 2 types x 6 legs (Obstacle: 5)
A = 2000                          # mean archive size over the run (of 4,096 cells): an assumption
S = 10 * 0.043 + 0.1              # rank 0 serial s per meta-generation: 10 rebuilds of 500k x 50-D
budget = 12_000_000               # the paper's RHex budget, counting all evaluations
per_meta_gen = lam * G * B + lam * A * E
meta_gens = budget / per_meta_gen


def pieces(R, P):
    if R <= 2 * P:
        return R
    return 2 * P * math.log(R / (2 * P)) + 2 * P


def request(R, P, t_ep, c_msg):
    busy = min(R, P)
    compute = math.ceil(R / busy) * t_ep + (0.5 * t_ep if R > P else 0.0)
    return max(compute, pieces(R, P) * c_msg)


def meta_generation_seconds(P, t_ep, c_msg):
    return lam * G * request(B, P, t_ep, c_msg) + lam * request(A * E, P, t_ep, c_msg) + S


def run_hours(P, t_ep, c_msg):
    """Wall-clock hours of one run of the whole budget on P cores."""
    return meta_gens * meta_generation_seconds(P, t_ep, c_msg) / 3600


def main(argv):
    t_ep = float(argv[0]) if len(argv) > 0 else 0.206   # CPU s per 5 s episode (bench/README.md)
    c_msg = float(argv[1]) if len(argv) > 1 else 20e-6  # rank 0's cost per piece (send + receive)
    ideal_rate = lambda P: P / t_ep
    print(f"t_episode {t_ep * 1e3:.0f} ms, c_msg {c_msg * 1e6:.0f} us, {per_meta_gen:,} evaluations per "
          f"meta-generation, {meta_gens:.1f} meta-generations")
    print(f"{'cores':>6} {'s/meta-gen':>11} {'episodes/s':>11} {'efficiency':>10} {'run time':>10} {'ideal':>8}")
    for P in [int(a) for a in argv[2:]] or (1, 2, 40, 400, 4000):
        t = meta_generation_seconds(P, t_ep, c_msg)
        rate = per_meta_gen / t
        hours = meta_gens * t / 3600
        ideal_h = budget / ideal_rate(P) / 3600
        print(f"{P:>6} {t:>11.1f} {rate:>11.1f} {rate / ideal_rate(P):>10.0%} {hours:>9.2f}h {ideal_h:>7.2f}h")


if __name__ == "__main__":
    main(sys.argv[1:])
