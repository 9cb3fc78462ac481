"""The engine cross-check's tables in docs/fidelity.md are what tools/rhex_engines_table.py makes
from the committed episodes (docs/results/rhex-engines/episodes.csv), the committed episodes are
the design (every environment and model: controllers 0-199 once each and the tripod; compliant
legs possibly fewer), and the statistics are right: by hand and, where Debian's python3-scipy is present, against
SciPy's pearsonr and spearmanr."""
import csv
import pathlib
import random
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import rhex_engines_table as table  # noqa: E402

ENVIRONMENTS = ["flat", "leg-removal leg 1", "leg-shortening leg 1", "blocked-hip leg 1", "passive-hip leg 1"]


def test_fidelity_md_holds_the_tables_made_from_the_committed_episodes():
    doc = (ROOT / "docs" / "fidelity.md").read_text()
    assert doc.count(table.BEGIN) == 1 and doc.count(table.END) == 1
    inside = doc.split(table.BEGIN + "\n", 1)[1].split(table.END, 1)[0]
    assert inside == table.tables(), "run tools/rhex_engines_table.py --write"


def test_the_committed_episodes_are_the_design():
    """Every environment on every model: controllers 0-199 once each and the tripod, but the
    compliant legs, whose run may stop at a round's end (scripts/rhex-engine-crosscheck.sh): then
    each compliant model has the same first n controllers (a multiple of 50) in every environment."""
    with open(table.CSV, newline="") as f:
        rows = list(csv.DictReader(f))
    episodes = table.read(table.CSV)
    assert list(episodes)[:5] == ENVIRONMENTS and len(episodes) == 14
    for model in ("dart-compliant", "mujoco-compliant"):
        counts = {len(models[model]["random"]) for models in episodes.values()}
        assert len(counts) == 1 and counts.pop() % 50 == 0, model
    for env, models in episodes.items():
        assert set(models) == set(table.MODELS), env
        for model, runs in models.items():
            n = len(runs["random"]) if model.endswith("compliant") else 200
            assert n >= 50 and sorted(runs["random"]) == list(range(n)), (env, model)
            assert "tripod" in runs, (env, model)
    assert len(rows) == sum(len(runs["random"]) + 1 for models in episodes.values() for runs in models.values())
    for row in rows:  # a dead robot walks 0 and has a cause; a live one neither
        assert (row["dead"] == "1") == (row["cause"] != "")
        assert row["dead"] == "0" or float(row["distance"]) == 0.0


def test_pearson_and_spearman_by_hand():
    assert table.pearson([1, 2, 3], [2, 4, 6]) == pytest.approx(1.0)
    assert table.pearson([1, 2, 3], [3, 2, 1]) == pytest.approx(-1.0)
    # x = 1, 2, 3, 4; y = 1, 3, 2, 4: deviations -1.5 -0.5 0.5 1.5 and -1.5 0.5 -0.5 1.5,
    # products sum 2.25 - 0.25 - 0.25 + 2.25 = 4, sums of squares 5: r = 0.8.
    assert table.pearson([1, 2, 3, 4], [1, 3, 2, 4]) == pytest.approx(0.8)
    # Ranks are what matter to Spearman: a monotone transform leaves it at 1.
    assert table.spearman([1, 2, 3, 4], [1, 8, 27, 64]) == pytest.approx(1.0)
    # Ties (dead robots at 0) share their mean rank: x ranks 1.5 1.5 3 4, y ranks 1 2 3 4.
    assert table.spearman([0, 0, 2, 3], [1, 2, 3, 4]) == pytest.approx(table.pearson([1.5, 1.5, 3, 4], [1, 2, 3, 4]))


def test_pearson_and_spearman_agree_with_scipy():
    stats = pytest.importorskip("scipy.stats")
    rng = random.Random(5)
    for _ in range(20):
        x = [rng.choice([0.0, rng.uniform(0, 4)]) for _ in range(30)]  # many ties at 0
        y = [v + rng.gauss(0, 1) if v else rng.choice([0.0, 1.0]) for v in x]
        assert table.pearson(x, y) == pytest.approx(stats.pearsonr(x, y)[0], abs=1e-12)
        assert table.spearman(x, y) == pytest.approx(stats.spearmanr(x, y)[0], abs=1e-12)


def test_the_tables_of_a_small_file(tmp_path):
    path = tmp_path / "episodes.csv"
    path.write_text("environment,model,controller,distance,dead,cause\n"
                    "flat,dart-rigid,0,1.0,0,\nflat,dart-rigid,1,2.0,0,\nflat,dart-rigid,2,3.0,0,\n"
                    "flat,dart-rigid,tripod,3.5,0,\n"
                    "flat,mujoco-rigid,0,0,1,turned_over\nflat,mujoco-rigid,1,2.5,0,\nflat,mujoco-rigid,2,4.0,0,\n"
                    "flat,mujoco-rigid,tripod,3.25,0,\n")
    text = table.tables(str(path))
    assert "| flat | 2.000 / 0 / 3.500 (3) | 2.167 / 1 / 3.250 (3) |" in text
    # r of (0, 2.5, 4) against (1, 2, 3): deviations -2.1667 0.3333 1.8333 and -1 0 1.
    r = (2.1667 + 1.8333) / ((2.1667 ** 2 + 0.3333 ** 2 + 1.8333 ** 2) * 2) ** 0.5
    assert f"| flat | {r:.3f}, 1.000 (3) |" in text


def test_replaced_swaps_only_the_marked_block():
    doc = f"a\n{table.BEGIN}\nold\n{table.END}\nb\n"
    assert table.replaced(doc, "new\n") == f"a\n{table.BEGIN}\nnew\n{table.END}\nb\n"
