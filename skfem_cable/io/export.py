"""Export of configurations and runs to VTK files for ParaView (through meshio).

scikit-fem's ``Mesh.save`` writes the 1-D parameter mesh of a cable, not the deformed 3-D
curve, so the mesh is built here from the solution:

every body draws itself (``Body.show`` returns a ``contract.Shape``), so a user's body
appears as it says:

* every cable is a smooth curve: its interpolant sampled at ``points_per_element`` points
  per element (``line`` cells, ``Cable.sample``), with the point data ``position``,
  ``velocity``, ``tension``, ``axial_strain``, ``curvature``, ``arc_length``, ``cable_id``
  (index among the cables) and ``element_id``;
* a rigid body is a closed triangulated surface following its motion: a cylinder for
  ``RigidBody.cylinder`` (axis along the body ``x`` axis), the tetrahedron of its base
  points otherwise (``RigidBody.surface``);
* point masses are ``vertex`` cells; a reel shows nothing;
* a line that carries the point data ``width_direction`` and ``width`` (a rod,
  ``Rod.show``: its material frame's ``d2`` and its section's width; also ``director``,
  ``d1``) is drawn as a ribbon too (``ribbon``): ``quad`` cells, part ``PART_RIBBON``,
  between its two edges ``r +- width / 2 width_direction``, with the line's point data on
  both edges (so ParaView colours the ribbon as the line; ``cable_id`` -1).

Fields that only some shapes carry (the cables' ``tension``, ``axial_strain``,
``curvature``, ``arc_length``) are NaN on the other points, and their ids are -1;
ParaView and pyvista leave NaN out of colour ranges.  Every point has ``body_id`` (index in
``System.bodies``) and every cell the cell data ``body_id`` and ``part`` (``PART_CABLE``,
``PART_RIGID``, ``PART_POINT_MASS``).

A time series is one ``.vtu`` per saved step and a ``.pvd`` collection listing them with
their times, which ParaView (and ``pyvista.get_reader``) opens as an animation.

Output frames (``FRAMES``, ``output_frame``): ``"inertial"`` writes the coordinates as
computed; ``"lvlh"`` (a system in orbit) writes them in the orbiting frame of
``Orbit.lvlh``: positions and slopes turned into its axes, velocities relative to it.
"""

import bisect
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np

from ..bodies.section import positive_int
from ..core.contract import PART_CABLE, PART_POINT_MASS, PART_RIBBON, Shape
from ..util.atomic import replacing


def loads_point_data(system, q, v=None, t=0.0, reference=None):
    """The point data the loads give at the state ``(q, v, t)`` (in the computed frame;
    ``reference``: the run's, ``output_frame``): a list of ``(body, {name: values(s)})``
    from every load with ``point_data(system, q, v, t, reference)``, ``values`` a
    function of the body's arc lengths (``ElectrodynamicForce``: its current and bias)."""
    return [load.point_data(system, q, v, t, reference) for load in system.loads
            if callable(getattr(load, "point_data", None))]


def system_mesh(system, q, v=None, points_per_element=8, resolution=32, t=0.0, loads=()):
    """The deformed system as one ``meshio.Mesh`` (see the module docstring): what every
    body shows (``Body.show``), with the loads' point data ``loads``
    (``loads_point_data``) on the bodies that carry an ``arc_length``, the point masses,
    and what a load with a ``show`` hook shows (the contact forces, ``loads.contact``;
    its cells of ``body_id`` -1).

    Parameters
    ----------
    system : System
    q, v : ndarray (system.n_dofs,)
        Coordinates and velocities (``v`` None: zero velocity).
    points_per_element : int
        Samples per cable element (``Cable.sample``).
    resolution : int
        Segments around a cylinder.
    t : float
        Time (s): the fields of deploying cables depend on it (``System.deploy``).
    """
    q = np.asarray(q, dtype=float)
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
    shapes = []
    for body_id, body in enumerate(system.bodies):
        shape = body.show(system, q, v, t, points_per_element=points_per_element,
                          resolution=resolution)
        if shape is None:
            continue
        for owner, fields in loads:
            if owner is body and "arc_length" in shape.data:
                s = shape.data["arc_length"]
                shape.data.update({name: fn(s) for name, fn in fields.items()})
        shapes.append((shape, body_id))
        if RIBBON_DATA <= set(shape.data):
            shapes.append((ribbon(shape), body_id))
    for point_mass in system.point_masses:
        dofs, G = system.position_map(point_mass.point)
        owner = max(i for i, b in enumerate(system.bodies) if system.dofs(b)[0] <= dofs[0])
        shapes.append((Shape((G @ q[dofs])[None], (G @ v[dofs])[None], "vertex", [[0]],
                             PART_POINT_MASS), owner))
    for load in system.loads:  # a load may show what it does (the contact forces): -1
        show = getattr(load, "show", None)
        shape = show(system, q, v, t) if callable(show) else None
        if shape is not None:
            shapes.append((shape, -1))
    return _mesh(shapes)


#: The point data of a line that make it drawn as a ribbon (``ribbon``).
RIBBON_DATA = {"width_direction", "width"}


def ribbon(line):
    """The ribbon of a ``line`` shape carrying the point data ``width_direction`` (unit)
    and ``width``: its points ``r - w/2 d2`` and ``r + w/2 d2`` interleaved (edge ``-``
    at even, ``+`` at odd indices), one ``quad`` between consecutive points of the line
    (the line's ``line`` cells in order), the line's velocity and point data on both
    edges; part ``PART_RIBBON``."""
    half = 0.5 * np.asarray(line.data["width"])[:, None] * line.data["width_direction"]
    points = np.stack([line.points - half, line.points + half], axis=1).reshape(-1, 3)
    a, b = np.asarray(line.cells).T
    quads = np.column_stack([2 * a, 2 * b, 2 * b + 1, 2 * a + 1])
    data = {k: np.repeat(np.asarray(x), 2, axis=0) for k, x in line.data.items()}
    return Shape(points, np.repeat(line.velocity, 2, axis=0), "quad", quads, PART_RIBBON,
                 data)


def _mesh(shapes):
    """One ``meshio.Mesh`` of ``(shape, body_id)`` pairs: their points, cells and point
    data, a field a shape lacks NaN on its points; ``body_id`` and ``part`` as cell data;
    ``cable_id`` (the index among the cables' shapes, -1 elsewhere) and ``element_id`` (-1
    where a shape has none) as integer point data."""
    names = {}
    for shape, _ in shapes:
        names.update({k: np.shape(a)[1:] for k, a in shape.data.items()})
    points, cells, data = [], [], {k: [] for k in ("velocity", "body_id", "cable_id")}
    data.update({k: [] for k in names})
    count, cable = 0, 0
    for shape, body_id in shapes:
        n = len(shape.points)
        points.append(np.asarray(shape.points, dtype=float))
        data["velocity"].append(np.asarray(shape.velocity, dtype=float))
        data["body_id"].append(np.full(n, body_id))
        data["cable_id"].append(np.full(n, cable if shape.part == PART_CABLE else -1))
        cable += shape.part == PART_CABLE
        for k, tail in names.items():
            fill = -1 if k == "element_id" else np.nan
            data[k].append(np.asarray(shape.data[k]) if k in shape.data
                           else np.full((n,) + tail, fill))
        cells.append((shape.cell_type, np.asarray(shape.cells) + count, shape.part, body_id))
        count += n
    point_data = {k: np.concatenate(parts) for k, parts in data.items()}
    point_data["position"] = np.vstack(points)
    for name in ("body_id", "cable_id", "element_id"):
        if name in point_data:
            point_data[name] = point_data[name].astype(np.int32)
    blocks = [meshio.CellBlock(kind, conn.astype(np.int64)) for kind, conn, _, _ in cells]
    cell_data = {"part": [np.full(len(c), p, np.int32) for _, c, p, _ in cells],
                 "body_id": [np.full(len(c), b, np.int32) for _, c, _, b in cells]}
    return meshio.Mesh(point_data["position"], blocks, point_data=point_data,
                       cell_data=cell_data)


class InertialFrame:
    """The system's own axes (inertial, or parallel to them in orbit): configurations are
    written as computed."""

    name = "inertial"
    label = ""  # nothing to say on a render
    view = None  # renders choose their view (plot.view_camera)

    def __init__(self, system, reference=None):
        self.system = system

    def configuration(self, t, q, v=None):
        """``(q, v)`` unchanged (the same arrays)."""
        return q, v


class LvlhFrame:
    """The orbiting frame of a system in orbit (``System.add_orbit``): axes radial,
    along-track and orbit normal (``Orbit.lvlh``), turning with the orbit.

    The frame turns with the run's ``reference`` (``orbit.Reference``: the orbit and
    the rebases of its rectification, ``Result.reference``); None: the system's orbit as
    given.

    Raises
    ------
    ValueError
        When ``system`` is not in orbit.
    """

    name = "lvlh"
    label = "orbiting frame (LVLH): x radial, y along-track"
    view = "orbital"  # renders look along the orbit normal, radial up

    def __init__(self, system, reference=None):
        if system.orbit is None:
            raise ValueError("frame 'lvlh' (the orbiting frame) needs a system in orbit "
                             "(System.add_orbit, or the [orbit] table of a scene file); "
                             "this one has no orbit: use frame 'inertial'")
        self.system = system
        self.orbit = system.orbit if reference is None else reference

    def configuration(self, t, q, v=None):
        """Coordinates ``q`` at time ``t`` in the orbiting frame (positions ``C r``,
        slopes ``C r'`` with ``C = Orbit.lvlh(t)``) and velocities relative to it,
        ``C (v - omega x r)`` (``v`` None stays None); scalar coordinates unchanged."""
        C = self.orbit.lvlh(t)
        turned = self.system.rotate(q, C)
        if v is None:
            return turned, None
        carried = self.system.rigid_motion_velocity(q, self.orbit.angular_velocity(t))
        return turned, self.system.rotate(np.asarray(v, dtype=float) - carried, C)


#: The output frames by name: ``cls(system, reference)`` with ``configuration(t, q, v) -> (q, v)``.
FRAMES = {"inertial": InertialFrame, "lvlh": LvlhFrame}


def frame_name(frame):
    """``frame`` if it names one of ``FRAMES``, else ``ValueError`` listing them."""
    if frame not in FRAMES:
        raise ValueError(f"frame must be one of {', '.join(map(repr, FRAMES))}, "
                         f"got {frame!r}")
    return frame


def output_frame(system, frame="inertial", reference=None):
    """The output frame named ``frame`` (one of ``FRAMES``) for ``system`` (in orbit:
    for the run of ``reference``, ``Result.reference``; None: the orbit as given).

    Raises
    ------
    ValueError
        For an unknown name, or ``"lvlh"`` on a system without orbit.
    """
    return FRAMES[frame_name(frame)](system, reference)


def _write_atomic(path, mesh):
    with replacing(path) as tmp:  # a full disk or an interrupt leaves no temporary file
        meshio.write(tmp, mesh, file_format="vtu")


def write_vtu(path, system, state, points_per_element=8, resolution=32, frame="inertial"):
    """Write one configuration (a ``State``, with or without velocities) to ``path``
    (``.vtu``) in the output ``frame`` (one of ``FRAMES``); returns the path."""
    path = Path(path)
    loads = loads_point_data(system, state.q, state.v, state.t)
    q, v = output_frame(system, frame).configuration(state.t, state.q, state.v)
    _write_atomic(path, system_mesh(system, q, v, points_per_element, resolution, state.t,
                                    loads))
    return path


#: A ``.pvd`` collection's text before and after its data sets (``write_pvd``).
_PVD_HEAD = (b"<?xml version='1.0' encoding='utf-8'?>\n"
             b'<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
             b"  <Collection>\n")
_PVD_TAIL = b"  </Collection>\n</VTKFile>\n"


def pvd_line(t, file):
    """The ``.pvd`` line (bytes) of the data set of time ``t`` in ``file``."""
    element = ET.Element("DataSet", timestep=repr(float(t)), group="", part="0",
                         file=str(file))
    return b"    " + ET.tostring(element) + b"\n"


def write_pvd(path, entries):
    """Write a ``.pvd`` collection of ``(time, file)`` entries (files relative to the
    ``.pvd``'s folder), atomically."""
    _write_collection(path, [pvd_line(t, file) for t, file in entries])


def _write_collection(path, lines):
    """Write the ``.pvd`` collection of the data-set ``lines`` (``pvd_line``), atomically:
    a series adding a frame writes the others' kept lines again, not their XML."""
    with replacing(path) as tmp:
        Path(tmp).write_bytes(_PVD_HEAD + b"".join(lines) + _PVD_TAIL)


def read_pvd(path):
    """The ``(time, file)`` entries of a ``.pvd`` collection."""
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


class VtuSeries:
    """A ParaView time series in a run directory: ``vtu/<name>_NNNNNN.vtu`` per step and
    ``<name>.pvd`` listing them, rewritten after every step (so an interrupted run can be
    opened up to its last step).  ``SeriesWriter`` (cable systems) and the rod chain's
    ``ChainSeriesWriter`` add the mesh of their model.

    Parameters
    ----------
    run_dir : path
        Created if missing.
    append : bool
        Continue the series already in ``run_dir`` (a restarted run): its entries are
        kept up to the first time written again.  Otherwise the series starts afresh.
    name : str
        Base name of the files.
    """

    def __init__(self, run_dir, append=False, name="series"):
        self.dir = Path(run_dir)
        (self.dir / "vtu").mkdir(parents=True, exist_ok=True)
        self.name = name
        self.pvd = self.dir / f"{name}.pvd"
        self.entries = read_pvd(self.pvd) if append and self.pvd.exists() else []
        self._lines = [pvd_line(*entry) for entry in self.entries]

    def add(self, t, mesh):
        """Write the ``meshio.Mesh`` of time ``t``; entries at or after ``t`` are replaced
        (the entries stay in the order of their times).  Returns the path of the
        ``.vtu``."""
        kept = bisect.bisect_left(self.entries, t, key=lambda entry: entry[0])
        del self.entries[kept:], self._lines[kept:]
        file = Path("vtu") / f"{self.name}_{kept:06d}.vtu"
        _write_atomic(self.dir / file, mesh)
        self.entries.append((float(t), file.as_posix()))
        self._lines.append(pvd_line(*self.entries[-1]))
        _write_collection(self.pvd, self._lines)
        return self.dir / file

    def close(self):
        """Nothing is held open; kept for use as a context manager."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class SeriesWriter(VtuSeries):
    """The time series of a cable system (see ``VtuSeries``).

    Parameters
    ----------
    run_dir : path
        Created if missing.
    system : System
    points_per_element, resolution : int
        See ``system_mesh``.
    append, name
        See ``VtuSeries``.
    frame : str
        The output frame, one of ``FRAMES``: ``"inertial"`` (as computed) or ``"lvlh"``
        (the orbiting frame of a system in orbit).
    reference : orbit.Reference, optional
        In orbit, the run's reference (``output_frame``).

    Examples
    --------
    >>> writer = SeriesWriter(run_dir, system)            # doctest: +SKIP
    >>> for t, q, v in steps:                             # doctest: +SKIP
    ...     writer.write(t, q, v)
    >>> writer.close()                                    # doctest: +SKIP
    """

    def __init__(self, run_dir, system, points_per_element=8, resolution=32, append=False,
                 name="series", frame="inertial", reference=None):
        self.frame = output_frame(system, frame, reference)  # refused before any file
        self.reference = reference
        super().__init__(run_dir, append, name)
        self.system = system
        self.points_per_element = positive_int("points_per_element", points_per_element)
        self.resolution = resolution

    def write(self, t, q, v=None):
        """Write the step at time ``t`` (in the writer's frame); entries at or after ``t``
        are replaced.  Returns the path of the ``.vtu``."""
        loads = loads_point_data(self.system, q, v, t, self.reference)
        q, v = self.frame.configuration(t, q, v)
        return self.add(t, system_mesh(self.system, q, v, self.points_per_element,
                                       self.resolution, t, loads))


def write_series(result, run_dir, every=1, **options):
    """Write every ``every``-th saved step of a ``Result`` (and the last) as a VTU series
    in ``run_dir``; ``options`` go to ``SeriesWriter``.  Returns the ``.pvd`` path."""
    if int(every) != every or every < 1:
        raise ValueError(f"every must be a positive integer, got {every!r}")
    indices = list(range(0, len(result), int(every)))
    if indices and indices[-1] != len(result) - 1:
        indices.append(len(result) - 1)
    writer = SeriesWriter(run_dir, result.system, reference=result.reference, **options)
    for i in indices:
        writer.write(result.t[i], result.q[i], result.v[i])
    writer.close()
    return writer.pvd
