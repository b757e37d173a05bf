"""Tether as a chain of straight elastic rods joined by frictionless spherical hinges
(Ma Shuguang & Wang Tianshu, "An Efficient Model of Tethers for Tethered Satellite
Systems", Advances in Astronautics Science and Technology, 2019,
doi:10.1007/s42423-018-0025-1), with the O(n) solve of the constant mass matrix.

The generalized coordinates are the rod vectors ``q_i = O_{i-1} -> O_i`` (no angles).  The
anchor ``O_0`` is fixed or follows a prescribed motion; ``O_n`` is free.  The equations of
motion, three decoupled copies of Eq. 18 (Eq. 20), are

    M q'' + K(q) q = Q_F F + F*  - c a_0(t),

with the constant mass matrix ``M`` (Eqs. 6-8), the diagonal ``K`` of axial factors
``k_i`` (Eq. 12), the generalized forces of distributed loads (Eqs. 14-16) and, for a
moving anchor, the inertial load of its acceleration ``a_0`` weighted by the first-moment
coefficients ``c_i = m_i / 2 + sum_{j>i} m_j``.  ``M^{-1}`` is applied in O(n) through
``M = Phi^T B^T B Phi`` (Eqs. 22-30).  See ``docs/rodchain.md``.

The pieces, one job each:

* ``model``: ``RodChain``, the chain, its mass matrix and O(n) solve, forces, energies,
  statics, stability limit and ``simulate``;
* ``problem``: ``Problem``, the loads and the anchor motion (right-hand side of Eq. 21),
  and ``circular_anchor``;
* ``orbiting``: ``OrbitingChain``, the chain with end bodies, both ends free, in the
  differential gravity of an ``Orbit`` (``RodChain.in_orbit``); ``tss``: ``tss_chain``, a
  tethered satellite system along the local vertical;
* ``integrate``: RK4 (compiled blocks, or Python for callable loads) and the adaptive
  methods, with ``contract.Observer`` observers; ``RodChainDivergence``;
* ``result``: ``RodChainResult`` (the API of the cable ``Result``) and ``ChainState``;
* ``export``: the VTU polyline of the joints and its series (written during a run by
  ``io.SeriesObserver``);
* ``plots``: figures and renders of a run; ``run``: a run directory (``run_chain``).
"""

from .export import ChainSeriesWriter, chain_mesh, write_series, write_vtu
from .integrate import METHODS, RK4_STABILITY, Integration, RodChainDivergence, rk4_step
from .model import RodChain
from .orbiting import OrbitingChain, OrbitingChainResult
from .problem import Problem, circular_anchor
from .result import ChainState, RodChainResult
from .tss import tss_chain

__all__ = ["METHODS", "RK4_STABILITY", "ChainSeriesWriter",
           "ChainState", "Integration", "OrbitingChain", "OrbitingChainResult", "Problem",
           "RodChain", "RodChainDivergence", "RodChainResult", "chain_mesh", "circular_anchor",
           "rk4_step", "tss_chain", "write_series", "write_vtu"]
