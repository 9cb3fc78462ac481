"""Diagnostic variants of pyribs 0.12's CMA-MAE run (peer_pyribs_cma.py), for finding why the
sphere's QD-score differs between qdmeta and pyribs (docs/fidelity.md, "Emitters against
pyribs"). Each variant changes one thing in pyribs at run time and otherwise runs
peer_pyribs_cma.py unchanged; it prints the same JSON line with the variant in "note".

    python cma_pyribs_variants.py --variant stock|rank-one|restart-result|both [peer_pyribs_cma.py options]

  stock           pyribs as installed.
  rank-one        CMA-ES's rank-one covariance term as Hansen's tutorial has it: c1 p_c p_c^T / sigma^2
                  (pyribs 0.12 adds c1^2 p_c p_c^T, p_c accumulated from unnormalised mean steps).
  restart-result  a restart's mean drawn from the result archive (each cell's best elite), as
                  qdmeta's emitters draw it, instead of from the thresholded archive.
  both            rank-one and restart-result.

Run with the venv's python (run.sh makes it).
"""
import sys

import numpy as np
from ribs.emitters.opt import _cma_es
from ribs.schedulers import Scheduler

import peer_pyribs_cma


def tutorial_cov_update(cov, c1a, cmu, c1, pc, sigma, rank_mu_update, weights):
    """pyribs's _calc_cov_update with the rank-one term c1 (p_c / sigma)(p_c / sigma)^T."""
    return cov * (1 - c1a - cmu * np.sum(weights)) + c1 * np.outer(pc, pc) / sigma**2 + rank_mu_update * cmu / sigma**2


def restart_from_result():
    original = Scheduler.__init__

    def init(self, archive, emitters, result_archive=None, **kwargs):
        original(self, archive, emitters, result_archive=result_archive, **kwargs)
        if result_archive is not None:
            for emitter in emitters:
                emitter._archive = result_archive  # pylint: disable=protected-access

    Scheduler.__init__ = init


def main():
    args = sys.argv[1:]
    if len(args) < 2 or args[0] != "--variant":
        sys.exit(__doc__)
    variant = args[1]
    if variant not in ("stock", "rank-one", "restart-result", "both"):
        sys.exit(f"--variant = {variant}: stock, rank-one, restart-result or both")
    if variant in ("rank-one", "both"):
        _cma_es.CMAEvolutionStrategy._calc_cov_update = staticmethod(tutorial_cov_update)
    if variant in ("restart-result", "both"):
        restart_from_result()
    emit = peer_pyribs_cma.common.emit
    peer_pyribs_cma.common.emit = lambda **row: emit(**{**row, "note": f"pyribs variant {variant}"})
    sys.argv = [sys.argv[0]] + args[2:]
    peer_pyribs_cma.main()


if __name__ == "__main__":
    main()
