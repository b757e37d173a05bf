"""Classic cable problems with known answers, used by tests, demos, benchmarks and the CLI.

Each builder returns a ``Scene``: the system, the cable and an initial ``State`` (with
velocities) for ``simulate``.
"""

from dataclasses import dataclass

import numpy as np
from skfem import MeshLine

from ..bodies.cable import Cable
from ..bodies.section import Section
from ..elements import DEFAULT_ELEMENT
from ..model.state import State
from ..model.system import System


@dataclass
class Scene:
    """A system, its (main) cable and an initial state."""

    system: System
    cable: Cable
    initial: State


def _at_rest(system, q):
    return State(system, q, v=np.zeros(system.n_dofs))


#: Section of the elastica cantilever: ``EA L^2 / EI = 1e7`` for ``L = 1 m`` (inextensible
#: within 1e-7 of the tip load).
ELASTICA_SECTION = Section(E=1e9, A=1e-4, I=1e-11, rho=7850.0)


def cantilever(n_elements=16, k=5.0, length=1.0, section=ELASTICA_SECTION, formulation=None,
               element=None):
    """Cantilever along x clamped at the origin (position and slope direction) with a
    transverse dead load ``P = k EI / L^2`` along -y at its tip (the elastica).
    ``formulation``, ``element``: see ``Cable`` (None: the defaults)."""
    cable = Cable.straight([0, 0, 0], [length, 0, 0], n_elements, section,
                           formulation=formulation, element=element or DEFAULT_ELEMENT)
    system = System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * section.EI / length**2, 0])
    return Scene(system, cable, _at_rest(system, cable.q0.copy()))


def pendulum(n_elements=16, length=1.2, radius=0.01, E=7e10, rho=7800.0, g=9.81,
             kind=None, formulation=None, element=None, **damping):
    """Flexible pendulum: a cable pinned (spherical joint) at the origin, released at rest
    from horizontal (along +x) under gravity along -y.  ``kind`` (the law),
    ``formulation``, ``element``: see ``Cable`` (None: the defaults)."""
    sec = Section.circular(radius=radius, E=E, rho=rho, **damping)
    cable = Cable.straight([0, 0, 0], [length, 0, 0], n_elements, sec, law=kind,
                           formulation=formulation, element=element or DEFAULT_ELEMENT)
    system = System([cable]).pin(cable.node(0)).add_gravity([0, -g, 0])
    return Scene(system, cable, _at_rest(system, cable.q0.copy()))


def stretched_bar(n_elements=16, length=1.0, radius=0.005, E=2e11, rho=7800.0, strain=1e-5,
                  mode=None, **damping):
    """Fixed-free bar along x clamped at ``x = 0``, released at rest from a uniform
    stretch ``strain`` (``mode=None``) or from the first axial mode shape
    ``u = strain L (2/pi) sin(pi x / 2L)`` (``mode=1``)."""
    sec = Section.circular(radius=radius, E=E, rho=rho, **damping)
    cable = Cable.straight([0, 0, 0], [length, 0, 0], n_elements, sec)
    system = System([cable]).clamp(cable.node(0))
    s = cable.mesh.p[0]
    q = cable.q0.reshape(-1, 2, 3).copy()
    if mode is None:
        q[:, 0, 0] = (1 + strain) * s
        q[:, 1, 0] = 1 + strain
    elif mode == 1:
        k = np.pi / (2 * length)
        q[:, 0, 0] = s + strain / k * np.sin(k * s)
        q[:, 1, 0] = 1 + strain * np.cos(k * s)
    else:
        raise ValueError(f"mode must be None or 1, got {mode!r}")
    return Scene(system, cable, _at_rest(system, q.ravel()))


def taut_string(n_elements=16, length=1.0, radius=0.001, E=2e11, rho=7800.0, strain=1e-3,
                amplitude=1e-4, kind="truss"):
    """Cable pinned at both ends after a uniform stretch ``strain`` (Green strain
    ``((1+strain)^2 - 1)/2``), released at rest from the first string mode of
    ``amplitude`` (m)."""
    sec = Section.circular(radius=radius, E=E, rho=rho)
    mesh = MeshLine(np.linspace(0.0, length, n_elements + 1))
    s = mesh.p[0]
    k = np.pi / length
    pos = np.column_stack([(1 + strain) * s, amplitude * np.sin(k * s), 0 * s])
    slopes = np.column_stack([(1 + strain) + 0 * s, amplitude * k * np.cos(k * s), 0 * s])
    cable = Cable(mesh, sec, pos, slopes, law=kind)
    system = System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    return Scene(system, cable, _at_rest(system, cable.q0.copy()))


def spinning_tether(n_elements=10, length=10.0, radius=5e-4, E=7e10, rho=2700.0,
                    tip_mass=0.5, spin=2.0, kind=None, formulation=None, element=None,
                    **damping):
    """Tether pinned at the origin, spinning rigidly about z at ``spin`` (rad/s) with a
    point mass at its tip: centrifugally stiffened, large rotations.  ``kind`` (the law),
    ``formulation``, ``element``: see ``Cable`` (None: the defaults)."""
    sec = Section.circular(radius=radius, E=E, rho=rho, **damping)
    cable = Cable.straight([0, 0, 0], [length, 0, 0], n_elements, sec, law=kind,
                           formulation=formulation, element=element or DEFAULT_ELEMENT)
    system = System([cable]).pin(cable.node(0)).add_point_mass(cable.node(-1), tip_mass)
    v = system.rigid_motion_velocity(cable.q0, [0.0, 0.0, spin])
    return Scene(system, cable, State(system, cable.q0.copy(), v=v))


def slack_arc(n_elements=20, length=2.0, radius=0.002, E=2e11, rho=7800.0, g=9.81,
              **damping):
    """Slack cable: a stress-free semicircular arc standing above its pinned end, released
    at rest under gravity; it falls, swings below the pin and snaps taut."""
    sec = Section.circular(radius=radius, E=E, rho=rho, **damping)
    R = length / np.pi
    s = np.linspace(0.0, length, n_elements + 1)
    th = s / R
    pos = np.column_stack([R - R * np.cos(th), R * np.sin(th), 0 * th])
    slopes = np.column_stack([np.sin(th), np.cos(th), 0 * th])
    cable = Cable(MeshLine(s), sec, pos, slopes)
    system = System([cable]).pin(cable.node(0)).add_gravity([0, -g, 0])
    return Scene(system, cable, _at_rest(system, cable.q0.copy()))
