"""The values of command-line options: each converter turns the text into the value or
raises the ``argparse`` error that names what is accepted."""

import argparse
import math
from pathlib import Path

from ..util import durations


def _number(text):
    """``text`` as a float; NaN when it is not a number (refused by the checks below)."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def finite_float(text):
    """``text`` as a finite number, or the ``argparse`` error that says so."""
    value = _number(text)
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


def duration(text):
    """``text`` as a duration > 0 in seconds (``durations.parse``: ``30d``, ``12h``,
    ``90min``, ``0.5s`` or a number of seconds), or the ``argparse`` error that says so."""
    forms = "seconds, or a number with a suffix s, min, h or d (30d)"
    try:
        value = durations.parse(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a finite number of {forms}, got "
                                         f"{text}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0 of {forms}, got {text}")
    return value


def positive_int(text):
    """``text`` as an integer >= 1, or the ``argparse`` error that says so."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text}")
    return value


def epoch(text):
    """``text`` checked as an epoch (``environment.as_epoch``: an ISO 8601 date or
    date-time, UTC), or the ``argparse`` error that says so; the text is the value."""
    from ..environment.epoch import as_epoch

    try:
        as_epoch(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an ISO 8601 date or date-time (UTC), "
                                         f"e.g. 2026-01-01 or 2026-01-01T12:00:00, got "
                                         f"{text}") from None
    return text


def directory(text):
    """``text`` as a path, refusing an empty one (an unset shell variable)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("is empty (an unset variable?): give a directory "
                                         "('.' for the current one)")
    return Path(text)
