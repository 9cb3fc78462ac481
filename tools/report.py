#!/usr/bin/python3
"""Figures and report.md for an experiment written by `qdmeta experiment`.

Usage: /usr/bin/python3 tools/report.py DIR [--quiet]

Reads DIR/experiment.toml and every finished run DIR/<condition>/seed-<r>/ (metrics.csv,
meta.csv, archive.csv, adapt-*.csv, summary.json); writes DIR/figures/*.png, DIR/report.md and
the small CSV summaries they are made from, DIR/data/runs.csv and DIR/data/curves.csv.
Replicates are aligned on a fixed evaluation grid (the last logged row at or before each grid
point), since meta-generation boundaries fall at different evaluation counts. Values are
mean +- standard error over replicates; every pair of conditions is compared by a two-sided
Mann-Whitney U test (Holm-adjusted per table) with the A12 effect size (tools/significance.py).
Needs only Debian's python3-matplotlib and numpy.
"""
import csv
import json
import warnings
import math
import os
import sys
import tomllib

import matplotlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import claims  # noqa: E402  (tools/claims.py)
import significance  # noqa: E402  (tools/significance.py)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

GRID_POINTS = 101
warnings.filterwarnings("ignore", message="Mean of empty slice")
warnings.filterwarnings("ignore", message="Degrees of freedom <= 0")


def read_csv(path):
    """Columns of a CSV file as float arrays (empty dict if the file is missing)."""
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return {}
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}


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


def on_grid(evals, values, grid):
    """The last logged value at or before each grid point (NaN before the first row)."""
    idx = np.searchsorted(evals, grid, side="right") - 1
    out = np.where(idx >= 0, values[np.clip(idx, 0, None)], np.nan)
    return out


def plot_band(ax, x, mean, se, label, linewidth=1.5):
    """A mean curve with its +- SE band."""
    ax.plot(x, mean, label=label, linewidth=linewidth)
    ax.fill_between(x, mean - se, mean + se, alpha=0.25)


def fmt(mean, se, digits=4):
    if mean is None or (isinstance(mean, float) and math.isnan(mean)):
        return "n/a"
    return f"{mean:.{digits}g} ± {se:.2g}"


class Run:
    def __init__(self, path):
        self.path = path
        self.metrics = read_csv(os.path.join(path, "metrics.csv"))
        self.meta = read_csv(os.path.join(path, "meta.csv"))
        with open(os.path.join(path, "summary.json")) as f:
            self.summary = json.load(f)
        self.adapt = {}
        for name in sorted(os.listdir(path)):
            if name.startswith("adapt-") and name.endswith(".csv"):
                self.adapt[name[len("adapt-"):-len(".csv")]] = read_csv(os.path.join(path, name))

    def archive(self):
        return read_csv(os.path.join(self.path, "archive.csv"))


def load(directory):
    with open(os.path.join(directory, "experiment.toml"), "rb") as f:
        spec = tomllib.load(f)
    conditions = []
    for c in spec.get("condition", []):
        slug = c.get("slug") or c["name"].lower().replace(" ", "-")
        runs, unfinished = [], []
        for r in range(1, int(spec.get("replicates", 1)) + 1):
            path = os.path.join(directory, slug, f"seed-{r}")
            summary = os.path.join(path, "summary.json")
            finished = False
            if os.path.exists(summary):
                with open(summary) as f:
                    finished = json.load(f).get("stop_reason") == "budget"
            (runs if finished else unfinished).append(Run(path) if finished else path)
        conditions.append({"name": c["name"], "slug": slug, "runs": runs, "unfinished": unfinished})
    return spec, conditions


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


def evaluation_grid(conditions):
    """The fixed evaluation grid replicates are aligned on (None when nothing was logged)."""
    budget = max((r.metrics["evals"][-1] for c in conditions for r in c["runs"] if r.metrics), default=0)
    return np.linspace(0, budget, GRID_POINTS) if budget > 0 else None


def figure_qd_statistics(conditions, out):
    """Two views side by side, as rows: QD-Meta's best map of each meta-generation (metrics.csv),
    and its whole meta-population (the mean over its maps, meta.csv), as the paper's figures
    aggregate "across the different archives within the meta-population". The other
    algorithms have one archive: the same curve in both rows."""
    grid = evaluation_grid(conditions)
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
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


G_WINDOW = 50


def trailing_mean(values, window):
    """Mean of each value and the up to window - 1 before it."""
    sums = np.cumsum(np.insert(np.asarray(values, dtype=float), 0, 0.0))
    n = np.arange(1, len(values) + 1)
    lo = np.maximum(n - window, 0)
    return (sums[n] - sums[lo]) / (n - lo)


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
        length = max(len(r.meta["meta_generation"]) for r in runs)
        for ax, (column, label) in zip(axes, panels):
            padded = np.full((len(runs), length), np.nan)
            for i, r in enumerate(runs):
                values = r.meta[column]
                if column == "generations":  # G is drawn anew each meta-generation: show its trend
                    values = trailing_mean(values, G_WINDOW)
                padded[i, : len(values)] = values
            mean, se = mean_se(padded)
            x = np.arange(1, length + 1)
            plot_band(ax, x, mean, se, f'{c["name"]} (n={len(runs)})', linewidth=0.8)
            ax.set_xlabel("meta-generation")
            ax.set_ylabel(label, fontsize=9)
    axes[0].legend(fontsize=8)
    fig.suptitle("Meta-evolution (mean ± SE over replicates)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def figure_adaptation(conditions, test, out):
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    drawn = False
    for c in conditions:
        runs = [r for r in c["runs"] if r.adapt.get(test)]
        if not runs:
            continue
        length = min(len(r.adapt[test]["best_mean"]) for r in runs)
        mean, se = mean_se([r.adapt[test]["best_mean"][:length] for r in runs])
        x = np.arange(1, length + 1)
        plot_band(ax, x, mean, se, f'{c["name"]} (n={len(runs)})')
        drawn = True
    if not drawn:
        plt.close(fig)
        return None
    ax.set_xlabel("evaluations (random search over the archive)")
    ax.set_ylabel("best score so far, mean over test functions")
    ax.set_title(f"Test phase: {test} (mean ± SE over replicates)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def figure_archives(conditions, out):
    shown = [c for c in conditions if c["runs"]]
    if not shown:
        return None
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 4), squeeze=False)
    for ax, c in zip(axes[0], shown):
        run = c["runs"][0]
        a = run.archive()
        if "measures_0" not in a or "measures_1" not in a:
            ax.set_title(f'{c["name"]}: fewer than 2 measures')
            continue
        points = ax.scatter(a["measures_0"], a["measures_1"], c=a["objective"], s=2, cmap="viridis", linewidths=0)
        fig.colorbar(points, ax=ax, label="fitness")
        ax.set_title(f'{c["name"]} (seed {os.path.basename(run.path).split("-")[-1]}, {len(a["objective"])} elites)',
                     fontsize=9)
        ax.set_xlabel("measure 0")
        ax.set_ylabel("measure 1")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


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


def claims_table(spec, conditions):
    """The experiment file's [[claim]] tables, each with what was measured and a verdict."""
    if not spec.get("claim"):
        return ""
    by_name = {c["name"]: c["runs"] for c in conditions}
    budget = experiment_budget(spec, conditions)
    lines = ["| claim | measured (mean ± SE over replicates) | verdict |", "|---|---|---|"]
    for claim in spec["claim"]:
        measured, verdict = claims.check(claim, lambda name, m: claims.measure_values(by_name.get(name, []), m), budget)
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
        gens = [len(r.meta["meta_generation"]) for r in runs]
        g = [float(np.mean(r.meta["generations"])) for r in runs]
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
        lines += [f"**{test}** (best score so far, mean over test functions; mean ± SE over replicates)", "",
                  "| condition | n | after 1 | after 10 | at the end |", "|---|---|---|---|---|"]
        for c in conditions:
            runs = [r for r in c["runs"] if r.adapt.get(test)]
            if not runs:
                continue
            cells = []
            for at in (0, 9, -1):
                values = [r.adapt[test]["best_mean"][at] for r in runs if len(r.adapt[test]["best_mean"]) > max(at, 0)]
                cells.append(fmt(*stat(values)))
            end = int(min(len(r.adapt[test]["best_mean"]) for r in runs))
            lines.append(f'| {c["name"]} | {len(runs)} | ' + " | ".join(cells[:2]) + f" | {cells[2]} ({end} evaluations) |")
        lines.append("")
    return "\n".join(lines)


ALPHA = 0.05


def comparison_table(title, samples):
    """Every pair of conditions on one measure: `samples` maps a condition's name to its
    replicates' values. Two-sided Mann-Whitney U, p Holm-adjusted over the pairs of this table,
    A12 of the first condition over the second; * marks adjusted p < ALPHA."""
    names = [n for n, v in samples.items() if len(v) > 0]
    pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    if not pairs:
        return ""
    tests = [significance.mann_whitney_u(samples[a], samples[b]) for a, b in pairs]
    adjusted = significance.holm([p for _, p in tests])
    lines = [f"**{title}**", "", "| first | second | median first | median second | U | p (Holm) | A12 | |",
             "|---|---|---|---|---|---|---|---|"]
    for (a, b), (u, _), p in zip(pairs, tests, adjusted):
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


def write_csv(path, header, rows):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    os.replace(path + ".tmp", path)


def write_data(directory, conditions, tests):
    """The small CSV summaries every table and figure is made from, in DIR/data/: runs.csv (one
    row per finished run: its final values and test-phase scores) and curves.csv (the plotted
    means and SEs over replicates). They are small enough to commit beside report.md."""
    data_dir = os.path.join(directory, "data")
    os.makedirs(data_dir, exist_ok=True)
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
            row = [c["name"], os.path.basename(r.path).split("-")[-1]] + [r.summary.get(k, "") for k in final_keys]
            for measure in [f"population:{s}" for s in population]:
                v = claims.measure_values([r], measure)
                row.append(v[0] if v else "")
            if r.meta:
                row += [r.meta["meta_fitness_best"][-1], r.meta["meta_fitness_mean"][-1], len(r.meta["meta_generation"]),
                        float(np.mean(r.meta["generations"]))]
            else:
                row += ["", "", "", ""]
            for t, at in test_points:
                v = claims.measure_values([r], f"test:{t}@{at}")
                row.append(v[0] if v else "")
            rows.append(row)
    write_csv(os.path.join(data_dir, "runs.csv"), header, rows)

    curves = []
    grid = evaluation_grid(conditions)
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
                length = min(len(r.adapt[test]["best_mean"]) for r in have)
                mean, se = mean_se([r.adapt[test]["best_mean"][:length] for r in have])
                curves += [[c["name"], "test", test, k + 1, m, e, len(have)] for k, (m, e) in enumerate(zip(mean, se))]
    write_csv(os.path.join(data_dir, "curves.csv"), ["condition", "view", "statistic", "evals", "mean", "se", "n"], curves)


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    directory = argv[1]
    quiet = "--quiet" in argv[2:]
    spec, conditions = load(directory)
    figures_dir = os.path.join(directory, "figures")
    os.makedirs(figures_dir, exist_ok=True)
    tests = list(spec.get("tests", []))
    figures = [("QD statistics over evaluations", figure_qd_statistics(conditions, os.path.join(figures_dir, "qd-statistics.png"))),
               ("Meta-fitness and generations per meta-generation", figure_meta(conditions, os.path.join(figures_dir, "meta-fitness.png")))]
    for test in tests:
        figures.append((f"Test phase: {test}", figure_adaptation(conditions, test, os.path.join(figures_dir, f"adaptation-{test}.png"))))
    figures.append(("One archive per condition (fitness over measures 0 and 1)", figure_archives(conditions, os.path.join(figures_dir, "archives.png"))))

    write_data(directory, conditions, tests)

    md = [f'# {spec.get("name", "Experiment")}', ""]
    evals = spec.get("evaluations")
    md.append(f'{len(conditions)} conditions x {spec.get("replicates", 1)} replicates (seeds 1..{spec.get("replicates", 1)})'
              + (f", {evals:,} evaluations each" if evals else "") + ". Values: mean ± standard error over finished replicates.")
    unfinished = [p for c in conditions for p in c["unfinished"]]
    if unfinished:
        md.append(f"\n{len(unfinished)} runs are not finished and are left out: " + ", ".join(os.path.relpath(p, directory) for p in unfinished[:10])
                  + (" ..." if len(unfinished) > 10 else ""))
    md += ["", "## Final archives", "", "The archive each run ends with (QD-Meta: the best map of its last meta-generation).",
           "", summary_table(conditions), ""]
    population = population_table(conditions)
    if population:
        md += ["The meta-population view (QD-Meta: the mean over every map of the last meta-generation, as the "
               "paper aggregates; then mean ± SE over replicates).", "", population, ""]
    meta = meta_table(conditions)
    if meta:
        md += ["## Meta-evolution", "", meta, ""]
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
    for title, path in figures:
        if path:
            md += [f"### {title}", "", f"![{title}](figures/{os.path.basename(path)})", ""]
    claim_rows = claims_table(spec, conditions)
    if claim_rows:
        budget = experiment_budget(spec, conditions)
        md += ["## The paper's claims", "",
               "Each claim of the experiment file, checked on the finished runs"
               + (f" ({budget:,} evaluations each)" if budget else "")
               + '. How each kind is judged: tools/claims.py and docs/config.md ("Claims").', "", claim_rows, ""]
    with open(os.path.join(directory, "report.md.tmp"), "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(os.path.join(directory, "report.md.tmp"), os.path.join(directory, "report.md"))
    if not quiet:
        print(f"report: {os.path.join(directory, 'report.md')} with {sum(1 for _, p in figures if p)} figures in {figures_dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
