"""Plasmas: the protocol the OML current reads, and a uniform plasma for checks.

A plasma has ``density(x, t)`` (electrons per m^3; quasi-neutral: as many singly charged
ions), ``temperature(x, t)`` (electron temperature, K), ``velocity(x, t)`` (the plasma's
velocity, m/s, in the GCRS axes: a tether's motional field is ``(v - velocity) x B``) and
``ion_mass`` (kg), at absolute positions ``x`` (..., 3) (m), ``t`` seconds after the
epoch.  ``IRI`` (module ``iri``) is the ionosphere; ``UniformPlasma`` a laboratory
plasma.
"""

import numpy as np

from ..bodies.section import check_positive

ATOMIC_MASS = 1.66053906660e-27
"""The atomic mass constant (kg, CODATA 2018)."""
OXYGEN_ION_MASS = 15.999 * ATOMIC_MASS
"""Mass (kg) of O+, the dominant ion of the F region (200 to 1000 km)."""


class UniformPlasma:
    """A uniform plasma moving at a constant velocity: laboratory-style checks.

    Parameters
    ----------
    density : float
        Electron (and ion) density (m^-3, > 0).
    temperature : float
        Electron temperature (K, > 0).
    velocity : array_like (3,)
        The plasma's velocity (m/s).
    ion_mass : float
        Ion mass (kg, > 0); default O+.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> plasma = sc.environment.UniformPlasma(1e11, temperature=1500.0)
    >>> plasma.density(np.zeros((2, 3)))
    array([1.e+11, 1.e+11])
    """

    def __init__(self, density, temperature=1500.0, velocity=(0.0, 0.0, 0.0),
                 ion_mass=OXYGEN_ION_MASS):
        self.electron_density = check_positive("density", density)
        self.electron_temperature = check_positive("temperature", temperature)
        self.plasma_velocity = np.array(velocity, dtype=float)
        if self.plasma_velocity.shape != (3,) or not np.all(np.isfinite(self.plasma_velocity)):
            raise ValueError(f"velocity must be a finite 3-vector (m/s), got {velocity!r}")
        self.ion_mass = check_positive("ion_mass", ion_mass)

    def density(self, x, t=0.0):
        """The uniform electron density (m^-3) at positions ``x`` (..., 3)."""
        return np.full(np.shape(x)[:-1], self.electron_density)

    def temperature(self, x, t=0.0):
        """The uniform electron temperature (K) at positions ``x`` (..., 3)."""
        return np.full(np.shape(x)[:-1], self.electron_temperature)

    def velocity(self, x, t=0.0):
        """The plasma's velocity (m/s) at positions ``x`` (..., 3)."""
        return np.broadcast_to(self.plasma_velocity, np.shape(x)).copy()

    def __repr__(self):
        return (f"UniformPlasma({self.electron_density:.6g}, "
                f"temperature={self.electron_temperature:.6g})")

