"""docs/tutorials/pyribs-cma-mae.md: its qdmeta script runs, differs from its pyribs script in
the import lines alone, and its result archive holds the elites its archive keeps."""
import pathlib
import re

import numpy as np

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "tutorials" / "pyribs-cma-mae.md"


def blocks():
    found = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    pyribs = [b for b in found if "from ribs" in b]
    ours = [b for b in found if "from qdmeta" in b]
    assert len(pyribs) == 1 and len(ours) == 1
    return pyribs[0], ours[0]


def without_imports(block):
    return [line for line in block.splitlines() if not line.startswith(("import ", "from "))]


def test_the_translation_changes_only_the_imports():
    pyribs, ours = blocks()
    assert without_imports(pyribs) == without_imports(ours)
    assert len(without_imports(ours)) > 20


def test_the_qdmeta_script_runs_and_its_result_archive_holds_the_archives_elites(capsys):
    names = {}
    exec(compile(blocks()[1], DOC.name, "exec"), names)
    archive, result = names["archive"], names["result_archive"]
    assert len(archive) > 100 and archive.learning_rate == 0.01
    for field in ("index", "objective", "solution"):
        assert np.array_equal(archive.data()[field], result.data()[field])
    printed = capsys.readouterr().out.split()
    assert float(printed[0]) == result.stats.qd_score and float(printed[1]) == result.stats.coverage
