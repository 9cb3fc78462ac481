#!/usr/bin/python3
"""Report against adapt: the inputs that both `qdmeta report` and `qdmeta adapt` read go to
both, and each must give the same verdict (docs/architecture.md, "One set of checks for run
files").

Usage: bench/robustness/report_vs_adapt.py --qdmeta BIN [--quick] [--work DIR] [--timeout S]

Makes damaged_files.py's small experiment with BIN, then edits its MAP-Elites run's
archive.csv one way at a time (each cell rule of qdmeta's reader, a number syntax Python's
float() takes and C++'s from_chars does not, the header, the file cut short, emptied or
deleted) and runs `qdmeta report` on the experiment and `qdmeta adapt` on the run. Both must
accept the edit (exit 0) or both refuse it in one line (exit 2), as the case's name says; a
difference, or anything damaged_files.py calls a defect, is a defect, printed one per line,
then `N cases, M defects`; exits 1 when there is a defect. --quick: a reduced set (ctest
robustness_report_vs_adapt). $QDMETA_TOOLS_DIR, when set, picks the report script. Plain
python3, no third-party package.
"""
import contextlib
import os
import shutil
import sys
import tempfile

import matrix
from damaged_files import classify, command_line, make_experiment, run


# (name, edit of archive.csv's text): each cell rule at the first row's cells
# (index, objective, measures_0, solution_0), each file rule. Every edit is refused by both
# readers but those marked accepted (numbers in both syntaxes, CR LF line ends).
def _cell(column, text):
    def edit(archive):
        lines = archive.split("\n")
        cells = lines[1].split(",")
        header = lines[0].split(",")
        where = {"index": 0, "objective": 1, "measures": header.index("measures_0"),
                 "solution": header.index("solution_0")}[column]
        cells[where] = text
        lines[1] = ",".join(cells)
        return "\n".join(lines)
    return edit


VERDICT_CASES = [
    ("index 2^63", _cell("index", "9223372036854775808")), ("index 2^63 - 1 (accepted)",
                                                            _cell("index", "9223372036854775807")),
    ("index -1", _cell("index", "-1")), ("index 1.5", _cell("index", "1.5")), ("index +1", _cell("index", "+1")),
    ("objective +1", _cell("objective", "+1")), ("objective ' 1'", _cell("objective", " 1")),
    ("objective 1_0", _cell("objective", "1_0")), ("objective Arabic-Indic 3", _cell("objective", "\u0663")),
    ("objective full-width 3", _cell("objective", "\uff13")), ("objective nan", _cell("objective", "nan")),
    ("objective -infinity", _cell("objective", "-infinity")), ("objective 1e39", _cell("objective", "1e39")),
    ("objective 1e-50", _cell("objective", "1e-50")), ("objective 1e-40 (accepted)", _cell("objective", "1e-40")),
    ("objective .5 (accepted)", _cell("objective", ".5")), ("objective 5. (accepted)", _cell("objective", "5.")),
    ("objective 1e", _cell("objective", "1e")), ("objective 0x1", _cell("objective", "0x1")),
    ("objective empty", _cell("objective", "")), ("measures_0 3.4e38 (accepted)", _cell("measures", "3.4e38")),
    ("solution_0 1.5", _cell("solution", "1.5")), ("solution_0 -0 (accepted)", _cell("solution", "-0")),
    ("solution_0 -1e-9", _cell("solution", "-1e-9")),
    ("header only", lambda a: a.split("\n", 1)[0] + "\n"),
    ("header index,objective swapped", lambda a: a.replace("index,objective", "objective,index", 1)),
    ("header measures_0 repeated", lambda a: a.replace("measures_1", "measures_0", 1)),
    ("a row too short", lambda a: a.replace("\n", ",\n", 2).replace(",\n", "\n", 1)),
    ("an empty line", lambda a: a.replace("\n", "\n\n", 2).replace("\n\n", "\n", 1)),
    ("last line without its line end", lambda a: a[:-1]),
    ("CR LF line ends (accepted)", lambda a: a.replace("\n", "\r\n")),
    ("deleted", None),
]
QUICK_VERDICTS = ["index 2^63", "index 2^63 - 1 (accepted)", "objective Arabic-Indic 3", "objective 1e39",
                  "solution_0 1.5", "header only", "last line without its line end", "deleted"]
VERDICT_RUN = "me/seed-1"


def verdict(status, output):
    """'accepted', 'refused' (one line, exit 2), or the defect (classify)."""
    wrong = classify(status, output)
    return wrong or ("accepted" if status == 0 else "refused")


def verdicts(binary, base, scratch, cases, timeout, env):
    """Report and adapt on each edited archive: the exit status, 1 when a verdict differs."""
    defects = 0
    for name, edit in cases:
        shutil.rmtree(scratch, ignore_errors=True)
        shutil.copytree(base, scratch, symlinks=True)
        archive = os.path.join(scratch, VERDICT_RUN, "archive.csv")
        if edit is None:
            os.unlink(archive)
        else:
            with open(archive, encoding="utf-8", newline="") as f:
                text = f.read()
            with open(archive, "w", encoding="utf-8", newline="") as f:
                f.write(edit(text))
        seen = []
        for command in ("report", "adapt"):  # the report first: adapt rewrites adapt-*.csv
            status, output = run(command_line(binary, command, scratch, os.path.join(scratch, VERDICT_RUN)), timeout,
                                 env)
            seen.append((verdict(status, output), output.strip().splitlines()[-1:] or [""]))
        (report_said, report_line), (adapt_said, adapt_line) = seen
        expected = "accepted" if name.endswith("(accepted)") else "refused"
        if report_said != adapt_said or report_said != expected:
            defects += 1
            print(f"DEFECT archive.csv {name}: report {report_said}, adapt {adapt_said} (expected {expected}): "
                  f"report: {report_line[0][:160]} | adapt: {adapt_line[0][:160]}", flush=True)
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"{len(cases)} cases, {defects} defects")
    return 1 if defects else 0


def main(argv):
    args = matrix.argument_parser(__doc__, "a reduced set (the test suite's)", timeout=60).parse_args(argv[1:])
    cases = [c for c in VERDICT_CASES if not args.quick or c[0] in QUICK_VERDICTS]
    scratch = contextlib.nullcontext(args.work) if args.work else tempfile.TemporaryDirectory(prefix="qdmeta-verdicts-")
    binary = os.path.abspath(args.qdmeta)
    with scratch as work:
        base, _ = make_experiment(binary, os.path.join(work, f"m{os.getpid()}"), os.environ, False)
        return verdicts(binary, base, os.path.join(os.path.dirname(base), "case"), cases, args.timeout, os.environ)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
