"""Writes iso_line.json beside this file: the mean and covariance of pyribs's IsoLineEmitter's
rows over a fixed archive, the reference that tests/python/test_iso_line_emitter.py holds
qdmeta's IsoLineEmitter to (the two draw from different generators, so the rows differ and
their statistics agree).

Run with pyribs 0.12.0 installed (the version bench/peers pins):
    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    /tmp/ribs/bin/python tests/python/pyribs_reference/make_iso_line_reference.py

The archive holds three elites of two genes, (0, 0), (4, 0) and (0, 2), one per cell of a
3-cell grid; the bounded case clamps to [-1, 3] in both genes.
"""

import json
import pathlib

import numpy as np
import ribs
from ribs.archives import GridArchive
from ribs.emitters import IsoLineEmitter

ELITES = [[0.0, 0.0], [4.0, 0.0], [0.0, 2.0]]
ROWS = 400_000


def archive():
    a = GridArchive(solution_dim=2, dims=[3], ranges=[(0.0, 3.0)])
    a.add(np.array(ELITES), [1.0, 2.0, 3.0], [[0.5], [1.5], [2.5]])
    return a


def moments(emitter):
    x = np.concatenate([emitter.ask() for _ in range(ROWS // emitter.batch_size)]).astype(np.float64)
    return {"mean": x.mean(axis=0).tolist(), "cov": np.cov(x.T, bias=True).tolist(), "rows": len(x)}


def main():
    cases = {
        "unbounded": dict(iso_sigma=0.5, line_sigma=1.0),
        "bounded": dict(iso_sigma=0.5, line_sigma=1.0, bounds=[(-1.0, 3.0)] * 2),
        "empty": dict(iso_sigma=0.3, line_sigma=1.0),
    }
    out = {"ribs": ribs.__version__, "elites": ELITES}
    for name, kwargs in cases.items():
        a = archive() if name != "empty" else GridArchive(solution_dim=2, dims=[3], ranges=[(0.0, 3.0)])
        emitter = IsoLineEmitter(a, x0=[0.5, -0.5], batch_size=1000, seed=1, **kwargs)
        out[name] = {"kwargs": kwargs, **moments(emitter)}
    path = pathlib.Path(__file__).parent / "iso_line.json"
    path.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
