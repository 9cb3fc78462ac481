"""One-line errors for calls with arguments a method does not take. pybind11's own error lists
the repr of every argument, which for a batch of arrays runs to kilobytes (a pyribs user's
add(solution=..., objective=...) or tell(objective=..., measures=...)); this one names the
method, the parameters it takes and the arguments it was given, by name only."""
import functools
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
            raise TypeError(f"{shown}() takes ({_takes(text)}); it was given {_given(args, kwargs)}") from None
    return call


def shorten_argument_errors(cls, *names):
    """Replaces cls.<name>, for each name, by a wrapper whose argument errors are one line."""
    for name in names:
        setattr(cls, name, _shortened(cls, name, getattr(cls, name)))
