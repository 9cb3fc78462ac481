"""A finished run as the report reads it: from its run directory (RunDirectory) or from its
summary (RunSummary), the file of kilobytes `qdmeta experiment --summaries` keeps of each
finished run so that a study can be committed, continued elsewhere and reported without its run
directories.

Both give the report the same numbers. A summary holds what the report reads from a run, at the
report's resolution, and the report reads a run directory at that resolution too:
  - the QD statistics at each point of the evaluation grid (GRID_POINTS points from 0 to the
    budget; the last point is the run's end): a summary keeps the rows of metrics.csv and
    meta.csv that a grid over the run's own budget picks, and whole (every column) the last row
    and the row at half the budget, where a claim about a larger budget reads the runs' curves
    (earlier_evals; tools/claims.py); the other rows' other columns are NaN in a RunSummary,
    and nothing reads them;
  - the meta-fitness figures' curves at every stride-th meta-generation (stride: the smallest
    power of two that leaves at most META_POINTS points), to META_DIGITS significant digits;
  - the test-phase curves, the generalisation means, summary.json and the keys of config.toml
    the report reads, whole;
  - one picture of the archive: the best fitness in each of PICTURE_BINS x PICTURE_BINS bins
    over the first two measures, in PICTURE_LEVELS levels between the archive's lowest and
    highest fitness (the report draws this picture, not the archive's points).
Each reduction is a function here, applied by both classes, so a report from summaries equals
the report from the run directories byte for byte (tests/tools/test_run_summaries.py).
"""
import json
import math
import os
import re

import numpy as np

import experiment_files
from run_files import InputError, list_dir, read_json_object

GRID_POINTS = 101
META_POINTS = 200
META_DIGITS = 6
G_WINDOW = 50  # the trailing mean of G (and of meta-fitness, Fig S4) spans this many meta-generations
PICTURE_BINS = 64
PICTURE_LEVELS = 64
PICTURE_ALPHABET = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz+*"  # level k is character k
PICTURE_EMPTY = "."
SUMMARY_FORMAT = "qdmeta run summary"
SUMMARY_VERSION = 1
# The meta-fitness figures' curves: meta.csv's columns, and their trailing means over G_WINDOW.
META_SERIES = ["meta_generation", "meta_fitness_best", "meta_fitness_mean", "generations"]
TRAILING = ["meta_fitness_best", "meta_fitness_mean", "generations"]
# The config.toml keys the report reads: (table, key).
CONFIG_KEYS = [("task", "name"), ("control", "kind"), ("meta_fitness", "kind")]


def evaluation_grid(budget):
    """The evaluation grid replicates are aligned on."""
    return np.linspace(0, budget, GRID_POINTS)


def grid_rows(evals, grid):
    """The row of each grid point: the last logged at or before it (-1 before the first row);
    the grid's last point takes the run's last row, its end (at or just past the budget)."""
    idx = np.searchsorted(evals, grid, side="right") - 1
    if len(evals):
        idx[-1] = len(evals) - 1
    return idx


def on_grid(evals, values, grid):
    """The values at each grid point (grid_rows; NaN before the first row)."""
    idx = grid_rows(evals, grid)
    return np.where(idx >= 0, values[np.clip(idx, 0, None)], np.nan)


def earlier_evals(budget):
    """The smaller budget at which the report reads each run's own curves for a claim about a
    larger budget than the experiment's (tools/claims.py): half the budget."""
    return budget // 2


def row_at(evals, count):
    """The last row logged at or before `count` evaluations (-1: none)."""
    return int(np.searchsorted(evals, count, side="right")) - 1


def kept_rows(evals, budget):
    """The rows a summary keeps of a table logged over evaluations, and among them (as positions
    in the kept rows) those it keeps whole: the rows the grid over `budget` picks and the row
    at earlier_evals(budget), the last kept whole too; every row, whole, without a budget."""
    if budget is None:
        return np.arange(len(evals)), list(range(len(evals)))
    idx = grid_rows(evals, evaluation_grid(budget))
    kept = np.unique(np.append(idx, row_at(evals, earlier_evals(budget))))
    kept = kept[kept >= 0]
    whole = sorted({int(np.searchsorted(kept, i)) for i in (row_at(evals, earlier_evals(budget)), len(evals) - 1)
                    if i >= 0})
    return kept, whole


def kept_table(table, columns, budget):
    """A logged table (metrics.csv, meta.csv) as a summary keeps it: `columns` at every kept row,
    every column at the rows kept whole."""
    rows, whole = kept_rows(table["evals"], budget)
    return {"rows": {c: table[c][rows].tolist() for c in columns if c in table}, "whole_at": whole,
            "whole": {c: table[c][rows[whole]].tolist() for c in table}}


def table_of(kept):
    """A kept table as the report reads one: every column over the kept rows, NaN where a column
    was not kept (nothing reads those cells: see the module's description)."""
    length = len(kept["rows"]["evals"])
    table = {}
    for c, values in kept["whole"].items():
        table[c] = np.full(length, np.nan)
        table[c][kept["whole_at"]] = values
    table.update({c: np.array(v, dtype=float) for c, v in kept["rows"].items()})
    return table


def trailing_mean(values, window):
    """Mean of each value and the up to window - 1 before it."""
    sums = np.cumsum(np.insert(np.asarray(values, dtype=float), 0, 0.0))
    n = np.arange(1, len(values) + 1)
    lo = np.maximum(n - window, 0)
    return (sums[n] - sums[lo]) / (n - lo)


def meta_stride(length):
    """The smallest power of two that leaves at most META_POINTS of `length` meta-generations."""
    stride = 1
    while math.ceil(length / stride) > META_POINTS:
        stride *= 2
    return stride


def rounded(values):
    """Values to META_DIGITS significant digits (what the meta-fitness figures draw)."""
    return np.array([float(f"{v:.{META_DIGITS}g}") for v in values], dtype=float)


def full_meta_series(meta):
    """Every meta-fitness curve of a meta.csv, each meta-generation: its columns META_SERIES and
    TRAILING's trailing means (named <column>_trailing)."""
    series = {name: np.asarray(meta[name], dtype=float) for name in META_SERIES}
    for name in TRAILING:
        series[f"{name}_trailing"] = trailing_mean(meta[name], G_WINDOW)
    return series


def sampled(name, values, stride):
    """A meta-fitness curve at every stride-th meta-generation, as the figures draw it."""
    values = np.asarray(values, dtype=float)[::stride]
    return values if name == "meta_generation" else rounded(values)


def archive_picture(archive):
    """The archive figure's picture of an archive table (None with fewer than 2 measures): each
    bin's best fitness as a level, rows from the lowest measure 1 up, PICTURE_EMPTY where no
    elite falls."""
    if "measures_0" not in archive or "measures_1" not in archive:
        return None
    fitness = np.asarray(archive.get("objective", []), dtype=float)
    axes, bins = [], []
    for name in ("measures_0", "measures_1"):
        x = np.asarray(archive[name], dtype=float)
        lo, hi = (float(x.min()), float(x.max())) if x.size else (0.0, 1.0)
        if hi <= lo:
            lo, hi = lo - 0.5, hi + 0.5
        axes.append([lo, hi])
        bins.append(np.minimum((PICTURE_BINS * (x - lo) / (hi - lo)).astype(int), PICTURE_BINS - 1))
    best = np.full((PICTURE_BINS, PICTURE_BINS), -np.inf)
    np.maximum.at(best, (bins[1], bins[0]), fitness)
    lo, hi = (float(fitness.min()), float(fitness.max())) if fitness.size else (0.0, 0.0)
    span = hi - lo if hi > lo else 1.0
    levels = np.where(np.isfinite(best), np.minimum((PICTURE_LEVELS * (best - lo) / span), PICTURE_LEVELS - 1), -1)
    rows = ["".join(PICTURE_ALPHABET[int(k)] if k >= 0 else PICTURE_EMPTY for k in row) for row in levels]
    return {"elites": int(fitness.size), "measures_0": axes[0], "measures_1": axes[1], "fitness": [lo, hi],
            "rows": rows}


def picture_values(picture):
    """A picture's bins as fitness (NaN where empty): each level's middle."""
    lo, hi = picture["fitness"]
    levels = np.array([[PICTURE_ALPHABET.find(ch) for ch in row] for row in picture["rows"]], dtype=float)
    values = lo + (levels + 0.5) / PICTURE_LEVELS * (hi - lo)
    values[levels < 0] = np.nan
    return values


def config_keys(config):
    """The keys of a run's config.toml the report reads (algorithm; CONFIG_KEYS), a table kept
    even when its key is absent (the report's defaults then apply)."""
    kept = {"algorithm": config["algorithm"]} if "algorithm" in config else {}
    for table, key in CONFIG_KEYS:
        if table in config:
            kept[table] = {key: config[table][key]} if key in config[table] else {}
    return kept


FINGERPRINT = "config_fingerprint"
_HEX = re.compile(r"[0-9a-f]+")


def fingerprint_of(where, sources):
    """The run's config fingerprint (lowercase hex; what `qdmeta run` derives from its resolved
    config), from the first of `sources` (its parsed files) that has key config_fingerprint at
    the top or in one of its tables; None for a run made before runs kept one."""
    for source in sources:
        tables = [source] + [v for v in source.values() if isinstance(v, dict)]
        for table in tables:
            if FINGERPRINT in table:
                value = table[FINGERPRINT]
                if not isinstance(value, str) or not _HEX.fullmatch(value):
                    raise InputError(f"{where}: {FINGERPRINT} must be a string of lowercase hexadecimal digits")
                return value
    return None


class RunDirectory:
    """A finished run's directory, every file read and checked when the run is loaded (a
    damaged or lost file stops the report before it writes anything), its archive included."""

    def __init__(self, path, summary, tests=None):
        """`tests`: the experiment's tests, whose files (adapt-<test>.csv, generalisation.csv) a
        finished run has (None: the tests whose files are there)."""
        self.path = path
        self.summary = summary
        self._config = experiment_files.read_config(os.path.join(path, "config.toml"))
        required = ["config.toml", "metrics.csv", "archive.csv"]
        if self._config.get("algorithm") == "qd-meta":
            required.append("meta.csv")
        required += [experiment_files.test_file(t) for t in tests or []]
        for name in required:
            if not os.path.lexists(os.path.join(path, name)):
                raise InputError(f"{os.path.join(path, name)}: no such file, but the run has finished (its "
                                 "summary.json says stop_reason \"budget\"): a finished run's file was lost")
        self.metrics = experiment_files.read_metrics(os.path.join(path, "metrics.csv"))
        self.meta = experiment_files.read_meta(os.path.join(path, "meta.csv"))
        self.adapt = {}
        for name in list_dir(path):
            if name.startswith("adapt-") and name.endswith(".csv"):
                test = name[len("adapt-"):-len(".csv")]
                self.adapt[test] = experiment_files.read_adaptation(os.path.join(path, name))
        self._generalisation = experiment_files.read_generalisation(os.path.join(path, "generalisation.csv"))
        # Every archive is read (and checked as `qdmeta adapt` checks it), though one is drawn.
        self._picture = archive_picture(experiment_files.read_archive(os.path.join(path, "archive.csv")))
        self._series = None
        self.fingerprint = fingerprint_of(path, [summary, self._config])

    def lacks(self, part):
        """Why the run has nothing for one part of the report, named by its file (metrics.csv,
        meta.csv, adapt-<test>.csv, generalisation.csv), as (the file, why)."""
        return os.path.join(self.path, part), "only its header, no row"

    @property
    def seed(self):
        """The replicate's seed, from its directory name (seed-<r>)."""
        return os.path.basename(self.path).split("-")[-1]

    def config(self):
        """The run's resolved config.toml (every key in force, written by `qdmeta run`); {} if absent."""
        return self._config

    def generalisation(self):
        return self._generalisation

    def picture(self):
        return self._picture

    @property
    def meta_generations(self):
        return len(self.meta["meta_generation"]) if self.meta else 0

    @property
    def mean_generations(self):
        return float(np.mean(self.meta["generations"]))

    @property
    def generations_vary(self):
        return bool(len(np.unique(self.meta["generations"])) > 1)

    def meta_series(self, name, stride):
        """A meta-fitness curve (META_SERIES or <TRAILING>_trailing) at every stride-th meta-generation."""
        if self._series is None:
            self._series = full_meta_series(self.meta)
        return sampled(name, self._series[name], stride)


def summary_of(run):
    """What a summary holds of a finished run (a RunDirectory), as a JSON-ready dict."""
    budget = run.summary.get("budget")
    metrics = kept_table(run.metrics, experiment_files.METRICS_COLUMNS, budget) if run.metrics else None
    meta = None
    if run.meta:
        stride = meta_stride(run.meta_generations)
        meta = {"table": kept_table(run.meta, ["evals"] + experiment_files.POPULATION_MEANS, budget),
                "meta_generations": run.meta_generations, "mean_generations": run.mean_generations,
                "generations_vary": run.generations_vary, "stride": stride,
                "series": {name: run.meta_series(name, stride).tolist()
                           for name in META_SERIES + [f"{t}_trailing" for t in TRAILING]}}
    kept = {FINGERPRINT: run.fingerprint} if run.fingerprint else {}  # none for a run made before them
    return {"format": SUMMARY_FORMAT, "version": SUMMARY_VERSION, **kept, "summary": run.summary,
            "config": config_keys(run.config()), "metrics": metrics, "meta": meta,
            "adapt": {t: a.get("best_mean", np.zeros(0)).tolist() for t, a in sorted(run.adapt.items())},
            "generalisation": run.generalisation(), "picture": run.picture()}


def _integral(value):
    """Numbers that are whole as integers, at any depth (5.0 as 5: the same double read back)."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 2 ** 53:
        return int(value)
    if isinstance(value, list):
        return [_integral(v) for v in value]
    if isinstance(value, dict):
        return {k: _integral(v) for k, v in value.items()}
    return value


def summary_text(summary):
    """A summary as JSON text: a line per key of the top two levels (a diff shows what changed),
    numbers as Python writes them (the shortest text that reads back as the same double), the
    curves' whole numbers as integers (summary.json's values stay as they were: the report
    writes them as they are)."""
    summary = {k: _integral(v) if k in ("metrics", "meta", "adapt") else v for k, v in summary.items()}
    lines = ["{"]
    for i, (key, value) in enumerate(summary.items()):
        end = "," if i < len(summary) - 1 else ""
        if isinstance(value, dict) and value:
            inner = [f" {json.dumps(k)}: {json.dumps(v, allow_nan=False)}" for k, v in value.items()]
            lines += [f"{json.dumps(key)}: {{", ",\n".join(inner), f"}}{end}"]
        else:
            lines.append(f"{json.dumps(key)}: {json.dumps(value, allow_nan=False)}{end}")
    return "\n".join(lines + ["}"]) + "\n"


class RunSummary:
    """A finished run from its summary, checked when loaded (InputError naming the file and the
    rule), with the interface of RunDirectory."""

    def __init__(self, path):
        data = read_json_object(path)
        if data is None:
            raise InputError(f"{path}: no such file")
        check = _Checker(path)
        check.summary(data)
        self.path = path
        self.summary = data["summary"]
        self._config = data["config"]
        self.metrics = table_of(data["metrics"]) if data["metrics"] is not None else {}
        meta = data["meta"]
        self.meta = {}
        if meta is not None:
            self.meta = table_of(meta["table"])
            self.meta_generations = meta["meta_generations"]
            self.mean_generations = float(meta["mean_generations"])
            self.generations_vary = meta["generations_vary"]
            self._stride = meta["stride"]
            self._series = {name: np.array(v, dtype=float) for name, v in meta["series"].items()}
        else:
            self.meta_generations = 0
        self.adapt = {t: ({"best_mean": np.array(v, dtype=float)} if v else {}) for t, v in data["adapt"].items()}
        self._generalisation = {g: float(v) for g, v in data["generalisation"].items()}
        self._picture = data["picture"]
        self.fingerprint = fingerprint_of(path, [data, data["summary"]])

    def lacks(self, part):
        """Why the run has nothing for one part of the report, named by its run file, as (the
        summary, why) (RunDirectory.lacks)."""
        why = {"metrics.csv": "its metrics are null", "meta.csv": "its meta is null",
               "generalisation.csv": "its generalisation is empty"}
        return self.path, why.get(part) or f"its adapt holds no curve of test '{part[len('adapt-'):-len('.csv')]}'"

    @property
    def seed(self):
        """The replicate's seed, from the file's name (seed-<r>.json)."""
        return os.path.basename(self.path)[: -len(".json")].split("-")[-1]

    def config(self):
        return self._config

    def generalisation(self):
        return self._generalisation

    def picture(self):
        return self._picture

    def meta_series(self, name, stride):
        if stride % self._stride:
            raise ValueError(f"{self.path}: meta-generation stride {stride} is not a multiple of the summary's "
                             f"{self._stride}")
        return sampled(name, self._series[name][:: stride // self._stride], 1)


def summary_path(directory, slug, replicate):
    """Where an experiment keeps the summary of a run: beside the run's directory."""
    return experiment_files.run_directory(directory, slug, replicate) + ".json"


class _Checker:
    """The rules a summary follows (what summary_of writes), each broken one an InputError."""

    def __init__(self, path):
        self.path = path

    def fail(self, rule):
        raise InputError(f"{self.path}: {rule}")

    def table(self, value, where, keys=None):
        if not isinstance(value, dict):
            self.fail(f"{where} must be an object")
        for key in keys or []:
            if key not in value:
                self.fail(f"{where} has no '{key}'")
        return value

    def numbers(self, value, where, length=None):
        if not isinstance(value, list) or not all(_is_number(v) for v in value):
            self.fail(f"{where} must be a list of finite numbers")
        if length is not None and len(value) != length:
            self.fail(f"{where} has {len(value)} values, {length} expected")
        return value

    def kept_table(self, value, where, rows_required, whole_required):
        """A kept_table: its rows' columns (`rows_required` among them, evals first) of one
        length, evals not decreasing; whole_at increasing positions among them, ending with the
        last; every whole column (`whole_required` among them) one value per such position."""
        self.table(value, where, ["rows", "whole_at", "whole"])
        rows = self.table(value["rows"], f"{where}.rows", rows_required)
        length = len(self.numbers(rows["evals"], f"{where}.rows.evals"))
        for c, v in rows.items():
            self.numbers(v, f"{where}.rows.{c}", length)
        if np.any(np.diff(rows["evals"]) < 0):
            self.fail(f"{where}.rows.evals must not decrease")
        at = value["whole_at"]
        if (not isinstance(at, list) or not at or not all(_is_int(i) for i in at) or at[-1] != length - 1 or
                any(b <= a for a, b in zip(at, at[1:])) or at[0] < 0):
            self.fail(f"{where}.whole_at must be increasing row positions in [0, {length}) ending with the last")
        whole = self.table(value["whole"], f"{where}.whole", whole_required)
        for c, v in whole.items():
            self.numbers(v, f"{where}.whole.{c}", len(at))

    def summary(self, data):
        keys = ["format", "version", "summary", "config", "metrics", "meta", "adapt", "generalisation", "picture"]
        for key in data:
            if key not in keys + [FINGERPRINT]:  # config_fingerprint: not in a summary made before runs kept one
                self.fail(f"unknown key '{key}' (a summary has {', '.join(keys)})")
        self.table(data, "the summary", keys)
        if data["format"] != SUMMARY_FORMAT or data["version"] != SUMMARY_VERSION:
            self.fail(f"not a {SUMMARY_FORMAT} of version {SUMMARY_VERSION} (format {data['format']!r}, version "
                      f"{data['version']!r})")
        experiment_files.check_summary(self.table(data["summary"], "summary"), self.path)
        if data["summary"].get("stop_reason") != "budget":
            self.fail("summary.stop_reason must be 'budget': a summary is of a finished run")
        config = self.table(data["config"], "config")
        if not isinstance(config.get("algorithm", ""), str):
            self.fail("config.algorithm must be a string")
        for table, key in CONFIG_KEYS:
            if table in config and (not isinstance(config[table], dict) or
                                    not isinstance(config[table].get(key, ""), str)):
                self.fail(f"config.{table} must be an object whose {key} is a string")
        if data["metrics"] is not None:  # null for a run without metrics.csv
            self.kept_table(data["metrics"], "metrics", experiment_files.METRICS_COLUMNS,
                            experiment_files.METRICS_COLUMNS)
        if data["meta"] is not None:
            self.meta(self.table(data["meta"], "meta", ["table", "meta_generations", "mean_generations",
                                                        "generations_vary", "stride", "series"]))
        for test, curve in self.table(data["adapt"], "adapt").items():
            self.numbers(curve, f"adapt.{test}")
        for group, mean in self.table(data["generalisation"], "generalisation").items():
            if not _is_number(mean):
                self.fail(f"generalisation.{group} must be a finite number")
        if data["picture"] is not None:
            self.picture(self.table(data["picture"], "picture", ["elites", "measures_0", "measures_1", "fitness",
                                                                 "rows"]))

    def meta(self, meta):
        self.kept_table(meta["table"], "meta.table", ["evals"], experiment_files.META_COLUMNS)
        length, stride = meta["meta_generations"], meta["stride"]
        if not _is_int(length) or length < 1:
            self.fail("meta.meta_generations must be an integer of at least 1")
        if not _is_int(stride) or stride != meta_stride(length):
            self.fail(f"meta.stride must be {meta_stride(length)} for {length} meta-generations")
        if not _is_number(meta["mean_generations"]) or not isinstance(meta["generations_vary"], bool):
            self.fail("meta.mean_generations must be a finite number and meta.generations_vary true or false")
        series = self.table(meta["series"], "meta.series", META_SERIES + [f"{t}_trailing" for t in TRAILING])
        for name, values in series.items():
            self.numbers(values, f"meta.series.{name}", math.ceil(length / stride))

    def picture(self, picture):
        if not _is_int(picture["elites"]) or picture["elites"] < 0:
            self.fail("picture.elites must be an integer of at least 0")
        for key in ("measures_0", "measures_1", "fitness"):
            self.numbers(picture[key], f"picture.{key}", 2)
        rows = picture["rows"]
        allowed = set(PICTURE_ALPHABET + PICTURE_EMPTY)
        if (not isinstance(rows, list) or len(rows) != PICTURE_BINS or
                not all(isinstance(r, str) and len(r) == PICTURE_BINS and set(r) <= allowed for r in rows)):
            self.fail(f"picture.rows must be {PICTURE_BINS} strings of {PICTURE_BINS} characters of "
                      f"'{PICTURE_ALPHABET}{PICTURE_EMPTY}'")


def _is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def _is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
