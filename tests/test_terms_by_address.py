"""A system's terms module calls its kernels at their machine addresses (issue 47, must-show
5): numba does not link the kernels' code into it, so LLVM does not optimise every kernel
again in every system's module, and the module depends on the kernels' types alone.  No
timing is asserted: these check what the module holds and that it computes the same."""

import re
import sys

import numba
import numpy as np
import pytest
from node_spring import CompiledNodeSpring, spring_kernel
from numba import njit

import skfem_cable as sc
from skfem_cable.kernels import erased
from skfem_cable.solvers import compiled
from skfem_cable.solvers.galpha import GeneralizedAlpha


@njit(cache=True)
def twice_kernel(pack, index, ev):
    """The node spring's kernel applied twice: another kernel of the same signature."""
    spring_kernel(pack, index, ev)
    spring_kernel(pack, index, ev)


class TwiceNodeSpring(CompiledNodeSpring):
    """The node spring counted twice by one kernel."""

    def bind(self, system):
        term = super().bind(system)
        return sc.Term(kernels=((twice_kernel, term.kernels[0][1]),), rows=term.rows,
                       cols=term.cols, name=self.name)


def _system(*springs):
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], n_elements=2,
                              section=sc.Section.circular(radius=0.01, E=7e10, rho=7800.0))
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    for spring in springs:
        system.add_load(spring(cable.node(-1), 50.0, [0.5, -0.8, 0.0]))
    return system


@pytest.fixture(scope="module")
def systems():
    """One spring, the spring twice in one kernel, two springs."""
    return {"once": _system(CompiledNodeSpring), "twice": _system(TwiceNodeSpring),
            "two": _system(CompiledNodeSpring, CompiledNodeSpring)}


def _terms_module(step):
    """The generated terms module whose ``evaluate`` the compiled step ``step`` calls."""
    return next(module for name, module in list(sys.modules.items())
                if name.startswith("skfem_cable_terms_") and not name.endswith("_python")
                and erased.address(module.evaluate, compiled.EVALUATE) == step.terms[0])


def _arithmetic(ir):
    """The floating-point operations of an LLVM module (a kernel's work; the spring's
    ``f_ext -= k (q - anchor)``, ``data += cK k``)."""
    return re.findall(r"= (?:fadd|fsub|fmul|fdiv)\b", ir)


def test_kernels_of_one_signature_share_a_terms_module(systems):
    """Before: a terms module per sequence of kernels (their sources in its digest, their
    code linked in).  Now two kernels of one signature share one module, each system
    calling its own kernel at the address held with its terms; the two springs of the
    third system take a module of two slots, and the same trajectory as one kernel
    applying the spring twice, bit for bit."""
    steps = {k: GeneralizedAlpha(s).compiled for k, s in systems.items()}
    assert steps["once"].terms[0] == steps["twice"].terms[0]
    assert steps["once"].terms[0] != steps["two"].terms[0]
    runs = {k: sc.simulate(s, t_end=6e-3, dt=2e-3) for k, s in systems.items()}
    assert all(r.stats["path"] == "compiled" for r in runs.values())
    assert np.array_equal(runs["twice"].q, runs["two"].q)
    assert not np.array_equal(runs["once"].q, runs["two"].q)


def test_a_terms_module_holds_no_kernel_code(systems):
    """The LLVM module of a system's ``evaluate`` (compiled afresh from its source: the
    cached one keeps no IR) holds no kernel's arithmetic; the same call of the kernel made
    directly links the kernel's code in (inlined there by LLVM)."""
    module = _terms_module(GeneralizedAlpha(systems["two"]).compiled)
    fresh = njit(compiled.EVALUATE, no_cfunc_wrapper=True,
                 no_cpython_wrapper=True)(module.evaluate.py_func)
    ir = fresh.inspect_llvm(compiled.EVALUATE.args)
    assert "define" in ir and not _arithmetic(ir)

    @njit
    def linked(pack, index, ev):
        spring_kernel(pack, index, ev)

    pack = (np.arange(3), 50.0, np.zeros(3))
    args = (numba.typeof(pack), numba.typeof(np.zeros((3, 3), dtype=np.int64)),
            compiled.EVALUATE.args[1])
    linked.compile(args)
    assert _arithmetic(linked.inspect_llvm(args))


def test_interpreted_terms_module_calls_the_same_kernels(systems):
    """``compiled=False``: the same module interpreted finds each kernel from its address
    (``kernels.erased.function``) and gives the compiled run's iterates bit for bit."""
    runs = [sc.simulate(systems["two"], t_end=6e-3, dt=2e-3, compiled=c)
            for c in (None, False)]
    assert runs[1].stats["path"] == "python (compiled=False)"
    for field in ("q", "v", "a", "lam"):
        assert np.array_equal(getattr(runs[0], field), getattr(runs[1], field)), field


def test_keep_and_drop_hold_a_value_leaf_by_leaf():
    """``kernels.erased.keep`` (from Python, no function compiled for the tuple's type)
    holds a nested tuple that compiled code reads back whole (``held``); ``drop`` gives
    back every reference it took."""
    shared = np.arange(4.0)
    value = (shared, (np.full(3, 2.5), np.arange(2), 3.5, (shared, np.int64(7))), (), True)
    kind = numba.typeof(value)

    @njit
    def total(address):
        v = erased.held(address, kind)
        return v[0].sum() + v[1][0].sum() + v[1][1].sum() + v[1][2] + v[1][3][0].sum() \
            + v[1][3][1] + v[3]

    blob = np.zeros(erased.size_of(kind), dtype=np.uint8)
    before = sys.getrefcount(shared)
    erased.keep(blob.ctypes.data, value, kind)
    assert sys.getrefcount(shared) == before + 2
    assert total(blob.ctypes.data) == 6.0 + 7.5 + 1.0 + 3.5 + 6.0 + 7.0 + 1.0
    erased.drop(blob.ctypes.data, kind)
    assert sys.getrefcount(shared) == before
