"""What the robustness matrices (damaged_files.py, interruptions.py) share: their scratch folder
and their verdict line."""
import contextlib
import os
import shutil
import tempfile


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
