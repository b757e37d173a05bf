"""The two-level Schur LU (issue 51, item 6; ``kernels.schur``): bodies joined to each
other besides the hub (the ring of an E-sail's tips) put their junctions in the border,
each block stores its coupling on the border unknowns it touches, and the sparse Schur
complement is factored as a band with the hub as its dense border.  Against SuperLU on
random matrices of a ring-and-hub pattern and on a small ringed E-sail; a zero pivot is
located at its unknown in either level; the same bits on one and two threads."""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

import skfem_cable as sc
from skfem_cable.core.linalg import PatternSolver, SingularMatrixError
from skfem_cable.scenes import esail

HUB, TETHER, TIP, AUX = 4, 10, 2, 2


def ring_and_hub(tethers, seed):
    """A random matrix (CSR) of ``tethers`` band blocks of ``TETHER`` unknowns (half-width
    2) joined to a dense hub of ``HUB`` unknowns through their first two and ending in a
    tip of ``TIP`` unknowns, and an auxiliary block of ``AUX`` between neighbouring tips
    (a ring); diagonally dominant.  Returns the matrix, the hub and the tips' unknowns."""
    rng = np.random.default_rng(seed)
    n = HUB + tethers * (TETHER + AUX)
    A = np.zeros((n, n))
    hub = np.arange(HUB)
    A[np.ix_(hub, hub)] = 1.0
    tips = []
    for j in range(tethers):
        first = HUB + j * TETHER
        for i in range(TETHER):
            A[first + i, max(first, first + i - 2): min(first + TETHER, first + i + 3)] = 1.0
        A[np.ix_(hub, [first, first + 1])] = A[np.ix_([first, first + 1], hub)] = 1.0
        tips.append(first + TETHER - TIP + np.arange(TIP))
    for j in range(tethers):
        aux = HUB + tethers * TETHER + AUX * j + np.arange(AUX)
        A[np.ix_(aux, aux)] = 1.0
        for tip in (tips[j], tips[(j + 1) % tethers]):
            A[np.ix_(aux, tip)] = A[np.ix_(tip, aux)] = 1.0
    A[A != 0] = rng.standard_normal(np.count_nonzero(A))
    A += 4 * n ** 0.5 * np.eye(n)
    return sp.csr_matrix(A), hub, np.concatenate(tips)


@pytest.fixture(scope="module")
def ring():
    A, hub, tips = ring_and_hub(7, 0)
    return A, hub, tips, np.random.default_rng(1).standard_normal(A.shape[0])


def test_two_levels_solve_a_ring_and_hub_as_superlu_does(ring):
    """Before: the ring joined every block into one band (the whole ring's half-width),
    or, its tips in the dense border, a dense Schur complement of every tip.  Now the
    blocks keep one tether's band, the tips' Schur complement a band of about two tips."""
    A, hub, tips, rhs = ring
    one = PatternSolver(A.indptr, A.indices, "banded", border=hub)
    two = PatternSolver(A.indptr, A.indices, "banded", border=hub, junctions=tips)
    assert (one.levels, two.levels) == (1, 2)
    assert two.band == 2 < one.band and two.border == HUB + tips.size
    inner = two.lu[1]
    assert inner[0][0][3] <= 3 * TIP and inner[1].shape[0] == HUB  # S: band of tips, hub dense
    exact = spsolve(A.tocsc(), rhs)
    for solver in (one, two):
        solver.factor(A.data)
        assert np.abs(solver.solve(rhs) - exact).max() < 1e-12 * np.abs(exact).max()


def _arrays(storage):
    """The arrays of a solver's nested storage, depth first."""
    if isinstance(storage, np.ndarray):
        return [storage]
    if isinstance(storage, tuple):
        return [a for member in storage for a in _arrays(member)]
    return []


@pytest.mark.parametrize("junctions", [False, True])
def test_a_renewed_solver_is_one_made_afresh(ring, junctions):
    """``PatternSolver.renewed`` (an integrator's solver: the layout's, with work arrays of
    its own) gives the storage a solver made afresh has, array for array, sharing with
    its original only what a factorization leaves as made (the plan of the pattern), and
    factors and solves to the same bits; one level (``kernels.bordered``) and two
    (``kernels.schur``)."""
    A, hub, tips, rhs = ring
    made = {"border": hub, "junctions": tips if junctions else None}
    original = PatternSolver(A.indptr, A.indices, "banded", **made)
    assert original.levels == 1 + junctions
    original.factor(A.data)
    x = original.solve(rhs)
    renewed = original.renewed()
    fresh = PatternSolver(A.indptr, A.indices, "banded", **made)
    old, new, afresh = (_arrays(s.lu) for s in (original, renewed, fresh))
    assert len(old) == len(new) == len(afresh) > 30
    written = 0
    for a, b, c in zip(old, new, afresh):
        np.testing.assert_array_equal(b, c)
        assert b.dtype == c.dtype and b.flags.c_contiguous == c.flags.c_contiguous
        if np.shares_memory(a, b):
            np.testing.assert_array_equal(a, c)
        written += not np.array_equal(a, c)
    assert written >= 5  # the band, its factor, pivots, S, ...
    assert renewed.factorizations == 0 and renewed.ordering is original.ordering
    renewed.factor(A.data)
    np.testing.assert_array_equal(renewed.solve(rhs), x)


@pytest.mark.parametrize("where", ["tip", "tether", "hub"])
def test_a_zero_pivot_is_located_at_its_unknown_in_either_level(ring, where):
    """A vanishing row and column: in a block (the first level), at a tip (the band of
    the Schur complement) or at the hub (its dense border)."""
    A, hub, tips, _ = ring
    unknown = {"tip": tips[5], "tether": HUB + 3 * TETHER + 4, "hub": hub[2]}[where]
    B = A.tolil()
    B[unknown, :] = 0.0
    B[:, unknown] = 0.0
    data = sp.csr_matrix(B)
    data = np.asarray(data[A.nonzero()]).ravel()
    solver = PatternSolver(A.indptr, A.indices, "banded", border=hub, junctions=tips)
    with pytest.raises(SingularMatrixError) as info:
        solver.factor(data)
    assert info.value.index == unknown


def test_the_same_bits_on_one_and_two_threads(ring):
    """The blocks on numba's threads; their parts of the Schur complement are summed in
    the order of the blocks."""
    A, hub, tips, rhs = ring
    solutions = []
    for threads in (1, 2):
        solver = PatternSolver(A.indptr, A.indices, "banded", border=hub, junctions=tips,
                               threads=threads)
        assert (solver.lu[-1] is True) == (threads == 2)
        solver.factor(A.data)
        solutions.append(solver.solve(rhs))
    assert np.array_equal(solutions[0], solutions[1])


@pytest.fixture(scope="module")
def ringed():
    """Six tethers of two elements with remote units and the auxiliary ring."""
    rig = replace(esail.FULL_RIG, config=replace(esail.FULL_SIZE, n_tethers=6))
    return rig.build(10.0, 2)


def test_the_ring_s_junctions_are_the_tips(ringed):
    """``Layout.junctions``: the tip node's position of every tether (where its two
    auxiliary tethers are pinned), not the auxiliary tethers' ends; the solver takes
    two levels, the band that of one tether."""
    system = ringed.system
    lay = system.current_layout()
    tips = np.concatenate([system.dofs(t)[-6:-3] for t in ringed.tethers])
    assert np.array_equal(lay.junctions, np.sort(tips))
    solver = PatternSolver(lay.indptr, lay.indices, border=lay.border,
                           junctions=lay.junctions)
    assert solver.levels == 2 and solver.band <= 13
    assert solver.border == lay.border.size + tips.size


def test_a_ringed_sail_takes_the_newton_steps_of_superlu(ringed):
    """Ten steps of 5 s from the windless spin: the two-level LU and SuperLU give the
    same states to 1e-10 and the same iterations."""
    runs = {method: sc.simulate(ringed.system, 50.0, 5.0, initial=ringed.initial,
                                rho_inf=0.25, method=method, compiled=False)
            for method in ("banded", "sparse")}
    assert [runs[m].stats["solver"] for m in runs] == ["banded", "sparse"]
    for key in ("newton", "factorizations"):
        assert runs["banded"].stats[key] == runs["sparse"].stats[key], key
    for field in ("q", "v", "lam"):
        a, b = getattr(runs["banded"], field), getattr(runs["sparse"], field)
        assert np.abs(a - b).max() <= 1e-10 * np.abs(b).max(), field
