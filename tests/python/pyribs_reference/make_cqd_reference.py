"""Writes cqd.json beside this file: pyribs's cqd_score on fixed archives and targets, the
reference that tests/python/test_cqd_score.py holds qdmeta's cqd_score to.

Run with pyribs 0.12.0 installed (the version bench/peers pins):
    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    /tmp/ribs/bin/python tests/python/pyribs_reference/make_cqd_reference.py

Each elite sits alone in its cell of a 10 x 10 grid over [0, 1]^2, at a point and with an
objective that float32 holds exactly, so both libraries' archives hold the same elites.
"""

import json
import pathlib

import numpy as np
import ribs
from ribs.archives import GridArchive, cqd_score


def elites(rng):
    cells = [(i, j) for i in range(10) for j in range(10) if rng.random() < 0.6]
    measures = np.array([[(10 * i + rng.integers(1, 10)) / 100 for i in cell] for cell in cells])
    measures = np.round(measures * 256) / 256  # float32-exact; still inside the cell
    objectives = rng.integers(-160, 160, len(cells)) / 16.0
    return objectives, measures


def case(name, rng, objectives, measures, iterations, targets, penalties, obj_min, obj_max, dist_ord):
    archive = GridArchive(solution_dim=2, dims=[10, 10], ranges=[(0, 1), (0, 1)])
    archive.add(measures.copy(), objectives, measures)
    assert len(archive) == len(objectives)
    target_points = rng.random((iterations, targets, 2))
    result = cqd_score(
        archive,
        iterations=iterations,
        target_points=target_points,
        penalties=penalties,
        obj_min=obj_min,
        obj_max=obj_max,
        dist_max=np.sqrt(2),
        dist_ord=dist_ord,
    )
    return {
        "name": name,
        "iterations": iterations,
        "target_points": target_points.tolist(),
        "penalties": penalties if np.isscalar(penalties) else list(penalties),
        "obj_min": obj_min,
        "obj_max": obj_max,
        "dist_max": float(np.sqrt(2)),
        "dist_ord": None if dist_ord is None else ("inf" if dist_ord == np.inf else dist_ord),
        "pyribs_scores": result.scores.tolist(),
        "pyribs_mean": float(result.mean),
    }


def main():
    rng = np.random.default_rng(2022)
    objectives, measures = elites(rng)
    cases = [
        case("euclidean, 5 penalties, 3 iterations", rng, objectives, measures, 3, 50, 5, 0.0, 10.0, None),
        case("L1, given penalties", rng, objectives, measures, 2, 40, [0.0, 0.3, 1.0], 0.0, 20.0, 1),
        case("max norm, one penalty", rng, objectives, measures, 1, 30, 1, 0.0, 10.0, np.inf),
        case("obj_min below 0", rng, objectives, measures, 2, 25, 4, -10.0, 10.0, None),
    ]
    out = {
        "pyribs": ribs.__version__,
        "objectives": objectives.tolist(),
        "measures": measures.tolist(),
        "cases": cases,
    }
    path = pathlib.Path(__file__).with_name("cqd.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path} ({len(objectives)} elites, {len(cases)} cases, pyribs {ribs.__version__})")


if __name__ == "__main__":
    main()
