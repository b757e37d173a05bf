"""The dataset of a parameter study and its directory.

A study directory holds

* ``study.zarr``: the study's ``xarray.Dataset`` (``open_study``), one dimension per swept
  parameter: per point the key numbers of its run (``task.numbers``), ``status``
  (``complete`` or ``failed``), ``error``, ``reused`` (finished before this call),
  ``t_last`` (time of its last stored step), ``task_wall_time`` and ``run_dir``;
* ``runs/NAME/``: each point's run directory (``runner``: the run store, the ParaView
  series, ``summary.json``), named by ``grid.run_name``; ``open_run`` opens its store
  lazily.
"""

import shutil
import uuid
import warnings
from pathlib import Path

import numpy as np

from ..io.reader import open_dataset
from ..util.atomic import TMP_MARK

#: The study's dataset in its directory.
STUDY = "study.zarr"

#: The folder of the run directories in the study's directory.
RUNS = "runs"


def dataset(dims, coords, indices, records, run_dirs):
    """The study's ``xarray.Dataset`` from the task records (``task.run_point``) at the
    grid indices ``indices``: one variable per key number (NaN where a run has none; a
    vector gets the extra dimension ``NAME_component``; a number named like a parameter
    is ``NAME_output``), and ``status``, ``error``,
    ``reused``, ``t_last``, ``task_wall_time``, ``run_dir``."""
    import xarray as xr

    shape = tuple(len(v) for v in dims.values())
    dimnames = tuple(dims)
    variables = {}
    names = list(dict.fromkeys(n for r in records for n in r["numbers"]))
    for name in names:
        size = max(np.size(r["numbers"].get(name, np.nan)) for r in records)
        vector = any(np.ndim(r["numbers"].get(name, np.nan)) for r in records)
        values = np.full(shape + ((size,) if vector else ()), np.nan)
        for index, r in zip(indices, records):
            value = np.asarray(r["numbers"].get(name, np.nan), dtype=float)
            values[index + ((slice(0, value.size),) if vector else ())] = value
        extra = (f"{name}_component",) if vector else ()
        variables[name + ("_output" if name in coords or name in dims else "")] = (
            dimnames + extra, values)
    for name, dtype, key in (("status", object, "status"), ("error", object, "error"),
                             ("reused", bool, "reused"), ("t_last", float, "t_last"),
                             ("task_wall_time", float, "task_wall_time")):
        values = np.empty(shape, dtype=dtype)
        for index, r in zip(indices, records):
            values[index] = r[key]
        variables[name] = (dimnames, values)
    paths = np.empty(shape, dtype=object)
    for index, path in zip(indices, run_dirs):
        paths[index] = path
    variables["run_dir"] = (dimnames, paths)
    return xr.Dataset(variables, coords={**{d: list(v) for d, v in dims.items()}, **coords})


def write_study(ds, path):
    """Write the study ``ds`` to the Zarr store ``path``: into a temporary folder beside
    it, then renamed over the old one, so that ``path`` never holds a part of a study."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f"{path.name}{TMP_MARK}{uuid.uuid4().hex[:12]}")
    old = path.with_name(f"{path.name}.old{TMP_MARK}{uuid.uuid4().hex[:12]}")
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata")
            ds.to_zarr(tmp, mode="w", zarr_format=3, consolidated=True)
        if path.exists():
            path.rename(old)
        tmp.rename(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.rmtree(old, ignore_errors=True)
    return path


def open_study(path):
    """The dataset of the study in the directory ``path`` (``study.zarr``), in memory."""
    import xarray as xr

    root = Path(path) / STUDY
    if not root.is_dir():
        raise FileNotFoundError(f"no {STUDY} in {path}: not a study directory")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata")
        return xr.open_zarr(root, consolidated=True).load()


def open_run(study, **params):
    """The run store of one point of ``study`` (a dataset of ``sweep``/``open_study``),
    selected by its parameters (``run=k`` for a list grid), as a lazy
    ``xarray.Dataset`` (``io.open_dataset``): its saved steps' time series."""
    run_dir = study.run_dir.sel(**params)
    if run_dir.ndim:
        raise ValueError(f"{params} selects {run_dir.size} runs: give a value for each of "
                         f"{', '.join(study.run_dir.dims)}")
    return open_dataset(Path(study.attrs["directory"]) / str(run_dir.item()))


#: Columns of ``format_study`` besides the parameters (the first scene outputs).
PRINTED = 4


def format_study(ds):
    """A few readable lines about a study (what ``skfem-cable sweep`` prints): counts, a
    table of the points with their status and first key numbers, the errors."""
    status = np.asarray(ds.status.values).ravel()
    failed = int((status != "complete").sum())
    lines = [f"study {ds.attrs.get('directory', '')}: {status.size} runs, "
             f"{status.size - failed} complete ({int(ds.reused.sum())} reused), "
             f"{failed} failed"]
    skip = {"task_wall_time", "t_last", "total_wall_time", "saved_steps"}
    numbers = [n for n, v in ds.data_vars.items() if v.dtype.kind == "f" and n not in skip
               and v.dims == ds.status.dims and not n.startswith(("newton", "energy"))]
    columns = [n for n in numbers if n not in ("wall_time", "steps")][:PRINTED]
    table = ds[["status", *columns, *(["wall_time"] if "wall_time" in ds else [])]]
    lines.append(table.to_dataframe().to_string(float_format=lambda x: f"{x:.6g}"))
    for index in np.argwhere(np.asarray(ds.status.values) != "complete"):
        point = {d: ds[d].values[i].item() for d, i in zip(ds.status.dims, index)}
        lines.append(f"failed {point}: {ds.error.values[tuple(index)]}")
    return "\n".join(lines)
