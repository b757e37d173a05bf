"""The compiled Newton step (``solvers.compiled``): the same iterates as its interpreted
run (``compiled=False``), bit for bit (pendulums, the E-sail); the same diagnostics; the
Python parts of a system are named; the LAPACK bridge and the band LU it factors with equal
scipy's, the bordered band LU solves an arrowhead, the rigid body's constraint kernel is its
definition."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import lapack

import skfem_cable as sc
from skfem_cable.core.linalg import PatternSolver, SingularMatrixError
from skfem_cable.kernels.band_sweeps import band_lu, band_substitute
from skfem_cable.kernels.generated import source_id
from skfem_cable.kernels.lapack import ADDRESSES, band_factor, band_solve
from skfem_cable.scenes import classics, esail
from skfem_cable.solvers.galpha import GeneralizedAlpha


def _damped_pendulum():
    return classics.pendulum(n_elements=6, gamma_axial=2e-3, gamma_bending=2e-3)


def _driven_pendulum():
    """A pendulum whose pin moves on a circle (a driven linear constraint: its offset
    changes every step)."""
    sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    cable = sc.Cable.straight([0, 0, 0], [1.2, 0, 0], 6, sec)
    w = 6.0
    system = sc.System([cable]).add_gravity([0, -9.81, 0])
    a = 0.05
    system.pin(cable.node(0), target=lambda t: [a * np.sin(w * t), a * (1 - np.cos(w * t)), 0],
               velocity=lambda t: [a * w * np.cos(w * t), a * w * np.sin(w * t), 0],
               acceleration=lambda t: [-a * w**2 * np.sin(w * t), a * w**2 * np.cos(w * t), 0])
    system.add_point_mass(cable.node(-1), 0.5)
    return classics.Scene(system, cable, None)


def _lobatto_pendulum():
    return classics.pendulum(n_elements=6, formulation="lobatto")


def _paper_pendulum():
    return classics.pendulum(n_elements=6, formulation="paper")


SCENES = {"damped": _damped_pendulum, "driven": _driven_pendulum,
          "lobatto": _lobatto_pendulum, "paper": _paper_pendulum}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_compiled_step_gives_the_python_iterates(name):
    """Trajectories, multipliers and Newton counts of both paths are identical (the
    compiled loop does the same sums in the same order)."""
    scene = SCENES[name]()
    runs = [sc.simulate(scene.system, t_end=0.2, dt=2e-3, initial=scene.initial,
                        compiled=c) for c in (True, False)]
    assert runs[0].stats["path"] == "compiled"
    assert runs[1].stats["path"] == "python (compiled=False)"
    for field in ("q", "v", "a", "lam"):
        assert np.array_equal(getattr(runs[0], field), getattr(runs[1], field)), field
    for key in ("newton", "factorizations", "steps"):
        assert runs[0].stats[key] == runs[1].stats[key]
    assert np.ptp(runs[0].q[:, -6]) > 0.01  # the tip moved


def test_full_newton_is_compiled_too():
    scene = _damped_pendulum()
    runs = [sc.simulate(scene.system, t_end=0.05, dt=2e-3, newton="full", compiled=c)
            for c in (True, False)]
    assert np.array_equal(runs[0].q, runs[1].q)
    assert runs[0].stats["factorizations"] == runs[0].stats["newton"] + 1


class _Push:
    """A user load with a Python hook: a force along y on the tip, sin(t)."""

    def __init__(self, cable):
        self.cable = cable

    def bind(self, system):
        tip = system.dofs(self.cable.node(-1))[1]

        def add(ev, index):
            ev.f_ext[tip] += np.sin(ev.t)

        return sc.Term(add=add, name="push")


def test_a_force_of_time_stays_on_the_compiled_step():
    """Before: a point load given as a function of time had a Python hook and made the
    Python step.  Now it is a compiled kernel refreshed once per step, with the Python
    step's iterates."""
    runs = []
    for compiled in (None, False):
        scene = _damped_pendulum()
        scene.system.add_point_load(scene.cable.node(-1), lambda t: [0.0, np.sin(t), 0.0])
        runs.append(sc.simulate(scene.system, t_end=0.02, dt=1e-3, compiled=compiled))
    assert runs[0].stats["path"] == "compiled" and runs[1].stats["path"].startswith("python")
    np.testing.assert_allclose(runs[0].q, runs[1].q, rtol=0, atol=1e-14)


def test_python_parts_of_the_compiled_step_are_named():
    """A load with a Python hook is called back from the compiled step, which names it
    (before issue 46 it sent the system to a Python step); ``compiled=True`` runs it."""
    scene = _damped_pendulum()
    scene.system.add_load(_Push(scene.cable))
    for compiled in (None, True):
        r = sc.simulate(scene.system, t_end=2e-3, dt=1e-3, compiled=compiled)
        assert r.stats["path"] == "compiled (Python: term 'push' has a Python add hook)"
    with pytest.raises(ValueError, match="compiled must be None, True or False"):
        sc.simulate(scene.system, t_end=2e-3, dt=1e-3, compiled="yes")


def test_compiled_failure_keeps_the_diagnostic():
    """A step that cannot converge in one iteration reports the residual history and the
    worst unknown, as the Python step does."""
    scene = _damped_pendulum()
    messages = []
    for compiled in (True, False):
        with pytest.raises(sc.SimulationError) as info:
            sc.simulate(scene.system, t_end=0.1, dt=0.05, max_iter=1, max_halvings=0,
                        compiled=compiled)
        messages.append(str(info.value))
    assert messages[0] == messages[1]
    assert "no convergence" in messages[0] and "scaled residual history" in messages[0]
    assert "largest dynamic residual at" in messages[0]


def _banded(n, kl, seed):
    rng = np.random.default_rng(seed)
    A = np.zeros((n, n))
    for i in range(n):
        lo, hi = max(0, i - kl), min(n, i + kl + 1)
        A[i, lo:hi] = rng.normal(size=hi - lo)
    ab = np.zeros((3 * kl + 1, n))
    for j in range(n):
        for i in range(max(0, j - kl), min(n, j + kl + 1)):
            ab[2 * kl + i - j, j] = A[i, j]
    return A, ab


def test_band_kernels_are_lapack():
    """``kernels.lapack`` calls scipy's own dgbtrf/dgbtrs: identical factors and
    solutions, and the 1-based column of a zero pivot."""
    A, ab = _banded(40, 3, seed=1)
    lu, piv, info = lapack.dgbtrf(ab.copy(), 3, 3)
    mine = np.ascontiguousarray(ab.T)
    ipiv = np.zeros(40, dtype=np.int32)
    ints = np.zeros(8, dtype=np.int32)
    assert band_factor(ADDRESSES, mine, 3, 3, ipiv, ints) == info == 0
    assert np.array_equal(mine.T, lu) and np.array_equal(ipiv, piv + 1)
    b = np.arange(40.0)
    x = b.copy()
    assert band_solve(ADDRESSES, mine, 3, 3, ipiv, x, ints) == 0
    assert np.array_equal(x, lapack.dgbtrs(lu, 3, 3, b, piv)[0])
    assert np.abs(A @ x - b).max() < 1e-10 * np.abs(b).max() * np.linalg.cond(A)
    ab[:, 7] = 0.0  # column 8 (1-based) vanishes
    singular = np.ascontiguousarray(ab.T)
    assert band_factor(ADDRESSES, singular, 3, 3, ipiv, ints) == 8


@pytest.mark.parametrize("n, kl", [(40, 3), (105, 11), (60, 13), (9, 5), (30, 1), (12, 0)])
def test_band_lu_is_lapacks_factor(n, kl):
    """``band_sweeps.band_lu`` (``dgbtf2`` as loops) makes scipy's ``dgbtrf`` pivots and
    factor, with row interchanges (tiny first diagonals) and without, and the 1-based
    column of a zero pivot.  The factor to round-off: bit for bit where scipy's OpenBLAS
    fuses its ``daxpy`` (x86-64 with FMA, this machine's), which other builds need not."""
    _, ab = _banded(n, kl, seed=n + kl)
    ab[2 * kl, :3] = 1e-3  # row interchanges in the first columns
    for matrix in (ab, np.where(np.arange(n) == 7, 0.0, ab)):  # column 8 vanishes
        lu, piv, info = lapack.dgbtrf(matrix.copy(), kl, kl)
        mine = np.ascontiguousarray(matrix.T)
        ipiv = np.zeros(n, dtype=np.int32)
        assert band_lu(mine, kl, ipiv) == info
        assert np.array_equal(ipiv, piv + 1)
        np.testing.assert_allclose(mine.T, lu, rtol=0, atol=1e-13 * np.abs(lu).max())
        assert kl == 0 or np.any(ipiv != np.arange(1, n + 1))
    assert info == 8


@pytest.mark.parametrize("voltage", [20e3, lambda t: 20e3 * (1.0 + 0.5 * np.sin(0.05 * t))],
                         ids=["constant", "modulated"])
def test_esail_takes_the_compiled_step(voltage):
    """The E-sail (tethers, solar wind with a constant or modulated voltage, hub with its
    rigid-body constraints through their compiled kernel, pins) takes the compiled step
    with the hub as the border of the band: the same iterates as the Python step."""
    cfg = esail.BaselineConfig(n_tethers=4, voltage=voltage)
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=3)
    runs = [sc.simulate(scene.system, t_end=3.0, dt=0.1, rho_inf=0.25, initial=scene.initial,
                        compiled=c) for c in (True, False)]
    assert runs[0].stats["path"] == "compiled" and runs[0].stats["solver"] == "banded"
    for field in ("q", "v", "lam"):
        assert np.array_equal(getattr(runs[0], field), getattr(runs[1], field)), field
    solver = GeneralizedAlpha(scene.system).solver
    assert solver.border == 12 + 6 and solver.band <= 13  # hub coordinates, rigid rows


def test_bordered_lu_solves_an_arrowhead():
    """A band with a dense border (unknowns ordered last) against a dense solve; a
    singular Schur complement is located at its unknown."""
    n, kl, border = 60, 2, [7, 31]
    rng = np.random.default_rng(3)
    A = np.zeros((n, n))
    for i in range(n):
        lo, hi = max(0, i - kl), min(n, i + kl + 1)
        A[i, lo:hi] = rng.normal(size=hi - lo)
    A[border, :] = rng.normal(size=(2, n))
    A[:, border] = rng.normal(size=(n, 2))
    A += n * np.eye(n)
    pattern = sp.csr_matrix(np.ones((n, n)) * (A != 0))
    solver = PatternSolver(pattern.indptr, pattern.indices, "banded", border=border)
    assert solver.border == 2 and solver.band <= 2 * kl + 1
    data = np.asarray(A[pattern.nonzero()]).ravel()
    solver.factor(data)
    b = rng.normal(size=n)
    assert np.abs(solver.solve(b) - np.linalg.solve(A, b)).max() < 1e-12
    A[31, :] = 0.0  # a vanishing border row: the Schur complement is singular there
    with pytest.raises(SingularMatrixError) as info:
        solver.factor(np.asarray(A[pattern.nonzero()]).ravel())
    assert info.value.index == 31


def test_border_of_every_unknown_is_a_dense_solve():
    """A border that holds every unknown (a system of one hub): no band is left, and the
    Schur complement is the whole matrix (reverse Cuthill-McKee failed on the empty
    rest)."""
    A = np.array([[4.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 4.0]])
    pattern = sp.csr_matrix(A)
    solver = PatternSolver(pattern.indptr, pattern.indices, "banded", border=[0, 1, 2])
    assert (solver.border, solver.band) == (3, 0)
    solver.factor(pattern.data)
    b = np.array([1.0, -2.0, 0.5])
    assert np.abs(solver.solve(b) - np.linalg.solve(A, b)).max() < 1e-14


def test_rigid_constraint_kernel_matches_its_definition():
    """The compiled hook of the rigid body's constraints writes ``scale C``, adds
    ``C_q^T lam`` and the scaled Jacobians and ``cK`` Hessian term, as ``value``,
    ``jacobian`` and ``hessian`` define them."""
    cfg = esail.BaselineConfig(n_tethers=3)
    scene = esail.build(cfg, alpha_deg=0.0, n_elements=2)
    system = scene.system
    lay = system.layout
    k = lay.nonlinear[0]
    c = system.constraints[k]
    rng = np.random.default_rng(5)
    q = system.q0 + 1e-2 * rng.normal(size=system.n_dofs)
    lam = rng.normal(size=lay.n_c)
    d, rows = lay.cdofs[k], lay.crows[k]
    r_c, f_con, data = np.zeros(lay.n_c), np.zeros(system.n_dofs), np.zeros(lay.nnz)
    function, pack = c.kernel
    function(pack, lay.cindex[k], (q, lam, np.array([0.0, 0.3, 2.0]), r_c, f_con, data))
    J = c.jacobian(q[d])
    assert r_c[rows] == pytest.approx(2.0 * c.value(q[d]), abs=1e-14)
    assert f_con[d] == pytest.approx(J.T @ lam[rows], rel=1e-13, abs=1e-13)
    assert data[lay.jac_index[k]] == pytest.approx(2.0 * J.ravel(), rel=1e-13, abs=1e-13)
    assert data[lay.jacT_index[k]] == pytest.approx(2.0 * J.T.ravel(), rel=1e-13, abs=1e-13)
    H = c.hessian(q[d], lam[rows])
    assert data[lay.hess_index[k]] == pytest.approx(0.3 * H.ravel(), rel=1e-13, abs=1e-13)


def test_newton_stops_at_a_share_of_the_local_error():
    """``tol_local``: Newton stops once its residual and correction are a hundredth of
    the step's estimated local error: fewer iterations (0.95 of the default's, which already
    stops on corrections whose estimated error is below ``tol``, starts steps from a fresh
    tangent where the stale one fails and predicts the unresolved modes; 0.91 before that
    predictor, 0.81 before the fresh tangents), the same accuracy against a tight
    reference, and the same iterates on both paths."""
    scene = classics.pendulum(n_elements=8)
    ref = sc.simulate(scene.system, t_end=0.3, dt=1e-4, every=10**6, tol=1e-12)
    runs = {key: sc.simulate(scene.system, t_end=0.3, dt=1e-3, every=10**6, **kw)
            for key, kw in (("tol", {}), ("local", {"tol_local": 1e-2}),
                            ("python", {"tol_local": 1e-2, "compiled": False}))}
    assert np.array_equal(runs["local"].q, runs["python"].q)
    assert runs["local"].stats["newton"] < 0.97 * runs["tol"].stats["newton"]
    errors = {k: np.abs(r.q[-1] - ref.q[-1]).max() for k, r in runs.items()}
    assert errors["local"] < 1.05 * errors["tol"]


def test_band_substitution_is_lapacks_solve():
    """``band_sweeps.band_substitute`` (one right-hand side, loops over contiguous slices)
    solves with dgbtrf's factor as dgbtrs does, to round-off, with row interchanges."""
    A, ab = _banded(40, 3, seed=2)
    lu, piv, info = lapack.dgbtrf(ab.copy(), 3, 3)
    assert info == 0 and np.any(piv != np.arange(40))
    b = np.arange(40.0)
    x = b.copy()
    band_substitute(np.ascontiguousarray(lu.T), 3, piv + 1, x)
    expected = lapack.dgbtrs(lu, 3, 3, b, piv)[0]
    assert np.abs(x - expected).max() < 1e-13 * np.abs(expected).max()


def test_newton_ends_on_a_correction_whose_error_estimate_is_below_tol():
    """Most E-sail steps end after one correction (its predictor is within about 4e-11 of
    the system size; the error estimate ``eta |dx|`` is below ``tol``): fewer than 1.2
    corrections per step (1.02 measured; 2 when the residual had to be evaluated at the
    accepted iterate), and positions within 1e-12 of the system size (3e-14 measured) of a
    run iterated to ``tol = 1e-14``."""
    cfg = esail.BaselineConfig(n_tethers=4)
    scene = esail.build(cfg, alpha_deg=10.0, n_elements=3)
    runs = [sc.simulate(scene.system, t_end=5.0, dt=0.1, rho_inf=0.25, initial=scene.initial,
                        tol=tol, every=10**6) for tol in (1e-11, 1e-14)]
    assert runs[0].stats["newton"] < 1.2 * runs[0].stats["steps"]
    size = scene.system.layout.length_scale
    assert np.abs(runs[0].q[-1] - runs[1].q[-1]).max() < 1e-12 * size


HELPERS = '''from numba import njit


@njit
def inner(x):
    return 2.5 * x


@njit
def scale(x):
    return inner(x) + 1.0
'''

KERNEL = '''from numba import njit

import digest_helpers as helpers
from digest_helpers import inner


@njit
def kernel(pack, index, ev):
    ev[3][0] += helpers.scale(1.0) + inner(2.0)
'''


def test_generated_module_digest_covers_the_kernels_compiled_callees(tmp_path, monkeypatch):
    """A user kernel's compiled helpers, named directly or through their module, and
    theirs in turn, are part of the generated step module's digest: numba's cache of that
    module would not notice a changed helper."""
    (tmp_path / "digest_helpers.py").write_text(HELPERS)
    (tmp_path / "digest_kernel.py").write_text(KERNEL)
    monkeypatch.syspath_prepend(str(tmp_path))
    import digest_kernel

    text = source_id(digest_kernel.kernel)
    for part in ("def kernel", "def scale", "def inner", "2.5 * x"):
        assert part in text, part
    assert text.count("def inner") == 1


def test_parameter_slots_are_named_in_order():
    """The compiled step's parameter vector is read through named slots; the generated
    module gets the same names and values as the template."""
    from skfem_cable.kernels import step
    from skfem_cable.solvers.compiled import source

    assert [getattr(step, name) for name in step.PRM_SLOTS] == list(range(len(step.PRM_SLOTS)))
    header = f"{', '.join(step.PRM_SLOTS)} = range({len(step.PRM_SLOTS)})"
    assert header in source()
