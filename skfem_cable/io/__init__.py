"""The I/O layer: observers that turn the saved steps of ``simulate`` into files and
progress reports (``docs/observers.md``).

* ``RunStore``: chunked raw results and a checkpoint (``store``); ``resume(path)`` continues
  an interrupted run, ``load_result(path, system)`` (= ``Result.load``) reads one back;
* ``SeriesObserver``: the ParaView series ``series.pvd`` + ``vtu/`` (``series``);
* ``ProgressBar``: a progress bar with ETA on stderr (``progress``);
* ``run_observers``: the standard list for a run directory.
"""

from .progress import Progress, ProgressBar
from .series import SeriesObserver
from .store import Resume, RunStore, load_result, read_run, resume

__all__ = ["Progress", "ProgressBar", "Resume", "RunStore", "SeriesObserver", "load_result",
           "read_run", "resume", "run_observers"]


def run_observers(output=None, progress=None, series_every=1, restart=False, chunk=200,
                  points_per_element=8):
    """The standard observers of a run.

    Parameters
    ----------
    output : path, optional
        Run directory: raw results (``RunStore`` with ``chunk``) and the ParaView series
        (``SeriesObserver`` with ``series_every`` and ``points_per_element``).  None: no
        files.
    progress : bool, optional
        Progress bar (None: when stderr is a terminal; False: none).
    restart : bool
        The run continues the one in ``output`` (``simulate(resume=resume(output))``):
        the series is continued rather than started afresh.

    Returns
    -------
    list of Observer
        Store first, then series, then progress bar.

    Examples
    --------
    >>> simulate(system, 10.0, 1e-3,                                    # doctest: +SKIP
    ...          observers=run_observers("runs/a", progress=True, series_every=10))
    """
    observers = []
    if output is not None:
        observers.append(RunStore(output, chunk))
        observers.append(SeriesObserver(output, every=series_every,
                                        points_per_element=points_per_element,
                                        append=restart))
    if progress is not False:
        observers.append(ProgressBar(progress))
    return observers
