"""The band ordering that keeps a cable's half-width (issue 47, item 4; ``core.ordering``).

Reverse Cuthill-McKee put a pin's three multipliers between the pinned node's unknowns
(half-width 13); placed at the nearest cut no coupling crosses, the band is the cable's
(11: two nodes of six coordinates).  The half-width of a pinned cable, of a catenary
pinned at both ends and of the E-sail rig's tether blocks; an ordering never wider than
reverse Cuthill-McKee; and a pendulum's run the same as with the old ordering to
rounding (its tip within 1e-13 m after 100 steps).  Layouts only, but for the run
(the 16-element pendulum's step, compiled by many files)."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.core import ordering
from skfem_cable.core.linalg import ordering_of
from skfem_cable.kernels import bordered
from skfem_cable.kernels.lapack import ADDRESSES
from skfem_cable.scenes import classics, esail

#: A cable's half-width: an element couples the six coordinates of each of its two nodes.
CABLE = 11


def _ordering(system):
    lay = system.current_layout()
    return ordering_of(lay.indptr, lay.indices, lay.border, lay.junctions), lay


def _catenary(n=40, length=100.0, span=80.0):
    """The tracked catenary's system (``benchmarks/commit_compare.py``) on ``n`` elements,
    its shape a straight sag (the pattern does not depend on it)."""
    s = np.linspace(0.0, length, n + 1)
    pos = np.column_stack([s * span / length, -0.3 * s * (length - s) / length, 0 * s])
    cable = sc.Cable(MeshLine(s), sc.Section.circular(radius=0.01, E=7e10, rho=7800.0),
                     pos, np.gradient(pos, s, axis=0))
    return sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))


def test_a_pinned_cable_keeps_the_cable_half_width():
    """The pendulum: 13 with the multipliers interleaved, 11 now, the three multipliers
    at the pinned end of the band."""
    system = classics.pendulum(n_elements=16).system
    (perm, nb, band, dense), lay = _ordering(system)
    assert band == CABLE and nb == lay.N and dense.size == 0
    multipliers = np.flatnonzero(perm >= system.n_dofs)
    assert multipliers.tolist() in ([0, 1, 2], [lay.N - 3, lay.N - 2, lay.N - 1])


def test_a_catenary_pinned_at_both_ends_keeps_the_cable_half_width():
    system = _catenary()
    (perm, nb, band, _), lay = _ordering(system)
    assert band == CABLE and nb == lay.N
    assert sorted(np.flatnonzero(perm >= system.n_dofs).tolist()) == [
        0, 1, 2, lay.N - 3, lay.N - 2, lay.N - 1]


def test_the_esail_rig_tether_blocks_keep_the_cable_half_width():
    """The rig's 12 tethers of 5 elements, each with its root joint's multipliers, hub
    last (the border); each tether a block of its own: the multipliers of two tethers
    put at the free cut between them each on its tether's side (in the order of their
    neighbours, else the two blocks were one)."""
    scene = esail.build(esail.BaselineConfig(), 10.0, 5)
    (perm, nb, band, dense), lay = _ordering(scene.system)
    assert band == CABLE and nb == lay.N - lay.border.size and dense.size == lay.border.size
    lu = bordered.storage(ADDRESSES, np.repeat(np.arange(lay.N), np.diff(lay.indptr)),
                          lay.indices, perm, nb, band)
    starts, rows_ptr = lu[0][0][6], lu[0][0][7]  # the blocks' storage (band_blocks)
    assert np.all(np.diff(starts) == 39) and np.all(np.diff(rows_ptr) == 3)


def _rcm_half_width(pattern):
    return ordering.half_width(pattern, reverse_cuthill_mckee(pattern, symmetric_mode=True))


def test_never_wider_than_reverse_cuthill_mckee():
    """A pin in the middle of a cable (no cut there is free: the multipliers widen the
    band wherever they go), random light unknowns on a random band: the ordering is a
    permutation and its band no wider than reverse Cuthill-McKee's."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 12, sc.Section.circular(0.01, 7e10, 7800.0))
    middle = sc.System([cable]).pin(cable.node(6)).pin(cable.node(0))
    lay = middle.current_layout()
    pattern = sp.csr_matrix((np.ones(lay.indices.size), lay.indices, lay.indptr))
    perm, _, band = ordering.band_ordering(pattern, np.zeros(0, dtype=np.int64))
    assert band <= _rcm_half_width(pattern)
    rng = np.random.default_rng(3)
    for _ in range(20):
        n, light = 60, 8
        A = sp.random(n, n, density=0.05, random_state=rng) + sp.eye(n)
        B = sp.lil_matrix(sp.block_diag([A + A.T, sp.eye(light)]))
        for u in range(n, n + light):
            B[u, rng.integers(0, n, 3)] = 1.0
        B = sp.csr_matrix(B + B.T)
        perm, nb, band = ordering.band_ordering(B, np.zeros(0, dtype=np.int64))
        assert np.array_equal(np.sort(perm), np.arange(n + light)) and nb == n + light
        assert band == ordering.half_width(B, perm) <= _rcm_half_width(B)


def test_light_unknowns_are_a_point_constraint_multipliers():
    system = classics.pendulum(n_elements=4).system
    lay = system.current_layout()
    pattern = sp.csr_matrix((np.ones(lay.indices.size), lay.indices, lay.indptr))
    assert np.flatnonzero(ordering.light(pattern)).tolist() == list(range(system.n_dofs,
                                                                         lay.N))


@pytest.fixture(scope="module")
def runs():
    """The 16-element pendulum over 100 steps in the old ordering (reverse Cuthill-McKee
    of all) and the new, each on its own system."""
    out = {}
    for name, light_last in (("old", lambda pattern: None), ("new", ordering.light_last)):
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(ordering, "light_last", light_last)
            scene = classics.pendulum(n_elements=16)
            result = sc.simulate(scene.system, t_end=0.1, dt=1e-3, rho_inf=0.8,
                                 initial=scene.initial, every=100)
            out[name] = result, scene.system.current_layout().derived("ordering", None)
    return out


def test_the_orderings_differ_in_the_run(runs):
    assert runs["old"][1][2] == 13 and runs["new"][1][2] == CABLE


def test_a_run_agrees_with_the_old_ordering_to_rounding(runs):
    """Other pivots, the same steps: positions within 1e-13 m of the 1.2 m pendulum
    (measured 2.1e-15 at 100 steps, 3.0e-14 at 1000), the same Newton corrections and
    factorizations; the pin's force within 1e-8 of its size (measured 3.2e-10, 2.8e-9 at
    1000 steps): the multipliers' corrections are not in Newton's stopping test
    (``kernels.step._iterate``), so they differ by the last correction's size, not by
    rounding."""
    old, new = runs["old"][0], runs["new"][0]
    assert np.abs(new.q[-1] - old.q[-1]).max() < 1e-13
    assert new.stats["newton"] == old.stats["newton"]
    assert new.stats["factorizations"] == old.stats["factorizations"]
    assert np.abs(new.lam[-1] - old.lam[-1]).max() < 1e-8 * np.abs(old.lam[-1]).max()
