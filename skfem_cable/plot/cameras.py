"""Cameras of the 3-D renders: the views by name (``VIEWS``), and the camera a scene
chooses for itself (``scene_camera``): up against gravity; along or across the spin axis of
a spinning scene (``spin_axis``); face on for a planar scene (``plane_normal``).

Numbers only (numpy): the renders (``plot.renders``) and the figures (``cable_histories``
asks ``spin_axis`` whether a run spins) use them.
"""

from collections import namedtuple

import numpy as np

from ..loads.gravity import Gravity

#: Views of ``render`` and ``animate`` (see ``view_camera``).
VIEWS = ("auto", "isometric", "xy", "xz", "yz", "orbital", "gravity", "axial", "side")

#: A camera: unit vectors from the focal point towards the eye, and up on the screen.
Camera = namedtuple("Camera", "eye up")


def gravity_vector(system):
    """Sum of the ``loads.Gravity`` loads of ``system`` (m/s^2); zeros without gravity."""
    return sum((load.g for load in system.loads if isinstance(load, Gravity)), np.zeros(3))


def spin_axis(system, q, v, share=0.5):
    """Unit vector along the angular momentum about the centroid of the positions when
    the motion is a spin, else None.

    It is a spin when the angular momenta of the coordinate blocks (position or slope
    times momentum) add up to at least ``share`` of the sum of their norms: a rigid
    rotation (the E-sail) passes, a state at rest or without a common axis does not.
    """
    if v is None:
        return None
    pos = system.vector_is_position
    blocks = np.asarray(q, dtype=float)[system.vectors]
    rel = np.where(pos[:, None], blocks - blocks[pos].mean(axis=0), blocks)
    momenta = np.cross(rel, (system.layout.mass @ np.asarray(v, dtype=float))[system.vectors])
    total = momenta.sum(axis=0)
    size = np.linalg.norm(total)
    if size == 0 or size < share * np.linalg.norm(momenta, axis=1).sum():
        return None
    return total / size


def scene_camera(system, q, v=None, view=None, sun=None, points=None):
    """The camera of ``view_camera`` for configurations of ``system``: its gravity
    (``gravity_vector``) and spin axis (``spin_axis`` of ``q``, ``v``; the first row when
    they are 2-D, e.g. a run's) decide the automatic view.

    Parameters
    ----------
    system : System
    q, v : ndarray (n_dofs,) or (n_frames, n_dofs)
        Coordinates and velocities (``v`` None: at rest).
    view, sun
        As in ``view_camera``.
    points : ndarray (..., 3), optional
        The points to frame (default: the position coordinates of ``q``).

    Returns
    -------
    Camera
    """
    q = np.atleast_2d(q)
    if points is None:
        points = q[:, system.vectors[system.vector_is_position]]
    g = gravity_vector(system)
    axis = spin_axis(system, q[0], None if v is None else np.atleast_2d(v)[0])
    return view_camera(view, points, gravity=g if np.any(g) else None, spin=axis, sun=sun,
                       plane=plane_normal(points))


def plane_normal(points, rtol=1e-6):
    """Unit normal of the plane ``points`` (..., 3) lie in, or None when they do not lie
    in one plane or lie on a line (their thickness across it, or their width, is more,
    or not more, than ``rtol`` times their extent)."""
    points = np.reshape(points, (-1, 3))
    rel = points - points.mean(axis=0)
    if len(rel) < 3:
        return None
    _, sizes, axes = np.linalg.svd(rel, full_matrices=False)
    if not sizes[0] > 0 or sizes[2] > rtol * sizes[0] or sizes[1] <= rtol * sizes[0]:
        return None
    return axes[2] * np.sign(axes[2][np.argmax(np.abs(axes[2]))])


def view_camera(view, points, gravity=None, spin=None, sun=None, plane=None):
    """Camera of a named view of ``points``.

    Parameters
    ----------
    view : str or None
        One of ``VIEWS``.  ``None`` or ``"auto"``: ``"gravity"`` with gravity, else
        ``"axial"`` with a spin axis, else looking along the normal ``plane`` of planar
        points (``plane_camera``), else ``"isometric"``.  ``"gravity"``: up is
        ``-gravity``, looking horizontally across the points' main horizontal extent,
        which runs left to right.  ``"axial"``: looking down the spin axis (the spin turns
        anticlockwise on the screen), the Sun's direction (else a coordinate axis)
        up.  ``"side"``: the spin axis up, looking perpendicular to it and to the Sun's
        direction (the Sun on the left).  ``"isometric"`` (z up) and ``"xy"``, ``"xz"``,
        ``"yz"`` (looking along the third axis) are pyvista's.  ``"orbital"``: the
        orbiting frame's view, ``x`` (radial) up, ``y`` (along-track) to the right,
        looking along ``z`` (the orbit normal).
    points : ndarray (..., 3)
    gravity, spin, sun : array_like (3,), optional
        Gravity (m/s^2), the unit spin axis and the direction towards the Sun.
    plane : array_like (3,), optional
        Unit normal of the plane of planar points (``plane_normal``).

    Returns
    -------
    Camera
        Its ``up`` is perpendicular to its ``eye``.
    """
    view = "auto" if view is None else view
    if view not in VIEWS:
        raise ValueError(f"view must be one of {VIEWS}, got {view!r}")
    if view == "auto" and gravity is None and spin is None and plane is not None:
        return plane_camera(plane)
    if view == "auto":
        view = "gravity" if gravity is not None else "axial" if spin is not None else "isometric"
    if view == "gravity":
        if gravity is None:
            raise ValueError("the 'gravity' view needs a scene with gravity")
        return _gravity_camera(np.reshape(points, (-1, 3)), -_unit(gravity))
    if view in ("axial", "side"):
        if spin is None:
            raise ValueError(f"the {view!r} view needs a spinning scene")
        axis = _unit(spin)
        across = _perpendicular(axis, sun)
        if view == "axial":
            return Camera(axis, across)
        return Camera(np.cross(axis, across), axis)
    eye, up = _FIXED_VIEWS[view]
    return Camera(_unit(eye), _perpendicular(_unit(eye), up))


def plane_camera(normal):
    """Looking along the unit ``normal`` of a planar scene, with up the in-plane part of
    ``z`` (of ``y`` when the plane is nearly horizontal: an ``xy`` scene is drawn as
    ``"xy"`` draws it)."""
    normal = _unit(normal)
    hint = (0.0, 1.0, 0.0) if abs(normal[2]) > 0.9 else (0.0, 0.0, 1.0)
    return Camera(normal, _perpendicular(normal, hint))


#: ``(eye, up)`` of pyvista's fixed views.
_FIXED_VIEWS = {"isometric": ((1, 1, 1), (0, 0, 1)), "xy": ((0, 0, 1), (0, 1, 0)),
                "xz": ((0, -1, 0), (0, 0, 1)), "yz": ((1, 0, 0), (0, 0, 1)),
                "orbital": ((0, 0, -1), (1, 0, 0))}


def _unit(x):
    x = np.asarray(x, dtype=float)
    return x / np.linalg.norm(x)


def _perpendicular(a, hint=None):
    """Unit vector perpendicular to the unit vector ``a``: the part of ``hint`` normal to
    ``a`` when there is one, else that of the coordinate axis least aligned with ``a``."""
    candidates = [] if hint is None else [_unit(hint)]
    for h in candidates + [np.eye(3)[np.argmin(np.abs(a))]]:
        normal = h - (h @ a) * a
        if np.linalg.norm(normal) > 1e-6:
            return _unit(normal)
    raise AssertionError("unreachable: a coordinate axis is never parallel to all of a")


def _gravity_camera(points, up):
    """Up ``up``, looking horizontally with the main horizontal extent of ``points`` (its
    first principal direction) running left to right, towards its positive side."""
    rel = points - points.mean(axis=0)
    horizontal = rel - np.outer(rel @ up, up)
    right = np.linalg.svd(horizontal, full_matrices=False)[2][0]
    right -= (right @ up) * up
    if np.linalg.norm(right) < 1e-6 or not np.any(horizontal):  # a vertical line
        right = _perpendicular(up)
    right = _unit(right)
    right *= np.sign(right[np.argmax(np.abs(right))])
    return Camera(np.cross(right, up), up)
