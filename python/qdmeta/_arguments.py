"""One-line errors for calls with arguments a method does not take. pybind11's own error lists
the repr of every argument, which for a batch of arrays runs to kilobytes (a pyribs user's
add(solution=..., objective=...) or tell(objective=..., measures=...)); this one names the
method, the parameters it takes and the arguments it was given, by name only, or, when an
argument's type cannot fit, that argument with the type expected and the type given. A path argument
that no path can be (a NUL in it, or text with no file-name encoding) is refused first, in one
line naming the argument, where pybind11 would list every overload."""
import functools
import os
import re

_INCOMPATIBLE = re.compile(r"^\w+\(\): incompatible (?:function|constructor) arguments")


def _parameters(signature):
    """'a: int, b: Dict[str, int] = None' -> ['a: int', 'b: Dict[str, int] = None']."""
    parts, depth, start = [], 0, 0
    for i, c in enumerate(signature):
        depth += 1 if c in "[(" else -1 if c in "])" else 0
        if c == "," and depth == 0:
            parts.append(signature[start:i].strip())
            start = i + 1
    parts.append(signature[start:].strip())
    return [p for p in parts if p]


def _takes(message):
    """The parameters of the first overload pybind11 lists, as 'a, b, c=None' (self left out)."""
    lines = message.split("\n")
    overload = lines[1] if len(lines) > 1 else ""
    names = []
    for parameter in _parameters(overload[overload.find("(") + 1:overload.rfind(") ->")]):
        name, _, default = parameter.partition(" = ")
        name = name.split(":")[0].strip()
        if name != "self":
            names.append(name + ("=" + default if default else ""))
    return ", ".join(names)


def _typed_parameters(message):
    """[(name, annotation)] of the first overload pybind11 lists, self left out."""
    lines = message.split("\n")
    overload = lines[1] if len(lines) > 1 else ""
    out = []
    for parameter in _parameters(overload[overload.find("(") + 1:overload.rfind(") ->")]):
        declared = parameter.partition(" = ")[0]
        name, _, annotation = declared.partition(":")
        if name.strip() != "self":
            out.append((name.strip(), _plain(annotation.strip())))
    return out


# pybind11 3 writes an int parameter as "typing.SupportsInt | typing.SupportsIndex", a float one as
# "typing.SupportsFloat | typing.SupportsIndex", a list one as collections.abc.Sequence[...] and an
# optional one as "X | None"; pybind11 2 writes int, float, List[...] and Optional[...]. Both are
# read as the latter.
_PLAIN_NAMES = {"typing.SupportsInt": "int", "typing.SupportsIndex": "int", "typing.SupportsFloat": "float",
                "collections.abc.Sequence": "List", "typing.Sequence": "List", "typing.List": "List",
                "list": "List", "typing.Optional": "Optional"}


def _split_top(text, separator):
    """text split at each separator outside brackets."""
    parts, depth, start = [], 0, 0
    for i, c in enumerate(text):
        depth += 1 if c in "[(" else -1 if c in "])" else 0
        if depth == 0 and text.startswith(separator, i):
            parts.append(text[start:i])
            start = i + len(separator)
    return [p.strip() for p in parts + [text[start:]]]


def _plain(annotation):
    """pybind11 3's annotation spelled as pybind11 2 spells it ('typing.SupportsInt |
    typing.SupportsIndex | None' -> 'Optional[int]')."""
    kinds = []
    for part in _split_top(annotation, " | "):
        head, bracket, rest = part.partition("[")
        head = _PLAIN_NAMES.get(head, head)
        if bracket:
            inner = ", ".join(_plain(a) for a in _split_top(rest[:-1], ","))
            part = f"{head}[{inner}]"
        else:
            part = head
        if part not in kinds:
            kinds.append(part)
    optional = "None" in kinds and len(kinds) > 1
    kinds = [k for k in kinds if k != "None"] if optional else kinds
    if kinds == ["float", "int"] or kinds == ["int", "float"]:  # SupportsFloat | SupportsIndex
        kinds = ["float"]
    plain = " | ".join(kinds)
    return f"Optional[{plain}]" if optional else plain


def _fits(value, annotation):
    """Whether pybind11 could convert `value` to `annotation` (True when the annotation is not one
    of the plain kinds checked here: the call's own error then stands)."""
    if annotation.startswith("Optional[") and annotation.endswith("]"):
        return value is None or _fits(value, annotation[9:-1])
    if annotation.startswith(("List[", "list[")) and annotation.endswith("]"):
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or not hasattr(value, "__getitem__"):
            return False
        return all(_fits(v, annotation[5:-1]) for v in value)
    if annotation in ("int", "bool"):
        return not isinstance(value, (str, bytes, float)) and hasattr(type(value), "__index__")
    if annotation == "float":
        return not isinstance(value, (str, bytes)) and hasattr(type(value), "__float__")
    if annotation == "str":
        return isinstance(value, str)
    if annotation == "dict":
        return isinstance(value, dict)
    if annotation.startswith("qdmeta."):
        return value is None or type(value).__name__ == annotation.rsplit(".", 1)[1]
    return True


def _readable(annotation):
    if annotation.startswith("Optional[") and annotation.endswith("]"):
        return _readable(annotation[9:-1]) + " or None"
    if annotation.startswith(("List[", "list[")) and annotation.endswith("]"):
        return "a list of " + _readable(annotation[5:-1])
    return annotation.replace("qdmeta._qdmeta.", "qdmeta.")


def _mismatch(message, args, kwargs):
    """'solution_dim must be int, got str' for the first argument given whose type cannot fit."""
    parameters = _typed_parameters(message)
    given = list(zip([n for n, _ in parameters], args)) + list(kwargs.items())
    annotations = dict(parameters)
    for name, value in given:
        if name in annotations and not _fits(value, annotations[name]):
            return f"{name} must be {_readable(annotations[name])}, got {type(value).__name__}"
    return None


def _given(args, kwargs):
    parts = [f"{len(args)} positional"] if args else []
    parts += [f"{k}=" for k in kwargs]
    return ", ".join(parts) if parts else "nothing"


def _shortened(cls, name, method):
    shown = cls.__name__ if name == "__init__" else f"{cls.__name__}.{name}"

    @functools.wraps(method)
    def call(self, *args, **kwargs):
        try:
            return method(self, *args, **kwargs)
        except TypeError as error:
            text = str(error)
            if not _INCOMPATIBLE.match(text):  # raised by the call itself (or the caller's task): as it is
                raise
            wrong = _mismatch(text, args, kwargs)
            if wrong:
                raise TypeError(f"{shown}(): {wrong}; it takes ({_takes(text)})") from None
            raise TypeError(f"{shown}() takes ({_takes(text)}); it was given {_given(args, kwargs)}") from None
    return call


def shorten_argument_errors(cls, *names):
    """Replaces cls.<name>, for each name, by a wrapper whose argument errors are one line."""
    for name in names:
        setattr(cls, name, _shortened(cls, name, getattr(cls, name)))


def _path_problem(value):
    """Why `value` cannot be a path (None when it can, or is no path at all: pybind11 names its type)."""
    try:
        path = os.fspath(value)
    except TypeError:
        return None
    if ("\0" if isinstance(path, str) else b"\0") in path:
        return "holds a NUL character, which no path can hold"
    try:
        os.fsencode(path)
    except UnicodeEncodeError as e:
        return f"holds {path[e.start]!a}, which has no file-name encoding here"
    return None


def check_paths(function, shown, **positions):
    """`function` with its path arguments (name=position among the positional ones) checked first:
    one that no path can be is a ValueError naming it."""
    @functools.wraps(function)
    def call(*args, **kwargs):
        for name, at in positions.items():
            value = kwargs[name] if name in kwargs else args[at] if at < len(args) else None
            problem = None if value is None else _path_problem(value)
            if problem:
                raise ValueError(f"{shown}(): {name} {problem}")
        return function(*args, **kwargs)
    return call
