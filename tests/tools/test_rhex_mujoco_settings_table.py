"""The table of MuJoCo's settings in docs/fidelity.md is what tools/rhex_mujoco_settings_table.py
makes from the committed sweep (docs/results/rhex-engines/mujoco-settings.csv); the sweep holds
its design (every variant, leg model and environment: controllers 0..n-1 once each), its faithful
variant is the cross-check's MuJoCo, episode for episode (the same model and controllers give the
same bits), and the table's statistics are right on a small file worked by hand."""
import csv
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import rhex_engines_table as engines  # noqa: E402
import rhex_mujoco_settings_table as settings  # noqa: E402


def test_fidelity_md_holds_the_table_made_from_the_committed_sweep():
    doc = (ROOT / "docs" / "fidelity.md").read_text()
    assert doc.count(settings.BEGIN) == 1 and doc.count(settings.END) == 1
    inside = doc.split(settings.BEGIN + "\n", 1)[1].split(settings.END, 1)[0]
    assert inside == settings.table(), "run tools/rhex_mujoco_settings_table.py --write"


def test_the_committed_sweep_is_its_design():
    runs, cpu = settings.read(settings.CSV)
    variants = list(dict.fromkeys(v for v, _ in runs))
    assert variants[0] == settings.FAITHFUL and len(variants) >= 2
    environments = list(runs[(settings.FAITHFUL, "rigid")])
    assert environments[0] == "flat" and len(environments) >= 3
    n = len(runs[(settings.FAITHFUL, "rigid")]["flat"])
    for key, by_env in runs.items():
        assert list(by_env) == environments, key
        for env, episodes in by_env.items():
            assert sorted(episodes) == list(range(n)), (key, env)
        assert len(cpu[key]) == n * len(environments) and min(cpu[key]) > 0, key
    with open(settings.CSV, newline="") as f:
        for row in csv.DictReader(f):  # a dead robot walks 0 and has a cause; a live one neither
            assert (row["dead"] == "1") == (row["cause"] != "")
            assert row["dead"] == "0" or float(row["distance"]) == 0.0


def test_the_faithful_variant_is_the_crosschecks_mujoco():
    runs, _ = settings.read(settings.CSV)
    crosscheck = engines.read(engines.CSV)
    compared = 0
    for legs in ("rigid", "compliant"):
        for env, episodes in runs.get((settings.FAITHFUL, legs), {}).items():
            reference = crosscheck[env][f"mujoco-{legs}"]["random"]
            for controller, value in episodes.items():
                if controller in reference:
                    assert value == reference[controller], (legs, env, controller)
                    compared += 1
    assert compared >= 100


def test_the_table_of_a_small_file(tmp_path):
    sweep = tmp_path / "sweep.csv"
    sweep.write_text("variant,legs,environment,controller,distance,dead,cause,cpu_s\n"
                     "faithful,rigid,flat,0,1.0,0,,0.04\nfaithful,rigid,flat,1,2.0,0,,0.04\n"
                     "faithful,rigid,flat,2,3.0,0,,0.04\n"
                     "fast,rigid,flat,0,0,1,turned_over,0.01\nfast,rigid,flat,1,2.5,0,,0.02\n"
                     "fast,rigid,flat,2,4.0,0,,0.03\n")
    crosscheck = tmp_path / "episodes.csv"
    crosscheck.write_text("environment,model,controller,distance,dead,cause\n"
                          "flat,dart-rigid,0,1.0,0,\nflat,dart-rigid,1,2.0,0,\nflat,dart-rigid,2,3.0,0,\n")
    text = settings.table(str(sweep), str(crosscheck))
    assert "| faithful | rigid | 40.0 (x1.00) | 2.000 / 0 (3); DART r 1.000 |" in text
    # fast against faithful (and DART, the same distances): (0, 2.5, 4) against (1, 2, 3), r as in
    # test_rhex_engines_table; |d| = (1 + 0.5 + 1) / 3; CPU 20 ms, half the faithful's 40.
    r = (2.1667 + 1.8333) / ((2.1667 ** 2 + 0.3333 ** 2 + 1.8333 ** 2) * 2) ** 0.5
    assert f"| fast | rigid | 20.0 (x0.50) | 2.167 / 1 (3); r {r:.3f}; DART r {r:.3f}; \\|d\\| 0.833 |" in text


def test_no_r_where_every_robot_died():
    assert settings.r_text([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]) == "-"
    assert settings.r_text([1.0, 2.0, 3.0], [2.0, 4.0, 6.0]) == "1.000"


def test_replaced_swaps_only_its_own_block():
    doc = f"a\n{engines.BEGIN}\nold\n{engines.END}\n{settings.BEGIN}\nold\n{settings.END}\nb\n"
    assert engines.replaced(doc, "new\n", settings.BEGIN, settings.END) == (
        f"a\n{engines.BEGIN}\nold\n{engines.END}\n{settings.BEGIN}\nnew\n{settings.END}\nb\n")


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))
