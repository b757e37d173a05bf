"""Runs into run directories, as ``skfem-cable run`` makes them.

A run directory holds

* the run store (written during the run by ``io.RunStore``): ``results.zarr`` (the saved
  steps; ``xarray.open_zarr`` opens it, ``Result.load(run_dir, system)`` reads it back),
  ``checkpoint_NNNNNNNN.npz`` (the state at the last commit) and ``manifest.json`` (the
  commit record); continue an interrupted run with ``--resume`` or
  ``simulate(..., resume=io.resume(run_dir))``;
* the VTU series ``series.pvd`` + ``vtu/`` (written during the run by
  ``io.SeriesObserver``), which ParaView opens as an animation;
* ``summary.json``: scene, parameters, wall time (and the kernels' compile time apart),
  steps, Newton statistics, key outputs, every file of the run directory with a one-line
  description (``files.described``), the store and the files written;
* ``plots/``: energy and cable histories, tension spectra and a rendered snapshot
  (``plot``), and ``animation.gif`` on request.

``RunOptions.frame`` chooses the frame of the series and the renders (``export.FRAMES``:
``"inertial"``, or ``"lvlh"``, the orbiting frame of a system in orbit); the store holds
the computed coordinates.  The summary of a system in orbit reports the reference orbit
and the osculating orbit of the centre of mass at the first and last saved steps
(``summary.orbit_summary``).

A directory that holds another run is not written into: ``RunOptions.overwrite`` removes
that run's files first (only files this package writes), ``RunOptions.resume`` continues
it, and only as the run it holds (``directory.run_directory``).  A run holds the lock of its
directory (``io.lock``) from the first check to its last file: a second process writing
the same directory is refused.

One module a job: ``options`` (``RunOptions``), ``directory`` (the run directory: its
files and their descriptions, which a scene's module extends with ``register_files``;
checking, holding and removing a run), ``summary`` (``summary.json`` and the printed
summary), ``figures`` (the figures of a run), ``continued`` (a continued run is the run it
continues) and ``drive`` (``run_dynamic``, ``RunScene``, ``run_static``).  Their public
names are importable from ``skfem_cable.runner`` too, each imported when first named
(``util.lazy``): ``runner.options`` alone (the command line's help) does without the
solvers.
"""

from ..util.lazy import exports

_WHERE = {
    "continued": ("MOVABLE", "resume_checked"),
    "directory": ("DESCRIPTIONS", "SUMMARY", "UNDESCRIBED", "check_run_dir",
                  "described_files", "recorded_files", "register_files", "remove_run",
                  "run_directory", "run_files", "run_patterns"),
    "drive": ("RunScene", "run_dynamic", "run_static", "store_summary"),
    "figures": ("framed_title", "plot_files", "run_figures", "snapshot"),
    "options": ("RunOptions",),
    "summary": ("BALANCE_WARNING", "MAX_PRINTED", "body_outputs", "centre_of_mass_orbit",
                "complete_summary", "format_summary", "orbit_elements", "orbit_summary",
                "run_outputs", "run_warnings", "warn", "write_summary"),
}

__all__ = [name for names in _WHERE.values() for name in names]

__getattr__, __dir__ = exports(__name__, _WHERE)
