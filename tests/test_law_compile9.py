"""What a law module compiles (issue 47, item 5): its point functions apart and inlined by
LLVM (not by numba, which compiled one large ``span`` more slowly than its parts), no
threaded loop for a run on one thread, and one module for a law that is its own part."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import laws
from skfem_cable.kernels.compile_log import Recorder
from skfem_cable.laws import codegen

TRUSS = laws.BUILTIN["truss"]


@pytest.fixture(scope="module")
def serial_run():
    """The compilations of the truss law's Gauss module (shared with tests/test_laws.py)
    while a pinned 4-element truss cable is assembled on one thread: none if this process
    or the cache held them already."""
    recorder = Recorder().install()
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sc.Section(E=1e9, A=1e-6, I=1e-12, rho=1e3),
                              law="truss", formulation="paper")
    system = sc.System([cable])
    recorder.take()
    f, _ = system.assemble(cable.q0 * 1.01, np.zeros(cable.n_dofs))
    return f, [name for name, _, _ in recorder.take()], TRUSS.compiled()


def test_a_serial_run_compiles_no_threaded_loop(serial_run):
    f, compiled, module = serial_run
    assert np.isfinite(f).all() and abs(f).max() > 0
    assert not [name for name in compiled if name.endswith("_parallel")]
    assert codegen.loop().kernel.signatures


def test_one_element_loop_serves_every_law():
    """The laws' modules hold their ``span`` and point functions, not the element loop:
    every law's hook is the one loop's (compiled once per machine, not once per law: 30
    compilations and 22 s of CPU of a cold test run), calling the law's own ``span`` at
    the address its pack ends with."""
    hooks = [laws.BUILTIN[name].hook("gauss", (0, 1), threads)
             for name in ("truss", "cable") for threads in (1, 2)]
    loop = codegen.loop()
    assert [function for function, _ in hooks] == [loop.kernel, loop.kernel_parallel] * 2
    assert hooks[0][1] == hooks[1][1] != hooks[2][1] == hooks[3][1]
    for name in ("truss", "cable"):
        assert not hasattr(laws.BUILTIN[name].compiled(), "kernel")


def test_point_functions_are_inlined_by_llvm_not_by_numba(serial_run):
    """Each point function is a dispatcher of its own (LLVM's ``forceinline``, not numba's
    ``inline="always"``), left out of the cache: ``span``'s cached code holds it."""
    *_, module = serial_run
    for name in ("point_g", "point_gh", "point_gd", "point_ghd"):
        options = getattr(module, name).targetoptions
        assert options.get("forceinline") and "inline" not in options, name
        assert getattr(module, name).stats.cache_path is None, name
    assert module.span.stats.cache_path is not None


def test_a_law_without_bending_is_its_own_axial_part():
    """The truss law (no ``b``) on the Lobatto rule: its axial part is the law itself, one
    module and one name, not a second module of the same expressions."""
    assert TRUSS.part(0) is TRUSS
    assert TRUSS.part(1).vanishes and TRUSS.part(1) is not TRUSS
    cable_law = laws.BUILTIN["cable"]
    assert cable_law.part(0) is not cable_law and cable_law.part(0).name == "cable-axial"
    assert codegen.module_name(TRUSS.part(0)) == codegen.module_name(TRUSS)


def test_an_edit_of_the_generator_renames_every_module(monkeypatch):
    """The module's digest holds the generator's own text: a cache that keeps the modules
    of an earlier commit (the CI machine's does) never serves them to an edited generator,
    whatever its ``GENERATOR``; the text is read once per process."""
    before = codegen.module_name(TRUSS)
    assert codegen._generator_id() is codegen._generator_id()
    assert "def _generator_id" in codegen._generator_id()
    monkeypatch.setattr(codegen, "_generator_id", lambda: "the generator, edited")
    assert codegen.module_name(TRUSS) != before
