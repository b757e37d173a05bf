"""The rod chain as a run store sees a system (``ChainSystem``): one body of ``3 n``
coordinates, the rod vectors, no constraints, the loads and anchor of the run
(``Problem``) as its one load.

``io.RunStore`` labels, fingerprints and reads back a store through
``protocols.SystemView``, which ``ChainSystem`` implements (and declares, by subclassing
it): ``n_dofs``, ``n_constraints``, ``bodies``, ``constraints``, ``loads``,
``point_masses``, ``vectors``, ``vector_is_position``, ``orbit``, ``dofs``, ``cables``
and ``mass_matrix``.  A rod vector is a 3-vector but not a position (its components are
labelled ``dx dy dz``): the store has no ``r`` of positions, which need the anchor's
motion; ``RodChainResult.joints`` has them.
"""

import numpy as np
import scipy.sparse as sp

from ..core.protocols import SystemView
from .problem import Problem


class ChainBody:
    """The chain as the one body of its run, as far as a store reads it: ``name``,
    ``n_dofs``, the initial rod vectors ``q0`` (3 n,) and ``describe_dof``."""

    name = "chain"

    def __init__(self, q0):
        self.q0 = np.asarray(q0, dtype=float).reshape(-1)
        self.n_dofs = self.q0.size

    def describe_dof(self, i):
        """``rod k x`` (``y``, ``z``): component of the vector of rod ``k``."""
        return f"rod {i // 3} {'xyz'[i % 3]}"


class ChainSystem(SystemView):
    """What a rod-chain run integrates, as a store sees a system (``contract.Run.system``
    of ``RodChain.simulate``): a ``protocols.SystemView``, and the ``chain``.

    Parameters
    ----------
    chain : RodChain
    problem : Problem
        Its loads and anchor motion (the system's one load).
    q0 : array_like (n, 3)
        The initial rod vectors (part of the fingerprint, as a body's ``q0``).
    """

    #: No reference orbit for a store to read back (its coordinates are not offsets).
    orbit = None
    #: No epoch (the chain's time is its own).
    epoch = None

    def __init__(self, chain, problem, q0):
        self.chain = chain
        self.bodies = [ChainBody(q0)]
        self.constraints, self.point_masses = [], []
        self.loads = [problem]
        self.n_dofs, self.n_constraints = 3 * chain.n, 0
        self.vectors = np.arange(self.n_dofs).reshape(chain.n, 3)
        self.vector_is_position = np.zeros(chain.n, dtype=bool)

    @classmethod
    def of(cls, chain, q0, **loads):
        """The system of ``chain`` from ``q0`` under ``loads`` (the ``Problem`` keywords
        of ``RodChain.simulate``: ``gravity``, ``line_load``, ``tip_force``, ``anchor``,
        ``quadrature``, ``max_strain``)."""
        return cls(chain, Problem(chain, **loads), q0)

    def dofs(self, item):
        """Global coordinates of ``item`` (the one body: all of them)."""
        return np.arange(self.n_dofs)

    def cables(self):
        """No cable: the chain's points are not cable nodes."""
        return []

    def mass_matrix(self):
        """The rod masses, each on the diagonal of its three coordinates: what the
        fingerprint of a store records of the masses (``M`` of Eq. 8 is dense, O(n^2):
        ``RodChain.mass_matrix``)."""
        return sp.diags(np.repeat(self.chain.masses, 3), format="csr")
