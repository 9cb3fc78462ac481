"""What a valid [[claim]] table is (docs/config.md, "Experiment files and claims").

`qdmeta experiment` refuses a malformed claim before any run starts (its C++ twin,
src/qdmeta/experiment/claim_rules.cpp, states the same rules in the same words), and the report
checks the claims of the experiment.toml it reads with these rules. The shared cases in
tests/data/claims/cases.toml keep the two readers in agreement.
"""
import math
import re

KINDS = ["near", "below", "between", "order", "ratio", "top"]
COMMON_KEYS = ["text", "kind", "measure"]
# Each kind's keys beyond the common ones: (required, optional). Every kind may also have `source`.
KIND_KEYS = {
    "near": (["conditions", "value", "tolerance"], ["budget"]),
    "below": (["conditions", "value"], ["tolerance", "budget"]),
    "between": (["conditions", "low", "high"], ["budget"]),
    "order": (["groups"], []),
    "ratio": (["numerator", "denominator", "value", "tolerance"], ["budget"]),
    "top": (["conditions", "top"], []),
}
# Whose claim it is: the paper's (the default), or a check of our own that the paper does not make
# (the report lists those under their own heading).
SOURCES = ["paper", "ours"]
FAMILIES = ["final", "population", "meta", "test", "generalisation"]
POPULATION_STATS = ["num_elites", "obj_mean", "obj_max", "qd_score"]
# meta.csv's columns (src/qdmeta/run/run_tables.cpp).
META_COLUMNS = ["meta_generation", "evals", "evals_bottom", "evals_meta", "meta_fitness_best", "meta_fitness_mean",
                "meta_fitness_sd", "generations", "states"] + [
    f"population_{s}_{m}" for s in POPULATION_STATS for m in ("mean", "se")]
# summary.json's keys that hold text, not a number a claim could measure.
SUMMARY_TEXT_KEYS = ["algorithm", "task", "stop_reason", "message", "budget_counts", "config_fingerprint"]
GENERALISATION = "generalisation"

_KEY_NAME = re.compile(r"[a-z0-9_]+")
_TEST_POINT = re.compile(r"([^@]+)@([1-9][0-9]{0,17})")


class ClaimError(ValueError):
    """The rule a claim breaks, in the words qdmeta experiment uses."""


def _is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _finite_number(claim, key):
    x = claim[key]
    if not _is_number(x) or not math.isfinite(x):
        raise ClaimError(f"{key} must be a finite number")


def _names(claim, key):
    """A non-empty list of strings."""
    x = claim[key]
    if not isinstance(x, list) or not x or not all(isinstance(n, str) for n in x):
        raise ClaimError(f"{key} must be a non-empty list of condition names")
    return x


def _check_measure(measure, tests):
    family, colon, name = measure.partition(":")
    if not colon or family not in FAMILIES or not name:
        raise ClaimError(f"unknown measure '{measure}' (families: {', '.join(FAMILIES)})")
    if family == "population" and name not in POPULATION_STATS:
        raise ClaimError(f"unknown measure '{measure}' (population: {', '.join(POPULATION_STATS)})")
    if family == "meta" and name not in META_COLUMNS:
        raise ClaimError(f"unknown measure '{measure}' (meta: a column of meta.csv: {', '.join(META_COLUMNS)})")
    if family == "final" and (not _KEY_NAME.fullmatch(name) or name in SUMMARY_TEXT_KEYS):
        raise ClaimError(f"unknown measure '{measure}' (final: a numeric key of summary.json)")
    if family == "test":
        point = _TEST_POINT.fullmatch(name)
        if not point:
            raise ClaimError(f"measure '{measure}' must be test:<test>@<evaluations>, evaluations at least 1")
        test = point.group(1)
        if test == GENERALISATION or test not in tests:
            curve_tests = [t for t in tests if t != GENERALISATION]
            raise ClaimError(f"measure '{measure}' names test '{test}', which the experiment does not run "
                             f"(tests: {', '.join(curve_tests) or 'none'})")
    if family == "generalisation" and GENERALISATION not in tests:
        raise ClaimError(f"measure '{measure}' needs '{GENERALISATION}' in the experiment's tests")


def _check_names(names, conditions):
    seen = set()
    for n in names:
        if n not in conditions:
            raise ClaimError(f"unknown condition '{n}' (conditions: {', '.join(conditions)})")
        if n in seen:
            raise ClaimError(f"condition '{n}' is named twice")
        seen.add(n)


def validate(claim, conditions, tests):
    """Raises ClaimError naming the rule `claim` (a parsed [[claim]] table) breaks; `conditions`:
    the experiment's condition names, `tests`: its tests."""
    if not isinstance(claim, dict):
        raise ClaimError("must be a table")
    if "kind" not in claim:
        raise ClaimError("missing key 'kind'")
    kind = claim["kind"]
    if not isinstance(kind, str) or kind not in KINDS:
        raise ClaimError(f"unknown kind '{kind}' (kinds: {', '.join(KINDS)})" if isinstance(kind, str)
                         else "kind must be a string")
    required, optional = KIND_KEYS[kind]
    valid = COMMON_KEYS + required + optional + ["source"]
    for key in claim:
        if key not in valid:
            raise ClaimError(f"unknown key '{key}' for kind '{kind}' (valid keys: {', '.join(valid)})")
    for key in COMMON_KEYS + required:
        if key not in claim:
            raise ClaimError(f"missing key '{key}' (kind '{kind}' needs {', '.join(COMMON_KEYS + required)})")

    text = claim["text"]
    if not isinstance(text, str) or not text.strip() or "\n" in text or "|" in text:
        raise ClaimError("text must be a non-empty string on one line without '|'")
    measures = claim["measure"]
    if isinstance(measures, str):
        measures = [measures]
    if not isinstance(measures, list) or not measures or not all(isinstance(m, str) for m in measures):
        raise ClaimError("measure must be a string or a non-empty list of strings")
    for i, m in enumerate(measures):
        if m in measures[:i]:
            raise ClaimError(f"measure '{m}' is listed twice")
        _check_measure(m, tests)

    if kind in ("near", "below", "between", "top"):
        named = _names(claim, "conditions")
    elif kind == "ratio":
        if not isinstance(claim["numerator"], str):
            raise ClaimError("numerator must be a condition name")
        named = [claim["numerator"]] + _names(claim, "denominator")
    else:
        groups = claim["groups"]
        if (not isinstance(groups, list) or len(groups) < 2
                or not all(isinstance(g, list) and g and all(isinstance(n, str) for n in g) for g in groups)):
            raise ClaimError("groups must be a list of at least 2 non-empty lists of condition names")
        named = [n for g in groups for n in g]
    _check_names(named, conditions)
    if kind == "top" and (not isinstance(claim["top"], str) or claim["top"] not in named):
        raise ClaimError("top must be one of the claim's conditions")

    if kind in ("near", "below") and isinstance(claim["value"], dict):
        for name, v in claim["value"].items():
            if name not in named:
                raise ClaimError(f"value names '{name}', which is not one of the claim's conditions")
            if not _is_number(v) or not math.isfinite(v):
                raise ClaimError(f"value for '{name}' must be a finite number")
        for name in named:
            if name not in claim["value"]:
                raise ClaimError(f"value has no number for condition '{name}'")
    elif kind in ("near", "below", "ratio"):
        _finite_number(claim, "value")
    if kind == "between":
        _finite_number(claim, "low")
        _finite_number(claim, "high")
        if not claim["low"] < claim["high"]:
            raise ClaimError("low must be below high")
    if "tolerance" in claim:
        t = claim["tolerance"]
        if not _is_number(t) or not math.isfinite(t) or t < 0:
            raise ClaimError("tolerance must be a finite number of at least 0")
    if "budget" in claim:
        b = claim["budget"]
        if not isinstance(b, int) or isinstance(b, bool) or b < 1:
            raise ClaimError("budget must be an integer of at least 1")
    if "source" in claim and claim["source"] not in SOURCES:
        raise ClaimError(f"source must be one of {', '.join(SOURCES)}")
