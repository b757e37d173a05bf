"""Adaptive steps (``simulate(..., rtol=, atol=)``): the error follows the tolerance, the
run ends exactly at ``t_end``, an interrupted adaptive run resumes bit for bit, and bad
tolerances are refused."""

import numpy as np
import pytest
from interrupting import Interrupt, InterruptingLoad

import skfem_cable as sc
from skfem_cable.cli.bench import largest_position_error
from skfem_cable.io import RunStore
from skfem_cable.scenes import classics


def _no_force(t):
    return [0.0, 0.0, 0.0]


def _pendulum(stop_at=None):
    scene = classics.pendulum(n_elements=6, gamma_axial=1e-4)
    if stop_at is not None:
        scene.system.add_point_load(scene.cable.node(-1), InterruptingLoad(_no_force, stop_at))
    return scene


def test_adaptive_error_follows_the_tolerance():
    """The global error follows the tolerance (the proportionality transform of
    ``GeneralizedAlpha``): over three decades of ``rtol = atol`` the largest error of the
    nodes' positions over 0.5 s, against a fixed-step reference (dt = 2.5e-5), stays
    within a factor 3 of a constant times the tolerance; tighter tolerances take more and
    smaller steps, some rejected."""
    scene = _pendulum()
    ref = sc.simulate(scene.system, t_end=0.5, dt=2.5e-5, every=1, tol=1e-12)
    nodes = scene.cable.mesh.p[0]
    ratios, steps = [], []
    for tol in (1e-3, 1e-4, 1e-5, 1e-6):
        r = sc.simulate(scene.system, t_end=0.5, dt=1e-3, every=1, rtol=tol, atol=tol)
        assert r.t[-1] == 0.5
        assert r.stats["h_min"] < r.stats["h_max"] and r.stats["rejected"] > 0
        ratios.append(largest_position_error(r, ref, scene.cable, nodes) / tol)
        steps.append(r.stats["steps"])
    # measured 7.5, 6.9, 5.7, 5.1 in 31, 135, 698, 4127 steps (without the transform
    # 7.5, 6.6, 33, 57 in 31, 80, 230, 700 steps)
    assert max(ratios) < 3 * min(ratios)
    assert max(ratios) < 20
    assert steps == sorted(steps) and len(set(steps)) == len(steps)


def test_interrupted_adaptive_run_resumes_bit_for_bit(tmp_path):
    kw = dict(t_end=0.2, dt=1e-3, rtol=1e-5, atol=1e-5, every=3)
    ref = sc.simulate(_pendulum().system, **kw)
    scene = _pendulum(stop_at=0.1234)
    with pytest.raises(Interrupt):
        sc.simulate(scene.system, observers=[RunStore(tmp_path / "run", chunk=4)], **kw)
    resumed = sc.simulate(_pendulum(stop_at=1.0).system, resume=RunStore.resume(tmp_path / "run"),
                          observers=[RunStore(tmp_path / "run", chunk=4)], **kw)
    assert len(resumed.t) == len(ref.t)
    for name in ("t", "q", "v", "lam"):
        assert np.array_equal(getattr(resumed, name), getattr(ref, name)), name


@pytest.mark.parametrize("kwargs, match", [
    ({"rtol": 1e-6}, "atol must be a number > 0"),
    ({"atol": 1e-6}, "rtol must be a number > 0"),
    ({"rtol": 1.5, "atol": 1e-6}, "rtol must be < 1"),
    ({"rtol": 1e-6, "atol": -1.0}, "atol must be a number > 0"),
])
def test_bad_tolerances_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sc.simulate(_pendulum().system, t_end=0.01, dt=1e-3, **kwargs)


def test_adaptive_steps_do_not_depend_on_the_frame():
    """The same pendulum turned about the vertical takes the same adaptive steps to the
    same motion, turned: the local error and its tolerance are taken on each 3-vector's
    length, and the system's size is its diameter about the centroid (per component and
    with the bounding box, turning it by 30 deg changed the steps, 194 against 208)."""
    sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0, gamma_axial=1e-4)
    runs, c, s = [], np.cos(np.pi / 6), np.sin(np.pi / 6)
    turn = np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])  # about y, x to (c, 0, s)
    for R in (np.eye(3), turn):
        cable = sc.Cable.straight([0, 0, 0], R @ [1.2, 0, 0], 6, sec)
        system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
        runs.append(sc.simulate(system, t_end=0.3, dt=1e-3, every=10**6, rtol=1e-5,
                                atol=1e-5))
    assert runs[0].stats["steps"] == runs[1].stats["steps"] > 100
    assert runs[0].stats["rejected"] == runs[1].stats["rejected"]
    turned = runs[0].q[-1].reshape(-1, 3) @ turn.T
    np.testing.assert_allclose(runs[1].q[-1].reshape(-1, 3), turned, atol=1e-9)


def test_error_ratio_measures_vectors_by_their_length():
    """``kernels.error.error_ratio``: the error of each 3-vector by its length against
    ``atol + rtol max(|q0|, |q1|)`` of its length, a scalar coordinate by its own size;
    the same ratio in any frame (rotated vectors, to round-off)."""
    from scipy.spatial.transform import Rotation

    from skfem_cable.kernels.error import error_ratio

    rng = np.random.default_rng(3)
    q0, q1, abar1, abar = rng.normal(size=(4, 10))
    vectors, scalars = np.arange(9).reshape(3, 3), np.array([9])
    atol = np.repeat([1e-3, 1e-4, 1e-3, 2e-3], [3, 3, 3, 1])
    e = 0.3 * (abar1 - abar)
    expected = max([np.linalg.norm(e[v]) / (atol[v[0]] + 1e-2 * max(
        np.linalg.norm(q0[v]), np.linalg.norm(q1[v]))) for v in vectors]
        + [abs(e[9]) / (atol[9] + 1e-2 * max(abs(q0[9]), abs(q1[9])))])
    ratio = error_ratio(q0, q1, abar1, abar, 0.3, vectors, scalars, atol, 1e-2)
    assert ratio == pytest.approx(expected, rel=1e-14)
    R = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()

    def turned(x):
        return np.concatenate([(x[:9].reshape(3, 3) @ R.T).ravel(), x[9:]])

    assert error_ratio(turned(q0), turned(q1), turned(abar1), turned(abar), 0.3, vectors,
                       scalars, atol, 1e-2) == pytest.approx(ratio, rel=1e-13)
