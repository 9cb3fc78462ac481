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


def _is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


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


def read_table(path, required=(), text_columns=(), increasing=()):
    """A CSV file as {column: values} (numbers as float arrays, `text_columns` as lists of strings);
    None when there is no file, {} when it has only its header. Every column in `required` must be
    in the header; every other value must be a finite number; the columns in `increasing` must not
    decrease from row to row."""
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
    if len(lines) < 2:
        return {}
    rows = [line.split(",") for line in lines[1:]]
    for number, cells in enumerate(rows, start=2):
        if len(cells) != len(header):
            raise InputError(f"{_at(path, number)}: {len(cells)} fields, the header has {len(header)}")
    columns, bad = {}, []  # bad: (line, column) of each numeric column's first bad value
    for i, name in enumerate(header):
        cells = [r[i] for r in rows]
        if name in text_columns:
            columns[name] = cells
            continue
        try:
            columns[name] = np.array(cells, dtype=float)
            wrong = np.flatnonzero(~np.isfinite(columns[name]))
            first = int(wrong[0]) if wrong.size else None
        except ValueError:
            first = next(k for k, c in enumerate(cells) if not _is_float(c))
        if first is not None:
            bad.append((first + 2, i + 1))
    if bad:
        number, column = min(bad)
        cell = rows[number - 2][column - 1]
        rule = "is not finite: every value must be" if _is_float(cell) else "is not a number"
        raise InputError(f"{_at(path, number, column)}: {header[column - 1]} '{cell[:40]}' {rule}")
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
