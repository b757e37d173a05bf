"""The benchmark scripts at small sizes: each test checks one figure of its run that would
catch a regression (an accuracy reached, a growth exponent, Newton iterations, a ratio
with a wide margin), never an absolute time.  And ``skfem-cable bench`` streams the
scripts' output, passes ``--quick`` on and writes a JSON record per run."""

import importlib.util
import json
import sys
import textwrap
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from skfem_cable.cli import bench
from skfem_cable.cli import command as cli

ROOT = Path(__file__).parents[1]
BENCH = ROOT / "benchmarks"


def load(path):
    """Import a script (a benchmark or ``tasks.py``) by its path."""
    path = Path(path)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_cantilever_error_level():
    """16 elements reach a relative tip error below 7e-4 at ``k = 5`` (5.6e-4 measured)."""
    rows = load(BENCH / "cantilever_convergence.py").table(ks=(5,), elements=(16,))
    assert rows[0]["errors"][5] < 7e-4


def test_kernel_cost_is_linear():
    """The structure that makes the cost linear, from 100 to 10,000 elements: every size is
    solved by the banded LU with the same band (the cable's 11: ``core.ordering``), so
    factor and solve cost O(n), like the element loop.  The timed growth exponents are the
    benchmark's to print (about 1; a timed bound failed under load), not a test's to
    assert."""
    figures = load(BENCH / "kernel_cost.py").table((100, 1000, 10000))
    assert {(r["solver"], r["band"]) for r in figures["rows"]} == {("banded", 11)}
    assert all(np.isfinite(list(figures["growth_exponents"].values())))


def test_rodchain_solve_table():
    """The O(n) mass solve of the rod chain agrees with the sparse LU at 10^4 to 10^5 rods
    (the benchmark asserts it) and with the dense LU at 300 rods to 1e-10, the dense LU's own
    error ``n^2 eps`` (3.9e-12 measured).  The growth exponent (about 1) is the benchmark's
    to print: the suite runs on every core, and a timed bound would measure the other
    workers, and the test times each solver once per repeat: ``budget=0``)."""
    figures = load(BENCH / "rodchain_speed.py").solve_table([300, 10_000, 100_000], budget=0)
    assert figures["rows"][0]["diff_to_lu"] < 1e-10
    assert np.isfinite(figures["growth_exponent"])


def test_law_benchmark_runs_on_this_tree(tmp_path, monkeypatch, capsys):
    """The snippets of ``benchmarks/laws.py`` (run in this process, not in fresh ones as
    the benchmark does), on a 4-element cable: the generated kernel of the built-in law
    gives the force and tangent of the scikit-fem forms (the benchmark's own check, to
    1e-12 of the largest entry), and the one-off costs of a law are measured (the
    snippets had fallen behind the API twice unseen: a law module's ``force_tangent``,
    ``System.evaluate``'s ``layout``)."""
    laws = load(BENCH / "laws.py")

    def run(snippet, *args):
        monkeypatch.setattr(sys, "argv", ["snippet", *map(str, args)])
        exec(compile(snippet, "snippet", "exec"), {"__name__": "snippet"})
        return json.loads(capsys.readouterr().out.strip().splitlines()[-1])

    for case in ("kernel", "forms"):
        out = run(laws.EVALUATE, case, 4, 0.0, tmp_path / case)
        assert out["calls"] >= 3 and out["ms"] > 0.0
    assert max(laws.relative_difference(tmp_path / "forms", tmp_path / "kernel")) < 1e-12
    costs = run(laws.ONE_OFF, "builtin")
    assert all(costs[key] >= 0.0 for key in ("import", "sym", "gen", "jit"))


def test_compiled_step_is_faster_than_python():
    """At 10 elements the compiled step takes less than the interpreted run of the same
    generated source (``compiled=False``): a ratio at 1 means the compiled path is lost.
    One size: the interpreted step runs plain-Python loops, and larger sizes only cost; a
    span of 20 ms of steps (the benchmark's 0.2 s ran the interpreted path for 40 s: the
    ratio is far below 1 either way) and one run of each (0.04-0.06 measured with the least
    of 3 runs and with one: a single run would have to be 17 times off to fail)."""
    rows = load(BENCH / "step_cost.py").table((10,), steps=50, repeats=1, span=0.02)["rows"]
    assert rows[0]["ratio"] < 1.0


@pytest.fixture(scope="module")
def pendulum_rows():
    """One fixed-step and one adaptive row of 4 elements against 16 elements at
    ``dt = 2.5e-4 s``."""
    figures = load(BENCH / "pendulum_speed_error.py").table(
        elements=(4,), steps=(2e-3,), reference=(16, 2.5e-4), tolerances=(1e-4,))
    return figures["rows"]


def test_pendulum_fixed_step_error(pendulum_rows):
    """``dt = 2e-3 s``: tip error at t = 1 s below 1e-4 m (6.2e-5 measured)."""
    fixed = next(r for r in pendulum_rows if "dt" in r)
    assert fixed["error"] < 1e-4


def test_pendulum_adaptive_error(pendulum_rows):
    """``rtol = atol = 1e-4``: tip error at t = 1 s below 2e-4 m (6.2e-5 measured with the
    proportionality transform, 1.0e-3 before it; the global error of adaptive steps moves
    within about a factor 2 when Newton starts elsewhere)."""
    adaptive = next(r for r in pendulum_rows if "tol" in r)
    assert adaptive["error"] < 2e-4


@pytest.mark.slow
def test_esail_report_newton_per_step():
    """Every E-sail of the cost table converges in fewer than 4 Newton iterations per step
    (2 to 3.2 measured)."""
    rows = load(BENCH / "esail_report.py").speed(steps=5)
    assert max(r["newton_per_step"] for r in rows) < 4


@pytest.mark.slow
def test_adaptive_fronts_measure_a_run_against_its_reference():
    """The fronts' pieces on 20 s of the 12-tether sail: an adaptive run's outputs differ
    from a fixed 0.025 s run's by little, and not at all from themselves."""
    from skfem_cable.scenes import esail

    fronts = load(BENCH / "adaptive_fronts.py")
    scene = esail.build(esail.BaselineConfig(), 10.0, 2)
    reference = fronts.outputs(scene, fronts.run(scene, 20.0, 1, dt=0.025)[1])
    wall, result = fronts.run(scene, 20.0, 1, dt=0.1, rtol=1e-7, atol=1e-5)
    error = fronts.largest_differences(fronts.outputs(scene, result), reference)
    assert wall > 0 and result.stats["steps"] < 200 and error.max() < 1e-2


def test_esail_full_parts_of_a_step():
    """The full-size sail's factorization, solve and evaluation are timed on its own
    pattern: the bordered band of 6918 unknowns, half-width 11 (a tether's), border 18."""
    from skfem_cable.scenes import esail

    scene = esail.build(esail.FULL_SIZE, 10.0, 10)
    parts = load(BENCH / "esail_full.py").parts(scene, repeats=1)
    assert (parts["unknowns"], parts["band"], parts["border"]) == (6918, 11, 18)
    assert all(parts[k] > 0 for k in ("factor", "solve", "evaluate"))


@pytest.mark.slow
def test_peers_pendulum_against_exudyn():
    """Runs where the ``peers`` extra is installed: both codes reach the same tip."""
    pytest.importorskip("exudyn")
    rows = load(BENCH / "peers.py").pendulum(quick=True, repeats=1)
    ours = rows[0]
    matched = next(r for r in rows if r["code"] == "exudyn" and "matched" in r["setting"])
    assert abs(ours["error"] - matched["error"]) < 1e-6


@pytest.mark.slow
def test_peers_falling_wire_against_moordyn():
    """Runs where the ``peers`` extra is installed: on the falling wire, at equal segments
    (40), our linear element is more accurate than MoorDyn's lumped masses (measured
    0.08 against 0.55 m) and both converge (their errors fall from 10 to 40 segments).
    Our cubic element's runs, which nothing here checks, are left out."""
    pytest.importorskip("moordyn")
    rows = load(BENCH / "peers.py").falling_wire(quick=True, repeats=1, ours=("ours-linear",))

    def error(code, n):
        return min(r["error"] for r in rows if r["code"] == code
                   and r.get("elements", r.get("segments")) == n)

    assert error("ours-linear", 40) < error("moordyn", 40)
    assert error("ours-linear", 40) < error("ours-linear", 10)
    assert error("moordyn", 40) < error("moordyn", 10)


PROBE = """
import time
from pathlib import Path


def main(argv):
    print("first")
    go = Path(__file__).with_name("go")
    deadline = time.monotonic() + 30
    while not go.exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    print("second" if go.exists() else "not streamed")
    return {"argv": argv}
"""


def test_bench_streams_each_line_as_it_is_printed(tmp_path):
    """The probe prints a line and waits until the parent has received it: it only goes
    on when its output is streamed, not collected at its end."""
    script = tmp_path / "probe.py"
    script.write_text(textwrap.dedent(PROBE))
    lines = []

    def sink(line):
        lines.append(line)
        (tmp_path / "go").touch()

    returncode, _, rows = bench.run_script(script, ["--quick"], sink)
    assert (returncode, lines, rows) == (0, ["first\n", "second\n"], {"argv": ["--quick"]})


def test_bench_quick_writes_a_json_record(tmp_path, capsys):
    """``skfem-cable bench --quick NAME``: the header, the table and the wall time are
    printed, the script runs its quick variant and the record holds its rows."""
    assert cli.main(["bench", "--quick", "--json", str(tmp_path), "cantilever_convergence"]) == 0
    out = capsys.readouterr().out
    assert "== [1/1] cantilever_convergence --quick" in out and "| 16 |" in out
    (path,) = tmp_path.glob("*-cantilever_convergence.json")
    record = json.loads(path.read_text())
    assert record["command"] == "python benchmarks/cantilever_convergence.py --quick"
    assert set(record["versions"]) >= {"python", "numpy", "scipy", "numba", "scikit-fem"}
    assert [row["elements"] for row in record["figures"]] == [4, 8, 16]


def test_tasks_bench_passes_arguments_after_a_double_dash(monkeypatch):
    """``python3 tasks.py bench -- --quick kernel_cost`` runs ``skfem-cable bench --quick
    kernel_cost`` (the venv step and the subprocess are replaced)."""
    tasks = load(ROOT / "tasks.py")
    commands = []

    def run(command, **_):
        commands.append(command)
        return SimpleNamespace(returncode=0)

    monkeypatch.setattr(tasks, "ensure_venv", lambda: None)
    monkeypatch.setattr(tasks, "subprocess", SimpleNamespace(run=run))
    assert tasks.main(["bench", "--", "--quick", "kernel_cost"]) == 0
    assert commands == [[str(tasks.PY), "-u", "-m", "skfem_cable.cli", "bench", "--quick",
                         "kernel_cost"]]


def test_largest_differences_are_relative_to_the_largest_value():
    """A run off by 0.01 at one time, on a reference that crosses zero and peaks at 2:
    0.005, interpolated to the reference's times; the same run, zero."""
    from skfem_cable.cli.bench import largest_differences

    t = np.linspace(0.0, 1.0, 11)
    y = np.stack([2 * np.sin(np.pi * t), np.ones_like(t)], axis=1)
    off = y.copy()
    off[5, 0] += 0.01
    assert np.array_equal(largest_differences((t, y), (t, y)), [0.0, 0.0])
    fine = np.linspace(0.0, 1.0, 21)
    run = (fine, np.stack([np.interp(fine, t, c) for c in off.T], axis=1))
    np.testing.assert_allclose(largest_differences(run, (t, y)), [0.005, 0.0], atol=1e-15)
