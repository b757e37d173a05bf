"""The ParaView series of a run, written as it goes: the observer ``SeriesObserver``."""

from pathlib import Path

from ..bodies.section import positive_int
from ..core.protocols import Observer
from . import export, signals


class SeriesObserver(Observer):
    """Writes ``run_dir/series.pvd`` and one ``vtu/series_NNNNNN.vtu`` per written step,
    so that ParaView opens a running or interrupted run up to its last written step: the
    one series observer of every model.  The run's integrator gives the writer
    (``series_writer``: ``export.SeriesWriter`` of a system of bodies, the rod chain's
    joints for a rod chain), the observer decides which steps it writes.  A signal
    (Ctrl-C, ``SIGTERM``) arriving while a step is written waits for it
    (``signals.deferred``): no half-written series.

    Parameters
    ----------
    run_dir : path
        Created at the start of the run.
    every : int
        A ``.vtu`` for every ``every``-th saved step (counted from the initial state, also
        across a resumed run) and for the last one (also the step at which an observer
        stopped the run).
    points_per_element : int
        Cable samples per element (``export.system_mesh``).
    append : bool
        Continue the series in ``run_dir`` (a resumed run always does): its entries are
        kept up to the first time written again.  Otherwise the series starts afresh.
    frame : str
        The output frame (``export.FRAMES``): ``"inertial"`` (as computed) or ``"lvlh"``
        (the orbiting frame of a system in orbit, refused at the start of a run without
        orbit).
    """

    def __init__(self, run_dir, every=1, points_per_element=8, append=False,
                 frame="inertial"):
        self.every = positive_int("every", every)
        self.points_per_element = positive_int("points_per_element", points_per_element)
        self.frame = export.frame_name(frame)
        self.dir = Path(run_dir)
        self.append = append
        self.writer = None
        self.last = None

    @property
    def pvd(self):
        """Path of the ``.pvd`` collection."""
        return self.dir / "series.pvd"

    def start(self, run):
        append = self.append or run.resumed
        # the writer refuses a frame the run cannot give before any file changes
        self.writer = run.integrator.series_writer(self.dir, export.SeriesWriter, append=append,
                                                   frame=self.frame,
                                                   points_per_element=self.points_per_element)
        if not append:
            self.pvd.unlink(missing_ok=True)  # a series left by an earlier run
        self.last = None

    def saved(self, run, step):
        # the ordinal of this step among the saved ones: saved steps are the multiples of
        # the run's ``every`` (and the last step)
        if (step.index // run.settings["every"]) % self.every == 0:
            with signals.deferred():  # a signal waits for the .vtu and the .pvd
                self.writer.write(step.t, step.q, step.v)
            self.last = None
        else:
            self.last = (step.t, step.q.copy(), step.v.copy())

    def finish(self, run, error):
        if error is None and self.last is not None:  # the last step (or the stop step)
            with signals.deferred():
                self.writer.write(*self.last)
        self.last = None
        if self.writer is not None:
            self.writer.close()
