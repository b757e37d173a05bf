"""The generalized-alpha step of ``GeneralizedAlpha`` (Arnold & Bruls' form) on one mode
``x'' = -omega^2 x``, for tests of the method's damping and of Newton's predictor."""

import numpy as np

from skfem_cable.solvers.galpha import galpha_parameters


def amplification(omega_h, rho_inf):
    """The amplification matrix of a step on ``x'' = -omega^2 x`` in units of ``h``: it
    maps ``(x, h v, h^2 a, h^2 abar)`` at ``t_n`` to those at ``t_(n+1)``."""
    am, af, gamma, beta = galpha_parameters(rho_inf)
    A = np.zeros((4, 4))
    for j, (x, v, a, abar) in enumerate(np.eye(4)):
        # a1 = -omega^2 x1, x1 = x + v + (1/2 - beta) abar + beta abar1
        known = x + v + (0.5 - beta) * abar + beta * (af * a - am * abar) / (1 - am)
        a1 = -omega_h**2 * known / (1 + omega_h**2 * beta * (1 - af) / (1 - am))
        abar1 = ((1 - af) * a1 + af * a - am * abar) / (1 - am)
        A[:, j] = (x + v + (0.5 - beta) * abar + beta * abar1,
                   v + (1 - gamma) * abar + gamma * abar1, a1, abar1)
    return A
