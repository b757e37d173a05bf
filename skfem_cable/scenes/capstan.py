"""The capstan (the ``capstan`` scene of ``skfem-cable run``): a rope over a fixed drum,
held at T1 on one side and pulled on the other until it slides, against Euler-Eytelwein's
``T2 / T1 = exp(mu theta)`` (``docs/contact.md``).

The rope (axial law only, EA = 1e5 N, 0.1 kg/m, d = 1 cm) goes over the top of a fixed
cylinder (R = 0.5 m, wrap angle pi).  Its left end is pulled down by T1 = 100 N (ramped
in over 0.05 s); a pin holds its right end, then pulls it down at V = 0.1 m/s (ramped
in over 0.05 s).  Friction regularised in the slip velocity (``eps`` = 1 mm/s) carries
nothing at rest, so the rope is made to slide (``V / eps = 100``: the friction is
``1 - 5e-5`` of Coulomb's), and the tensions are read in steady sliding, averaged over
the last 0.1 s (the elements passing over the drum ripple them by about 1 %).
"""

import numpy as np
from skfem import MeshLine

from ..bodies.cable import Cable
from ..bodies.section import Section
from ..loads.surfaces import Cylinder
from ..model.system import System
from ..runner.drive import RunScene

R, LEG, T1, V, RAMP = 0.5, 0.3, 100.0, 0.1, 0.05
ROPE = Section.circular(5e-3, 1.27e9, 1273.0, gamma_axial=1e-4)  # EA 1e5 N, 0.1 kg/m
DRUM = Cylinder([0, 0, 0], [0, 0, 1], R)


def smooth(t):
    """0 before 0, 1 after 1, ``3 t^2 - 2 t^3`` between."""
    t = min(max(t, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def wrapped(radius, leg, n_arc, n_leg, section=ROPE, law="truss"):
    """A cable over the top of a cylinder of axis z (through the origin): left leg up,
    a half circle of ``radius``, right leg down; nodes at the tangent points."""
    arc = np.pi * radius
    s = np.concatenate([np.linspace(0, leg, n_leg + 1)[:-1],
                        leg + np.linspace(0, arc, n_arc + 1)[:-1],
                        leg + arc + np.linspace(0, leg, n_leg + 1)])
    phi = np.clip((s - leg) / radius, 0, np.pi)
    left, right = s < leg, s > leg + arc
    x = np.where(left, -radius, np.where(right, radius, -radius * np.cos(phi)))
    y = np.where(left, s - leg, np.where(right, leg + arc - s, radius * np.sin(phi)))
    tx = np.where(left | right, 0.0, np.sin(phi))
    ty = np.where(left, 1.0, np.where(right, -1.0, np.cos(phi)))
    return Cable(MeshLine(s), section, np.stack([x, y, 0 * x], 1),
                    np.stack([tx, ty, 0 * x], 1), law=law)


def capstan(mu, speed=V, cable=None):
    """The capstan rig (module notes) on ``cable`` (default a new one): ``(system,
    cable, contact)``; ``speed = 0``: the pin holds, and T1 is constant."""
    radius = R + 5e-3 + 1e-5          # the rope's axis, 10 um off the drum at the start
    cable = wrapped(radius, LEG, 24, 4) if cable is None else cable

    def pull(t):
        u = t - RAMP                  # the pull starts when T1 is in
        d = 0.0 if u <= 0 else speed * (u - RAMP / 2) if u > RAMP else \
            speed * u**3 / RAMP**2 * (1 - u / (2 * RAMP))
        return np.array([radius, -LEG - d, 0.0])

    system = (System([cable]).pin(cable.node(-1), pull)
              .add_point_load(cable.node(0), lambda t: [0.0, -T1 * smooth(t / RAMP), 0.0]
                              if speed else [0.0, -T1, 0.0])
              .contact(cable, DRUM, friction=mu, slip_velocity=1e-3))
    return system, cable, system.loads[-1]


def leg_tensions(result, cable, since):
    """The tensions (N) in the middle of the left and right legs, averaged over the saved
    steps from ``since``."""
    states = [result.state(i) for i in range(len(result)) if result.t[i] >= since - 1e-12]
    left = np.mean([s.tension(cable, LEG / 2) for s in states])
    right = np.mean([s.tension(cable, cable.length - LEG / 2) for s in states])
    return left, right


def outputs(cable, mu, since):
    """The scene's key numbers of a result: the legs' tensions from ``since`` and their
    ratio against ``exp(mu pi)``."""

    def numbers(result):
        left, right = leg_tensions(result, cable, since)
        return {"T1_N": left, "T2_N": right, "ratio": right / left,
                "exp_mu_pi": float(np.exp(mu * np.pi))}

    return numbers


def scene(mu=0.3, t_end=0.35, dt=1e-3, every=2):
    """The ``capstan`` scene with friction ``mu``, run to ``t_end``; its outputs are the
    legs' tensions averaged over the last 0.1 s."""
    system, cable, _ = capstan(mu)
    return RunScene("capstan", system, None, {"t_end": t_end, "dt": dt, "every": every},
                    {"mu": mu, "radius": R, "T1": T1, "speed": V},
                    outputs=outputs(cable, mu, t_end - 0.1))


def run(options):
    """``skfem-cable run capstan``: the rope sliding over the drum with ``mu = 0.3``."""
    return scene().run(options)
