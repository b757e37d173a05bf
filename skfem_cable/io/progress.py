"""A dependency-free progress bar with ETA for long runs (to stderr): ``Progress`` and
the observer ``ProgressBar``."""

import sys
import time

from ..core.protocols import Observer
from ..util import durations


def eta(elapsed, frac):
    """The remaining time after ``elapsed`` s for the part ``frac`` done, as shown
    (``durations.format``): ``--`` until a rate is known (nothing done yet, or no time
    measured)."""
    if not (frac > 0 and elapsed > 0):
        return f"{'--':>7}"
    return f"{durations.format(elapsed * (1 - frac) / frac):>7}"


class Progress:
    """``Progress(t_start, t_end, enabled)``; call ``update(t)`` and ``close()``.

    ``enabled=None`` shows the bar only when stderr is a terminal; ``label`` names the
    progress variable (``t=``, or ``runs=`` for a study's tasks).
    """

    def __init__(self, t_start, t_end, enabled=None, stream=None, width=30, label="t"):
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else bool(enabled)
        self.t0, self.t1, self.width, self.label = t_start, t_end, width, label
        self.wall0 = time.perf_counter()
        self.last = -1.0
        self.shown = None  # the time last shown

    def update(self, t, note=""):
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self.last < 0.2 and t < self.t1:
            return
        self.last, self.shown = now, t
        frac = self.fraction(t)
        elapsed = now - self.wall0
        bar = "#" * int(frac * self.width)
        self.stream.write(f"\r[{bar:<{self.width}}] {100 * frac:5.1f}%  {self.label}="
                          f"{self.show(t)}{self.speed(t, elapsed)}  elapsed "
                          f"{durations.format(elapsed):>8}  ETA {eta(elapsed, frac)} {note}")
        self.stream.flush()

    def show(self, t):
        """``t`` as shown: a duration (``durations.format``) for the time, a count
        otherwise."""
        return durations.format(t) if self.label == "t" else f"{t:.6g}"

    def speed(self, t, elapsed):
        """The simulated time per wall second (``, 2.5 h/s``), for the time only."""
        if self.label != "t" or not elapsed > 0:
            return ""
        return f", {durations.format((t - self.t0) / elapsed)}/s"

    def fraction(self, t):
        """The part of the span done at ``t``, in [0, 1] (1 for an empty span)."""
        if not self.t1 > self.t0:
            return 1.0
        return min(max((t - self.t0) / (self.t1 - self.t0), 0.0), 1.0)

    def close(self):
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


class ProgressBar(Observer):
    """The progress of a run (``Progress``), updated at every saved step.

    Parameters
    ----------
    enabled : bool, optional
        Default: shown when ``stream`` is a terminal.
    stream : file, optional
        Default: ``sys.stderr``.
    width : int
        Characters of the bar.
    """

    def __init__(self, enabled=None, stream=None, width=30):
        self.enabled, self.stream, self.width = enabled, stream, width
        self.bar = None

    def start(self, run):
        self.bar = Progress(run.settings["t_start"], run.settings["t_end"], self.enabled,
                            self.stream, self.width)

    def saved(self, run, step):
        self.bar.update(step.t)

    def finish(self, run, error):
        if self.bar is None:
            return
        t = run.integrator.t
        if error is None and (self.bar.shown != t or run.stop_reason):
            self.bar.last = -1.0  # show where the run ended (and why, if stopped)
            self.bar.update(t, run.stop_reason or "")
        self.bar.close()
