"""Reading the files of an experiment and its runs as `qdmeta report` does: each checked to be a
regular file before it is opened (a FIFO must not hang the report, /dev/zero must not fill its
memory), read with a size bound, and checked against the rules qdmeta's writers follow. A broken
rule is an InputError whose message is one line naming the file, the line and column where there
is one, and the rule.
"""
import json
import math
import os
import re
import stat
import tomllib

import numpy as np

# qdmeta writes kilobytes of TOML, JSON and TSV; a CSV log or archive of a long run may reach
# hundreds of megabytes (a 100,000-cell archive of 1,000-gene solutions is about 2 GB: refused).
SMALL_FILE_LIMIT = 16 << 20
TABLE_LIMIT = 1 << 30
_KINDS = [(stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")]


class InputError(Exception):
    """A damaged or unexpected input: the message is one line naming file, line, column and rule."""


def _kind(mode):
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def _at(path, line=None, column=None):
    return f"{path}:{line}:{column}" if column else f"{path}:{line}" if line else str(path)


def read_bytes(path, limit):
    """The file's bytes, None when there is no file at `path`. Anything else than a regular file
    (or a symbolic link to one), or a file over `limit` bytes, is an InputError."""
    try:
        os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    try:
        before = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"{path}: a symbolic link to nothing (dangling): the run file is lost") from None
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    if not stat.S_ISREG(before.st_mode):
        raise InputError(f"{path}: {_kind(before.st_mode)}, not a regular file: a run file must be one")
    try:
        # Non-blocking: should it turn into a FIFO after the check, opening it must not wait.
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    except OSError as e:
        raise InputError(f"{path}: cannot open: {e.strerror}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{path}: {_kind(st.st_mode)}, not a regular file: a run file must be one")
        if st.st_size > limit:
            raise InputError(f"{path}: {st.st_size} bytes, more than the {limit} a file the report reads may hold")
        chunks, total = [], 0
        while total <= limit:  # bounded even if the file grows while it is read
            chunk = os.read(fd, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > limit:
            raise InputError(f"{path}: more than the {limit} bytes a file the report reads may hold")
        return b"".join(chunks)
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    finally:
        os.close(fd)


# The number syntax of qdmeta's C++ reader of run files (std::from_chars, src/qdmeta/io/csv.cpp):
# ASCII digits, a '-' but no '+', no spaces or '_'. Python's float() takes more ('+1', ' 1',
# '1_0', Arabic-Indic digits), so a cell is matched against this syntax first. inf and nan parse
# there too, and are refused as not finite.
_DECIMAL = r"-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?"
_WHOLE = r"-?[0-9]+"
_NUMBERS = {False: re.compile(f"{_DECIMAL}(?:,{_DECIMAL})*"), True: re.compile(f"{_WHOLE}(?:,{_WHOLE})*")}
_NOT_FINITE = re.compile(r"-?(?:inf(?:inity)?|nan(?:\([0-9A-Za-z_]*\))?)", re.IGNORECASE)
INT64_MAX = 2 ** 63 - 1


class ColumnRule:
    """What a numeric column's cells must be beyond a finite number in qdmeta's syntax: whole (a
    64-bit integer, written without a point), at least `low`, within [0, 1] (`unit`) or [-1, 1]
    (`signed_unit`), or a 32-bit float (`single`: what the C++ reader stores; past its range the reader refuses the value)."""

    def __init__(self, whole=False, low=None, unit=False, single=False, low_rule=None, signed_unit=False):
        self.whole, self.low, self.unit, self.single = whole, low, unit, single
        self.signed_unit = signed_unit
        self.low_rule = low_rule or f"is below {low}"


ANY_NUMBER = ColumnRule()


def _is_number(text):
    return re.fullmatch(_DECIMAL, text) is not None


def _first_bad(cells, rule):
    """The column as floats, and the (row, message) of its first bad cell (None when all are good)."""
    if not _NUMBERS[rule.whole].fullmatch(",".join(cells)):
        for k, cell in enumerate(cells):
            if rule.whole and re.fullmatch(_WHOLE, cell) is None and _is_number(cell):
                return None, (k, "is not a whole number: qdmeta writes this column as one")
            if not _is_number(cell):
                return None, (k, "is not finite: every value must be" if _NOT_FINITE.fullmatch(cell)
                              else "is not a number")
    values = np.array(cells, dtype=float)
    checks = []
    if rule.whole:
        checks.append((np.array([len(c) > 18 and abs(int(c)) > INT64_MAX for c in cells], dtype=bool),
                       "is out of range of a 64-bit integer"))
    if rule.single:
        with np.errstate(over="ignore"):
            single = values.astype(np.float32)
        checks.append((np.isinf(single) | ((single == 0) & (values != 0)), "is out of range of a 32-bit float"))
    if rule.low is not None:
        checks.append((values < rule.low, rule.low_rule))
    if rule.unit:
        checks.append((~((values >= 0) & (values <= 1)), "is outside [0, 1], where every gene must lie"))
    if rule.signed_unit:
        checks.append((~((values >= -1) & (values <= 1)), "is outside [-1, 1], where every stored base feature "
                                                           "must lie"))
    firsts = [(int(np.flatnonzero(bad)[0]), why) for bad, why in checks if bad.any()]
    return values, min(firsts, key=lambda f: f[0]) if firsts else None


def _line_column(text, offset):
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def read_text(path, limit=SMALL_FILE_LIMIT):
    """The file as UTF-8 text without NUL bytes; None when there is no file."""
    data = read_bytes(path, limit)
    if data is None:
        return None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        good = data[: e.start].decode("utf-8")
        raise InputError(f"{_at(path, *_line_column(good, len(good)))}: byte 0x{data[e.start]:02x} is not UTF-8 "
                         "text") from None
    nul = text.find("\0")
    if nul >= 0:
        raise InputError(f"{_at(path, *_line_column(text, nul))}: a NUL byte: the file is damaged")
    return text


def read_toml(path):
    """The parsed TOML file; None when there is no file."""
    text = read_text(path)
    if text is None:
        return None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        # tomllib's message ends with "(at line L, column C)": the position goes first, as qdmeta's.
        where = re.search(r"\(at line (\d+), column (\d+)\)$", str(e))
        rule = str(e)[: where.start()].strip() if where else str(e)
        raise InputError(f"{_at(path, *(where.groups() if where else ()))}: not valid TOML: {rule}") from None


def _no_constant(name):
    raise ValueError(f"{name} is not a JSON number")


def read_json_object(path):
    """The parsed JSON object; None when there is no file."""
    text = read_text(path)
    if text is None:
        return None
    try:
        value = json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as e:
        raise InputError(f"{_at(path, e.lineno, e.colno)}: not valid JSON: {e.msg}") from None
    except (ValueError, RecursionError) as e:
        raise InputError(f"{path}: not valid JSON: {e}") from None
    if not isinstance(value, dict):
        raise InputError(f"{path}: not a JSON object")
    return value


def _lines(path, text):
    """The lines of a CSV file as qdmeta writes it: each ends with a newline (CR LF accepted)."""
    if text == "":
        raise InputError(f"{path}: empty: the file starts with its header line")
    lines = text.split("\n")
    if lines[-1] != "":
        raise InputError(f"{_at(path, len(lines))}: the last line has no line end: the file was cut short")
    return [line[:-1] if line.endswith("\r") else line for line in lines[:-1]]


def read_table(path, required=(), text_columns=(), increasing=(), rules=None, check_header=None):
    """A CSV file as {column: values} (numbers as float arrays, `text_columns` as lists of strings);
    None when there is no file, {} when it has only its header. Every column in `required` must be
    in the header (and `check_header`, given the header, may refuse it with a rule); every other
    value must be a finite number in qdmeta's syntax, and follow its column's rule in `rules`
    (a function of the column's name returning a ColumnRule, or None for ANY_NUMBER); the columns
    in `increasing` must not decrease from row to row."""
    text = read_text(path, TABLE_LIMIT)
    if text is None:
        return None
    lines = _lines(path, text)
    header = lines[0].split(",")
    for i, name in enumerate(header):
        if not name or name in header[:i]:
            raise InputError(f"{_at(path, 1, i + 1)}: column {i + 1} "
                             + ("has no name" if not name else f"'{name}' repeats an earlier column's name"))
    missing = [c for c in required if c not in header]
    if missing:
        raise InputError(f"{_at(path, 1)}: no column '{missing[0]}' (the report needs {', '.join(required)})")
    refused = check_header(header) if check_header else None
    if refused:
        raise InputError(f"{_at(path, 1)}: {refused}")
    if len(lines) < 2:
        return {}
    rows = [line.split(",") for line in lines[1:]]
    for number, cells in enumerate(rows, start=2):
        if len(cells) != len(header):
            raise InputError(f"{_at(path, number)}: {len(cells)} fields, the header has {len(header)}")
    columns, bad = {}, []  # bad: (line, column, rule) of each numeric column's first bad value
    for i, name in enumerate(header):
        cells = [r[i] for r in rows]
        if name in text_columns:
            columns[name] = cells
            continue
        columns[name], first = _first_bad(cells, (rules and rules(name)) or ANY_NUMBER)
        if first is not None:
            bad.append((first[0] + 2, i + 1, first[1]))
    if bad:
        number, column, rule = min(bad)
        raise InputError(f"{_at(path, number, column)}: {header[column - 1]} '{rows[number - 2][column - 1][:40]}' "
                         f"{rule}")
    for name in increasing:
        drops = np.flatnonzero(np.diff(columns[name]) < 0)
        if drops.size:
            row = int(drops[0]) + 3  # the row after the drop, counting the header as line 1
            raise InputError(f"{_at(path, row, header.index(name) + 1)}: {name} {rows[row - 2][header.index(name)]} "
                             f"is below the row before's: {name} must not decrease")
    return columns


def list_dir(path):
    """The names in a directory, sorted."""
    try:
        return sorted(os.listdir(path))
    except OSError as e:
        raise InputError(f"{path}: cannot list: {e.strerror}") from None
