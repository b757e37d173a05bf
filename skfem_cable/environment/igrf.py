"""The International Geomagnetic Reference Field in the inertial axes of an orbit.

``IGRF(epoch).field(x, t)`` has the protocol of ``MagneticDipole.field``: the field ``B``
(T) and its gradient ``dB/dx`` (T/m) at absolute positions ``x`` (..., 3) (m) in the GCRS
axes, ``t`` seconds after the epoch.  ppigrf evaluates the spherical-harmonic model
(geocentric spherical components, degree 13, coefficients interpolated in time) at the
Earth-fixed positions ``y = R(t) x`` (``Epoch.gcrs_to_itrs``); the field and its gradient
are rotated back, ``B = R^T B_ITRS`` and ``dB/dx = R^T (dB_ITRS/dy) R``.

The gradient is the central difference of ppigrf's field in the Earth-fixed Cartesian
axes with the step ``GRADIENT_STEP`` (100 m): the field varies on the scale ``r / 3``
of the distance from the centre (``r ~ 6.8e6 m``), so the truncation error is about
``(h / r)^2 ~ 2e-10`` relative and the rounding error ``eps r / h ~ 1.5e-11``; the seven
positions per point go to ppigrf in one call.

References
----------
1. P. Alken et al., "International Geomagnetic Reference Field: the thirteenth
   generation", Earth Planets Space 73 (2021) 49; the fourteenth generation (IGRF-14,
   2025), the coefficient file ppigrf ships.
2. K. M. Laundal, ppigrf: Pure Python IGRF (the evaluation of the model).
"""

import numpy as np

from ..bodies.section import check_positive
from .coefficients import read_once
from .epoch import epoch_or_none, model_epoch

GRADIENT_STEP = 100.0
"""Step (m) of the central-difference gradient in the Earth-fixed axes."""
NANOTESLA = 1e-9


def ppigrf():
    """ppigrf, its coefficient file read once per file in a process: ``igrf_gc`` parses
    the whole ``.shc`` file on every call (7 ms of a 25 ms call for tens of points), and a
    load evaluates it once per step; the memo (``coefficients.read_once``) replaces
    ``ppigrf.ppigrf.read_shc``, which ``igrf_gc`` looks up at each call."""
    import ppigrf
    from ppigrf import ppigrf as module
    read_once(module, "read_shc", 4, handed=_copies)
    return ppigrf


def _copies(frames):
    """Copies of ppigrf's coefficient frames ``g, h`` (pandas: not made read-only), so
    that a caller that edited them would not change the next call's."""
    return tuple(frame.copy() for frame in frames)


def itrs_field(y, when):
    """The IGRF field (T) at Earth-fixed Cartesian positions ``y`` (n, 3) (m) at the
    datetime ``when``: ppigrf's geocentric components ``(B_r, B_theta, B_phi)`` (nT) on
    the local spherical basis, turned into Cartesian components."""
    r = np.linalg.norm(y, axis=-1)
    theta = np.arccos(np.clip(y[:, 2] / r, -1.0, 1.0))
    phi = np.arctan2(y[:, 1], y[:, 0])
    Br, Bt, Bp = (b[0] for b in ppigrf().igrf_gc(r * 1e-3, np.degrees(theta),
                                                  np.degrees(phi), when))
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(phi), np.cos(phi)
    e_r = np.stack([st * cp, st * sp, ct], axis=-1)
    e_t = np.stack([ct * cp, ct * sp, -st], axis=-1)
    e_p = np.stack([-sp, cp, np.zeros_like(sp)], axis=-1)
    return NANOTESLA * (Br[:, None] * e_r + Bt[:, None] * e_t + Bp[:, None] * e_p)


class IGRF:
    """The IGRF geomagnetic field in the GCRS axes, with its gradient.

    Parameters
    ----------
    epoch : Epoch, datetime, astropy Time, str or None
        The instant of ``t = 0``; None: the epoch of the system whose load the model
        serves (``System.add_orbit(orbit, epoch=...)``; ``epoch.bound_model``).
    gradient_step : float
        Step (m, > 0) of the central-difference gradient (default ``GRADIENT_STEP``).

    Notes
    -----
    A load evaluates the field once per step (its ``Term.prepare(t)``, at the step's
    positions) and keeps it through the Newton iterations; the rotation ``R(t)`` is cached
    per time by the epoch, shared by the models built on the same ``Epoch``.

    Examples
    --------
    >>> import numpy as np
    >>> import skfem_cable as sc
    >>> igrf = sc.environment.IGRF("2026-01-01")
    >>> B, dB = igrf.field([[sc.R_EARTH + 400e3, 0.0, 0.0]])
    >>> B.shape, dB.shape
    ((1, 3), (1, 3, 3))
    >>> bool(2e-5 < float(np.linalg.norm(B)) < 5e-5)
    True
    """

    def __init__(self, epoch=None, gradient_step=GRADIENT_STEP):
        self.epoch = epoch_or_none(epoch)
        self.gradient_step = check_positive("gradient_step", gradient_step)

    def field(self, x, t=0.0):
        """The field ``B`` (T) and its gradient ``dB/dx`` (T/m; ``[..., i, j] = dB_i /
        dx_j``) at absolute GCRS positions ``x`` (..., 3) (m), ``t`` s after the epoch:
        shapes (..., 3) and (..., 3, 3)."""
        shifts = self.gradient_step * np.vstack([np.zeros(3), np.eye(3), -np.eye(3)])
        B, R = self._itrs(x, t, shifts)
        dB = (B[1:4] - B[4:7]).transpose(1, 2, 0) / (2.0 * self.gradient_step)
        dB_gcrs = np.einsum("ki,nkl,lj->nij", R, dB, R)
        return (B[0] @ R).reshape(np.shape(x)), dB_gcrs.reshape(np.shape(x) + (3,))

    def field_series(self, x, times):
        """``field`` at several times in one ppigrf call: positions ``x`` (k, n, 3) at the
        times ``times`` (k,) (s), each with its own rotation ``R(t_k)``, the coefficients
        at the middle time (IGRF's secular variation, at most about 200 nT a year, moves
        the field by 1e-7 of itself in an hour): shapes (k, n, 3) and (k, n, 3, 3)."""
        x, times = np.asarray(x, dtype=float), np.asarray(times, dtype=float)
        epoch = model_epoch(self)
        R = np.stack([epoch.gcrs_to_itrs(t) for t in times])
        y = np.einsum("kij,knj->kni", R, x)
        shifts = self.gradient_step * np.vstack([np.zeros(3), np.eye(3), -np.eye(3)])
        B = itrs_field((y[:, None] + shifts[None, :, None]).reshape(-1, 3),
                       epoch.datetime(0.5 * (times.min() + times.max())))
        B = B.reshape(x.shape[0], len(shifts), x.shape[1], 3)
        dB = (B[:, 1:4] - B[:, 4:7]).transpose(0, 2, 3, 1) / (2.0 * self.gradient_step)
        return (np.einsum("kna,kaj->knj", B[:, 0], R),
                np.einsum("kai,knab,kbj->knij", R, dB, R))

    def __call__(self, x, t=0.0):
        """The field ``B`` (T) alone at GCRS positions ``x`` (..., 3): the callable field
        ``ElectrodynamicForce`` accepts."""
        B, R = self._itrs(x, t, np.zeros((1, 3)))
        return (B[0] @ R).reshape(np.shape(x))

    def _itrs(self, x, t, shifts):
        """The ITRS field (k, n, 3) at the Earth-fixed images of the positions ``x``
        shifted by each of ``shifts`` (k, 3) (m, Earth-fixed axes), and ``R(t)``."""
        x = np.asarray(x, dtype=float)
        if x.shape[-1:] != (3,):
            raise ValueError(f"positions must have shape (..., 3), got {x.shape}")
        R = model_epoch(self).gcrs_to_itrs(t)
        y = x.reshape(-1, 3) @ R.T
        B = itrs_field((y[None, :, :] + shifts[:, None, :]).reshape(-1, 3),
                       model_epoch(self).datetime(t))
        return B.reshape(len(shifts), -1, 3), R

    def __repr__(self):
        return f"IGRF({self.epoch!r})"
