"""Tether-tether contact in a sail (issue 49, item 5; ``docs/contact.md``, "Many lines: a
sail's tethers"): the baseline E-sail whose control fails (``failed_sail``: one tether's
voltage off, the spin rate halved, the contact over all its tethers), its tethers'
closest approach (``closest_approach``), and a small sail whose tethers are made to touch
(``crossing_sail``: one tether lowered across its neighbour).
"""

from dataclasses import dataclass, replace

import numpy as np

from ..bodies.cable import Cable
from ..bodies.rigid import RigidBody
from ..bodies.section import Section
from ..model.system import System
from . import esail

#: The capstan's rope (EA = 1e5 N, d = 1 cm, 0.1 kg/m) without its material damping.
ROPE = Section.circular(5e-3, 1.27e9, 1273.0)


@dataclass(frozen=True)
class CrossingRig:
    """The geometry of ``crossing_sail`` (m, s): the hub's radius and height, the tethers'
    length, their strain after the ``ramp``, the arc along tether 2 where tether 1 crosses
    it, the gap there at the start and the drop of tether 1's tip (over 0.3 s after the
    ramp), and the hub's density (kg/m^3: 2.8e6 kg, so that it barely moves)."""

    hub_radius: float = 0.15
    hub_height: float = 0.04
    length: float = 1.0
    strain: float = 0.01
    ramp: float = 0.1
    cross: float = 0.5
    gap: float = 2e-3
    drop: float = 0.02
    hub_density: float = 1e8


def smooth(u):
    """0 before 0, 1 after 1, ``3 u^2 - 2 u^3`` between."""
    u = min(max(u, 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


def _held(rig, root, tip, drop):
    """A tip target: ``tip`` moved away from ``root`` by the rig's strain over its ramp,
    then by ``drop`` (3,) over the next 0.3 s."""
    root, tip, drop = (np.asarray(x, float) for x in (root, tip, drop))

    def target(t):
        return tip + rig.strain * smooth(t / rig.ramp) * (tip - root) \
            + smooth((t - rig.ramp) / 0.3) * drop
    return target


def crossing_sail(n_tethers=4, elements=3, tangent=None, rig=CrossingRig(), section=ROPE):
    """A small sail: ``n_tethers`` tethers (``elements`` each, of ``section``) pinned to
    the rim of a free hub (its axis along x), evenly around it, their tips held and
    stretched.  Tether 1 leaves the hub's top face (x = h/2) towards tether 2 (the next
    around), across it ``rig.cross`` from its root and ``rig.gap`` above touching; its
    tip then drops along -x, pressing it on tether 2.  The contact over all the tethers
    (``system.contact(tethers, tangent=tangent)``).  Returns ``(system, hub, tethers,
    contact)``."""
    R, h, L = rig.hub_radius, rig.hub_height, rig.length
    d = 2 * np.sqrt(section.A / np.pi)
    hub = RigidBody.cylinder(R, h, rig.hub_density)
    zeta = 2 * np.pi * np.arange(n_tethers) / n_tethers
    radial = np.column_stack([np.zeros(n_tethers), np.cos(zeta), np.sin(zeta)])
    anchors = R * radial
    anchors[0, 0] = h / 2
    tips = anchors + L * radial
    cross = R * radial[1] + rig.cross * radial[1]              # on tether 2's line
    along = np.linalg.norm((cross - anchors[0])[1:])
    share = along / L                                          # of tether 1 at the crossing
    tip = anchors[0] + L * np.append(0.0, (cross - anchors[0])[1:] / along)
    tip[0] = h / 2 + (d + rig.gap - h / 2) / share
    tips[0] = anchors[0] + L * (tip - anchors[0]) / np.linalg.norm(tip - anchors[0])
    tethers = [Cable.straight(a, t, elements, section, name=f"tether{k + 1}")
               for k, (a, t) in enumerate(zip(anchors, tips))]
    system = System([hub, *tethers])
    for k, (cable, a, t) in enumerate(zip(tethers, anchors, tips)):
        system.pin(cable.node(0), hub.point(a))
        drop = (-rig.drop / share, 0.0, 0.0) if k == 0 else (0.0, 0.0, 0.0)
        system.pin(cable.node(-1), _held(rig, a, t, drop))
    system.contact(tethers, tangent=tangent)
    return system, hub, tethers, system.loads[-1]


def failed_sail(n_elements=5, alpha_deg=10.0, spin_share=0.5, off=0, **options):
    """The baseline E-sail (``esail.BaselineConfig``, 12 tethers) whose control failed:
    tether ``off``'s voltage switched off and the spin rate ``spin_share`` of the nominal
    (the sail built spinning at it, stretched for it), with the contact over all its
    tethers (``system.contact(scene.tethers, **options)``).  Returns the
    ``esail.ESailScene``."""
    nominal = esail.BaselineConfig()
    voltage = [0.0 if k == off else nominal.voltage for k in range(nominal.n_tethers)]
    config = replace(nominal, spin_rate=spin_share * nominal.spin_rate, voltage=voltage)
    scene = esail.build(config, alpha_deg, n_elements)
    scene.system.contact(scene.tethers, **options)
    return scene


def closest_approach(system, tethers, q):
    """``(distance, i, j)``: the smallest distance (m) between the quadrature points of
    two different ``tethers`` at ``q`` (their first element left out: the hub's
    neighbourhood), and the two tethers."""
    points = []
    for tether in tethers:
        x = tether.line_points(system).at(q)[0]
        points.append(x[1:].reshape(-1, 3))
    best = (np.inf, -1, -1)
    for i in range(len(points)):
        for j in range(i + 1, len(points)):
            gap = np.linalg.norm(points[i][:, None] - points[j][None], axis=2).min()
            best = min(best, (float(gap), i, j))
    return best
