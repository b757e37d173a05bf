"""The I/O layer: observers that turn the saved steps of ``simulate`` into files and
progress reports (``docs/observers.md``, ``docs/output.md``).

* ``RunStore``: the run store (``writer``; its format: ``schema``): a Zarr store of the
  saved steps that xarray reads, a checkpoint and a manifest, committed
  crash-consistently as the run goes; ``resume(path)`` continues an interrupted run
  (``resume``), ``Result.load(path, system)`` and ``open_dataset(path)`` read one back
  (``reader``; the format before the Zarr store: ``legacy``);
* ``fingerprint(system, settings)``: what a store must match to be read or continued
  (``fingerprint``); ``signals``: ``SIGTERM`` ends a run like Ctrl-C; ``lock``: one
  writer per run directory (``RunLocked`` refuses the second);
* ``SeriesObserver``: the ParaView series ``series.pvd`` + ``vtu/`` (``series``);
* ``ProgressBar``: a progress bar with ETA on stderr (``progress``);
* ``run_observers``: the standard list for a run directory.
"""

from ..model.fingerprint import fingerprint
from .lock import RunLocked
from .manifest import RunExists, StoreCorrupt, StoreError, StoreMismatch
from .progress import Progress, ProgressBar
from .reader import open_dataset, read_run
from .resume import Resume, resume
from .schema import DEFAULT_FIELDS
from .series import SeriesObserver
from .signals import Terminated
from .writer import RunStore

__all__ = ["DEFAULT_FIELDS", "Progress", "ProgressBar", "Resume", "RunExists", "RunLocked",
           "RunStore", "SeriesObserver", "StoreCorrupt", "StoreError", "StoreMismatch",
           "Terminated", "fingerprint", "open_dataset", "read_run", "resume",
           "run_observers"]


def run_observers(output=None, progress=None, series_every=1, restart=False, chunk=200,
                  points_per_element=8, fields=None, overwrite=False, source=None,
                  attrs=None, frame="inertial"):
    """The standard observers of a run.

    Parameters
    ----------
    output : path, optional
        Run directory: the run store (``RunStore`` with ``chunk``, ``fields``,
        ``overwrite``, ``source``, ``attrs``) and the ParaView series (``SeriesObserver``
        with ``series_every`` and ``points_per_element``).  None: no files.
    progress : bool, optional
        Progress bar (None: when stderr is a terminal; False: none).
    restart : bool
        The run continues the one in ``output`` (``simulate(resume=resume(output))``):
        the series is continued rather than started afresh.
    source : path, optional
        The run continues the one in ``source`` (``simulate(resume=resume(source))``)
        but is written to ``output``: the store of ``source`` is copied first, so that
        ``output`` holds the whole run.
    frame : str
        Frame of the ParaView series (``export.FRAMES``): ``"inertial"`` (the coordinates
        as computed) or ``"lvlh"`` (the orbiting frame of a system in orbit: positions
        and slopes in the axes of ``Orbit.lvlh``, velocities relative to it; refused at
        the start of a run without orbit).  The run store always holds the computed
        coordinates.

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
        observers.append(RunStore(output, chunk, fields=fields, overwrite=overwrite,
                                  source=source, attrs=attrs))
        observers.append(SeriesObserver(output, every=series_every,
                                        points_per_element=points_per_element,
                                        append=restart or source is not None,
                                        frame=frame))
    if progress is not False:
        observers.append(ProgressBar(progress))
    return observers
