"""What the robustness matrices (damaged_files.py, interruptions.py, report_vs_adapt.py) share:
their common options, their scratch folder and their verdict line."""
import argparse
import contextlib
import os
import shutil
import tempfile


def argument_parser(doc, quick_help, timeout):
    """A parser with the options every matrix takes: --qdmeta, --quick, --work, --timeout."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--qdmeta", required=True, help="the qdmeta binary")
    parser.add_argument("--quick", action="store_true", help=quick_help)
    parser.add_argument("--work", help="scratch folder (default: a new temporary one, removed at the end)")
    parser.add_argument("--timeout", type=float, default=timeout, help="seconds per command")
    return parser


@contextlib.contextmanager
def work_folder(path, prefix):
    """`path`, made if missing and kept; or a new temporary folder, removed at the end."""
    work = path or tempfile.mkdtemp(prefix=prefix)
    os.makedirs(work, exist_ok=True)
    try:
        yield work
    finally:
        if not path:
            shutil.rmtree(work, ignore_errors=True)


def verdict(cases, defects):
    """Prints `N cases, M defects`; the exit status: 1 when there is a defect."""
    print(f"{cases} cases, {defects} defects")
    return 1 if defects else 0
