"""ParaView files of a rod chain: its joints as a polyline (one ``line`` cell per rod).

The mesh of a configuration (``chain_mesh``) has the joints ``O_0 .. O_n`` as points with
the point data ``position``, ``velocity``, ``arc_length`` (reference arc length of the
joint from the anchor) and ``joint_id``, and one ``line`` cell per rod with the cell data
``tension`` (N), ``strain`` (engineering strain ``(l - l0) / l0``), ``length`` (current,
m) and ``rod_id``.  meshio, pyvista and ParaView read it; a series is one ``.vtu`` per
saved step and a ``.pvd`` collection (``export.write_pvd``), written atomically by the
low-level writers of ``skfem_cable.io.export``: ``write_series`` after a run,
``io.SeriesObserver`` during one (through ``Integration.series_writer``).
"""

from pathlib import Path

import meshio
import numpy as np

from ..io.export import VtuSeries, _write_atomic


def chain_mesh(chain, q, v=None, origin=(0.0, 0.0, 0.0), origin_velocity=(0.0, 0.0, 0.0)):
    """The chain with rod vectors ``q`` (n, 3), rates ``v`` (None: at rest) and the
    anchor at ``origin`` moving with ``origin_velocity``, as a ``meshio.Mesh`` (see the
    module docstring)."""
    q = np.asarray(q, dtype=float).reshape(chain.n, 3)
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float).reshape(chain.n, 3)
    points = chain.joints(q, origin)
    n = chain.n
    lines = np.column_stack([np.arange(n), np.arange(1, n + 1)]).astype(np.int64)
    point_data = {"position": points, "velocity": chain.joints(v, origin_velocity),
                  "arc_length": np.concatenate([[0.0], np.cumsum(chain.lengths)]),
                  "joint_id": np.arange(n + 1, dtype=np.int32)}
    cell_data = {"tension": [chain.tension(q)], "strain": [chain.strain(q)],
                 "length": [np.linalg.norm(q, axis=1)],
                 "rod_id": [np.arange(n, dtype=np.int32)]}
    return meshio.Mesh(points, [meshio.CellBlock("line", lines)], point_data=point_data,
                       cell_data=cell_data)


def state_mesh(state):
    """``chain_mesh`` of a ``ChainState`` (``RodChainResult.state(i)``)."""
    return chain_mesh(state.chain, state.rods, state.rod_velocities, state.origin,
                      state.origin_velocity)


def write_vtu(path, state):
    """Write one configuration (a ``ChainState``) to ``path`` (``.vtu``), atomically;
    returns the path."""
    path = Path(path)
    _write_atomic(path, state_mesh(state))
    return path


class ChainSeriesWriter(VtuSeries):
    """Writes a rod-chain time series into a run directory (the layout of
    ``export.VtuSeries``, so that ParaView opens an interrupted run too).

    Parameters
    ----------
    run_dir : path
        Created if missing.
    chain : RodChain
    append, name
        See ``export.VtuSeries``.
    anchor : callable, optional
        ``anchor(t) -> (position, velocity, ...)`` of ``O_0`` (a run's
        ``Integration.anchor``), for ``write`` without an ``origin``.
    """

    def __init__(self, run_dir, chain, append=False, name="series", anchor=None):
        super().__init__(run_dir, append, name)
        self.chain = chain
        self.anchor = anchor

    def write(self, t, q, v=None, origin=None, origin_velocity=None):
        """Write the configuration at time ``t`` (rod vectors ``q``, (n, 3) or flattened)
        with the anchor at ``origin`` moving with ``origin_velocity`` (default: the
        writer's ``anchor(t) -> (position, velocity, ...)``, else at rest at the origin);
        entries at or after ``t`` are replaced.  Returns the path of the ``.vtu``."""
        if origin is None:
            origin, origin_velocity = (self.anchor(t)[:2] if self.anchor is not None
                                       else (np.zeros(3), np.zeros(3)))
        return self.add(t, chain_mesh(self.chain, q, v, origin, origin_velocity))


def write_series(result, run_dir, every=1, name="series"):
    """Write every ``every``-th saved step of a ``RodChainResult`` (and the last) as a VTU
    series in ``run_dir``.  Returns the ``.pvd`` path."""
    if isinstance(every, bool) or int(every) != every or every < 1:
        raise ValueError(f"every must be a positive integer, got {every!r}")
    indices = list(range(0, len(result), int(every)))
    if indices[-1] != len(result) - 1:
        indices.append(len(result) - 1)
    writer = ChainSeriesWriter(run_dir, result.chain, name=name)
    for i in indices:
        s = result.state(i)
        writer.write(s.t, s.rods, s.rod_velocities, s.origin, s.origin_velocity)
    writer.close()
    return writer.pvd
