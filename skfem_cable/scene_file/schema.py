"""The vocabulary of scene files: ``Table`` (a TOML table being read, whose errors name the
key and whose unknown keys are refused) and the value checks (each returns the converted
value or raises ``ValueError`` with the expectation, which ``Table.get`` turns into a
``SceneFileError`` naming the file and the key)."""

import difflib
import math

import numpy as np

from ..util import durations


class SceneFileError(ValueError):
    """A scene file that does not follow the schema."""


_REQUIRED = object()


# --- value checks: each returns the converted value or raises ValueError(expectation) ----------
def number(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError("must be a finite number")
    return float(v)


def boolean(v):
    if not isinstance(v, bool):
        raise ValueError("must be true or false")
    return v


def positive(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
        raise ValueError("must be a number > 0")
    return float(v)


def duration(v):
    """A time span > 0: a number of seconds (``positive``), or a string with a suffix
    ``s``, ``min``, ``h``, ``d`` (``durations.parse``: ``t_end = "30d"``)."""
    if not isinstance(v, str):
        return positive(v)
    try:
        seconds = durations.parse(v)
    except ValueError:
        raise ValueError("must be a number > 0 of seconds, or a string of one with a "
                         "suffix s, min, h or d (\"30d\")") from None
    return positive(seconds)


def non_negative(v):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v >= 0):
        raise ValueError("must be a number >= 0")
    return float(v)


def count(v):
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise ValueError("must be an integer >= 1")
    return v


def integer(v):
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError("must be an integer")
    return v


def vector3(v):
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError("must be a list of 3 numbers")
    return np.array([number(x) for x in v])


def input_or(check):
    """A value checked by ``check``, or ``{input = "name", value = ...}``: an ``Input`` of
    that name holding the checked value until a controller sets it (``[[controllers]]``)."""
    from ..core.inputs import Input

    def read(v):
        if not isinstance(v, dict):
            return check(v)
        if set(v) != {"input", "value"} or not isinstance(v["input"], str):
            raise ValueError('must be a value or a table {input = "name", value = ...}')
        return Input(v["input"], check(v["value"]))

    return read


def direction3(v):
    """A vector that gives a direction: three numbers, not all zero."""
    x = vector3(v)
    if not np.linalg.norm(x) > 0:
        raise ValueError("must be a non-zero list of 3 numbers")
    return x


def matrix3(v):
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError("must be a 3 x 3 list of lists of numbers")
    return np.array([vector3(row) for row in v])


def text(v):
    if not isinstance(v, str) or not v:
        raise ValueError("must be a non-empty string")
    return v


def choice(*options):
    def check(v):
        if v not in options:
            raise ValueError(f"must be one of {', '.join(map(repr, options))}")
        return v
    return check


def interval(lo, hi):
    def check(v):
        x = number(v)
        if not lo <= x <= hi:
            raise ValueError(f"must lie in [{lo}, {hi}]")
        return x
    return check


class Table:
    """A TOML table being read: remembers the keys asked for, so that ``finish`` can reject
    the others, and turns every problem into a ``SceneFileError`` naming the key."""

    def __init__(self, data, where, source):
        self.data, self.where, self.source = data, where, source
        self.asked = []

    def name(self, key):
        return f"{self.where}.{key}" if self.where else key

    def fail(self, key, problem, value=_REQUIRED):
        got = "" if value is _REQUIRED else f", got {value!r}"
        raise SceneFileError(f"{self.source}: {self.name(key)} {problem}{got}")

    def missing(self, key, problem, keys=None):
        """Fail: ``key`` (one of ``keys``, default ``key`` alone) is missing; the message
        names the unknown key of the table closest to one of them (a misspelling), and
        which one it resembles when that is not ``key``."""
        unknown = [k for k in self.data if k not in self.asked]
        close = [(match, name) for name in (keys or (key,))
                 for match in difflib.get_close_matches(name, unknown, n=1)]
        if close:
            match, name = close[0]
            problem += f" (found the unknown key {match!r}" + \
                ("" if name == key else f": did you mean {name!r}?") + ")"
        self.fail(key, problem)

    def has(self, key):
        self.asked.append(key)
        return key in self.data

    def get(self, key, check, default=_REQUIRED):
        if not self.has(key):
            if default is _REQUIRED:
                self.missing(key, "is required")
            return default
        value = self.data[key]
        try:
            return check(value)
        except ValueError as err:
            self.fail(key, str(err), value)

    def table(self, key):
        """The sub-table ``key`` (empty if missing)."""
        value = self.data.get(key, {}) if self.has(key) else {}
        if not isinstance(value, dict):
            self.fail(key, "must be a table", value)
        return Table(value, self.name(key), self.source)

    def inline(self, key):
        """The value of ``key``, a table (``{...}``), as a ``Table`` named after the key."""
        self.asked.append(key)
        return Table(self.data[key], self.name(key), self.source)

    def tables(self, key):
        """The array of tables ``[[key]]`` (empty if missing)."""
        value = self.data.get(key, []) if self.has(key) else []
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            self.fail(key, "must be an array of tables ([[...]])", value)
        return [Table(v, f"{self.name(key)}[{i}]", self.source) for i, v in enumerate(value)]

    def finish(self):
        """Refuse the first key not asked for, naming it (never its value, which may be a
        whole table) and the closest known key."""
        unknown = [k for k in self.data if k not in self.asked]
        if unknown:
            known = list(dict.fromkeys(self.asked))
            close = difflib.get_close_matches(unknown[0], known, n=1)
            guess = f": did you mean {close[0]!r}?" if close else ""
            self.fail(unknown[0], f"is not a known key{guess} (allowed here: "
                      f"{', '.join(known) or 'none'})")


def one_of(t, keys, check):
    """The one of ``keys`` given in the ``Table`` ``t`` (``(key, value)``, the value
    checked by ``check``), ``(None, None)`` if none; two of them fail."""
    given = [k for k in keys if k in t.data]
    if len(given) > 1:
        t.fail(given[1], f"excludes {t.name(given[0])} (give one of them)", t.data[given[1]])
    for k in keys:
        t.has(k)
    return (given[0], t.get(given[0], check)) if given else (None, None)


def rotation(v):
    R = matrix3(v)
    if not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ValueError("must be a proper rotation matrix (orthonormal rows, det = +1)")
    return R
