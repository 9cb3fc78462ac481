"""docs/python.md: every python block runs, in order, as one module (so the tutorial cannot
rot, and its functions pickle by reference as a script's do), with `output_dir` a temporary
folder."""
import pathlib
import re
import sys
import types

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def test_every_python_block_of_the_tutorial_runs(tmp_path):
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    assert len(blocks) >= 6
    tutorial = types.ModuleType("qdmeta_tutorial")
    tutorial.output_dir = tmp_path
    sys.modules[tutorial.__name__] = tutorial
    try:
        for i, block in enumerate(blocks):
            exec(compile(block, f"{DOC.name} block {i + 1}", "exec"), tutorial.__dict__)
    finally:
        del sys.modules[tutorial.__name__]
    assert (tmp_path / "arm-archive.png").stat().st_size > 1000
    assert (tmp_path / "arm-qd-meta" / "summary.json").exists()


def test_the_readmes_python_example_runs(tmp_path, monkeypatch):
    readme = DOC.parents[1] / "README.md"
    # The module's example (another block reads a demo run's archive.csv with numpy alone).
    blocks = [b for b in re.findall(r"```python\n(.*?)```", readme.read_text(), flags=re.S) if "qdmeta.Task" in b]
    assert blocks, "README.md has the module's example"
    monkeypatch.chdir(tmp_path)  # it writes runs/sphere
    for i, block in enumerate(blocks):
        exec(compile(block, f"README.md block {i + 1}", "exec"), {})
    assert (tmp_path / "runs" / "sphere" / "summary.json").exists()
