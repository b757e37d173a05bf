"""Reference frames and Euler angles (paper Sects. 2.1, 3.3, 3.4).

Direction cosine matrices here map coordinates: ``C_to_from`` gives ``r^to = C r^from``.
``R1, R2, R3`` are the elementary frame rotations about x, y, z.
"""

import numpy as np


def R1(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


def R2(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def R3(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def dcm_321(psi, theta, phi):
    """``C = R1(phi) R2(theta) R3(psi)``: the yaw-pitch-roll sequence of Eq. 65."""
    return R1(phi) @ R2(theta) @ R3(psi)


def euler_321(C):
    """``(psi, theta, phi)`` of ``dcm_321`` (theta in [-pi/2, pi/2]); ``C`` (..., 3, 3)."""
    C = np.asarray(C)
    theta = -np.arcsin(np.clip(C[..., 0, 2], -1.0, 1.0))
    psi = np.arctan2(C[..., 0, 1], C[..., 0, 0])
    phi = np.arctan2(C[..., 1, 2], C[..., 2, 2])
    return np.stack([psi, theta, phi], axis=-1)


def dcm_323(Psi, Theta, Phi):
    """``C = R3(Phi) R2(Theta) R3(Psi)``: the sequence of Eq. 71."""
    return R3(Phi) @ R2(Theta) @ R3(Psi)


def euler_323(C):
    """``(Psi, Theta, Phi)`` of ``dcm_323`` (Theta in [0, pi]); ``C`` (..., 3, 3)."""
    C = np.asarray(C)
    Theta = np.arccos(np.clip(C[..., 2, 2], -1.0, 1.0))
    Psi = np.arctan2(C[..., 2, 1], C[..., 2, 0])
    Phi = np.arctan2(C[..., 1, 2], -C[..., 0, 2])
    return np.stack([Psi, Theta, Phi], axis=-1)


def orbit_frame(R):
    """Orbit frame O at heliocentric positions ``R`` (..., 3) (Sect. 2.1, Eq. 44): columns
    ``X_O, Y_O, Z_O`` in H (or I) coordinates with ``Z_O`` radial from the Sun,
    ``X_O = k_H x Z_O / |k_H x Z_O|`` (``k_H`` the ecliptic normal) and
    ``Y_O = Z_O x X_O``.  Returns ``C_I_O`` (..., 3, 3): ``r^I = C_I_O r^O``."""
    R = np.asarray(R, dtype=float)
    k = R / np.linalg.norm(R, axis=-1, keepdims=True)
    i = np.cross(np.array([0.0, 0.0, 1.0]), k)
    i /= np.linalg.norm(i, axis=-1, keepdims=True)
    j = np.cross(k, i)
    return np.stack([i, j, k], axis=-1)
