"""The measures of issue 47's linear cost and floor (``benchmarks/step_exponent.py``,
``benchmarks/esail_floor.py``): the exponent fitted to the minima over rounds with its
spread and halves, and the work counted of the bordered band LU.  No timing is
asserted."""

import numpy as np
import scipy.sparse as sp
from test_benchmarks import BENCH, load

from skfem_cable.core.linalg import ADDRESSES
from skfem_cable.kernels import bordered


def test_exponent_is_fitted_to_the_minima_over_rounds():
    """A cost growing as ``n^1.02`` in every round, one round slowed in one chunk of its
    largest size: the exponent of the chunks' minima is 1.02 (standard error 0 on an
    exact power law), the slowed round widens the range of the single rounds only."""
    exponent = load(BENCH / "step_exponent.py")
    sizes = np.array([1000, 1800, 3200, 5600, 10000])
    steps, chunk = 200, 20
    cost = 1e-3 * (sizes / 1000) ** 1.02
    times = np.empty((3, sizes.size, steps // chunk))
    times[:] = chunk * cost[:, None]
    times[1, -1, 4] *= 4.0  # a slow spell in one chunk of the largest size
    fit = exponent.exponents(sizes, times, np.full(sizes.size, 2.4 * steps), steps)
    slope, error = fit["per_step"]
    assert abs(slope - 1.02) < 1e-12 and error < 1e-12
    low, high = fit["rounds_range"]
    assert abs(low - 1.02) < 1e-12 and high > 1.1
    assert abs(fit["per_iteration"][0] - 1.02) < 1e-12
    assert abs(fit["ends"] - 1.02) < 1e-12


def test_exponent_halves_are_those_of_the_even_and_odd_processes():
    """``step_exponent.interleaved``: the rounds of four processes, round ``r`` of process
    ``p`` at ``4 r + p``, so that the halves of ``exponents`` (the even and the odd rounds)
    are the minima over the even and over the odd processes: the odd processes slow at
    the largest size all along (a draw of the layout, a spell of the machine) move their
    half only."""
    exponent = load(BENCH / "step_exponent.py")
    sizes = np.array([1000, 3200, 10000])
    steps, chunk = 40, 20
    runs = [np.empty((3, sizes.size, steps // chunk)) for _ in range(4)]
    for p, run in enumerate(runs):
        run[:] = (chunk * 1e-3 * (sizes / 1000) ** 1.01)[:, None]
        run[:, -1] *= 1.2 if p % 2 else 1.0
    times = exponent.interleaved(runs)
    assert times.shape == (12, 3, 2) and np.array_equal(times[4 * 2 + 1], runs[1][2])
    even, odd = exponent.exponents(sizes, times, np.full(3, 2.4 * steps), steps)["halves"]
    assert abs(even - 1.01) < 1e-12 and odd > even + 0.05


def test_the_exponents_processes_run_the_package_of_the_caller(tmp_path, monkeypatch):
    """``step_exponent.apart`` started in another tree's folder (a side-by-side
    comparison): its fresh processes import the package the caller imported, not the
    folder's, which is first on a child's path."""
    exponent = load(BENCH / "step_exponent.py")
    (tmp_path / "skfem_cable").mkdir()
    (tmp_path / "skfem_cable" / "__init__.py").write_text("raise ImportError('a decoy')\n")
    monkeypatch.chdir(tmp_path)
    times, newton = exponent.apart((8,), 20, 1, 2)
    assert times.shape == (2, 1, 1) and np.all(times > 0) and newton[0] >= 20


def test_band_work_is_counted_from_the_storage():
    """A tridiagonal-by-blocks band of half-width 2 without border: a factorization of
    ``4 n b^2`` flops and a solve of ``6 n b`` (``esail_floor.band_flops``)."""
    floor = load(BENCH / "esail_floor.py")
    n, band = 50, 2
    pattern = sp.diags([np.ones(n - abs(k)) for k in range(-band, band + 1)],
                       list(range(-band, band + 1)), format="csr")
    rows = np.repeat(np.arange(n), np.diff(pattern.indptr))
    lu = bordered.storage(ADDRESSES, rows, pattern.indices, np.arange(n), n, band)
    assert floor.band_flops(lu) == (4 * n * band**2, 6 * n * band)


def test_a_tangent_costs_more_than_a_residual():
    """The counted work of an element's tangent exceeds its residual's, in both kernels."""
    floor = load(BENCH / "esail_floor.py")
    assert floor.cable_flops(4, 5, 3, True) > 2 * floor.cable_flops(4, 5, 3, False) > 0
    assert floor.coulomb_flops(4, 5, True) > 2 * floor.coulomb_flops(4, 5, False) > 0
