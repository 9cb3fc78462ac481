#!/usr/bin/python3
"""Figures and report.md for an experiment written by `qdmeta experiment`.

Usage: /usr/bin/python3 tools/report.py DIR [--out OUT] [--quiet] [--supplementary]

Reads DIR/experiment.toml and every finished run: its directory DIR/<condition>/seed-<r>/
(metrics.csv, meta.csv, archive.csv, adapt-*.csv, generalisation.csv, summary.json,
config.toml) or, without one, its summary DIR/<condition>/seed-<r>.json (tools/runs.py: the
same report from either); writes OUT/figures/*.png, OUT/report.md and the small CSV summaries
they are made from, OUT/data/runs.csv, OUT/data/curves.csv and (when runs have
generalisation.csv) OUT/data/generalisation.csv, the paper's Table 2 (OUT: DIR unless given).
The paper's supplementary meta-fitness figures (S4: meta-fitness with its running average; S5:
G against meta-fitness) are drawn for RHex experiments, or for any experiment with
--supplementary.
Replicates are aligned on a fixed evaluation grid from 0 to the experiment's budget (the last
logged row at or before each grid point; the last point is each run's end), since
meta-generation boundaries fall at different evaluation counts. Values are
mean +- standard error over replicates; every pair of conditions is compared by a two-sided
Mann-Whitney U test (Holm-adjusted per table) with the A12 effect size (tools/significance.py).
A file lost from a finished run, and runs of one condition with different config fingerprints,
are errors; a finished run that lacks what a table reads is left out of it and named in
report.md and on stderr (left_out).
Needs only Debian's python3-matplotlib and numpy.
"""
import csv
import io
import warnings
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import script_exit  # noqa: E402  (tools/script_exit.py: one line and exit 2 or 130, never a traceback)

if __name__ == "__main__":
    script_exit.before_main("report.py")
import matplotlib  # noqa: E402
import archive_plots  # noqa: E402  (tools/archive_plots.py: the archive pictures qdmeta.visualize draws too)
import claims  # noqa: E402  (tools/claims.py)
import experiment_files  # noqa: E402  (tools/experiment_files.py: every input, read and checked)
import runs as run_data  # noqa: E402  (tools/runs.py: a run from its directory or its summary)
import significance  # noqa: E402  (tools/significance.py)
from output_files import OutputDir  # noqa: E402  (tools/output_files.py: writes that follow no planted link)
from run_files import InputError  # noqa: E402
from runs import G_WINDOW, on_grid, trailing_mean  # noqa: E402, F401  (trailing_mean: for its tests)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

warnings.filterwarnings("ignore", message="Mean of empty slice")
warnings.filterwarnings("ignore", message="Degrees of freedom <= 0")


def mean_se(samples):
    """Mean and standard error along axis 0 (SE 0 for one replicate); NaNs ignored."""
    a = np.asarray(samples, dtype=float)
    n = np.sum(~np.isnan(a), axis=0)
    mean = np.nanmean(a, axis=0)
    sd = np.nanstd(a, axis=0, ddof=1) if a.shape[0] > 1 else np.zeros_like(mean)
    se = np.where(n > 1, sd / np.sqrt(np.maximum(n, 1)), 0.0)
    return mean, se


def stat(values):
    """Mean and standard error of one number per replicate."""
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        return float("nan"), 0.0
    se = float(np.std(v, ddof=1) / math.sqrt(v.size)) if v.size > 1 else 0.0
    return float(np.mean(v)), se


def plot_band(ax, x, mean, se, label, linewidth=1.5):
    """A mean curve with its +- SE band."""
    ax.plot(x, mean, label=label, linewidth=linewidth)
    ax.fill_between(x, mean - se, mean + se, alpha=0.25)


def fmt(mean, se, digits=4):
    if mean is None or (isinstance(mean, float) and math.isnan(mean)):
        return "n/a"
    return f"{mean:.{digits}g} ± {se:.2g}"


def load(directory):
    """The experiment in force and its conditions' finished and unfinished runs, each from its
    run directory or, without a finished one, its summary; every file the report reads is
    checked here (InputError), every archive included, and a condition's runs must share one
    config (same_config)."""
    spec = experiment_files.read_experiment(os.path.join(directory, "experiment.toml"))
    conditions = []
    for c in spec["condition"]:
        runs, unfinished = [], []
        for r in range(1, spec["replicates"] + 1):
            path = experiment_files.run_directory(directory, c["slug"], r)
            summary = experiment_files.read_summary(os.path.join(path, "summary.json"))
            kept = run_data.summary_path(directory, c["slug"], r)
            if summary is not None and summary.get("stop_reason") == "budget":
                runs.append(run_data.RunDirectory(path, summary, spec["tests"]))
            elif os.path.lexists(kept):
                runs.append(run_data.RunSummary(kept))
            else:
                unfinished.append(path)
        same_config(c["name"], runs)
        conditions.append({"name": c["name"], "slug": c["slug"], "runs": runs, "unfinished": unfinished})
    return spec, conditions


def same_config(condition, runs):
    """Refuses to pool runs made from different configs (an experiment interrupted, its config
    changed, then continued): their config fingerprints differ. A run made before runs kept a
    fingerprint has none, and pools with any."""
    first = next((r for r in runs if r.fingerprint), None)
    other = next((r for r in runs if r.fingerprint and r.fingerprint != first.fingerprint), None)
    if other:
        raise InputError(f"condition '{condition}': runs {first.path} and {other.path} were made from different "
                         f"configs (config_fingerprint {first.fingerprint} and {other.fingerprint}): a condition "
                         "pools the runs of one config; run the other again, or remove it")


def left_out(conditions, tests):
    """(condition, run, file, why) of each finished replicate a table or figure leaves out, for lack of
    the part of it that table reads: its metrics, its meta-generations (QD-Meta), a test's curve
    or generalisation table (the experiment's tests). The report names each one."""
    out = []
    for c in conditions:
        qd_meta = any(r.meta or r.config().get("algorithm") == "qd-meta" for r in c["runs"])
        for r in c["runs"]:
            parts = [("metrics.csv", bool(r.metrics))] + ([("meta.csv", bool(r.meta))] if qd_meta else [])
            parts += [(experiment_files.test_file(t), bool(r.generalisation() if t == GENERALISATION else
                                                           r.adapt.get(t))) for t in tests]
            out += [(c, r, *r.lacks(part)) for part, present in parts if not present]
    return out


QD_PANELS = [("num_elites", "archive size"), ("obj_mean", "average fitness"), ("obj_max", "global fitness"),
             ("qd_score", "QD-score")]


def population_curve(run, column):
    """(evals, values) of one QD statistic in the meta-population view: for QD-Meta the mean over
    every map of each meta-generation (meta.csv), otherwise the archive itself (metrics.csv)."""
    key = f"population_{column}_mean"
    if run.meta and key in run.meta:
        return run.meta["evals"], run.meta[key]
    return run.metrics["evals"], run.metrics[column]


def best_map_curve(run, column):
    """(evals, values) of one QD statistic of the archive a run logs (QD-Meta: its best map)."""
    return run.metrics["evals"], run.metrics[column]


# The two views of QD-Meta's archives; the other algorithms look the same in both.
QD_VIEWS = [("best map", best_map_curve), ("meta-population", population_curve)]


def evaluation_grid(spec, conditions):
    """The fixed evaluation grid replicates are aligned on: up to the experiment's budget, or
    without one the last logged evaluation count (None when nothing was logged)."""
    budget = experiment_budget(spec, conditions) or max(
        (r.metrics["evals"][-1] for c in conditions for r in c["runs"] if r.metrics), default=0)
    return run_data.evaluation_grid(budget) if budget > 0 else None


def save_figure(fig, out):
    """Lays out, writes and closes a figure; `out` is (OutputDir, file name). Returns its path."""
    fig.tight_layout()
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=110)
    plt.close(fig)
    directory, name = out
    return directory.write(name, png.getvalue())


def figure_qd_statistics(conditions, grid, out):
    """Two views side by side, as rows: QD-Meta's best map of each meta-generation (metrics.csv),
    and its whole meta-population (the mean over its maps, meta.csv), as the paper's figures
    aggregate "across the different archives within the meta-population". The other
    algorithms have one archive: the same curve in both rows."""
    if grid is None:
        return None
    fig, axes = plt.subplots(2, len(QD_PANELS), figsize=(5 * len(QD_PANELS), 8.4), squeeze=False)
    for row, (view, curve) in zip(axes, QD_VIEWS):
        for c in conditions:
            runs = [r for r in c["runs"] if r.metrics]
            if not runs:
                continue
            for ax, (column, label) in zip(row, QD_PANELS):
                mean, se = mean_se([on_grid(*curve(r, column), grid) for r in runs])
                plot_band(ax, grid, mean, se, f'{c["name"]} (n={len(runs)})')
                ax.set_xlabel("evaluations")
                ax.set_ylabel(f"{label} ({view})", fontsize=9)
    axes[0][0].legend(fontsize=8)
    fig.suptitle("QD statistics over evaluations (mean ± SE over replicates). Top: QD-Meta's best map; "
                 "bottom: the mean over its meta-population")
    return save_figure(fig, out)


def figure_meta(conditions, out):
    meta = [c for c in conditions if any(r.meta for r in c["runs"])]
    if not meta:
        return None
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    panels = [("meta_fitness_mean", "meta-fitness (mean over the meta-population)"),
              ("meta_fitness_best", "meta-fitness (best of the meta-population)"),
              ("generations", f"G per meta-generation (mean of the last {G_WINDOW})")]
    for c in meta:
        runs = [r for r in c["runs"] if r.meta]
        length = max(r.meta_generations for r in runs)
        stride = run_data.meta_stride(length)
        x = np.arange(0, length, stride) + 1
        for ax, (column, label) in zip(axes, panels):
            padded = np.full((len(runs), len(x)), np.nan)
            for i, r in enumerate(runs):
                # G is drawn anew each meta-generation: show its trend
                values = r.meta_series("generations_trailing" if column == "generations" else column, stride)
                padded[i, : len(values)] = values
            mean, se = mean_se(padded)
            plot_band(ax, x, mean, se, f'{c["name"]} (n={len(runs)})', linewidth=0.8)
            ax.set_xlabel("meta-generation")
            ax.set_ylabel(label, fontsize=9)
    axes[0].legend(fontsize=8)
    fig.suptitle("Meta-evolution (mean ± SE over replicates)")
    return save_figure(fig, out)


# A test entry that is a table, not a recovery curve: `qdmeta experiment` writes generalisation.csv
# for it (no adapt-generalisation.csv), reported as the paper's Table 2.
GENERALISATION = "generalisation"


def curve_tests(tests):
    """The experiment's tests that have recovery curves (adapt-<test>.csv)."""
    return [t for t in tests if t != GENERALISATION]


def continued_curves(curves):
    """Curves as rows of one array, each continued with its last value up to the longest's length:
    a random search over an archive with fewer solutions than the test's budget stops early, and
    the paper continues such lines "for comparability" (Fig 7) rather than cutting every curve to
    the shortest. Curves of equal length are unchanged."""
    length = max(len(c) for c in curves)
    out = np.empty((len(curves), length))
    for i, c in enumerate(curves):
        out[i, : len(c)] = c
        out[i, len(c):] = c[-1]
    return out


def adaptation_curves(runs, test):
    """The test's best-so-far curves of `runs`, continued to a common length (continued_curves)."""
    return continued_curves([r.adapt[test]["best_mean"] for r in runs])


def archive_exhausted(runs, test):
    """Whether some run's curve was continued past the end of its archive: shorter than the
    longest curve (continued here), or longer than its archive has solutions (continued by
    qdmeta's writer, which keeps the best once every solution has been tried)."""
    length = max(len(r.adapt[test]["best_mean"]) for r in runs)
    return any(len(r.adapt[test]["best_mean"]) < length or
               ("num_elites" in r.summary and float(r.summary["num_elites"]) < length) for r in runs)


CONTINUED_NOTE = ("For comparability, a line is continued with its last value once an archive is exhausted "
                  "(fewer solutions than evaluations), though no further evaluations are made.")


def adaptation_runs(conditions, test):
    """[(condition, runs with the test's curve)] of the conditions that have one."""
    return [(c, runs) for c in conditions for runs in [[r for r in c["runs"] if r.adapt.get(test)]] if runs]


def figure_adaptation(conditions, test, out):
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    shown = adaptation_runs(conditions, test)
    for c, runs in shown:
        mean, se = mean_se(adaptation_curves(runs, test))
        x = np.arange(1, len(mean) + 1)
        plot_band(ax, x, mean, se, f'{c["name"]} (n={len(runs)})')
    if not shown:
        plt.close(fig)
        return None
    ax.set_xlabel("evaluations (random search over the archive)")
    ax.set_ylabel("best score so far, mean over test functions")
    title = f"Test phase: {test} (mean ± SE over replicates)"
    if any(archive_exhausted(runs, test) for _, runs in shown):
        title += "\nlines continued with their last value once an archive is exhausted"
    ax.set_title(title, fontsize=10 if "\n" in title else None)
    ax.legend(fontsize=8)
    return save_figure(fig, out)


def meta_fitness_kind(run):
    """The [meta_fitness] kind a QD-Meta run evolved for (its config.toml), None for the others."""
    config = run.config()
    if config.get("algorithm") != "qd-meta" or not isinstance(config.get("meta_fitness"), dict):
        return None
    return config["meta_fitness"].get("kind", "damage")  # qdmeta's RHex default when the key is left out


def meta_conditions(conditions):
    """[(condition, its runs with meta.csv)] of the QD-Meta conditions."""
    return [(c, runs) for c in conditions for runs in [[r for r in c["runs"] if r.meta]] if runs]


def replicate_matrix(series):
    """Per-replicate series of different lengths (runs make different numbers of meta-generations
    within one budget) as rows of one array, NaN past each one's end: the mean at a meta-generation
    is over the replicates that reached it."""
    out = np.full((len(series), max(len(v) for v in series)), np.nan)
    for i, v in enumerate(series):
        out[i, : len(v)] = v
    return out


def figure_meta_running_average(conditions, out):
    """The paper's Fig S4: meta-fitness per meta-generation (thin, faint) and its trailing mean
    over G_WINDOW meta-generations (thick, with the SE band over replicates), mean over
    replicates. One column per meta-fitness kind, as the kinds' scales differ (RHex: obstacle
    courses against damages); rows: the best map of the meta-population, and the mean over it
    (the paper's y-axis)."""
    meta = meta_conditions(conditions)
    if not meta:
        return None
    kinds = {}
    for c, runs in meta:
        kinds.setdefault(meta_fitness_kind(runs[0]) or "meta-fitness", []).append((c, runs))
    rows = [("meta_fitness_best", "best of the meta-population"), ("meta_fitness_mean", "mean over the meta-population")]
    fig, axes = plt.subplots(len(rows), len(kinds), figsize=(6.5 * len(kinds), 4 * len(rows)), squeeze=False)
    for col, (kind, members) in enumerate(kinds.items()):
        for row, (column, label) in enumerate(rows):
            ax = axes[row][col]
            for i, (c, runs) in enumerate(members):
                colour = f"C{i}"
                stride = run_data.meta_stride(max(r.meta_generations for r in runs))
                raw = replicate_matrix([r.meta_series(column, stride) for r in runs])
                smooth = replicate_matrix([r.meta_series(f"{column}_trailing", stride) for r in runs])
                x = np.arange(0, raw.shape[1]) * stride + 1
                ax.plot(x, np.nanmean(raw, axis=0), color=colour, linewidth=0.5, alpha=0.35)
                mean, se = mean_se(smooth)
                ax.plot(x, mean, color=colour, linewidth=2, label=f'{c["name"]} (n={len(runs)})')
                ax.fill_between(x, mean - se, mean + se, color=colour, alpha=0.2)
            ax.set_xlabel("meta-generation")
            ax.set_ylabel(f"meta-fitness ({label})", fontsize=9)
            ax.set_title(f"meta-fitness kind: {kind}", fontsize=10)
            ax.legend(fontsize=8)
    fig.suptitle(f"Meta-fitness per meta-generation (faint) and its running average over the last {G_WINDOW} "
                 "(thick, mean ± SE over replicates)")
    return save_figure(fig, out)


def controls_generations(runs):
    """Whether G varies in these runs: [control] kind = "sarsa" in their config (or, without a
    config, G not constant in meta.csv). A static control fixes G, so S5 has nothing to show."""
    config = runs[0].config()
    if config:
        return config.get("control", {}).get("kind") == "sarsa"
    return any(r.generations_vary for r in runs)


def figure_generations_and_meta_fitness(conditions, out):
    """The paper's Fig S5: for each QD-Meta condition with SARSA control of G, one panel per run
    (row: condition; column: replicate) with the meta-fitness (mean over the meta-population,
    the paper's top panels; left axis) and G, drawn and as its running average over G_WINDOW
    meta-generations (right axis), over meta-generations."""
    shown = [(c, runs) for c, runs in meta_conditions(conditions) if controls_generations(runs)]
    if not shown:
        return None
    columns = max(len(runs) for _, runs in shown)
    fig, axes = plt.subplots(len(shown), columns, figsize=(4.6 * columns, 3.4 * len(shown)), squeeze=False)
    for row, (c, runs) in zip(axes, shown):
        for ax in row[len(runs):]:
            ax.axis("off")
        for ax, r in zip(row, runs):
            stride = run_data.meta_stride(r.meta_generations)
            x = r.meta_series("meta_generation", stride)
            ax.plot(x, r.meta_series("meta_fitness_mean", stride), color="C0", linewidth=1)
            ax.set_xlabel("meta-generation")
            ax.set_ylabel("meta-fitness (mean over the meta-population)", color="C0", fontsize=8)
            ax.tick_params(axis="y", labelcolor="C0")
            g = ax.twinx()
            g.plot(x, r.meta_series("generations", stride), color="C1", linewidth=0.5, alpha=0.3)
            g.plot(x, r.meta_series("generations_trailing", stride), color="C1", linewidth=2)
            g.set_ylabel(f"G (faint: drawn; thick: mean of the last {G_WINDOW})", color="C1", fontsize=8)
            g.tick_params(axis="y", labelcolor="C1")
            ax.set_title(f'{c["name"]}, seed {r.seed}', fontsize=9)
    fig.suptitle("Generations per meta-generation (G, SARSA control) and meta-fitness, per run")
    return save_figure(fig, out)


def supplementary_figures(conditions):
    """Whether to draw S4 and S5: the paper shows them for its RHex study only, and the Rastrigin
    reports stay as they were (--supplementary draws them for any experiment)."""
    return any(r.config().get("task", {}).get("name") == "rhex" for c in conditions for r in c["runs"][:1])


# Table 2's rows: generalisation.csv's groups in the paper's order, with its names.
GENERALISATION_GROUPS = [("damage-training", "Training-Damages"), ("obstacle-training", "Training-Obstacles"),
                         ("damage", "Test-Damages"), ("obstacle", "Test-Obstacles")]


def trained_groups(runs):
    """The generalisation groups a condition met during meta-evolution: a QD-Meta run of meta-fitness
    kind K evaluates its maps on K's training environments, the group "K-training"; baselines
    (no meta-fitness) met none. Read from the runs' saved config.toml."""
    return {f"{kind}-training" for r in runs for kind in [meta_fitness_kind(r)] if kind}


def generalisation_rows(conditions):
    """One row per (condition, group) for Table 2: the replicates' generalisation means (each the mean
    over the archive's solutions and the group's environments), their mean and sample SD (the
    paper's Table 2 gives mean ± SD, not SE; NaN SD for one replicate), whether it is trained."""
    rows = []
    for c in conditions:
        values = [r.generalisation() for r in c["runs"]]
        runs = [r for r, v in zip(c["runs"], values) if v]
        values = [v for v in values if v]
        if not runs:
            continue
        trained = trained_groups(runs)
        known = [g for g, _ in GENERALISATION_GROUPS]
        others = sorted({g for v in values for g in v} - set(known))
        for group in known + others:
            v = np.array([x[group] for x in values if group in x])
            if v.size == 0:
                continue
            sd = float(np.std(v, ddof=1)) if v.size > 1 else float("nan")
            rows.append({"condition": c["name"], "group": group, "n": int(v.size), "mean": float(np.mean(v)),
                         "sd": sd, "trained": group in trained})
    return rows


def generalisation_table(rows):
    """Table 2 in markdown: rows = environment groups, columns = conditions, cells mean ± SD over
    replicates; bold = the highest mean of the row; underlined = the group the condition was
    trained on (met during meta-evolution)."""
    if not rows:
        return ""
    names = list(dict.fromkeys(r["condition"] for r in rows))
    labels = dict(GENERALISATION_GROUPS)
    groups = list(dict.fromkeys(r["group"] for r in sorted(rows, key=lambda r: group_order(r["group"]))))
    cell = {(r["condition"], r["group"]): r for r in rows}
    n = {name: sorted({r["n"] for r in rows if r["condition"] == name}) for name in names}
    lines = ["| environment | " + " | ".join(f'{name} (n={"/".join(map(str, n[name]))})' for name in names) + " |",
             "|---|" + "---|" * len(names)]
    for group in groups:
        best = max(cell[name, group]["mean"] for name in names if (name, group) in cell)
        cells = []
        for name in names:
            r = cell.get((name, group))
            if r is None:
                cells.append("n/a")
                continue
            text = f'{r["mean"]:.4g} ± ' + ("n/a" if math.isnan(r["sd"]) else f'{r["sd"]:.2g}')
            if r["mean"] == best:
                text = f"**{text}**"
            if r["trained"]:
                text = f"<u>{text}</u>"
            cells.append(text)
        lines.append(f"| {labels.get(group, group)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def group_order(group):
    known = [g for g, _ in GENERALISATION_GROUPS]
    return (known.index(group), "") if group in known else (len(known), group)


def figure_archives(conditions, out):
    """One archive per condition, its first finished replicate's: the best fitness in each bin
    over measures 0 and 1 (tools/runs.py, archive_picture)."""
    shown = [c for c in conditions if c["runs"]]
    if not shown:
        return None
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 4), squeeze=False)
    for ax, c in zip(axes[0], shown):
        run = c["runs"][0]
        picture = run.picture()
        if picture is None:
            ax.set_title(f'{c["name"]}: fewer than 2 measures')
            continue
        # The picture is a grid of bins (rows: measure 1), drawn as qdmeta.visualize draws a grid.
        values = run_data.picture_values(picture)
        rows, columns = np.nonzero(np.isfinite(values))
        archive_plots.grid_heatmap(ax, columns * values.shape[0] + rows, values[rows, columns], [values.shape[1], values.shape[0]],
                                   lower=[picture["measures_0"][0], picture["measures_1"][0]],
                                   upper=[picture["measures_0"][1], picture["measures_1"][1]],
                                   vmin=picture["fitness"][0], vmax=picture["fitness"][1], colorbar=False)
        fig.colorbar(ax.images[-1], ax=ax, label="fitness")
        ax.set_title(f'{c["name"]} (seed {run.seed}, {picture["elites"]} elites)',
                     fontsize=9)
    return save_figure(fig, out)


def population_table(conditions):
    """The meta-population view of the final archives: for QD-Meta, the last meta-generation's
    mean over its maps (then mean ± SE of that over replicates)."""
    rows = []
    for c in conditions:
        runs = [r for r in c["runs"] if r.meta and "population_num_elites_mean" in r.meta]
        if not runs:
            continue
        cells = [fmt(*stat([r.meta[f"population_{key}_mean"][-1] for r in runs]), digits)
                 for key, _, digits in POPULATION_COLUMNS]
        rows.append(f'| {c["name"]} | {len(runs)} | ' + " | ".join(cells) + " |")
    if not rows:
        return ""
    return "\n".join(["| condition | n | " + " | ".join(label for _, label, _ in POPULATION_COLUMNS) + " |",
                      "|---|---|" + "---|" * len(POPULATION_COLUMNS)] + rows)


POPULATION_COLUMNS = [("num_elites", "archive size", 5), ("obj_mean", "average fitness", 4),
                      ("obj_max", "global fitness", 4), ("qd_score", "QD-score", 4)]


def experiment_budget(spec, conditions):
    """The evaluation budget of the experiment's runs (the largest, should they differ)."""
    if spec.get("evaluations"):
        return int(spec["evaluations"])
    budgets = [int(r.summary["budget"]) for c in conditions for r in c["runs"] if "budget" in r.summary]
    return max(budgets) if budgets else None


def claims_table(spec, conditions, source):
    """The experiment file's [[claim]] tables of one source ("paper": the paper's claims; "ours":
    checks the paper does not make), each with what was measured and a verdict. A magnitude
    claim about a larger budget is compared with the runs' own curves at half the budget
    (tools/claims.py)."""
    chosen = [c for c in spec.get("claim", []) if c.get("source", "paper") == source]
    if not chosen:
        return ""
    by_name = {c["name"]: c["runs"] for c in conditions}
    budget = experiment_budget(spec, conditions)
    earlier = None
    if budget:
        half = run_data.earlier_evals(budget)  # a summary keeps its runs' rows at this count

        def pairs(name, m):  # each run's (final, half-budget) values: the same runs, paired
            values = [(claims.measure_values([r], m), claims.measure_values_at([r], m, half))
                      for r in by_name.get(name, [])]
            return [(now[0], then[0]) for now, then in values if now and then]
        earlier = (half, lambda name, m: claims.measure_values_at(by_name.get(name, []), m, half), pairs)
    lines = ["| claim | measured (mean ± SE over replicates) | verdict |", "|---|---|---|"]
    for claim in chosen:
        measured, verdict = claims.check(claim, lambda name, m: claims.measure_values(by_name.get(name, []), m), budget,
                                         earlier)
        lines.append(f'| {claim["text"]} | {measured} | **{verdict}** |')
    return "\n".join(lines)


def summary_table(conditions):
    columns = [("num_elites", "archive size", 5), ("coverage", "coverage", 3), ("obj_mean", "average fitness", 4),
               ("obj_max", "global fitness", 4), ("qd_score", "QD-score", 4), ("evals", "evaluations", 9),
               ("wall_seconds", "wall time (s)", 3)]
    lines = ["| condition | n | " + " | ".join(label for _, label, _ in columns) + " |",
             "|---|---|" + "---|" * len(columns)]
    for c in conditions:
        runs = c["runs"]
        cells = []
        for key, _, digits in columns:
            values = [float(r.summary[key]) for r in runs if key in r.summary]
            cells.append(fmt(*stat(values), digits) if values else "n/a")
        lines.append(f'| {c["name"]} | {len(runs)} | ' + " | ".join(cells) + " |")
    return "\n".join(lines)


def meta_table(conditions):
    rows = []
    for c in conditions:
        runs = [r for r in c["runs"] if r.meta]
        if not runs:
            continue
        best = [r.meta["meta_fitness_best"][-1] for r in runs]
        mean = [r.meta["meta_fitness_mean"][-1] for r in runs]
        gens = [r.meta_generations for r in runs]
        g = [r.mean_generations for r in runs]
        states = [r.meta["states"][-1] for r in runs]
        rows.append(f'| {c["name"]} | {len(runs)} | {fmt(*stat(best))} | {fmt(*stat(mean))} | '
                    f'{fmt(*stat(gens), 5)} | {fmt(*stat(g), 3)} | {fmt(*stat(states), 3)} |')
    if not rows:
        return ""
    return "\n".join(["| condition | n | final best meta-fitness | final mean meta-fitness | meta-generations | "
                      "mean G | final states |", "|---|---|---|---|---|---|---|"] + rows)


def test_table(conditions, tests):
    lines = []
    for test in tests:
        shown = adaptation_runs(conditions, test)
        caption = f"**{test}** (best score so far, mean over test functions; mean ± SE over replicates)"
        if any(archive_exhausted(runs, test) for _, runs in shown):
            caption += " " + CONTINUED_NOTE
        lines += [caption, "", "| condition | n | after 1 | after 10 | at the end |", "|---|---|---|---|---|"]
        for c, runs in shown:
            curves = adaptation_curves(runs, test)
            cells = [fmt(*stat(curves[:, at])) for at in (0, 9, -1) if at < curves.shape[1]]
            if len(cells) < 3:  # a test budget under 10: "after 10" does not exist
                cells.insert(1, "n/a")
            lines.append(f'| {c["name"]} | {len(runs)} | ' + " | ".join(cells[:2])
                         + f" | {cells[2]} ({curves.shape[1]} evaluations) |")
        lines.append("")
    return "\n".join(lines)


ALPHA = significance.ALPHA


def comparison_table(title, samples):
    """Every pair of conditions on one measure: `samples` maps a condition's name to its
    replicates' values. Two-sided Mann-Whitney U, p Holm-adjusted over the pairs of this table,
    A12 of the first condition over the second; * marks adjusted p < ALPHA."""
    names = [n for n, v in samples.items() if len(v) > 0]
    pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    if not pairs:
        return ""
    tested = significance.pairwise([(samples[a], samples[b]) for a, b in pairs])
    lines = [f"**{title}**", "", "| first | second | median first | median second | U | p (Holm) | A12 | |",
             "|---|---|---|---|---|---|---|---|"]
    for (a, b), (u, p) in zip(pairs, tested):
        mark = "*" if p < ALPHA else ""
        lines.append(f"| {a} | {b} | {np.median(samples[a]):.4g} | {np.median(samples[b]):.4g} | {u:g} | {p:.3g} | "
                     f"{significance.a12(samples[a], samples[b]):.2f} | {mark} |")
    return "\n".join(lines + [""])


def comparisons(conditions, tests):
    """The pairwise tables: the final archives, the final best meta-fitness (QD-Meta), and the
    test phase after 1, 10 and 100 evaluations (or the last, when shorter)."""
    tables = []
    for key, label in [("num_elites", "archive size"), ("obj_mean", "average fitness"), ("obj_max", "global fitness"),
                       ("qd_score", "QD-score")]:
        tables.append(comparison_table(f"Final {label}", {c["name"]: [float(r.summary[key]) for r in c["runs"]
                                                                       if key in r.summary] for c in conditions}))
    tables.append(comparison_table("Final best meta-fitness", {c["name"]: [r.meta["meta_fitness_best"][-1]
                                                                           for r in c["runs"] if r.meta]
                                                               for c in conditions}))
    for test in tests:
        for at in (1, 10, 100):
            tables.append(comparison_table(
                f"Test phase {test}, after {at} evaluations",
                {c["name"]: [r.adapt[test]["best_mean"][min(at, len(r.adapt[test]["best_mean"])) - 1]
                             for r in c["runs"] if r.adapt.get(test)] for c in conditions}))
    return "\n".join(t for t in tables if t)


def write_csv(directory, name, header, rows):
    text = io.StringIO(newline="")
    w = csv.writer(text)
    w.writerow(header)
    w.writerows(rows)
    directory.write(name, text.getvalue())


def write_data(data_dir, conditions, tests, grid):
    """The small CSV summaries every table and figure is made from, in DIR/data/ (`data_dir`, an
    OutputDir): runs.csv (one row per finished run: its final values and test-phase scores) and
    curves.csv (the plotted means and SEs over replicates). They are small enough to commit
    beside report.md."""
    final_keys = ["evals", "evals_bottom", "evals_meta", "wall_seconds", "num_elites", "coverage", "obj_mean", "obj_max",
                  "qd_score"]
    population = [s for s, _, _ in POPULATION_COLUMNS]
    test_points = [(t, at) for t in tests for at in (1, 10, 100)]
    header = (["condition", "seed"] + final_keys + [f"population_{s}" for s in population]
              + ["meta_fitness_best", "meta_fitness_mean", "meta_generations", "mean_generations"]
              + [f"test_{t}_at_{at}" for t, at in test_points])
    rows = []
    for c in conditions:
        for r in c["runs"]:
            row = [c["name"], r.seed] + [r.summary.get(k, "") for k in final_keys]
            for measure in [f"population:{s}" for s in population]:
                v = claims.measure_values([r], measure)
                row.append(v[0] if v else "")
            if r.meta:
                row += [r.meta["meta_fitness_best"][-1], r.meta["meta_fitness_mean"][-1], r.meta_generations,
                        r.mean_generations]
            else:
                row += ["", "", "", ""]
            for t, at in test_points:
                v = claims.measure_values([r], f"test:{t}@{at}")
                row.append(v[0] if v else "")
            rows.append(row)
    write_csv(data_dir, "runs.csv", header, rows)

    curves = []
    for c in conditions:
        runs = [r for r in c["runs"] if r.metrics]
        if not runs or grid is None:
            continue
        for view, curve in QD_VIEWS:
            for column, _ in QD_PANELS:
                mean, se = mean_se([on_grid(*curve(r, column), grid) for r in runs])
                curves += [[c["name"], view, column, f"{x:.0f}", m, e, len(runs)] for x, m, e in zip(grid, mean, se)]
        for test in tests:
            have = [r for r in c["runs"] if r.adapt.get(test)]
            if have:
                mean, se = mean_se(adaptation_curves(have, test))
                curves += [[c["name"], "test", test, k + 1, m, e, len(have)] for k, (m, e) in enumerate(zip(mean, se))]
    write_csv(data_dir, "curves.csv", ["condition", "view", "statistic", "evals", "mean", "se", "n"], curves)

    table2 = generalisation_rows(conditions)
    if table2:
        write_csv(data_dir, "generalisation.csv", ["condition", "group", "n", "mean", "sd", "trained"],
                  [[r["condition"], r["group"], r["n"], r["mean"], "" if math.isnan(r["sd"]) else r["sd"], int(r["trained"])]
                   for r in table2])


def main(argv):
    """The report, or one line on stderr and exit status 2 when an input is damaged or an output
    cannot be written (qdmeta report relays that line as its own), 130 on Ctrl-C (script_exit)."""
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    options = argv[2:]
    out = argv[1]
    if "--out" in options:
        at = options.index("--out")
        if at + 1 == len(options):
            print(__doc__, file=sys.stderr)
            return 2
        out = options.pop(at + 1)
        options.pop(at)
    return script_exit.run("report.py", lambda: report(argv[1], "--quiet" in options, "--supplementary" in options,
                                                       out))


def report(directory, quiet, supplementary, out_directory=None):
    """The report on the experiment in `directory`, written into `out_directory` (default: the same)."""
    spec, conditions = load(directory)
    if out_directory:
        try:
            os.makedirs(out_directory, exist_ok=True)
        except OSError as e:
            raise InputError(f"{out_directory}: cannot make the folder: {e.strerror}") from None
    out = OutputDir.open(out_directory or directory)
    figures_dir = out.subdir("figures")
    tests = curve_tests(spec.get("tests", []))  # "generalisation" is Table 2, not a curve
    grid = evaluation_grid(spec, conditions)
    # (title, figure or None, caption or "")
    figures = [("QD statistics over evaluations",
                figure_qd_statistics(conditions, grid, (figures_dir, "qd-statistics.png")), ""),
               ("Meta-fitness and generations per meta-generation", figure_meta(conditions, (figures_dir, "meta-fitness.png")), "")]
    if supplementary or supplementary_figures(conditions):
        figures.append(("Meta-fitness with its running average (Fig S4)",
                        figure_meta_running_average(conditions, (figures_dir, "meta-fitness-running-average.png")),
                        "Each QD-Meta condition's meta-fitness per meta-generation (faint: mean over replicates) and its "
                        f"trailing mean over the last {G_WINDOW} meta-generations (thick: mean ± SE over replicates); one "
                        "column per meta-fitness kind; top: the best map of the meta-population, bottom: the mean over it."))
        figures.append(("Generations per meta-generation and meta-fitness (Fig S5)",
                        figure_generations_and_meta_fitness(conditions, (figures_dir, "generations-and-meta-fitness.png")),
                        "One panel per run of each QD-Meta condition whose G is chosen by SARSA: the meta-fitness (mean "
                        "over the meta-population, left axis) and G (faint: as drawn; thick: the mean of the last "
                        f"{G_WINDOW}; right axis) over meta-generations."))
    for test in tests:
        shown = adaptation_runs(conditions, test)
        figures.append((f"Test phase: {test}", figure_adaptation(conditions, test, (figures_dir, f"adaptation-{test}.png")),
                        CONTINUED_NOTE if any(archive_exhausted(runs, test) for _, runs in shown) else ""))
    figures.append(("One archive per condition (fitness over measures 0 and 1)", figure_archives(conditions, (figures_dir, "archives.png")), ""))

    write_data(out.subdir("data"), conditions, tests, grid)

    md = [f'# {spec.get("name", "Experiment")}', ""]
    evals = spec.get("evaluations")
    md.append(f'{len(conditions)} conditions x {spec.get("replicates", 1)} replicates (seeds 1..{spec.get("replicates", 1)})'
              + (f", {evals:,} evaluations each" if evals else "") + ". Values: mean ± standard error over finished replicates.")
    unfinished = [p for c in conditions for p in c["unfinished"]]
    if unfinished:
        md.append(f"\n{len(unfinished)} of {len(unfinished) + sum(len(c['runs']) for c in conditions)} runs are not "
                  "finished and are left out: " + ", ".join(os.path.relpath(p, directory) for p in unfinished[:10])
                  + (" ..." if len(unfinished) > 10 else ""))
    dropped = left_out(conditions, spec.get("tests", []))
    if dropped:
        md.append(f"\n{len(dropped)} times a finished run lacks what a table or figure reads, and that table or figure "
                  "leaves its replicate out (n counts the others):\n")
        md += [f"- {c['name']}, seed {r.seed}: {os.path.relpath(file, directory)}: {why}" for c, r, file, why in dropped]
    for c, r, file, why in dropped:  # on stderr too, --quiet or not: the tables' n has changed
        print(f"report.py: warning: {c['name']} seed {r.seed} is left out where it lacks data: {file}: {why}",
              file=sys.stderr)
    md += ["", "## Final archives", "", "The archive each run ends with (QD-Meta: the best map of its last meta-generation).",
           "", summary_table(conditions), ""]
    population = population_table(conditions)
    if population:
        md += ["The meta-population view (QD-Meta: the mean over every map of the last meta-generation, as the "
               "paper aggregates; then mean ± SE over replicates).", "", population, ""]
    meta = meta_table(conditions)
    if meta:
        md += ["## Meta-evolution", "", meta, ""]
    table2 = generalisation_table(generalisation_rows(conditions))
    if table2:
        md += ["## Generalisation test (Table 2)", "",
               "Each archive's mean score over its solutions and the group's environments (RHex: forward distance), "
               "then mean ± SD (sample standard deviation, not SE) over replicates; n per condition in the header. "
               "**Bold**: the best condition of the row. <u>Underlined</u>: the environments the condition met during "
               "meta-evolution (a QD-Meta run's meta-fitness kind, from its config.toml). For QD-Meta the archive is "
               "the best map of the last meta-generation. Data: data/generalisation.csv.", "", table2, ""]
    if tests:
        md += ["## Test phase", "", test_table(conditions, tests)]
    pairwise = comparisons(conditions, tests)
    if pairwise:
        md += ["## Pairwise comparisons", "",
               f"Two-sided Mann-Whitney U over replicates, p adjusted by Holm's method over the pairs of each table, "
               f"A12 (Vargha-Delaney) of the first condition over the second; * marks p < {ALPHA} after adjustment. "
               "With few replicates no difference can reach significance (2 against 2: the smallest exact p is "
               "1/3).", "", pairwise]
    md += ["## Figures", ""]
    for title, path, caption in figures:
        if path:
            md += [f"### {title}", ""] + ([caption, ""] if caption else []) + [f"![{title}](figures/{os.path.basename(path)})", ""]
    budget = experiment_budget(spec, conditions)
    at = f" ({budget:,} evaluations each)" if budget else ""
    rule = ('. How each kind is judged, and when a claim about a larger budget is "not testable at this budget": '
            'tools/claims.py and docs/config.md ("Claims").')
    for source, heading, what in [("paper", "The paper's claims", "Each claim of the paper in the experiment file"),
                                  ("ours", "Our own checks (not in the paper)",
                                   "Each check of the experiment file that the paper does not make")]:
        rows = claims_table(spec, conditions, source)
        if rows:
            md += [f"## {heading}", "", f"{what}, checked on the finished runs{at}{rule}", "", rows, ""]
    written = out.write("report.md", "\n".join(md) + "\n")
    if not quiet:
        print(f"report: {written} with {sum(1 for _, p, _ in figures if p)} figures in {figures_dir.path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
