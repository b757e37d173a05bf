"""One Newton iteration (issue 46, must-shows 1 and 2): the generalized-alpha iteration is
``kernels.step``, generated per system (``solvers.compiled``) and run compiled, or
interpreted from the same generated source (``compiled=False``, the debugging mode) with
the same iterates; what is Python in a system (a term's ``add`` hook, a nonlinear
constraint without kernel, the sparse LU) is called back from the compiled step, and a
restart stays bit for bit."""

import numpy as np
import pytest
from interrupting import Interrupt, InterruptingLoad
from node_spring import CompiledNodeSpring, NodeSpring

import skfem_cable as sc
from skfem_cable.core.contract import OutOfDomain
from skfem_cable.core.records import FIELDS
from skfem_cable.io import RunStore
from skfem_cable.scenes import classics
from skfem_cable.solvers import galpha, step_lu
from skfem_cable.solvers.compiled import PYTHON, source, system_source


def _pendulum(spring=NodeSpring, load=None):
    scene = classics.pendulum(n_elements=6, gamma_axial=2e-3, gamma_bending=2e-3)
    scene.system.add_load(spring(scene.cable.node(-1), 50.0, [0.5, -0.8, 0.0]))
    if load is not None:
        scene.system.add_point_load(scene.cable.node(-1), load)
    return scene


def _same_runs(a, b):
    for field in ("q", "v", "a", "lam"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    for key in ("newton", "factorizations", "steps"):
        assert a.stats[key] == b.stats[key], key


def test_there_is_one_newton_iteration():
    """The integrator has no Python Newton loop of its own: both runs execute the
    generated module of ``kernels.step``; a fully compiled system's modules hold no call
    back into Python (the step, the banded LU's module of ``solvers.step_lu``, its
    terms), a system with Python parts has one per part (the sparse LU's in its
    module)."""
    assert not hasattr(galpha.GeneralizedAlpha, "_python_step")
    compiled = source() + step_lu.source(False, False) + system_source((None, None), (None,))
    assert "objmode" not in compiled and "python_part" not in compiled
    mixed = step_lu.source(True, False) + system_source((None, PYTHON), (PYTHON,))
    for call in ("python_term(packs[1], np.int64(1),",
                 "python_constraint(packs[0], np.int64(0),",
                 "def lu_factor", "def lu_solve"):
        assert call in mixed, call


def test_a_python_term_keeps_the_compiled_step():
    """The pendulum with the ``NodeSpring`` of ``docs/extending.md`` (a Python ``add``
    hook) takes the compiled step, the term called back once per evaluation; the
    interpreted run of the same source gives the same iterates bit for bit, the compiled
    twin of the spring the same trajectory to round-off."""
    runs = [sc.simulate(_pendulum().system, t_end=0.1, dt=2e-3, compiled=c)
            for c in (None, False)]
    assert runs[0].stats["path"] == \
        "compiled (Python: term 'node spring' has a Python add hook)"
    assert runs[1].stats["path"] == "python (compiled=False)"
    _same_runs(*runs)
    twin = sc.simulate(_pendulum(CompiledNodeSpring).system, t_end=0.1, dt=2e-3)
    assert twin.stats["path"] == "compiled"
    assert np.abs(twin.q - runs[0].q).max() < 1e-13
    assert np.ptp(runs[0].q[:, -6]) > 0.01


def test_a_python_constraint_and_the_sparse_lu_are_called_back():
    """A clamp whose slope direction turns in time (``SlopeDirection``: nonlinear, no
    kernel) and the sparse LU run inside the compiled step; the interpreted run agrees
    bit for bit."""
    runs = []
    for compiled in (None, False):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sc.Section.circular(1e-2, 7e10,
                                                                              2700))
        system = sc.System([cable]).add_gravity([0, -9.81, 0])
        system.clamp(cable.node(0), direction=lambda t: [np.cos(2 * t), np.sin(2 * t), 0])
        runs.append(sc.simulate(system, t_end=0.05, dt=1e-3, method="sparse",
                                compiled=compiled))
    path = runs[0].stats["path"]
    assert path.startswith("compiled (Python: constraint 'slope direction") and \
        path.endswith("sparse LU)") and runs[0].stats["solver"] == "sparse"
    _same_runs(*runs)


def test_an_error_of_a_python_term_leaves_the_compiled_step():
    """``OutOfDomain`` raised in a Python term inside the compiled step makes the driver
    retry the step smaller, as before."""
    raised = []

    class Once:
        def bind(self, system):
            def add(ev, index):
                if ev.t > 0 and not raised:  # the first iterate of the first step
                    raised.append(ev.t)
                    raise OutOfDomain("an iterate left the domain")

            return sc.Term(add=add, name="once")

    scene = _pendulum()
    scene.system.add_load(Once())
    result = sc.simulate(scene.system, t_end=4e-3, dt=2e-3)
    assert raised and result.t[-1] == pytest.approx(4e-3) and result.stats["rejected"] >= 1


def tip_force(t):
    return [0.0, 0.0, 2.0 * np.sin(20 * t)]


@pytest.mark.parametrize("newton", ["full", "modified"])
def test_a_run_with_a_python_term_restarts_bit_for_bit(tmp_path, newton):
    """Interrupted and resumed, the pendulum with the Python spring continues bit for
    bit (its compiled step rebuilds the factor of the checkpoint)."""
    kw = dict(t_end=0.1, dt=2e-3, rho_inf=0.7, every=2, newton=newton)
    ref = sc.simulate(_pendulum(load=InterruptingLoad(tip_force)).system, **kw)
    scene = _pendulum(load=InterruptingLoad(tip_force, 0.0567))
    with pytest.raises(Interrupt):
        sc.simulate(scene.system, observers=[RunStore(tmp_path / "run", chunk=7, fields=FIELDS)],
                    **kw)
    resumed = sc.simulate(_pendulum(load=InterruptingLoad(tip_force)).system,
                          resume=RunStore.resume(tmp_path / "run"),
                          observers=[RunStore(tmp_path / "run", chunk=7)], **kw)
    assert "Python" in resumed.stats["path"]
    for name in FIELDS:
        assert np.array_equal(getattr(resumed, name), getattr(ref, name)), name
