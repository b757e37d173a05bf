"""Observers of ``simulate``: user observers (a custom history, a clean stop), failures
inside observers and loads keep the saved steps on disk, and the integrator does no I/O."""

import ast
import re
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.records import FIELDS
from skfem_cable.io import RunStore, resume
from skfem_cable.scenes import classics

SIMULATE = Path(sc.simulate.__code__.co_filename)


class TipHeight(sc.Observer):
    """Records the height ``y`` of a cable's tip at every saved step."""

    def __init__(self, cable):
        self.cable, self.z, self.calls = cable, [], []

    def start(self, run):
        self.calls.append("start")
        self.dofs = run.system.dofs(self.cable)

    def saved(self, run, step):
        tip = self.cable.interpolate(step.q[self.dofs], self.cable.length)[0]
        self.z.append(tip[1])

    def finish(self, run, error):
        self.calls.append(("finish", error))


class StopBelow(sc.Observer):
    """Stops the run when a cable's tip falls below ``y = z``."""

    def __init__(self, cable, z):
        self.cable, self.z = cable, z

    def saved(self, run, step):
        tip = self.cable.interpolate(step.q[run.system.dofs(self.cable)], self.cable.length)
        if tip[0][1] < self.z:
            return f"tip below {self.z} m at t = {step.t:.3f} s"


def test_user_observer_records_a_custom_history():
    scene = classics.pendulum(n_elements=4)
    tip = TipHeight(scene.cable)
    result = sc.simulate(scene.system, t_end=0.1, dt=2e-3, every=5, observers=[tip])
    assert tip.calls == ["start", ("finish", None)]
    assert len(tip.z) == len(result) == 11
    expected = result.position(scene.cable, scene.cable.length)[:, 1]
    assert np.array_equal(tip.z, expected)
    assert tip.z[-1] < tip.z[0]  # released horizontally, the pendulum falls
    assert result.stats["stopped"] is None


def test_observer_stops_the_run_cleanly(tmp_path):
    scene = classics.pendulum(n_elements=4)
    kw = dict(t_end=0.5, dt=2e-3, every=5)
    full = sc.simulate(scene.system, **kw)
    z_tip = full.position(scene.cable, scene.cable.length)[:, 1]
    stop = StopBelow(scene.cable, z_tip[0] - 0.05)
    store = RunStore(tmp_path, chunk=4, fields=FIELDS)  # the accelerations too
    result = sc.simulate(scene.system, observers=[stop, store], **kw)
    n = int(np.argmax(z_tip < z_tip[0] - 0.05)) + 1  # the stop step is the last saved one
    assert 1 < n < len(full)
    assert len(result) == n and result.t[-1] == full.t[n - 1]
    assert result.stats["stopped"].startswith("tip below")
    assert result.stats["steps"] == 5 * (n - 1)
    for name in FIELDS:
        assert np.array_equal(getattr(result, name), getattr(full, name)[:n]), name
    stored = sc.Result.load(tmp_path, scene.system)  # the store has every step, stop step too
    assert np.array_equal(stored.q, result.q)
    assert stored.stats["status"] == "stopped" and stored.stats["stopped"].startswith("tip")
    # ... and the stopped run continues bit for bit to the end
    resumed = sc.simulate(scene.system, resume=resume(tmp_path), **kw)
    for name in FIELDS:
        assert np.array_equal(getattr(resumed, name), getattr(full, name)), name


def test_true_value_stops_with_a_generic_reason():
    class Once(sc.Observer):
        def saved(self, run, step):
            return True

    scene = classics.pendulum(n_elements=3)
    result = sc.simulate(scene.system, t_end=0.01, dt=1e-3, observers=[Once()])
    assert len(result) == 1 and result.stats["steps"] == 0
    assert result.stats["stopped"] == "stopped by Once"


class Boom(Exception):
    pass


def test_failing_observer_keeps_the_saved_steps_on_disk(tmp_path):
    class FailAt(sc.Observer):
        def saved(self, run, step):
            if step.index == 12:
                raise Boom

    scene = classics.pendulum(n_elements=3)
    kw = dict(t_end=0.05, dt=1e-3, every=3)
    ref = sc.simulate(scene.system, **kw)
    log = TipHeight(scene.cable)
    with pytest.raises(Boom):
        sc.simulate(scene.system, observers=[RunStore(tmp_path, chunk=100), FailAt(), log],
                    **kw)
    assert isinstance(log.calls[-1][1], Boom)  # every observer's finish saw the error
    kept = sc.Result.load(tmp_path, scene.system)
    assert len(kept) == 5  # steps 0, 3, ..., 12: the store had the failing step first
    assert np.array_equal(kept.q, ref.q[:5])
    resumed = sc.simulate(scene.system, resume=resume(tmp_path), **kw)
    assert np.array_equal(resumed.q, ref.q)


def test_failing_load_and_simulation_error_keep_the_saved_steps(tmp_path):
    """A load that blows up after t = 5.5 ms: the step halving gives up and raises
    ``SimulationError``; its result and the store hold the steps up to the failure."""
    scene = classics.pendulum(n_elements=3)

    def load(t):
        return [0.0, 0.0 if t < 0.0055 else 1e300 * np.exp(1e3 * t), 0.0]

    scene.system.add_point_load(scene.cable.node(-1), load)
    log = TipHeight(scene.cable)
    with pytest.raises(sc.SimulationError, match="smallest step size") as info:
        sc.simulate(scene.system, t_end=0.01, dt=1e-3, max_halvings=2,
                    observers=[RunStore(tmp_path, chunk=100), log])
    partial = info.value.result
    assert np.allclose(partial.t, np.arange(6) * 1e-3, rtol=0, atol=1e-15)
    assert partial.stats["rejected"] >= 3
    assert np.array_equal(sc.Result.load(tmp_path, scene.system).q, partial.q)
    assert log.calls[-1][1] is info.value


def test_failing_finish_does_not_hide_the_other_observers():
    class BadFinish(sc.Observer):
        def finish(self, run, error):
            raise Boom("finish")

    scene = classics.pendulum(n_elements=3)
    log = TipHeight(scene.cable)
    with pytest.raises(Boom, match="finish"):
        sc.simulate(scene.system, t_end=0.003, dt=1e-3, observers=[BadFinish(), log])
    assert log.calls[-1] == ("finish", None)


def test_observers_see_the_run():
    seen = {}

    class Look(sc.Observer):
        def start(self, run):
            seen["settings"] = dict(run.settings)
            seen["resumed"] = run.resumed

        def saved(self, run, step):
            seen.setdefault("index", []).append(step.index)
            seen["energies"] = sorted(step.energies)
            seen["steps"] = run.stats["steps"]

    scene = classics.pendulum(n_elements=3)
    sc.simulate(scene.system, t_end=0.0105, dt=1e-3, every=4, observers=[Look()])
    assert seen["index"] == [0, 4, 8, 11]
    assert seen["steps"] == 11 and seen["resumed"] is False
    assert seen["settings"]["every"] == 4 and seen["settings"]["t_end"] == 0.0105
    assert seen["energies"] == sorted(["kinetic", "axial", "bending", "potential",
                                       "dissipated", "external_work"])
    with pytest.raises(TypeError, match="not an Observer"):
        sc.simulate(scene.system, t_end=0.01, dt=1e-3, observers=[object()])


def test_simulate_module_does_no_io():
    """The integrator imports the contract and the protocols, the stepper and the
    in-memory ``Result`` only: nothing of ``io``, ``export``, the progress bar or file
    formats."""
    tree = ast.parse(SIMULATE.read_text())
    imported = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                imported.setdefault(alias.name, set())
        elif isinstance(node, ast.ImportFrom):
            module = "." * node.level + (node.module or "")
            imported.setdefault(module, set()).update(a.name for a in node.names)
    assert set(imported) <= {"contextlib", "functools", "numbers", "time", "numpy",
                             "..core.contract", "..core.protocols", "..results.result",
                             "..core.records", ".observing", ".galpha", ".rectify",
                             "..control.controller", "..bodies.section", "..core.inputs",
                             "..kernels"}, imported
    assert imported.get("..kernels", set()) <= {"compile_log"}  # its clock, no output
    assert imported[".galpha"] <= {"GeneralizedAlpha", "galpha_parameters"}
    assert imported["..results.result"] <= {"Result"}
    assert imported["..core.records"] <= {"FIELDS", "SETTINGS", "settings_array", "step_record"}
    # and result.py itself writes nothing (its load goes through io lazily)
    result_src = (SIMULATE.parents[1] / "results" / "result.py").read_text()
    for word in ("savez", "open(", "meshio", "SeriesWriter", "Progress"):
        assert word not in result_src, word


def test_the_examples_of_the_observers_page_run(tmp_path, monkeypatch, capsys):
    page = Path(__file__).resolve().parents[1] / "docs" / "observers.md"
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)
    assert len(blocks) == 3
    monkeypatch.chdir(tmp_path)
    namespace = {}
    exec(blocks[0], namespace)
    assert "tip below -0.05 m at t = 0.09 s" in capsys.readouterr().out
    stopped = namespace["result"]
    exec(blocks[1], namespace)
    assert np.array_equal(namespace["result"].q, stopped.q)
    exec(blocks[2], namespace)
    result = namespace["result"]
    assert result.t[-1] == 2.0 and result.stats["stopped"] is None
    assert np.array_equal(result.q[: len(stopped)], stopped.q)
    assert len(sc.Result.load(tmp_path / "runs" / "pendulum", stopped.system)) == len(result)
