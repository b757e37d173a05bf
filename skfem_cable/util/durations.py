"""Durations as users write them: ``"30d"``, ``"12h"``, ``"90min"``, ``"0.5s"`` or a plain
number of seconds (``parse``), and seconds as people read them (``format``).

Examples
--------
>>> from skfem_cable.util import durations
>>> durations.parse("30d"), durations.parse("1.5h"), durations.parse(2.5)
(2592000.0, 5400.0, 2.5)
>>> durations.format(2592000.0), durations.format(95.0), durations.format(0.25)
('30 d', '1.6 min', '0.25 s')
"""

import math
import re

#: Seconds per unit of the accepted suffixes.
UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0, "d": 86400.0}

_PATTERN = re.compile(r"\s*([-+0-9.eE]+)\s*(s|min|h|d)?\s*")


def parse(value, name="duration"):
    """Seconds (float) of ``value``: a number (seconds) or a string of a number with one
    of the suffixes ``s``, ``min``, ``h``, ``d``; ``ValueError`` naming ``name`` and the
    accepted forms otherwise (not finite included)."""
    if isinstance(value, str):
        match = _PATTERN.fullmatch(value)
        try:
            seconds = float(match.group(1)) * UNITS[match.group(2) or "s"] if match else None
        except ValueError:
            seconds = None
    else:
        try:
            seconds = float(value)
        except (TypeError, ValueError):
            seconds = None
    if seconds is None or not math.isfinite(seconds):
        raise ValueError(f"{name} must be a finite number of seconds or a number with a "
                         f"suffix s, min, h or d (e.g. 30d, 1.5h), got {value!r}")
    return seconds


def format(seconds):
    """``seconds`` in the largest unit that keeps the number at least 1 (``"2.5 h"``),
    three significant figures."""
    seconds = float(seconds)
    for unit in ("d", "h", "min"):
        if abs(seconds) >= UNITS[unit]:
            return f"{seconds / UNITS[unit]:.3g} {unit}"
    return f"{seconds:.3g} s"
