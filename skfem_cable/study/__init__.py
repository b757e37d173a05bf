"""Parameter studies on Dask distributed (``docs/sweeps.md``).

* ``sweep(build, grid, ...)`` (``sc.sweep``): one task per point of ``grid``
  (``client.map``), each run into its own run directory of the study, the key numbers
  gathered into one ``xarray.Dataset`` (``cluster``, ``dataset``);
* ``open_study(path)``, ``open_run(study, **params)``: read a study and one run's time
  series (lazily);
* ``grid``: points, run-directory names, command-line parameters; ``task``: one point
  (reuse, continue or run; the record it returns).
"""

from .cluster import sweep
from .dataset import format_study, open_run, open_study
from .grid import parse_param, points, run_name
from .task import run_point

__all__ = ["format_study", "open_run", "open_study", "parse_param", "points", "run_name",
           "run_point", "sweep"]
