"""The initial shapes of a cable (``CableShapes``, a base of ``Cable``): straight between two
points, or hanging as the inextensible catenary of its length when the points are closer
than it (``between``, ``hanging``)."""

import numpy as np
from skfem import MeshLine

from .cable_options import is_count
from .memory import check_memory


class CableShapes:
    """The constructors and shapes of ``Cable`` from end points: ``straight``, ``between``
    and ``hanging`` (the cable's class builds from a mesh, a section and nodal fields)."""

    @classmethod
    def straight(cls, start, end, n_elements, section, law=None, **kwargs):
        """A stress-free straight cable from ``start`` to ``end`` with ``n_elements`` elements.

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m); the reference length is their distance.
        n_elements : int
            Number of equal elements, >= 1.
        section : Section
        law : CableLaw or str
            See ``Cable``.
        **kwargs
            The other parameters of ``Cable`` (``element``, ``intorder``, ``name``,
            ``formulation``, ``quadrature``).

        Returns
        -------
        Cable
            Nodes equally spaced, unit slopes along ``end - start``.

        Examples
        --------
        >>> import skfem_cable as sc
        >>> sec = sc.Section.circular(1e-3, 2e11, 7850.0)
        >>> tether = sc.Cable.straight([0, 0, 0], [0, 10, 0], 5, sec, law="truss", name="t1")
        >>> tether.n_dofs, tether.q0[:6].tolist()
        (36, [0.0, 0.0, 0.0, 0.0, 1.0, 0.0])
        """
        start, end = _point("start", start), _point("end", end)
        return cls.between(start, end, np.linalg.norm(end - start), n_elements, section,
                           law=law, **kwargs)

    @classmethod
    def between(cls, start, end, length, n_elements, section, sag=None, law=None, **kwargs):
        """A cable of unstretched ``length`` from ``start`` to ``end``, whatever their
        distance: stretched straight when ``length`` is at most the distance, else hanging
        as the inextensible catenary of that length through both points, sagging along
        ``sag`` (a start that ``solve_static`` converges from under the weight).

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m), distinct.
        length : float
            Unstretched length (m), > 0: the mesh's arc length.
        n_elements : int
            Number of equal elements, >= 1.
        section : Section
        sag : array_like (3,), optional
            The direction the slack cable sags to (the direction of its weight), not
            parallel to ``end - start``; default ``(0, 0, -1)``.  Not used by a cable that
            is stretched straight.
        law : CableLaw or str
            See ``Cable``.
        **kwargs
            The other parameters of ``Cable`` (``element``, ``quadrature``, ``name``, ...).

        Returns
        -------
        Cable
            Nodes equally spaced in the unstretched arc length; straight: slopes
            ``(end - start) / length`` (``|r_x| >= 1``, the uniform stretch); slack: the
            catenary's unit tangents (and curvatures on an element that has them).

        Examples
        --------
        MoorDyn's pendulum line, 100.5 m long between points 100.499 m apart, and the
        same line stretched between points 101 m apart:

        >>> import numpy as np, skfem_cable as sc
        >>> sec = sc.Section.circular(0.05, 1e9 / (np.pi * 0.05**2), 1000.0)
        >>> slack = sc.Cable.between([0, 0, 0], [10, 0, -100], 100.5, 20, sec, sag=[0, 0, -1])
        >>> slack.length, bool(np.allclose(slack.q0[-6:-3], [10, 0, -100]))
        (100.5, True)
        >>> taut = sc.Cable.between([0, 0, 0], [0, 0, -101], 100.0, 4, sec)
        >>> taut.q0[3:6].tolist()
        [0.0, 0.0, -1.01]
        """
        if not is_count(n_elements):
            raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
        check_memory(int(n_elements))
        start, end = _point("start", start), _point("end", end)
        chord = end - start
        distance = np.linalg.norm(chord)
        if not distance > 0:
            raise ValueError(f"start and end must differ, got {start.tolist()} for both")
        try:
            length = float(length)
        except (TypeError, ValueError):
            length = np.nan
        if not (np.isfinite(length) and length > 0):
            raise ValueError(f"length must be a finite unstretched length > 0 (m), got "
                             f"{length!r}")
        s = np.linspace(0.0, length, int(n_elements) + 1)
        if length <= distance:
            slope = chord / length
            positions = start + s[:, None] * slope
            return cls(MeshLine(s), section, positions, np.tile(slope, (len(s), 1)),
                       law=law, curvatures=np.zeros_like(positions), **kwargs)
        fields = _catenary(chord, length, s, (0.0, 0.0, -1.0) if sag is None else sag)
        positions, slopes, curvatures = fields
        return cls(MeshLine(s), section, start + positions, slopes, law=law,
                   curvatures=curvatures, **kwargs)

    def hanging(self, start, end, sag):
        """Coordinates of this cable hanging from ``start`` to ``end`` as the inextensible
        catenary of its length sagging along ``sag``, the slack shape ``between`` builds
        (``solve_static`` starts from it a cable whose ends are held closer than its
        length); None when the ends are at least its length apart.

        Parameters
        ----------
        start, end : array_like (3,)
            End points (m).
        sag : array_like (3,)
            The direction the cable sags to, not parallel to ``end - start``.

        Returns
        -------
        ndarray (n_dofs,) or None
        """
        start, end = _point("start", start), _point("end", end)
        if not np.linalg.norm(end - start) < self.length:
            return None
        positions, slopes, curvatures = _catenary(end - start, self.length,
                                                  self.mesh.p[0] - self.mesh.p[0, 0], sag)
        fields = self._nodal_fields(start + positions, slopes, curvatures)
        return np.stack(fields, axis=1).ravel()


def _point(name, value):
    """``value`` as an array of 3 finite coordinates; ``ValueError`` naming ``name``
    otherwise."""
    try:
        x = np.asarray(value, float)
    except (TypeError, ValueError):
        x = None
    if x is None or x.shape != (3,) or not np.isfinite(x).all():
        raise ValueError(f"{name} must be 3 finite coordinates (m), got {value!r}")
    return x


def _catenary(chord, length, s, sag):
    """Positions (from the start), unit tangents and their arc-length derivatives at the
    arc lengths ``s`` of the inextensible catenary of ``length`` spanning ``chord`` and
    sagging along ``sag`` (``Cable.between``), each (len(s), 3)."""
    from .catenary import catenary_xz, solve_catenary

    down = _point("sag", sag)
    if not np.linalg.norm(down) > 0:
        raise ValueError(f"sag must be a non-zero direction, got {sag!r}")
    up = -down / np.linalg.norm(down)
    across = chord - (chord @ up) * up
    span = np.linalg.norm(across)
    if not span > 1e-9 * np.linalg.norm(chord):
        raise ValueError(f"sag {np.asarray(sag).tolist()} is parallel to end - start: a "
                         "slack cable needs a sag direction across the line between its "
                         "ends")
    across /= span
    H, VA, _ = solve_catenary(span, chord @ up, length, 1.0)
    xz = catenary_xz(s, H, VA, 1.0)
    V = s - VA
    T = np.hypot(H, V)
    tangent = np.column_stack([H / T, V / T])
    bend = np.column_stack([-H * V / T**3, H**2 / T**3])
    basis = np.stack([across, up])
    return xz @ basis, tangent @ basis, bend @ basis
