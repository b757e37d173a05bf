"""Sensors: what a controller measures, as functions of a ``State`` (``control``).

Each reads the state's coordinates ``q`` (and velocities ``v``) through the bodies'
own maps, in the system's axes:

* ``spin_rate(state, hub)``: the hub's angular velocity about its axis (rad/s);
* ``sail_normal(state, tips)``: the normal of the least-squares plane of the remote units
  (the E-sail paper's Sect. 3, Eqs. 67-70), oriented along the spin;
* ``sail_angle(state, tips, sun_direction)``: the angle between that normal and the
  direction of the wind;
* ``sail_spin_rate(state, tips, hub=None)``: the remote units' mean angular rate about
  the sail's normal (``mean_spin_rate``: the sail's spin without the hub's libration);
* ``tether_arms(state, cables, hub)``: the vectors from the hub's centre to the tethers'
  tips;
* ``tether_phase(state, cable, hub)``: the angle of a tether's tip about the hub's axis,
  from the hub's second axis (its rotation phase);
* ``libration(state, cable, orbit)``: pitch and roll of the line through a cable's ends
  in the orbiting frame;
* ``reel_length(state, reel)``: a reel's free length and its rate (its encoder);
* ``noisy(sensor, sigma, seed)``: a sensor with Gaussian noise of standard deviation
  ``sigma`` that is the same in every run with the same ``seed`` (drawn per call from
  ``seed`` and the call's time, so a continued run reads the same noise).
"""

import functools

import numpy as np

from ..core.node import Node


def _hub_frame(state, hub):
    """``(d, v)``: the hub's coordinates and velocities in ``state``."""
    dofs = _body_index(state.system.layout, hub)
    v = np.zeros(len(dofs)) if state.v is None else state.v[dofs]
    return state.q[dofs], v


@functools.lru_cache(maxsize=256)
def _centre_coefficients(hub):
    """The coefficients (4,) of the hub's centre of mass in its natural coordinates
    (``RigidBody.coefficients``; its geometry does not change)."""
    return hub.coefficients(hub.center_of_mass)


@functools.lru_cache(maxsize=256)
def _body_index(layout, body):
    """The coordinates of ``body`` in the system of ``layout`` (looked up once)."""
    return layout.system.dofs(body)


def spin_rate(state, hub):
    """The hub's angular velocity about its first body axis (rad/s; the E-sail's spin
    axis ``x_B``)."""
    d, v = _hub_frame(state, hub)
    return float(hub.angular_velocity(d, v)[0])


def _point(state, node):
    """The position (3,) of a cable ``Node`` in ``state``: its position coordinates (no
    interpolation: a sensor is read at every sample)."""
    return state.q[state.system.dofs(node)[:3]]


def _tips(state, points):
    """The positions (k, 3) of tips: the cables' last nodes, or the ``Node``s given."""
    return state.q[_tip_index(state.system.layout, tuple(points))]


@functools.lru_cache(maxsize=256)
def _tip_index(layout, points):
    """The coordinates (k, 3) of the tips ``points`` in the system of ``layout``, looked
    up once per layout (a system edited since has a new one)."""
    system = layout.system
    return np.array([system.dofs(p if isinstance(p, Node) else p.node(-1))[:3]
                     for p in points])


def sail_normal(state, tips, hub=None):
    """Unit normal (3,) of the least-squares plane of the ``tips`` (cables, whose ends are
    the remote units, or their end ``Node``s): the right singular vector of least
    singular value of the tips about their centre (Eqs. 67-70).  Oriented along the
    spin axis of ``hub`` when given, else so that the tips turn counter-clockwise about
    it."""
    points = _tips(state, tips)
    centre = points.mean(axis=0)
    normal = np.linalg.svd(points - centre)[2][-1]
    if hub is not None:
        axis = hub.rotation(_hub_frame(state, hub)[0])[:, 0]
    else:
        axis = np.cross(points[0] - centre, points[1] - centre)
    return normal if normal @ axis >= 0 else -normal


def sail_angle(state, tips, sun_direction, hub=None):
    """Angle (rad) between the sail's normal (``sail_normal``) and ``sun_direction``, the
    direction the wind blows along (from the Sun outwards)."""
    normal = sail_normal(state, tips, hub)
    wind = np.asarray(sun_direction, dtype=float)
    cos = normal @ wind / np.linalg.norm(wind)
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def mean_spin_rate(arms, velocities, normal):
    """The points' mean angular rate (rad/s) about ``normal`` (..., 3), from their
    positions relative to their centre ``arms`` and their velocities (..., p, 3): the
    spin of the sail's remote units, without the hub's libration against the tethers
    (``esail.outputs``' ``spin_rate``; leading axes: e.g. time)."""
    relative = velocities - velocities.mean(axis=-2, keepdims=True)
    radial = arms - np.einsum("...pi,...i->...p", arms, normal)[..., None] \
        * normal[..., None, :]
    rate = np.einsum("...pi,...i->...p", np.cross(radial, relative), normal)
    return (rate / np.einsum("...pi,...pi->...p", radial, radial)).mean(axis=-1)


def sail_spin_rate(state, tips, hub=None):
    """The sail's spin rate (rad/s): the mean angular rate of the ``tips`` (cables, whose
    ends are the remote units, or their end ``Node``s) about the sail's normal
    (``sail_normal``, oriented by ``hub``), relative to their centre
    (``mean_spin_rate``)."""
    points = _tips(state, tips)
    index = _tip_index(state.system.layout, tuple(tips))
    velocities = np.zeros_like(points) if state.v is None else state.v[index]
    normal = sail_normal(state, tips, hub)
    return float(mean_spin_rate(points - points.mean(axis=0), velocities, normal))


def tether_arms(state, cables, hub):
    """The vectors (k, 3) from the hub's centre of mass to the tips of ``cables`` (their
    last nodes)."""
    d, _ = _hub_frame(state, hub)
    return _tips(state, cables) - _centre_coefficients(hub) @ d.reshape(4, 3)


def tether_phase(state, cable, hub):
    """Rotation phase (rad, in ``(-pi, pi]``) of the tip of ``cable`` about the hub's
    spin axis ``x_B``, measured from its axis ``y_B`` towards ``z_B``; for a sequence of
    cables, their phases (an array)."""
    axes = hub.rotation(_hub_frame(state, hub)[0])
    single = not isinstance(cable, (list, tuple))
    arms = tether_arms(state, [cable] if single else cable, hub)
    phase = np.arctan2(arms @ axes[:, 2], arms @ axes[:, 1])
    return float(phase[0]) if single else phase


def libration(state, cable, orbit):
    """Pitch and roll (rad) of the line from the first to the last node of ``cable`` in
    the orbiting frame of ``orbit`` at the state's time: pitch in the orbit plane from
    the local vertical, roll out of it."""
    axis = _tips(state, [cable])[0] - _point(state, cable.node(0))
    y = orbit.to_lvlh(float(state.t), axis)
    return float(np.arctan2(y[1], y[0])), float(np.arcsin(-y[2] / np.linalg.norm(y)))


def reel_length(state, reel):
    """``(length, rate)``: the free length (m) a ``Reel`` has paid out and its rate (m/s;
    0 in a state without velocities)."""
    i = _body_index(state.system.layout, reel)[0]
    return float(state.q[i]), 0.0 if state.v is None else float(state.v[i])


def noisy(sensor, sigma, seed):
    """``sensor`` with additive Gaussian noise of standard deviation ``sigma`` (its units),
    reproducible: the noise of a call at time ``t`` is drawn from ``(seed, t)``, so every
    run (and a continued one) reads the same values at the same times."""
    if not (np.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be a finite number >= 0, got {sigma!r}")

    def read(state, *args, **kwargs):
        value = np.asarray(sensor(state, *args, **kwargs), dtype=float)
        key = np.frombuffer(np.float64(state.t).tobytes(), dtype=np.uint32)
        rng = np.random.default_rng([int(seed), *map(int, key)])
        noise = sigma * rng.standard_normal(value.shape)
        out = value + noise
        return float(out) if out.ndim == 0 else out

    read.__name__ = f"noisy_{getattr(sensor, '__name__', 'sensor')}"
    return read
