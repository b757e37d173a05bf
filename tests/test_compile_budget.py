"""What the suite compiles from a cold kernel cache (issue 47, must-show 5): a Newton-step
module is generated per sequence of term kernels, not per system, so that systems which
differ in their sizes and values share one compiled step; and on one thread the bordered
LU's threaded loops are neither compiled nor linked into the step.  No timing is
asserted: these count what is compiled."""

import numba
import numpy as np
import scipy.sparse as sp
from node_spring import NodeSpring

import skfem_cable as sc
from skfem_cable.core.linalg import PatternSolver
from skfem_cable.kernels import bordered
from skfem_cable.solvers.galpha import GeneralizedAlpha


def _pinned_cable(n_elements, length, E, rho, g):
    cable = sc.Cable.straight([0, 0, 0], [length, 0, 0], n_elements=n_elements,
                              section=sc.Section.circular(radius=0.01, E=E, rho=rho))
    return sc.System([cable]).pin(cable.node(0)).add_gravity([0, -g, 0])


def test_systems_differing_in_sizes_and_values_share_one_step_module():
    """Before: nothing said so; a literal size or value in the generated text would give
    every system its own module (about 10 s of compilation each)."""
    systems = [_pinned_cable(2, 1.0, 7e10, 7800.0, 9.81),
               _pinned_cable(7, 3.0, 2e11, 1500.0, 1.62),
               _pinned_cable(4, 0.5, 1e9, 1000.0, 0.0)]
    steps = {id(GeneralizedAlpha(s).compiled.newton) for s in systems}
    assert len(steps) == 1


def _two_blocks(threads):
    """A solver of two independent tridiagonal 3 x 3 blocks on ``threads`` threads, and
    the matrix ``4 I - (sub + super diagonals)`` on its pattern."""
    matrix = sp.csr_matrix(np.kron(np.eye(2), 4.0 * np.eye(3) - np.eye(3, k=1)
                                   - np.eye(3, k=-1)))
    return PatternSolver(matrix.indptr, matrix.indices, threads=threads), matrix


def test_one_thread_leaves_the_threaded_lu_out_of_the_compiled_code():
    """Before: the storage held a run-time flag, so every compilation of the LU (and of
    every Newton step linking it) compiled its ``prange`` loops too, on one thread as on
    many.  Now the flag is ``None`` on one thread, a type numba prunes the branch on."""
    (one, matrix), (two, _) = _two_blocks(1), _two_blocks(2)
    assert one.lu[-1] is None and two.lu[-1] is True
    one.factor(matrix.data)
    rhs = np.arange(1.0, 7.0)
    assert np.allclose(one.solve(rhs), np.linalg.solve(matrix.toarray(), rhs), rtol=1e-14)
    assert any(signature[0][-1] == numba.types.none for signature in
               bordered.factor.signatures)


class _Push:
    """A constant force on a node, a Python ``add`` hook without tangent (its index
    ``None``)."""

    def __init__(self, node):
        self.node, self.name = node, "push"

    def bind(self, system):
        d = system.dofs(self.node)[:3]

        def add(ev, index):
            ev.f_ext[d] += 1.0

        return sc.Term(add=add, name=self.name)


def test_python_terms_of_any_index_shape_share_one_step_signature():
    """Before: a Python term's index (never read by the compiled step) went into the
    step's arguments, so a node spring (a 2-d index) and a push (none) gave the same module
    two signatures, two compilations (7 of the 252 step modules of this machine's cache had
    two, all so)."""
    steps = []
    for load in (lambda cable: NodeSpring(cable.node(-1), 50.0, [1.0, 0, 0]), _Push):
        system = _pinned_cable(2, 1.0, 7e10, 7800.0, 9.81)
        system.add_load(load(system.bodies[0]))
        steps.append(GeneralizedAlpha(system).compiled)
    assert steps[0].newton is steps[1].newton
    assert numba.typeof(steps[0].terms) == numba.typeof(steps[1].terms)


def test_systems_of_different_terms_share_one_compiled_newton_step():
    """Before: the Newton step was generated and compiled for each sequence of term
    kernels (about 10 s each); now it is compiled once, for every system, and a system
    compiles only its terms module (``solvers.compiled.system_module``)."""
    plain = _pinned_cable(2, 1.0, 7e10, 7800.0, 9.81)
    dragged = _pinned_cable(3, 1.0, 7e10, 7800.0, 9.81)
    dragged.add_load(sc.MorisonDrag(dragged.bodies[0], rho=1000.0, cd_normal=1.2,
                                    cd_tangential=0.1, diameter=0.02))
    newton = GeneralizedAlpha(plain).compiled.newton
    runs = [sc.simulate(plain, t_end=3e-3, dt=1e-3)]
    compiled_before = len(newton.overloads)  # the suite's other systems may have added some
    runs.append(sc.simulate(dragged, t_end=3e-3, dt=1e-3))
    assert len(newton.overloads) == compiled_before
    steps = [GeneralizedAlpha(s).compiled for s in (plain, dragged)]
    assert steps[0].newton is steps[1].newton is newton
    assert steps[0].terms[0] != steps[1].terms[0]  # their own evaluate
    assert all(r.stats["path"] == "compiled" for r in runs)


def test_held_terms_outlive_the_references_python_dropped():
    """``kernels.erased``: a tuple held at an address is read back intact after Python
    dropped its own references (the hold keeps numba's), and given back once."""
    import gc

    from numba import njit

    from skfem_cable.kernels import erased

    value = (np.arange(4.0), (np.full(3, 2.5), np.arange(2)))
    kind = numba.typeof(value)

    @njit
    def keep(address, v):
        erased.hold(address, v)

    @njit
    def total(address):
        v = erased.held(address, kind)
        return v[0].sum() + v[1][0].sum() + v[1][1].sum()

    @njit
    def drop(address):
        erased.release(address, kind)

    blob = np.zeros(erased.size_of(kind), dtype=np.uint8)
    keep(blob.ctypes.data, value)
    del value
    gc.collect()
    assert total(blob.ctypes.data) == 6.0 + 7.5 + 1.0
    drop(blob.ctypes.data)


def test_a_compiled_step_refuses_to_be_copied():
    """Its terms are behind an address of this process: a copy or a pickle is refused by
    name instead of reading them after the original gave them back."""
    import copy
    import pickle

    import pytest

    step = GeneralizedAlpha(_pinned_cable(2, 1.0, 7e10, 7800.0, 9.81)).compiled
    for clone in (copy.copy, copy.deepcopy, pickle.dumps):
        with pytest.raises(TypeError, match="cannot be copied or pickled"):
            clone(step)
