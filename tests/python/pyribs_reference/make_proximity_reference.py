"""Writes proximity.json beside this file: pyribs's ProximityArchive on fixed batches, the
reference that tests/python/test_proximity_archive.py holds qdmeta.ProximityArchive to.

Run with pyribs 0.12.0 installed (the version bench/peers pins):
    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    /tmp/ribs/bin/python tests/python/pyribs_reference/make_proximity_reference.py
"""

import json
import pathlib

import numpy as np
import ribs
from ribs.archives import ProximityArchive

SETTINGS = [
    {"k_neighbors": 5, "novelty_threshold": 0.08},
    {"k_neighbors": 3, "novelty_threshold": 0.05, "local_competition": True},
    {"k_neighbors": 1, "novelty_threshold": 0.3, "threshold_decay_rate": 0.7, "threshold_decay_itrs": 2,
     "threshold_decay_min": 0.1},
]


def run(settings, batches):
    archive = ProximityArchive(solution_dim=3, measure_dim=2, **settings)
    adds = []
    for solution, objective, measures in batches:
        info = archive.add(solution, objective, measures)
        adds.append({key: np.asarray(value).tolist() for key, value in info.items()}
                    | {"threshold_after": float(archive.novelty_threshold)})
    data = archive.data()
    order = np.argsort(data["index"])
    return {
        "settings": settings,
        "adds": adds,
        "final": {field: np.asarray(data[field])[order].tolist() for field in ("solution", "objective", "measures")},
    }


def main():
    rng = np.random.default_rng(7)
    batches = [(rng.random((40, 3)), rng.normal(size=40), rng.random((40, 2))) for _ in range(8)]
    out = {
        "pyribs": ribs.__version__,
        "batches": [[b.tolist() for b in batch] for batch in batches],
        "runs": [run(settings, batches) for settings in SETTINGS],
    }
    path = pathlib.Path(__file__).with_name("proximity.json")
    path.write_text(json.dumps(out) + "\n")
    print(f"wrote {path} ({len(SETTINGS)} settings, {len(batches)} batches, pyribs {ribs.__version__})")


if __name__ == "__main__":
    main()
