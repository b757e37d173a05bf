"""Closed-loop control (``control``, ``inputs``, ``sensors``): outputs held between
samples, delays, the compiled step, bit-for-bit continuation with a stateful controller,
and failures that name the controller and keep the steps."""

import numpy as np
import pytest
import xarray as xr

import skfem_cable as sc
from skfem_cable import io
from skfem_cable.scenes import esail

SECTION = sc.Section.circular(1e-3, 2e11, 7850.0)
DT, SAMPLE = 1e-3, 1e-2


def pendulum(push=None):
    """A pinned cable under gravity with a controlled force at its tip and a reel-free
    setup: the input ``push`` (N, a vector)."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, name="cable")
    push = push or sc.Input("push", [0.0, 0.0, 0.0])
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    system.add_load(sc.PointLoad(cable.node(-1), push))
    return system, cable, push


class Ramp(sc.Controller):
    """Pushes along y with the sample time as its value: a new value at every sample."""

    def update(self, t, state):
        return {"push": [0.0, t, 0.0]}


class Held(sc.Observer):
    """Records the run's value of the input at every saved step (``Step.inputs``: the
    user's ``Input`` keeps its initial value)."""

    def __init__(self, x):
        self.x, self.values = x, []

    def saved(self, run, step):
        self.values.append((step.t, step.inputs[self.x.name][1]))


def held_values(controller, t_end=0.05):
    system, cable, push = pendulum()
    held = Held(push)
    result = sc.simulate(system, t_end, DT, controllers=[controller], observers=[held])
    return result, np.array(held.values)


def test_outputs_hold_between_samples_on_the_compiled_step():
    result, values = held_values(Ramp(SAMPLE))
    assert result.stats["path"] == "compiled" and result.stats["control_updates"] == 6
    np.testing.assert_array_equal(result.inputs["push"][:, 1], values[:, 1])  # recorded
    t, held = values.T
    # zero-order hold: the value set at the last sample at or before t
    np.testing.assert_allclose(held, np.floor(t / SAMPLE + 1e-9) * SAMPLE, atol=1e-12)
    assert np.count_nonzero(np.diff(held)) == 5  # changes on whole samples only


def test_a_delay_of_one_sample_is_honoured():
    _, values = held_values(Ramp(SAMPLE, delay=SAMPLE))
    t, held = values.T
    expected = np.maximum(np.floor(t / SAMPLE + 1e-9) - 1, 0) * SAMPLE
    expected[t < SAMPLE - 1e-12] = 0.0  # the initial value until the first output arrives
    np.testing.assert_allclose(held, expected, atol=1e-12)


def test_samples_must_fall_on_steps():
    system, _, _ = pendulum()
    with pytest.raises(ValueError, match=r"sample_time = 0.0015 s must be a multiple of the "
                                         r"step dt = 0.001 s"):
        sc.simulate(system, 0.01, DT, controllers=[Ramp(1.5e-3)])
    with pytest.raises(ValueError, match="sample_time must be a finite number > 0"):
        Ramp(0.0)


class PI(sc.Controller):
    """Holds the tip's height at ``target`` with a proportional-integral force (20 N/m,
    200 N/(m s)): its integral is its memory."""

    def __init__(self, cable, target):
        super().__init__(sample_time=SAMPLE)
        self.cable, self.target = cable, target
        self.memory["integral"] = 0.0

    def update(self, t, state):
        error = self.target - state.position(self.cable, 1.0)[1]
        self.memory["integral"] += error * self.sample_time
        return {"push": [0.0, 20.0 * error + 200.0 * self.memory["integral"], 0.0]}


def test_a_controlled_run_continues_bit_for_bit(tmp_path):
    class Interrupt(sc.Observer):
        def saved(self, run, step):
            if step.t >= 0.0455:
                raise KeyboardInterrupt

    system, first, push = pendulum()
    control = PI(first, 0.0)
    full = sc.simulate(system, 0.1, DT, every=5, controllers=[control])
    integral = control.memory["integral"]
    system, cable, push = pendulum()
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(system, 0.1, DT, every=5, controllers=[PI(cable, 0.0)],
                    observers=[io.RunStore(tmp_path, chunk=3), Interrupt()])
    system, cable, push = pendulum()
    control = PI(cable, 0.0)
    resumed = sc.simulate(system, 0.1, DT, every=5, controllers=[control],
                          resume=io.resume(tmp_path), observers=[io.RunStore(tmp_path)])
    np.testing.assert_array_equal(resumed.q, full.q)
    np.testing.assert_array_equal(resumed.v, full.v)
    np.testing.assert_array_equal(resumed.inputs["push"], full.inputs["push"])
    assert control.memory["integral"] == integral
    # the store holds the inputs' history: a variable per input, read back by Result.load
    stored = xr.open_zarr(tmp_path / "results.zarr")["input_push"]
    assert stored.dims == ("time", "input_push_0")
    np.testing.assert_array_equal(stored.values, full.inputs["push"])
    np.testing.assert_array_equal(sc.Result.load(tmp_path, pendulum()[0]).inputs["push"],
                                  full.inputs["push"])
    assert resumed.stats["control_updates"] == full.stats["control_updates"] == 11
    # the control works: the tip falls 6 mm instead of 65 mm
    assert np.abs(full.position(first, 1.0)[:, 1]).max() < 0.01


def test_a_failing_controller_stops_the_run_naming_it():
    class Broken(sc.Controller):
        def update(self, t, state):
            if t > 0.02:
                raise ZeroDivisionError("no gain")
            return {}

    system, _, _ = pendulum()
    with pytest.raises(sc.ControlError, match=r"controller 'Broken' failed at t = 0.03 s: "
                                              r"ZeroDivisionError: no gain") as info:
        sc.simulate(system, 0.1, DT, controllers=[Broken(SAMPLE)])
    # the steps saved so far are kept (the step that ended on the failed sample is not)
    assert info.value.result.t[-1] == pytest.approx(0.029)

    class Typo(sc.Controller):
        def update(self, t, state):
            return {"psuh": [0.0, 1.0, 0.0]}

    with pytest.raises(sc.ControlError, match=r"set the input 'psuh' at t = 0 s, which the "
                                              r"system does not have \(its inputs: push\)"):
        sc.simulate(system, 0.1, DT, controllers=[Typo(SAMPLE)])

    class Scalar(sc.Controller):
        def update(self, t, state):
            return {"push": 1.0}

    with pytest.raises(sc.ControlError, match=r"input 'push' holds shape \(3,\)"):
        sc.simulate(system, 0.1, DT, controllers=[Scalar(SAMPLE)])


def test_inputs_are_named_once_and_finite():
    with pytest.raises(ValueError, match="name must be a non-empty string"):
        sc.Input("a b", 1.0)
    with pytest.raises(ValueError, match="input 'v': value must be finite"):
        sc.Input("v", np.nan)
    system, cable, _ = pendulum()
    system.add_load(sc.PointLoad(cable.node(2), sc.Input("push", [0.0, 0.0, 0.0])))
    with pytest.raises(ValueError, match="two inputs are named 'push'"):
        sc.simulate(system, 0.01, DT, controllers=[Ramp(SAMPLE)])


def test_reel_motor_input_is_the_held_function_of_time():
    """A reel's motor torque as an input stays compiled, and the controlled run is bit
    for bit the run with the zero-order hold written as a function of time: a step
    ending at ``t`` takes the output of the last sample before it."""
    def run(drive_torque, controllers=()):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SECTION)
        reel = sc.Reel(1.0, 0.1, inertia=1e-3, drive=sc.Motor(drive_torque))
        system = sc.System([cable, reel])
        result = sc.simulate(system, 0.1, DT, controllers=controllers)
        return result, result.q[:, system.dofs(reel)[0]]

    class Wind(sc.Controller):
        def update(self, t, state):
            return {"torque": 0.01 if t < 0.05 else 0.0}

    controlled, length = run(sc.Input("torque", 0.0), [Wind(SAMPLE)])
    assert controlled.stats["path"] == "compiled"
    held, reference = run(lambda t: 0.01 if t - DT < 0.05 - 1e-9 else 0.0)
    np.testing.assert_array_equal(length, reference)
    # l'' = (torque / R) / (J / R^2) = 1 m/s^2 for 0.05 s, then a constant rate (the
    # integrator's first-order error at the jump: 0.7 %)
    assert length[-1] - 1.0 == pytest.approx(0.05**2 / 2 + 0.05 * 0.05, rel=1e-2)


def test_sensors_on_the_spinning_sail():
    """The sensors read the paper's sail: spin rate, the sail's normal along the spin
    axis, the sail angle against the wind, and the tethers' phases 30 deg apart."""
    scene = esail.build(esail.BaselineConfig(), 10.0, 2)
    state = scene.initial
    hub, tethers = scene.hub, scene.tethers
    assert sc.sensors.spin_rate(state, hub) == pytest.approx(esail.BaselineConfig().spin_rate,
                                                             rel=1e-12)
    axis = hub.rotation(state.q[state.system.dofs(hub)])[:, 0]
    np.testing.assert_allclose(sc.sensors.sail_normal(state, tethers, hub), axis, atol=1e-9)
    wind = np.asarray(scene.R0)  # the Sun sits at -R0: the wind blows along R0
    assert np.degrees(sc.sensors.sail_angle(state, tethers, wind, hub)) == pytest.approx(
        10.0, abs=1e-9)
    phases = [sc.sensors.tether_phase(state, c, hub) for c in tethers]
    np.testing.assert_allclose(np.diff(np.unwrap(phases)), np.radians(30.0), atol=1e-9)
    noisy = sc.sensors.noisy(sc.sensors.spin_rate, 1e-3, seed=7)
    assert noisy(state, hub) == noisy(state, hub) != sc.sensors.spin_rate(state, hub)


SCENE = """
title = "held pendulum"

[sections.steel]
radius = 1e-3
E = 2e11
rho = 7850.0

[[cables]]
name = "cable"
section = "steel"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 4

[[constraints]]
type = "pin"
node = { cable = "cable", index = 0 }

[loads]
gravity = [0, -9.81, 0]

[[loads.point]]
at = { cable = "cable", index = -1 }
force = { input = "push", value = [0.0, 0.0, 0.0] }

[[controllers]]
callable = "hold.py:make"
parameters = { target = 0.0 }

[solver]
t_end = 0.1
dt = 1e-3
every = 5
"""

CONTROLLER = '''
import skfem_cable as sc


class Hold(sc.Controller):
    def __init__(self, cable, target):
        super().__init__(sample_time=0.01)
        self.cable, self.target = cable, target
        self.memory["integral"] = 0.0

    def update(self, t, state):
        error = self.target - state.position(self.cable, 1.0)[1]
        self.memory["integral"] += error * self.sample_time
        return {"push": [0.0, 20.0 * error + 200.0 * self.memory["integral"], 0.0]}


def make(system, target):
    return Hold(system.cables()[0], target)
'''


def test_a_scene_file_names_its_inputs_and_controllers(tmp_path):
    """``{input = ..., value = ...}`` makes an input, ``[[controllers]]`` names the code
    that controls it (a file beside the scene); the run holds the tip as the API run
    does, and a bad name is refused naming the key."""
    from skfem_cable import scene_file
    from skfem_cable.cli import command as cli

    (tmp_path / "hold.py").write_text(CONTROLLER)
    path = tmp_path / "held.toml"
    path.write_text(SCENE)
    spec = scene_file.load(path)
    assert [type(c).__name__ for c in spec.controllers] == ["Hold"]
    assert sc.core.inputs.system_inputs(spec.system)["push"].initial.tolist() == [0, 0, 0]
    out = tmp_path / "run"
    assert cli.main(["run", str(path), "--out", str(out), "--no-progress", "--no-plots"]) == 0
    result = sc.Result.load(out, scene_file.load(path).system)
    system, cable, _ = pendulum()
    api = sc.simulate(system, 0.1, DT, every=5, controllers=[PI(cable, 0.0)])
    np.testing.assert_allclose(result.q, api.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result.inputs["push"], api.inputs["push"], atol=1e-9)
    path.write_text(SCENE.replace("hold.py:make", "hold.py:missing"))
    with pytest.raises(scene_file.SceneFileError, match=r"controllers\[0\].callable cannot be "
                                                        r"loaded \(AttributeError"):
        scene_file.load(path)
