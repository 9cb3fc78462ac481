#!/usr/bin/python3
"""Writes the summary of a finished run: what the report reads of it, in kilobytes (tools/runs.py).

Usage: /usr/bin/python3 tools/run_summary.py RUN_DIR SUMMARY_FILE

`qdmeta experiment --summaries DIR` runs it on each run once its test phases are done, with
SUMMARY_FILE = DIR/<condition>/seed-<r>.json; `qdmeta report DIR` then reads the summaries as it
reads run directories. The file is written through a temporary file renamed over its target.
Needs only numpy. A damaged or unfinished run is one line on stderr and exit status 2.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import script_exit  # noqa: E402  (tools/script_exit.py: one line and exit 2 or 130, never a traceback)

if __name__ == "__main__":
    script_exit.before_main("run_summary.py")
import experiment_files  # noqa: E402  (tools/experiment_files.py)
import runs  # noqa: E402  (tools/runs.py)
from output_files import OutputDir  # noqa: E402  (tools/output_files.py)
from run_files import InputError  # noqa: E402


def write_summary(run_dir, target):
    """The summary of the finished run in `run_dir`, written as `target`; returns its path."""
    summary = experiment_files.read_summary(os.path.join(run_dir, "summary.json"))
    if summary is None or summary.get("stop_reason") != "budget":
        raise InputError(f"{run_dir}: the run has not finished (its summary.json does not say stop_reason "
                         "\"budget\"): nothing to summarise yet")
    text = runs.summary_text(runs.summary_of(runs.RunDirectory(run_dir, summary)))
    folder = os.path.dirname(target) or "."
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise InputError(f"{folder}: cannot make the folder: {e.strerror}") from None
    out = OutputDir.open(folder)
    try:
        return out.write(os.path.basename(target), text)
    finally:
        out.close()


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    return script_exit.run("run_summary.py", lambda: write_summary(argv[1], argv[2]) and 0)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
