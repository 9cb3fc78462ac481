"""The files of an experiment and its runs as the report needs them: each read with run_files
(regular files only, size-bounded) and checked for what the report relies on, so that a damaged
file is one line naming it and the rule it breaks (an InputError), never a traceback.
"""
import math
import os
import re

import claim_rules
from run_files import ColumnRule, InputError, read_json_object, read_table, read_toml

METRICS_COLUMNS = ["evals", "num_elites", "obj_mean", "obj_max", "qd_score"]
META_COLUMNS = ["meta_generation", "evals", "meta_fitness_best", "meta_fitness_mean", "generations", "states"]
POPULATION_MEANS = [f"population_{s}_mean" for s in claim_rules.POPULATION_STATS]
EXPERIMENT_KEYS = ["name", "replicates", "evaluations", "tests", "generalisation_solutions", "condition", "claim"]
CONDITION_KEYS = ["name", "slug", "config", "set"]
MAX_REPLICATES = 100_000  # as qdmeta experiment allows
_SLUG = re.compile(r"[a-z0-9]+(?:-[a-z0-9]+)*")


def _is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def slug_of(name):
    """A condition's directory from its name, as qdmeta experiment makes it (experiment.cpp)."""
    s = ""
    for c in name:
        if "a" <= c <= "z" or "0" <= c <= "9" or "A" <= c <= "Z":
            s += c.lower()
        elif s and s[-1] != "-":
            s += "-"
    return s.rstrip("-")


# The rules of each run file's columns: the whole numbers qdmeta writes (the integer cells of the
# tables in src/qdmeta/run/run_tables.cpp and adaptation.cpp: counts), and archive.csv's
# cells as qdmeta's C++ reader of archives checks them (read_elites_csv, src/qdmeta/io/csv.cpp),
# the reader of `qdmeta adapt` and of the tests an experiment runs: the report refuses what they
# refuse (bench/robustness/report_vs_adapt.py holds both readers to the same verdicts).
COUNT = ColumnRule(whole=True, low=0)
POSITIVE = ColumnRule(whole=True, low=1)
COLUMN_RULES = {
    "metrics.csv": {"evals": COUNT, "evals_bottom": COUNT, "evals_meta": COUNT, "generation": COUNT,
                    "num_elites": COUNT},
    "meta.csv": {"meta_generation": POSITIVE, "evals": COUNT, "evals_bottom": COUNT, "evals_meta": COUNT,
                 "generations": POSITIVE, "states": COUNT},
    "adapt-*.csv": {"evaluations": POSITIVE},
    "generalisation.csv": {"environments": POSITIVE, "solutions": POSITIVE},
}
ARCHIVE_GROUPS = ["measures_", "solution_", "base_"]  # after index and objective, in this order
ARCHIVE_RULES = {"index": ColumnRule(whole=True, low=0, low_rule="is negative: a cell index must be >= 0"),
                 "measures_": ColumnRule(single=True), "solution_": ColumnRule(single=True, unit=True),
                 # stored base features: [-1, 1], as QD-Meta's 2g - 1 database inputs store them
                 "base_": ColumnRule(single=True, signed_unit=True)}
ARCHIVE_VALUE = ColumnRule(single=True)  # objective


def _rules(file):
    return COLUMN_RULES[file].get


def archive_rule(name):
    """An archive.csv column's rule (ARCHIVE_RULES by the column's name or its group's prefix)."""
    group = next((g for g in ARCHIVE_GROUPS if name.startswith(g)), name)
    return ARCHIVE_RULES.get(group, ARCHIVE_VALUE)


def archive_header(header):
    """Why archive.csv's header is not one qdmeta writes (None when it is): index, objective, then
    measures_*, solution_* and base_* in that order (as the C++ reader requires)."""
    if header[:2] != ["index", "objective"]:
        return "not an archive file (header must start with index,objective)"
    group = 0
    for c, name in enumerate(header[2:], start=3):
        while group < len(ARCHIVE_GROUPS) and not name.startswith(ARCHIVE_GROUPS[group]):
            group += 1
        if group == len(ARCHIVE_GROUPS):
            return f"column {c} ('{name}') is not measures_*, solution_* or base_* in that order"
    return None


def test_file(test):
    """The file of a run that holds a test's results."""
    return "generalisation.csv" if test == claim_rules.GENERALISATION else f"adapt-{test}.csv"


def read_metrics(path):
    """metrics.csv ({} without one): evals must not decrease (replicates are aligned on it)."""
    return read_table(path, METRICS_COLUMNS, increasing=["evals"], rules=_rules("metrics.csv")) or {}


def read_meta(path):
    """meta.csv ({} without one, as for algorithms without a meta-population)."""
    meta = read_table(path, META_COLUMNS, increasing=["evals"], rules=_rules("meta.csv")) or {}
    present = [c for c in POPULATION_MEANS if c in meta]
    if present and len(present) != len(POPULATION_MEANS):
        missing = next(c for c in POPULATION_MEANS if c not in meta)
        raise InputError(f"{path}:1: no column '{missing}' beside {present[0]}: the population means come together")
    return meta


def read_adaptation(path):
    """An adapt-<test>.csv: the best-so-far curve."""
    return read_table(path, ["best_mean"], rules=_rules("adapt-*.csv")) or {}


def read_archive(path):
    """archive.csv ({} without one), checked as qdmeta's C++ reader checks it (ARCHIVE_RULES); an
    archive of no elite is refused, as `qdmeta adapt` refuses it."""
    archive = read_table(path, rules=archive_rule, check_header=archive_header)
    if archive == {}:
        raise InputError(f"{path}: the archive holds no elite (only its header): a finished run's archive has one")
    return archive or {}


def read_generalisation(path):
    """generalisation.csv as {group: mean} ({} without one)."""
    table = read_table(path, ["group", "mean"], text_columns=["group"], rules=_rules("generalisation.csv")) or {}
    return {g: float(m) for g, m in zip(table.get("group", []), table.get("mean", []))}


def read_summary(path):
    """summary.json (None without one): its text keys strings, every other value a finite
    number; null (qdmeta's NaN) is left out, as if the key were absent."""
    summary = read_json_object(path)
    return None if summary is None else check_summary(summary, path)


def check_summary(summary, path):
    """summary.json's rules (read_summary) on its parsed object; returns it, nulls left out."""
    for key, value in list(summary.items()):
        if key in claim_rules.SUMMARY_TEXT_KEYS:
            if not isinstance(value, str):
                raise InputError(f"{path}: {key} must be a string")
        elif value is None:
            del summary[key]
        elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(f"{path}: {key} must be a finite number")
    return summary


def read_config(path):
    """A run's resolved config.toml ({} without one): the tables and names the report reads."""
    config = read_toml(path)
    if config is None:
        return {}
    if not isinstance(config.get("algorithm", ""), str):
        raise InputError(f"{path}: algorithm must be a string")
    for table, key in [("task", "name"), ("control", "kind"), ("meta_fitness", "kind"), ("budget", None)]:
        if table not in config:
            continue
        if not isinstance(config[table], dict):
            raise InputError(f"{path}: {table} must be a table ([{table}])")
        if key and not isinstance(config[table].get(key, ""), str):
            raise InputError(f"{path}: {table}.{key} must be a string")
    return config


def read_experiment(path):
    """experiment.toml as qdmeta experiment writes it, checked as qdmeta experiment reads one;
    every condition given its slug and every claim checked by claim_rules."""
    spec = read_toml(path)
    if spec is None:
        raise InputError(f"{path}: no such file: run qdmeta experiment first")
    for key in spec:
        if key not in EXPERIMENT_KEYS:
            raise InputError(f"{path}: unknown key '{key}' (valid keys: {', '.join(EXPERIMENT_KEYS)})")
    if not isinstance(spec.get("name", ""), str):
        raise InputError(f"{path}: name must be a string")
    replicates = spec.setdefault("replicates", 1)
    if not _is_int(replicates) or not 1 <= replicates <= MAX_REPLICATES:
        raise InputError(f"{path}: replicates must be an integer in [1, {MAX_REPLICATES}]")
    for key in ("evaluations", "generalisation_solutions"):
        if key in spec and (not _is_int(spec[key]) or spec[key] < 1):
            raise InputError(f"{path}: {key} must be an integer of at least 1")
    tests = spec.setdefault("tests", [])
    if not isinstance(tests, list) or not all(isinstance(t, str) and _SLUG.fullmatch(t) for t in tests):
        raise InputError(f"{path}: tests must be a list of test names")
    conditions = spec.get("condition")
    if not isinstance(conditions, list) or not conditions or not all(isinstance(c, dict) for c in conditions):
        raise InputError(f"{path}: condition must be a non-empty list of [[condition]] tables")
    slugs = set()
    for i, c in enumerate(conditions, start=1):
        for key in c:
            if key not in CONDITION_KEYS:
                raise InputError(f"{path}: [[condition]] {i}: unknown key '{key}' (valid keys: "
                                 f"{', '.join(CONDITION_KEYS)})")
        if not isinstance(c.get("name"), str) or not c["name"]:
            raise InputError(f"{path}: [[condition]] {i}: name must be a non-empty string")
        c.setdefault("slug", slug_of(c["name"]))
        # The slug is a directory under the experiment: nothing that could lead out of it.
        if not isinstance(c["slug"], str) or not _SLUG.fullmatch(c["slug"]):
            raise InputError(f"{path}: [[condition]] {i}: slug must be lower-case letters and digits joined by '-'")
        if c["slug"] in slugs:
            raise InputError(f"{path}: [[condition]] {i}: condition '{c['name']}' repeats another's name")
        slugs.add(c["slug"])
    claims = spec.get("claim", [])
    if not isinstance(claims, list):
        raise InputError(f"{path}: claim must be a list of [[claim]] tables")
    names = [c["name"] for c in conditions]
    for i, claim in enumerate(claims, start=1):
        try:
            claim_rules.validate(claim, names, tests)
        except claim_rules.ClaimError as e:
            raise InputError(f"{path}: [[claim]] {i}: {e}") from None
    return spec


def run_directory(experiment, slug, replicate):
    return os.path.join(experiment, slug, f"seed-{replicate}")
