"""Each demo imported at reduced size, checking one number (scikit-fem's habit)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc

DEMOS = Path(__file__).resolve().parents[1] / "demos"


def load(name):
    spec = importlib.util.spec_from_file_location(f"demo_{name}", DEMOS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_cantilever_demo():
    (row,) = load("cantilever").main(n_elements=8, ks=(2.0,))
    assert row["rel_error"] < 1e-2


def test_pendulum_demo():
    """Quarter period of the nearly rigid cable within 1e-3 of the compound pendulum."""
    out = load("pendulum").main(n_elements=4, dt=2e-3)
    assert out["quarter_period"] == pytest.approx(out["rigid_quarter_period"], rel=1e-3)


def test_spinning_tether_demo():
    """Radial oscillation period within 3 % of the spring-mass estimate."""
    out = load("spinning_tether").main(n_elements=4, t_end=0.5)
    assert out["radial_period"] == pytest.approx(out["radial_period_spring"], rel=0.03)


def test_custom_element_density_and_forces():
    """The tutorial's density has the gradient and Hessian of its energy (finite
    differences), and a uniformly stretched element pulls its end with EA (stretch - 1)."""
    demo = load("custom_element")
    rng = np.random.default_rng(1)
    a, b = rng.standard_normal(3) + [1.0, 0, 0], rng.standard_normal(3)
    W, G, H = demo.biot_density(a, b, 3.0, 0.7)
    h = 1e-6
    x = np.concatenate([a, b])
    for i in range(6):
        dx = h * np.eye(6)[i]
        Wp, Gp, _ = demo.biot_density(*np.split(x + dx, 2), 3.0, 0.7)
        Wm, Gm, _ = demo.biot_density(*np.split(x - dx, 2), 3.0, 0.7)
        assert (Wp - Wm) / (2 * h) == pytest.approx(G[i], rel=1e-6, abs=1e-8)
        assert np.allclose((Gp - Gm) / (2 * h), H[i], rtol=1e-5, atol=1e-7)
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    bar = demo.BiotCable.straight([0, 0, 0], [1, 0, 0], 1, section)
    q = bar.q0.copy()
    q[0::6] *= 1.3
    q[3::6] = 1.3
    f, _ = sc.System([bar]).evaluate(q, None, 0.0, np.zeros(0))
    assert f[6] == pytest.approx(0.3 * section.EA, rel=1e-12)


def test_custom_element_demo():
    """With the engineering strain the pulled bar stretches by exactly P L / EA (the Green
    cable by 0.088): the system evaluates the subclass's own forces."""
    out = load("custom_element").main(n_elements=8)
    assert out["stretch_biot"] == pytest.approx(0.1, rel=1e-8)
