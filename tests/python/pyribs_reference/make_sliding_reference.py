"""Writes sliding.json beside this file: pyribs's SlidingBoundariesArchive on fixed batches,
the reference that tests/python/test_sliding_boundaries_archive.py holds
qdmeta.SlidingBoundariesArchive to.

Run with pyribs 0.12.0 installed (the version bench/peers pins):
    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    /tmp/ribs/bin/python tests/python/pyribs_reference/make_sliding_reference.py
"""

import json
import pathlib

import numpy as np
import ribs
from ribs.archives import SlidingBoundariesArchive

SETTINGS = [
    {"dims": [5, 4], "ranges": [[0, 1], [-1, 1]], "remap_frequency": 50, "buffer_capacity": 120},
    {"dims": [10], "ranges": [[0, 1]], "remap_frequency": 7, "buffer_capacity": 30},
]


def run(settings, rng):
    measure_dim = len(settings["dims"])
    archive = SlidingBoundariesArchive(solution_dim=2, **settings)
    batches, adds = [], []
    for _ in range(8):
        # Measures bunched toward one end, so that the boundaries move.
        measures = rng.beta(2, 5, (60, measure_dim)) * 1.2 - 0.1
        batch = (rng.random((60, 2)), rng.normal(size=60), measures)
        info = archive.add(*batch)
        batches.append([b.tolist() for b in batch])
        adds.append({
            "status": info["status"].tolist(),
            "value": info["value"].tolist(),
            "boundaries": [np.asarray(b).tolist() for b in archive.boundaries],
        })
    data = archive.data()
    return {
        "settings": settings,
        "batches": batches,
        "adds": adds,
        "final": {field: np.asarray(data[field]).tolist() for field in ("solution", "objective", "measures", "index")},
    }


def main():
    rng = np.random.default_rng(19)
    out = {"pyribs": ribs.__version__, "runs": [run(settings, rng) for settings in SETTINGS]}
    path = pathlib.Path(__file__).with_name("sliding.json")
    path.write_text(json.dumps(out) + "\n")
    print(f"wrote {path} ({len(SETTINGS)} settings, pyribs {ribs.__version__})")


if __name__ == "__main__":
    main()
