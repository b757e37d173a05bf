"""Faults, round three: controllers (issue 45, items 6, 7, 15 and 16b).

Each test reproduces one fault of the issue and asserts what the user gets now.

* a controller's state kept in an attribute (``self.integral``) is checkpointed: the
  continued run is bit for bit the uninterrupted one; state a checkpoint cannot hold (a
  list the controller appends to) refuses the continuation, naming the attribute;
* a continuation with another controller (a scene file's ``parameters`` edited, its code
  edited) is refused naming what changed; the numbers a callable closes over or reads
  from its module are in the system's fingerprint;
* mistakes in writing a controller, a controller that raises and a controller file that
  does not compile end ``skfem-cable run`` with one message (exit 2), the run kept;
* two controllers setting one input are refused before the first step.
"""

import os
import subprocess
import sys

import numpy as np
import pytest
from test_control import SCENE  # the held pendulum's scene file

import skfem_cable as sc
from skfem_cable import io
from skfem_cable.cli import command as cli
from skfem_cable.io import StoreMismatch
from skfem_cable.io.manifest import read_manifest, write_manifest
from skfem_cable.model.fingerprint import system_fingerprint

SECTION = sc.Section.circular(1e-3, 2e11, 7850.0)
DT, SAMPLE = 1e-3, 1e-2


def pendulum():
    """A pinned 1 m cable under gravity with the force ``push`` (an input) at its tip."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, name="cable")
    push = sc.Input("push", [0.0, 0.0, 0.0])
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    system.add_load(sc.PointLoad(cable.node(-1), push))
    return system, cable


class AttributePI(sc.Controller):
    """Holds the tip's height at ``target`` with a proportional-integral force, its
    integral kept in an attribute (not in ``memory``)."""

    def __init__(self, cable, target):
        super().__init__(sample_time=SAMPLE)
        self.cable, self.target, self.integral = cable, target, 0.0

    def update(self, t, state):
        error = self.target - state.position(self.cable, 1.0)[1]
        self.integral += error * self.sample_time
        return {"push": [0.0, 20.0 * error + 200.0 * self.integral, 0.0]}


class Interrupt(sc.Observer):
    """Ctrl-C after the step saved at ``at`` (s)."""

    def __init__(self, at):
        self.at = at

    def saved(self, run, step):
        if step.t >= self.at:
            raise KeyboardInterrupt


def interrupted(tmp_path, make, at=0.0455):
    """Run ``make(cable)``'s controller on the pendulum into ``tmp_path`` until ``at``."""
    system, cable = pendulum()
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(system, 0.1, DT, every=5, controllers=[make(cable)],
                    observers=[io.RunStore(tmp_path, chunk=3), Interrupt(at)])


def resumed(tmp_path, make):
    """Continue the run of ``tmp_path`` with a new ``make(cable)`` controller."""
    system, cable = pendulum()
    controller = make(cable)
    result = sc.simulate(system, 0.1, DT, every=5, controllers=[controller],
                         resume=io.resume(tmp_path), observers=[io.RunStore(tmp_path)])
    return result, controller


# ===========================================================================================
# Item 6: controller state outside memory
# ===========================================================================================
def test_a_controller_attribute_is_checkpointed_bit_for_bit(tmp_path):
    """Before: the integral, kept in ``self.integral``, restarted from 0 on the resume,
    without a word (status complete): the continued run's tip ended at -7.13 mm instead
    of -5.77 mm (5.5 mm off at most; the integral 3.16e-4 instead of 3.79e-4).  Now the
    controller's attributes of numbers and arrays are in the checkpoint."""
    system, cable = pendulum()
    control = AttributePI(cable, 0.0)
    full = sc.simulate(system, 0.1, DT, every=5, controllers=[control])
    interrupted(tmp_path, lambda c: AttributePI(c, 0.0))
    result, again = resumed(tmp_path, lambda c: AttributePI(c, 0.0))
    np.testing.assert_array_equal(result.q, full.q)
    np.testing.assert_array_equal(result.inputs["push"], full.inputs["push"])
    assert again.integral == control.integral
    assert read_manifest(tmp_path)["status"] == "complete"


class Logger(AttributePI):
    """Keeps the errors it saw in a list: state a checkpoint cannot hold."""

    def __init__(self, cable, target):
        super().__init__(cable, target)
        self.errors = []

    def update(self, t, state):
        self.errors.append(self.target - state.position(self.cable, 1.0)[1])
        return super().update(t, state)


def test_state_a_checkpoint_cannot_hold_refuses_the_continuation(tmp_path):
    """Before: accepted, the list (and the integral) restarted empty; a continuation
    without the controller continued without control.  Now a list appended to at every
    sample, which a checkpoint cannot save, refuses the continuation naming the
    controller and the attribute, before anything is written; so does a continuation
    with another number of controllers."""
    interrupted(tmp_path, lambda c: Logger(c, 0.0))
    before = read_manifest(tmp_path)
    with pytest.raises(StoreMismatch, match=r"controller 'Logger' \(controllers\[0\]\) "
                                            r"changed its attribute 'errors' during the "
                                            r"run: it held a list"):
        resumed(tmp_path, lambda c: Logger(c, 0.0))
    assert read_manifest(tmp_path)["saved"] == before["saved"]
    system, _ = pendulum()  # and without its controller
    with pytest.raises(StoreMismatch, match="the run was started with 1 controllers, given 0"):
        sc.simulate(system, 0.1, DT, every=5, resume=io.resume(tmp_path))


# ===========================================================================================
# Item 7: changed controllers and closed-over numbers
# ===========================================================================================

CONTROLLER = '''
import skfem_cable as sc


class Hold(sc.Controller):
    def __init__(self, cable, target):
        super().__init__(sample_time=0.01)
        self.cable, self.target, self.integral = cable, target, 0.0

    def update(self, t, state):
        error = self.target - state.position(self.cable, 1.0)[1]
        self.integral += error * self.sample_time
        return {"push": [0.0, 20.0 * error + 200.0 * self.integral, 0.0]}


def make(system, target):
    return Hold(system.cables()[0], target)
'''


def run_cli(*argv):
    return cli.main(["run", *map(str, argv), "--no-progress", "--no-plots"])


def test_a_scene_file_controller_changed_before_resume_is_refused(tmp_path, capsys):
    """Before: ``parameters = { target = 0.5 }`` edited before ``--resume`` was accepted
    (exit 0): the second half of the run lifted the tip to +0.714 m where the run it
    continued ends at -0.0058 m.  Now the checkpoint records each controller's class,
    code and attributes at the start: a changed target or code is refused naming it; the
    unchanged scene continues bit for bit (the integral, an attribute, included)."""
    (tmp_path / "hold.py").write_text(CONTROLLER)
    scene = tmp_path / "held.toml"
    scene.write_text(SCENE)
    assert run_cli(scene, "--out", tmp_path / "full") == 0
    out = tmp_path / "run"
    assert run_cli(scene, "--out", out, "--t-end", "0.05") == 0
    capsys.readouterr()
    scene.write_text(SCENE.replace("target = 0.0", "target = 0.5"))
    assert run_cli(scene, "--out", out, "--t-end", "0.1", "--resume") == 2
    err = capsys.readouterr().err
    assert "another controller 'Hold' (controllers[0]): target: stored 0.0, given 0.5" in err
    assert len(err.strip().splitlines()) == 1
    scene.write_text(SCENE)
    (tmp_path / "hold.py").write_text(CONTROLLER.replace("200.0", "300.0"))
    assert run_cli(scene, "--out", out, "--t-end", "0.1", "--resume") == 2
    assert "its class's code differs" in capsys.readouterr().err
    (tmp_path / "hold.py").write_text(CONTROLLER)
    assert run_cli(scene, "--out", out, "--t-end", "0.1", "--resume") == 0
    system = sc.scene_file.load(scene).system
    full, cont = (sc.Result.load(tmp_path / d, system) for d in ("full", "run"))
    np.testing.assert_array_equal(cont.q, full.q)
    np.testing.assert_array_equal(cont.inputs["push"], full.inputs["push"])


LAW = '''
import skfem_cable as sc
from skfem_cable import laws

EA0 = 1e5


def build(k):
    law = laws.green.with_parameters(EA=lambda t: EA0 * k * (1 + t))
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0),
                              law=law)
    return sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
'''


def test_numbers_a_callable_closes_over_are_in_the_fingerprint(tmp_path, monkeypatch):
    """Before: ``with_parameters(EA=lambda t: EA0 * k * (1 + t))`` had one fingerprint
    for every ``k`` and ``EA0`` (a documented limitation): a continuation with another
    ``k`` was accepted.  Now the values a function closes over and the numbers it reads
    from its module's globals are described, the same in every process."""
    (tmp_path / "lawmod.py").write_text(LAW)
    monkeypatch.syspath_prepend(str(tmp_path))
    import lawmod

    first = system_fingerprint(lawmod.build(1.0))
    assert system_fingerprint(lawmod.build(1.0)) == first
    assert system_fingerprint(lawmod.build(2.0)) != first
    monkeypatch.setattr(lawmod, "EA0", 2e5)
    assert system_fingerprint(lawmod.build(1.0)) != first
    monkeypatch.setattr(lawmod, "EA0", 1e5)
    other = subprocess.run(
        [sys.executable, "-c", "import lawmod; from skfem_cable.model.fingerprint import "
         "system_fingerprint as f; print(f(lawmod.build(1.0)))"],
        capture_output=True, text=True, check=True,
        env={**os.environ,
             "PYTHONPATH": f"{tmp_path}:{sc.__file__.rsplit('/skfem_cable/', 1)[0]}"})
    assert other.stdout.strip() == first
    run = tmp_path / "run"
    sc.simulate(lawmod.build(1.0), 0.01, DT, observers=[io.RunStore(run)])
    with pytest.raises(StoreMismatch, match="written by another system"):
        io.resume(run, lawmod.build(2.0))
    # a store of an earlier version (no closures described) is checked as it was written
    manifest = read_manifest(run)
    fp = {k: v for k, v in manifest["fingerprint"].items() if k != "version"}
    write_manifest(run, dict(manifest, fingerprint=dict(
        fp, system=system_fingerprint(lawmod.build(1.0), version=1))))
    assert len(sc.Result.load(run, lawmod.build(1.0))) == 11


# ===========================================================================================
# Item 15: mistakes in writing a controller, from the command line
# ===========================================================================================
MISTAKES = '''
import skfem_cable as sc


class NoSuper(sc.Controller):
    def __init__(self, system):
        self.gain = 1.0

    def update(self, t, state):
        return {}


class TextSample(sc.Controller):
    def __init__(self, system):
        super().__init__(sample_time="0.01")

    def update(self, t, state):
        return {}


class NoSample(sc.Controller):
    def __init__(self, system):
        super().__init__(sample_time=None)

    def update(self, t, state):
        return {}


class DictMemory(sc.Controller):
    def __init__(self, system):
        super().__init__(sample_time=0.01)
        self.memory["gains"] = {"p": 1.0}

    def update(self, t, state):
        return {}


class Raises(sc.Controller):
    def __init__(self, system):
        super().__init__(sample_time=0.01)

    def update(self, t, state):
        if t > 0.02:
            raise ZeroDivisionError("no gain")
        return {}
'''


@pytest.mark.parametrize("name, message", [
    ("NoSuper", "controllers[0].callable mistakes.py:NoSuper: controller 'NoSuper' has no "
                "sample_time: its __init__ must call super().__init__(sample_time"),
    ("TextSample", "controller 'TextSample': sample_time must be a finite number > 0 (s), "
                   "got '0.01'"),
    ("NoSample", "controller 'NoSample': sample_time must be a finite number > 0 (s), got "
                 "None"),
    ("DictMemory", "controller 'DictMemory': memory['gains'] holds a dict; memory holds "
                   "numbers, strings and arrays"),
])
def test_a_mistake_in_writing_a_controller_is_one_message(tmp_path, capsys, name, message):
    """Before: no ``super().__init__`` read "must return a Controller ..., got NoSuper" (a
    Controller); ``sample_time="0.01"`` or None "TypeError: ufunc 'isfinite' not
    supported"; a dict in ``memory`` ran (exit 0) and left a checkpoint that cannot be
    read back.  Now each names the controller and the parameter, exit 2, before any
    step."""
    (tmp_path / "mistakes.py").write_text(MISTAKES)
    scene = tmp_path / "bad.toml"
    scene.write_text(SCENE.replace("hold.py:make", f"mistakes.py:{name}")
                     .replace("parameters = { target = 0.0 }\n", ""))
    assert run_cli(scene, "--out", tmp_path / "run") == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "run" / "manifest.json").exists()


def test_a_controller_that_raises_or_does_not_compile_is_one_message(tmp_path, capsys):
    """Before: a controller raising in ``update`` ended ``skfem-cable run`` with a
    49-line traceback and exit 1, and a controller file with a syntax error with a
    40-line one.  Now one message names the controller, the time and the line (exit 2),
    and the run store keeps the steps before the failure."""
    (tmp_path / "mistakes.py").write_text(MISTAKES)
    scene = tmp_path / "bad.toml"
    scene.write_text(SCENE.replace("hold.py:make", "mistakes.py:Raises")
                     .replace("parameters = { target = 0.0 }\n", ""))
    out = tmp_path / "run"
    assert run_cli(scene, "--out", out) == 2
    err = capsys.readouterr().err
    assert ("error: controller 'Raises' failed at t = 0.03 s: ZeroDivisionError: no gain "
            "(mistakes.py, line 44, in update)") in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 2
    manifest = read_manifest(out)
    assert manifest["status"] == "failed" and manifest["last"]["t"] == pytest.approx(0.025)
    (tmp_path / "broken.py").write_text("def make(system) return 1\n")
    scene.write_text(SCENE.replace("hold.py:make", "broken.py:make")
                     .replace("parameters = { target = 0.0 }\n", ""))
    assert run_cli(scene, "--out", tmp_path / "other") == 2
    err = capsys.readouterr().err
    assert ("controllers[0].callable cannot be loaded (SyntaxError: expected ':' "
            "(broken.py, line 1))") in err and len(err.strip().splitlines()) == 1


# ===========================================================================================
# Item 16b: two controllers, one input
# ===========================================================================================
def test_two_controllers_setting_one_input_are_refused(tmp_path):
    """Before: both wrote ``push`` and the one listed last won at every sample, silently.
    Now the first samples (at the start, before any step or file) refuse it, naming both
    controllers and the input."""
    system, cable = pendulum()
    second = AttributePI(cable, 0.1)
    second.name = "Second"
    with pytest.raises(sc.ControlError, match=r"controllers\[0\] 'AttributePI' and "
                                              r"controllers\[1\] 'Second' both set the "
                                              r"input 'push' \(at t = 0 s\)"):
        sc.simulate(system, 0.1, DT, controllers=[AttributePI(cable, 0.0), second],
                    observers=[io.RunStore(tmp_path / "run")])
    assert not (tmp_path / "run" / "manifest.json").exists()
def _named(controller, name):
    controller.name = name
    return controller
