"""Round three of "never a silent wrong answer" (issue 45), the command line's items:
failures a user could not read, checks that took a wrong value for 1, and the default
output of scene files."""

import importlib.util
import inspect
import json
import sys
from pathlib import Path

import pytest

from skfem_cable.cli import bench
from skfem_cable.cli import command as cli
from skfem_cable.util.jsonable import jsonable

ROOT = Path(__file__).resolve().parents[1]


def load_benchmark(path):
    """Import a benchmark script as ``skfem-cable bench`` does (its folder on the path)."""
    sys.path.insert(0, str(path.parent))
    try:
        spec = importlib.util.spec_from_file_location(f"benchmark_{path.stem}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(path.parent))
    return module


@pytest.mark.parametrize("name", list(bench.scripts()))
def test_every_benchmark_takes_the_argument_list_of_the_cli(name, capsys):
    """``skfem-cable bench`` calls ``main(ARGS)`` with the list of arguments (``--quick``):
    every script's ``main`` takes that list as ``argv`` and parses it (``--help`` exits 0
    naming ``--quick`` before anything runs).  Before, ``rectification.main`` took it as
    ``days`` (``TypeError: can't multiply sequence by non-int of type 'float'``, ``bench
    --quick`` exit 1), ``peer_suites.main`` took no argument and three took it as
    ``quick``."""
    main = load_benchmark(bench.scripts()[name]).main
    assert list(inspect.signature(main).parameters) == ["argv"]
    with pytest.raises(SystemExit) as leaving:
        main(["--help"])
    assert leaving.value.code == 0 and "--quick" in capsys.readouterr().out


def test_bench_quick_runs_the_rectification_benchmark(capsys):
    """``skfem-cable bench --quick rectification``'s run (the script's ``main(["--quick"])``,
    what the command's child process calls): one day with and without rectification, its
    rows as the JSON record holds them.  In this process: a child would add 2 s of start
    (the command's plumbing, child and record, is tested on ``cantilever_convergence`` in
    test_benchmarks.py)."""
    rectification = load_benchmark(bench.scripts()["rectification"])
    rows = json.loads(json.dumps(jsonable(rectification.main(["--quick"]))))
    assert "1 days, dt = 60 s" in capsys.readouterr().out
    assert [row["rectify"] for row in rows] == [1e-4, None] and rows[0]["rebases"] > 0


ORBIT_SCENE = """
[solver]
analysis = "dynamic"
t_end = 1.0
dt = 0.1

[sections.s]
E = 1e11
rho = 1000.0
radius = 1e-3

[[cables]]
name = "tether"
section = "s"
start = [0, 0, 0]
end = [0, 100, 0]
elements = 2

[orbit]
{orbit}
"""


@pytest.mark.parametrize("orbit, message", [
    ('central_body = "earth"\naltitud = 400e3',
     "orbit.a is required (the semi-major axis, m), or altitude (m above the central "
     "body's radius) (found the unknown key 'altitud': did you mean 'altitude'?)"),
    ('central_bdy = "earth"\naltitude = 400e3',
     "orbit.central_body is required ('earth' or 'sun'), or mu (m^3/s^2) (found the "
     "unknown key 'central_bdy')"),
    ('central_body = "earth"\nmuu = 1.0\naltitude = 400e3',
     "orbit.muu is not a known key: did you mean 'mu'?"),
])
def test_a_misspelled_orbit_key_is_named_with_the_key_meant(orbit, message):
    """``[orbit] altitud = 400e3``: before, ``orbit.a is required ... or altitude`` without
    the hint other tables give; now the misspelled key and the key it resembles."""
    from skfem_cable import scene_file

    with pytest.raises(scene_file.SceneFileError) as refused:
        scene_file.loads_text(ORBIT_SCENE.format(orbit=orbit), "orbit.toml")
    assert message in str(refused.value)


def test_scene_file_is_an_attribute_of_the_package():
    """``import skfem_cable as sc; sc.scene_file`` (an ``AttributeError`` unless imported
    first, before), in a fresh interpreter."""
    import subprocess

    code = ("import skfem_cable as sc; print(sc.scene_file.loads_text.__name__); "
            "print(hasattr(sc, 'no_such_module'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT).stdout.split()
    assert out == ["loads_text", "False"]


def small_pendulum():
    """A cable of 2 elements pinned at one end, under gravity."""
    import skfem_cable as sc

    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    return sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])


@pytest.mark.parametrize("keyword, value, message", [
    ("rectify", True, "rectify must be a finite number > 0 (a relative offset of the centre "
                      "of mass, e.g. 1e-4) or None, got True"),
    ("rectify", "1e-4", "rectify must be a finite number > 0 (a relative offset of the "
                        "centre of mass, e.g. 1e-4) or None, got '1e-4'"),
    ("rectify", -1.0, "rectify must be a finite number > 0"),
    ("every", True, "every must be an integer >= 1, got True"),
])
def test_simulate_refuses_a_bool_or_a_string_for_a_number(keyword, value, message):
    """``simulate(rectify=True)`` and ``rectify="1e-4"``: before, taken as 1 (a system in
    orbit rebased at a relative offset of 1) or failing inside numpy; refused before the
    run, naming the parameter and what it takes (a system not in orbit too)."""
    import skfem_cable as sc

    with pytest.raises(ValueError) as refused:
        sc.simulate(small_pendulum(), 0.01, 1e-3, **{keyword: value})
    assert message in str(refused.value)


def test_points_per_element_true_is_refused(tmp_path):
    """``points_per_element=True``: before, one sample per element (``int(True)``); now
    refused where the series is set up and where a cable is sampled."""
    import skfem_cable as sc

    system = small_pendulum()
    message = "points_per_element must be an integer >= 1, got True"
    with pytest.raises(ValueError, match=message):
        sc.io.run_observers(tmp_path / "run", points_per_element=True)
    with pytest.raises(ValueError, match=message):
        sc.export.SeriesWriter(tmp_path / "series", system, points_per_element=True)
    cable = system.bodies[0]
    with pytest.raises(ValueError, match=message):
        cable.sample(cable.q0, points_per_element=True)


def pin_loop():
    """Three cables meeting at a point, their meeting nodes pinned in a closed loop
    (``a`` to ``b``, ``b`` to ``c``, ``c`` to ``a``): each pair is independent, the three
    together are not."""
    import skfem_cable as sc

    section = sc.Section.circular(1e-3, 2e11, 7850.0)
    a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, section, name="a")
    b = sc.Cable.straight([1, 0, 0], [2, 0, 0], 4, section, name="b")
    c = sc.Cable.straight([1, 0, 0], [1, -1, 0], 4, section, name="c")
    system = sc.System([a, b, c]).pin(a.node(0))
    system.pin(a.node(-1), b.node(0)).pin(b.node(0), c.node(0)).pin(c.node(0), a.node(-1))
    return system.add_gravity([0, -9.81, 0])


LOOP = ("dependent constraints at {}: 'pin Node(a, 4)-Node(b, 0)', 'pin Node(b, 0)-Node(c, "
        "0)', 'pin Node(c, 0)-Node(a, 4)' (their equations have rank 6)")


def test_a_closed_loop_of_pins_is_named_as_dependent_constraints():
    """Before: ``SingularMatrixError: singular iteration matrix at unknown 92`` from
    ``simulate`` (a numpy ``LinAlgError`` traceback from the CLI), and ``solve_static``
    named one of the pins' equations.  Now both name the three pins, not the pin to the
    ground."""
    import skfem_cable as sc

    with pytest.raises(ValueError) as refused:
        sc.simulate(pin_loop(), 0.01, 1e-3)
    assert LOOP.format("the initial state (t=0)") in str(refused.value)
    assert "Node(a, 0)" not in str(refused.value)
    with pytest.raises(sc.StaticConvergenceError) as failed:
        sc.solve_static(pin_loop())
    assert LOOP.format("this state") in str(failed.value)


def test_the_memory_guard_counts_every_cable_of_a_scene():
    """30 cables of 900,000 elements in a scene file: before, each cable passed the guard
    alone (22.5 GB of 25 GB) and the build ended in a ``MemoryError`` traceback; now the
    scene is refused before any cable is built, naming the total."""
    from skfem_cable import scene_file

    cables = "".join(f'\n[[cables]]\nname = "c{i}"\nsection = "s"\nstart = [{i}, 0, 0]\n'
                     f'end = [{i}, 100, 0]\nelements = 900000\n' for i in range(30))
    text = ORBIT_SCENE.split("[orbit]")[0].replace(
        '[[cables]]\nname = "tether"\nsection = "s"\nstart = [0, 0, 0]\nend = [0, 100, 0]\n'
        'elements = 2\n', "") + cables
    with pytest.raises(scene_file.SceneFileError,
                       match=r"big.toml: cables are too large: a system of 30 cables with "
                             r"27000000 elements in all needs about 675 GB"):
        scene_file.loads_text(text, "big.toml")


def test_the_memory_guard_counts_every_cable_of_a_system(monkeypatch):
    """``sc.System`` of cables that each fit but not together is refused (the guard's
    memory per element raised so that 10 elements fit and 20 do not)."""
    import os

    import skfem_cable as sc
    from skfem_cable.bodies import memory as memory_module

    memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    monkeypatch.setattr(memory_module, "MEMORY_PER_ELEMENT", memory / 15)
    section = sc.Section.circular(1e-3, 2e11, 7850.0)
    cables = [sc.Cable.straight([0, i, 0], [1, i, 0], 10, section, name=f"c{i}")
              for i in range(2)]
    with pytest.raises(ValueError, match="a system of 2 cables with 20 elements in all"):
        sc.System(cables)


def test_a_reel_paid_out_to_its_capacity_stops_in_one_message():
    """A motor pays a tether out until the reel is empty: before, ``SimulationError``
    under a traceback of ten recursive ``advance`` calls, its message a failed step;
    now the halved steps wait on a stack (the error is raised one call below
    ``simulate``'s loop), the message says that the reel is empty, and the steps
    computed so far are kept, up to the capacity."""
    import traceback

    import numpy as np

    import skfem_cable as sc

    section = sc.Section.circular(1e-3, 1e9, 1000.0)
    tether = sc.Cable.straight([0, 0, 0], [2.0, 0, 0], 4, section)
    reel = sc.Reel(2.0, radius=0.1, inertia=0.01, drive=sc.Motor(0.5))
    system = sc.System([tether, reel]).deploy(tether, reel=reel, capacity=2.5)
    system.add_point_mass(tether.node(-1), 0.1)
    with pytest.raises(sc.SimulationError) as stopped:
        sc.simulate(system, t_end=5.0, dt=0.01, max_halvings=4)
    assert "must lie in (0, 2.5] (the capacity): the reel is empty" in str(stopped.value)
    frames = [f.name for f in traceback.extract_tb(stopped.value.__traceback__)]
    assert frames.count("advance") == 1
    ell = stopped.value.result.q[:, system.dofs(reel)[0]]
    assert 2.4 < ell[-1] <= 2.5 and np.all(np.diff(ell) > 0)


def test_the_cli_stops_a_reel_at_its_capacity_with_one_message(tmp_path, capsys):
    """``demos/reel_brake.toml`` with 5.5 m on the reel: exit 2, one message naming the
    empty reel and the run kept in its store (its steps up to 0.81 s), no traceback."""
    scene = tmp_path / "reel.toml"
    text = (ROOT / "demos" / "reel_brake.toml").read_text()
    scene.write_text(text.replace("capacity = 30.0 ", "capacity = 5.5 ")
                     .replace("dt = 1e-3 ", "dt = 1e-2 ").replace("every = 10", "every = 1"))
    assert cli.main(["run", str(scene), "--out", str(tmp_path / "run"), "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "the reel is empty" in err
    assert f"run store {tmp_path / 'run'}: scene 'reel'" in err and "failed" in err


PENDULUM_FILE = """
[solver]
t_end = 0.54
dt = 2e-3
{every}

[sections.s]
E = 1e9
rho = 1000.0
radius = 1e-3

[[cables]]
name = "wire"
section = "s"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 2

[[constraints]]
type = "pin"
node = {{ cable = "wire", index = 0 }}

[loads]
gravity = [0, 0, -9.81]
"""


@pytest.mark.parametrize("every, saved", [("", 136), ("every = 1", 271)])
def test_a_scene_file_saves_about_250_steps_by_default(tmp_path, every, saved):
    """270 steps without ``[solver] every``: before, every step saved (271 VTU files; the
    3 h dumbbell at 20 s steps wrote 541); now every 2nd (``ceil(270 / 250)``), 136 saved
    steps and files, and ``every = 1`` still saves them all."""
    scene = tmp_path / "pendulum.toml"
    scene.write_text(PENDULUM_FILE.format(every=every))
    out = tmp_path / "run"
    assert cli.main(["run", str(scene), "--out", str(out), "--no-plots",
                     "--no-progress"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["saved_steps"] == saved and summary["steps"] == 270
    assert len(list((out / "vtu").glob("*.vtu"))) == saved
