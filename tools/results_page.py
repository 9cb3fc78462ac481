#!/usr/bin/python3
"""The results pages, docs/results/NAME.md, made from their templates docs/results/NAME.md.in and
the committed data under docs/results/, so that no number on a page is typed by hand and a page
cannot drift from its data (tests/tools/test_results_pages.py renders every template and
compares).

Usage: tools/results_page.py TEMPLATE          print the page
       tools/results_page.py TEMPLATE --write  write it (TEMPLATE without .in)
       tools/results_page.py --check           exit 1 naming each page that differs from its template's

A template is Markdown with:

  {% STATEMENT %}          on a line of its own: a Python statement, run and not printed,
                           e.g. {% S = study("rastrigin/sigma") %}
  {{ EXPRESSION }}         the value of a Python expression: a float with 4 significant
                           digits, anything else as str()
  {{ EXPRESSION | SPEC }}  the value formatted with format(value, SPEC), e.g. ",.0f" or ".2g"

Expressions see: study(PATH), a committed report directory under docs/results (study_if_run(PATH):
the same, or None while none is committed)
(tools/study_data.py: S.mean(condition, measure), S.se, S.pm, S.median, S.u, S.holm, S.a12,
S.n, S.curve, S.table2, S.budget, S.values ...); claims_table(SOURCE, (NAME, EXPERIMENT FILE,
[(LABEL, study)]), ...) (tools/claims_summary.py) and verdict(EXPERIMENT FILE, CLAIM TEXT,
[study, ...]) for one claim's verdict on the last study; claim_texts(EXPERIMENT FILE[, SOURCE]) the
texts of its claims; claim_band(EXPERIMENT FILE, CLAIM TEXT, CONDITION) the band a magnitude claim
allows; ratio_stat(NUMERATOR VALUES, [DENOMINATOR VALUES, ...]) a ratio claim's
(ratio, SE) as tools/claims.py computes it; table2(study) (the report's Table 2 from
data/generalisation.csv); scorecard(ROWS, COLUMNS) (tools/scorecard.py: each claim's verdict
under each setting and variant, and the cause of a miss); comparison_table(PAIRS, MEASURES),
comparison_verdict(PAIRS, MEASURE, FIRST, SECOND) and comparison_verdicts(PAIRS, MEASURES, FIRST,
SECOND) (tools/comparisons.py: conditions of different
studies compared run against run); config(PATH) (a committed TOML file, parsed); and Python's builtins
(min, max, sorted, ...).
"""
import glob
import os
import re
import sys
import tomllib

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
RESULTS = os.path.join(ROOT, "docs", "results")
sys.path.insert(0, TOOLS)
import claims  # noqa: E402
import claims_summary  # noqa: E402
import comparisons  # noqa: E402
import scorecard as scorecards  # noqa: E402
from study_data import Study  # noqa: E402

_STATEMENT = re.compile(r"^\{%(.*)%\}$")
_EXPRESSION = re.compile(r"\{\{(.*?)\}\}")
GENERATED = ("<!-- Made by tools/results_page.py from {template}: edit that file, then run "
             "tools/results_page.py {template} --write -->")


def namespace():
    studies = {}

    def study(path):
        if path not in studies:
            studies[path] = Study(os.path.join(RESULTS, path))
        return studies[path]

    def study_if_run(path):
        """study(path), or None while its report is not committed (a study not run yet)."""
        return study(path) if os.path.exists(os.path.join(RESULTS, path, "report.md")) else None

    def claims_table(source, *experiments):
        return claims_summary.table([(name, os.path.join(ROOT, file), labelled)
                                     for name, file, labelled in experiments], source)

    def table2(s):
        import report  # the report's own Table 2 (matplotlib is imported with it)
        return report.generalisation_table([
            {"condition": r["condition"], "group": r["group"], "n": int(r["n"]), "mean": float(r["mean"]),
             "sd": float(r["sd"]) if r["sd"] else float("nan"), "trained": r["trained"] == "1"}
            for r in s.generalisation])
    def verdict(experiment_file, text, studies):
        """The verdict of the claim with this text on the last of `studies` (smallest budget
        first), as claims_table gives it: for {% assert %} lines under prose that cites it."""
        return claims_summary.verdicts(claims_summary.claim_of(os.path.join(ROOT, experiment_file), text), studies)[-1][1]

    def claim_band(experiment_file, text, condition):
        """The band a near, below or between claim allows the condition (tools/claims.py's Band:
        .low, .high, .holds(x), str() as the claims table shows it)."""
        return claims.bands(claims_summary.claim_of(os.path.join(ROOT, experiment_file), text), [condition])[condition]

    def claim_texts(experiment_file, source="paper"):
        """The texts of an experiment file's claims of `source`, in the file's order."""
        return [c["text"] for c in claims_summary.claims_of(os.path.join(ROOT, experiment_file), source)]

    def scorecard(rows, columns):
        return scorecards.table([(label, {c: (os.path.join(ROOT, f), t, s) for c, (f, t, s) in cells.items()})
                                 for label, cells in rows], columns)

    def config(path):
        with open(os.path.join(ROOT, path), "rb") as f:
            return tomllib.load(f)
    return {"study": study, "study_if_run": study_if_run, "claims_table": claims_table, "table2": table2, "config": config, "verdict": verdict,
            "claim_texts": claim_texts, "claim_band": claim_band, "ratio_stat": claims.ratio_stat, "scorecard": scorecard,
            "comparison_table": comparisons.table, "comparison_verdict": comparisons.verdict,
            "comparison_verdicts": comparisons.verdicts}


def value_text(value, spec):
    if spec is not None:
        return format(value, spec)
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def render(template_path):
    """The page the template makes, with a first line saying so."""
    with open(template_path) as f:
        lines = f.read().splitlines()
    names = namespace()
    relative = os.path.relpath(template_path, ROOT)
    out = [GENERATED.format(template=relative)]
    for number, line in enumerate(lines, 1):
        where = f"{relative}:{number}"
        statement = _STATEMENT.match(line.strip())
        if statement:
            try:
                exec(statement.group(1).strip(), names)
            except Exception as e:
                raise SystemExit(f"{where}: {statement.group(1).strip()}: {type(e).__name__}: {e}")
            continue

        def substitute(match):
            text = match.group(1)
            expression, bar, spec = text.rpartition(" | ")
            if not bar:
                expression, spec = text, None
            try:
                return value_text(eval(expression.strip(), names), spec.strip() if spec else None)
            except Exception as e:
                raise SystemExit(f"{where}: {{{{{text}}}}}: {type(e).__name__}: {e}")
        out.append(_EXPRESSION.sub(substitute, line))
    return "\n".join(out) + "\n"


def page_of(template_path):
    return template_path[:-len(".in")]


def main(argv):
    if argv[1:] == ["--check"]:
        stale = []
        for template in sorted(glob.glob(os.path.join(RESULTS, "*.md.in"))):
            with open(page_of(template)) as f:
                if f.read() != render(template):
                    stale.append(os.path.relpath(page_of(template), ROOT))
        for page in stale:
            print(f"{page} differs from its template's output: run tools/results_page.py {page}.in --write",
                  file=sys.stderr)
        return 1 if stale else 0
    if len(argv) not in (2, 3) or not argv[1].endswith(".md.in") or argv[2:] not in ([], ["--write"]):
        print(__doc__, file=sys.stderr)
        return 2
    page = render(argv[1])
    if argv[2:] == ["--write"]:
        with open(page_of(argv[1]), "w") as f:
            f.write(page)
    else:
        sys.stdout.write(page)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
