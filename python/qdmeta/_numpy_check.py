"""The import's check that the extension reads and writes this numpy's integer and boolean
arrays right. pybind11 before 2.12 reads numpy 1's dtype layout; a build that still took an
array's strides or item size from it would return every element as the first under numpy 2,
silently. The module refuses to import rather than compute with such arrays."""


def check(module, numpy):
    """Raises ImportError, one line, when an integer or boolean array made or read by `module`
    (the extension) is not what numpy sees."""
    problem = _first_problem(module, numpy)
    if problem:
        raise ImportError(
            f"qdmeta: this build (pybind11 {module.build_info.get('pybind11', '?')}) gets numpy "
            f"{numpy.__version__}'s arrays wrong ({problem}); rebuild it against this numpy "
            f"(pip install .) or use numpy<2")


def _first_problem(module, numpy):
    # One elite per cell of a 4-bin grid, cells 0, 2 and 3 (row 1 is invalid).
    measures = numpy.array([[0.1], [0.3], [0.6], [0.9]], dtype=numpy.float32)
    cells = module.GridArchive(solution_dim=1, dims=[4]).index_of(measures)
    if cells.tolist() != [0, 1, 2, 3]:
        return f"GridArchive.index_of gave {cells.tolist()} for [0, 1, 2, 3]"
    task = module.Task(lambda g: (g[:, 0], g, g[:, 0] > 0.5), 1, 1, name="numpy-check")
    valid = task.evaluate(measures)[2]
    if valid.dtype != numpy.bool_ or valid.tolist() != [False, False, True, True]:
        return f"Task.evaluate's valid flags were {valid.tolist()} for [False, False, True, True]"
    archive = module.GridArchive(solution_dim=1, dims=[4])
    status = archive.add(measures, numpy.zeros(4), measures, valid=numpy.array([True, False, True, True]))
    if status.tolist() != [2, 0, 2, 2]:
        return f"GridArchive.add's statuses were {status.tolist()} for [2, 0, 2, 2]"
    index = archive.data()["index"]
    if index.tolist() != [0, 2, 3]:
        return f"the elites' index was {index.tolist()} for [0, 2, 3]"
    return None
