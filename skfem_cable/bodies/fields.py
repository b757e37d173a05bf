"""The fields of a cable at arc lengths: position, slopes, strain, tension and curvature,
from its element type's functions (``elements``) and its formulation's recovery
(``formulation``).  ``CableFields`` is the part of ``Cable`` that reads them; it needs the
cable's ``mesh``, ``h``, ``length``, ``n_elements``, ``element``, ``element_dofs``,
``law``, ``section``, ``formulation`` and ``_shape``."""

import numpy as np

from ..core.contract import PART_CABLE, Shape
from ..laws import SLOPE_FLOOR
from .formulation import FORMULATIONS
from .section import positive_int


class CableFields:
    """The fields of a cable at arc lengths ``s`` (module docstring), and what the cable
    shows (``show``) and reports (``outputs``) of them (the hooks of ``contract.Body``)."""

    def sample(self, q, v=None, points_per_element=8, stretch=1.0, t=0.0):
        """Fields at ``points_per_element`` equally spaced points of each element.

        Parameters
        ----------
        q, v : ndarray (n_dofs,)
            The cable's coordinates and velocities (``v`` None: zero velocity).
        points_per_element : int
            Samples per element, the element's first node included; consecutive elements
            share their common node, so there are ``n_elements * points_per_element + 1``
            points.
        stretch : float
            Mesh stretch of a deploying cable (``System.stretch``): its fields are
            derivatives in the material arc length ``arc_length = stretch x``.

        Returns
        -------
        dict
            ``arc_length`` and ``element_id`` (npts,), ``position`` and ``velocity``
            (npts, 3), ``tension`` (N), ``axial_strain`` (Green strain) and ``curvature``
            (1/m), each (npts,).
        """
        m = positive_int("points_per_element", points_per_element)
        x = self.mesh.p[0]
        ne = self.n_elements
        s = np.append((x[:-1, None] + self.h[:, None] * (np.arange(m) / m)).ravel(), x[-1])
        velocity = np.zeros((len(s), 3)) if v is None else self.interpolate(v, s)[0]
        return {"arc_length": stretch * s,
                "element_id": np.append(np.repeat(np.arange(ne), m), ne - 1),
                "position": self.interpolate(q, s)[0],
                "velocity": velocity,
                "tension": self.tension(q, s, stretch, t),
                "axial_strain": self.strain(q, s, stretch),
                "curvature": self.curvature(q, s, stretch)}

    def show(self, system, q, v, t, points_per_element=8, **detail):
        """``Body.show``: the curve sampled at ``points_per_element`` points per element
        (``sample``), ``line`` cells, with its fields as point data."""
        dofs = system.dofs(self)
        f = self.sample(q[dofs], v[dofs], points_per_element, system.stretch(self, t, q), t)
        n = len(f["arc_length"])
        return Shape(f.pop("position"), f.pop("velocity"), "line",
                     np.column_stack([np.arange(n - 1), np.arange(1, n)]), PART_CABLE, f)

    def outputs(self, system, q, t):
        """``Body.outputs``: tip position, root and peak tension (at the nodes), (free)
        length and number of elements."""
        qc, stretch = q[system.dofs(self)], system.stretch(self, t, q)
        tension = self.tension(qc, self.mesh.p[0], stretch, t)
        return {"tip_position": self.interpolate(qc, self.length)[0],
                "root_tension": tension[0], "max_tension": tension.max(),
                "length": self.length * stretch, "elements": self.n_elements}

    def locate(self, s):
        """Element index and reference coordinate of arc lengths ``s``."""
        s = np.asarray(s, dtype=float)
        x = self.mesh.p[0]
        if np.any(s < x[0] - 1e-12 * self.length) or np.any(s > x[-1] + 1e-12 * self.length):
            raise ValueError(f"arc length s must lie in [{x[0]}, {x[-1]}]")
        e = np.clip(np.searchsorted(x, s, side="right") - 1, 0, self.n_elements - 1)
        return e, (s - x[e]) / self.h[e]

    def interpolate(self, q, s):
        """Position ``r``, slope ``r_x`` and ``r_xx`` at arc lengths ``s``.

        ``q`` may carry leading dimensions (e.g. time): shape ``(..., n_dofs)``; results
        have shape ``(...,) + s.shape + (3,)``.
        """
        return self._fields(q, *self.locate(s))

    def _fields(self, q, e, xi, stretch=1.0):
        """``r``, ``r_s``, ``r_ss`` in elements ``e`` at reference coordinates ``xi``:
        derivatives in the material arc length ``s = stretch x`` of a mesh stretched by
        ``stretch`` (scalar, or one value per leading index of ``q``; 1 unless the cable
        is deploying, see ``deploy``)."""
        S = self.element.remembered_shape(xi, self.h[e])
        qe = self.element_vectors(q, e)
        r, a, b = (np.einsum("A...,...Ai->...i", Sk, qe) for Sk in S)
        lam = np.reshape(stretch, np.shape(stretch) + (1,) * (np.ndim(e) + 1))
        return r, a / lam, b / lam**2

    def slopes_at(self, q, xi, stretch=1.0):
        """``r_s`` at the reference coordinates ``xi`` (nx,) of every element: (...,
        n_elements, nx, 3) for coordinates ``q`` (..., n_dofs) (``_fields``)."""
        Sx = self._shape(xi)[1]
        lam = np.reshape(stretch, np.shape(stretch) + (1, 1, 1))
        return np.einsum("eXA,...eAi->...eXi", Sx, self.element_vectors(q)) / lam

    def element_vectors(self, q, e=slice(None)):
        """The element's nodal 3-vectors ``(..., n_elements, n_functions, 3)`` of the
        coordinates ``q`` (..., n_dofs) of this cable, in elements ``e`` (any index of
        the elements; all by default): what the tables ``S``, ``Sx``, ``Sxx`` weight."""
        q = np.asarray(q)
        dofs = self.element_dofs[e]
        return q[..., dofs].reshape(q.shape[:-1] + dofs.shape[:-1]
                                    + (self.element.n_functions, 3))

    def green(self, q, e, xi, stretch=1.0):
        """Green strain ``(|r_x|^2 - 1)/2`` of the cubic field in elements ``e`` at
        reference coordinates ``xi`` (``_fields``)."""
        a = self._fields(q, e, xi, stretch)[1]
        return 0.5 * (np.einsum("...i,...i", a, a) - 1.0)

    def strain(self, q, s, stretch=1.0):
        """Green axial strain ``eps = (|r_x|^2 - 1)/2`` (Eq. 24) at arc lengths ``s``, as
        the cable's formulation defines it (``formulation``): the assumed strain by
        default, recovered from the Lobatto points on a ``"lobatto"`` cable, the raw strain
        of the cubic field on a ``"paper"`` cable.  ``stretch``: the mesh stretch of a
        deploying cable (``_fields``)."""
        return FORMULATIONS[self.formulation].strain(self, q, s, stretch)

    def tension(self, q, s, stretch=1.0, t=0.0):
        """Axial force in the section (N) at arc lengths ``s``, the elastic part (at rest).

        The axial force of a law ``W(a, b)`` is ``N = t . W_a + t' . W_b`` with ``t =
        r_x/|r_x|`` (``section_force``), the axial component of its section force.  For
        the built-in law it is ``EA eps |r_x| - EI kappa^2 / |r_x|``: the Green-strain
        force (``dW/d|r_x|``; the second Piola-Kirchhoff force ``EA eps`` differs by the
        factor ``|r_x|``) and the axial part of the bending section force (zero for a
        truss and negligible for taut tethers).

        The axial part comes from the strain the formulation integrates (``formulation``):
        by default the assumed strain, a continuous field accurate to the discretisation
        (an elastica of 16 elements matches the exact ``P sin(theta)`` to better than 1 %
        of ``P``, root included); on a ``"lobatto"`` cable the values at the nodes and
        midpoints, interpolated; on a ``"paper"`` cable the raw strain of the cubic field,
        which membrane locking makes useless in bending (stripes of tens of times the
        load).  ``stretch``: the mesh stretch of a deploying cable (``_fields``); ``t``:
        the time (s; scalar, or one per leading index of ``q``), which only a law whose
        parameters vary in time reads (``CableLaw.values_at``).
        """
        return FORMULATIONS[self.formulation].tension(self, q, s, stretch, t)

    def section_force(self, q, e, xi, stretch=1.0, law=None, t=0.0):
        """``N = t . W_a + t' . W_b`` of ``law`` (default the cable's) evaluated on the
        cubic field in elements ``e`` at reference coordinates ``xi``: the axial component
        ``t . (W_a - (W_b)')`` of the law's section force, exact when ``W`` depends on
        ``b`` only through its part normal to ``a`` (the curvature), as every law of the
        gallery does."""
        _, a, b = self._fields(q, e, xi, stretch)
        x = np.moveaxis(np.concatenate([a, b], axis=-1), -1, 0)
        lam = np.reshape(stretch, np.shape(stretch) + (1,) * np.ndim(e))
        h = np.broadcast_to(self.h[e] * lam, x.shape[1:])
        G = self.gradient(x, np.zeros_like(x), h, law, t)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        lam = np.sqrt(p)[..., None]
        t = a / lam
        t_x = (b - np.einsum("...i,...i", t, b)[..., None] * t) / lam
        return (np.einsum("...i,i...->...", t, G[:3])
                + np.einsum("...i,i...->...", t_x, G[3:]))

    def densities(self, x, xd, h, law=None, t=0.0):
        """The densities of ``law`` (default the cable's) at points ``x = (a, b)``, ``xd``
        (6, ...) of elements of length ``h`` (...) at time ``t`` (scalar, or an array that
        leads the points' shape) (its generated ``numpy_point``): energy
        ``ea``/``eb`` and power ``pa``/``pb`` (axial, bending), ``G = W_x + D_xd`` and
        ``Gd = D_xd`` (6, ...), ``H = W_xx + D_xd,x`` and ``Hc = D_xd,xd`` (6, 6, ...)."""
        out = self._vectorised("numpy_point", x, xd, h, law, t)
        out["G"] = np.stack([out.pop(f"G_{i}") for i in range(6)])
        out["Gd"] = np.stack([out.pop(f"Gd_{i}") for i in range(6)])
        for k in ("H", "Hc"):
            out[k] = np.stack([[out.pop(f"{k}_{i}_{j}") for j in range(6)] for i in range(6)])
        return out

    def gradient(self, x, xd, h, law=None, t=0.0):
        """``G = W_x + D_xd`` (6, ...) of ``law`` (default the cable's) alone, as in
        ``densities`` (its generated ``numpy_gradient``: the same arithmetic, without the
        Hessians)."""
        return self._vectorised("numpy_gradient", x, xd, h, law, t)

    def _vectorised(self, name, x, xd, h, law, t):
        """The generated vectorised function ``name`` of ``law`` (default the cable's) at
        ``x``, ``xd``, ``h`` with the law's values at ``t``."""
        law = self.law if law is None else law
        return getattr(law.compiled(), name)(x, xd, law.values_at(self.section, t, x.ndim - 1),
                                             h)

    def curvature(self, q, s, stretch=1.0):
        """Curvature ``kappa = |r_x x r_xx| / |r_x|^3`` (Eq. 24), 1/m; ``stretch``: the
        mesh stretch of a deploying cable (``_fields``)."""
        _, a, b = self._fields(q, *self.locate(s), stretch)
        p = np.maximum(np.einsum("...i,...i", a, a), SLOPE_FLOOR)
        return np.sqrt(_kappa2(a, b, p))


def _kappa2(a, b, p):
    return np.einsum("...i,...i", np.cross(a, b), np.cross(a, b)) / p**3
