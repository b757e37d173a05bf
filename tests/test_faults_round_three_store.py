"""Faults, round three (issue 45): stores and edits.

Each test reproduces one fault of the issue and asserts what the user gets now.

* a store with a chunk file deleted is refused by every reader (``open_dataset``,
  ``Result.load``, ``--resume``), naming the missing files, instead of read as NaN, 0 or
  -1 (item 9);
* ``[output] points_per_element`` changed on ``--resume`` is refused as ``--frame`` is,
  and the refusals of a continued run advise neither the command that failed nor
  ``--overwrite`` for data that can be read (item 16);
* a rigid body's ``base_points`` edited after construction, a ``Result`` read after its
  system was edited and ``System.evaluate`` after an edit (item 8).
"""

import shutil
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.cli import command as cli
from skfem_cable.io import StoreCorrupt, open_dataset
from skfem_cable.io.schema import STORE
from skfem_cable.scenes import classics

#: Options of every small command-line run.
QUIET = ["--no-progress", "--no-plots"]


def _run(out, *extra, scene="pendulum"):
    """``skfem-cable run`` of a 3-element pendulum (by default) into ``out``."""
    args = ["run", scene, *QUIET, *(["--elements", "3"] if scene == "pendulum" else [])]
    return cli.main([*args, "--out", str(out), *extra])


def _pendulum():
    return classics.pendulum(n_elements=3).system


# ===========================================================================================
# Item 9: a damaged store read as data
# ===========================================================================================
@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A finished command-line run (pendulum, t = 0 .. 0.05 s, 6 saved steps)."""
    out = tmp_path_factory.mktemp("finished") / "run"
    assert _run(out, "--t-end", "0.05") == 0
    return out


@pytest.mark.parametrize("array, file, read_as", [
    ("q", "c/0/0", np.nan),          # a variable: 6 rows of NaN
    ("stat_steps", "c/0", 0),        # a solver counter: 0 steps
    ("node", "c/0", -1),             # a coordinate (labels): node -1
    ("step", "c/0", 0),              # the step numbers: --resume blamed the manifest
])
def test_deleted_chunk_is_named_by_every_reader(finished, tmp_path, capsys, array, file,
                                                read_as):
    """Before: with ``results.zarr/q/c/0/0`` deleted, ``open_dataset(run).q`` gave rows of
    NaN; a deleted ``stat_steps`` chunk read back as 0 (``Result.load`` said 0 steps) and
    a deleted ``node`` chunk as -1, without a word, and ``--resume`` continued the
    ``stat_steps`` and ``node`` stores with exit 0, keeping the hole (a deleted ``step``
    chunk: "the manifest was edited or damaged after the run").  Now every reader
    checks, by listing the folders, that the chunks the manifest commits exist, and
    names the missing ones; ``--resume`` is refused (exit 2) and advises neither
    ``--resume`` nor ``--overwrite``."""
    run = Path(shutil.copytree(finished, tmp_path / "run"))
    chunk = run / STORE / array / file
    intact = open_dataset(run)[array].values
    assert not np.isnan(intact).all() and not (intact == read_as).all()
    chunk.unlink()
    named = rf"1 file that its manifest commits .* is missing \({chunk}\)"
    with pytest.raises(StoreCorrupt, match=named) as info:
        open_dataset(run)
    assert info.value.path == chunk
    with pytest.raises(StoreCorrupt, match=named):
        sc.Result.load(run, _pendulum())
    with pytest.raises(StoreCorrupt, match=named):
        sc.io.resume(run)
    capsys.readouterr()
    assert _run(run, "--t-end", "0.08", "--resume") == 2
    err = capsys.readouterr().err
    assert str(chunk) in err and "--overwrite" not in err and "--resume" not in err
    assert "new directory (--out)" in err
    assert not chunk.exists()  # the hole is not filled with fill values by a resume


def test_deleted_chunks_are_all_counted(finished, tmp_path):
    """Several missing files: the message counts them and names the first ones."""
    run = Path(shutil.copytree(finished, tmp_path / "run"))
    for name in ("q", "v", "lam", "kinetic", "time", "step"):
        for chunk in (run / STORE / name / "c").rglob("*"):
            if chunk.is_file():
                chunk.unlink()
    with pytest.raises(StoreCorrupt, match=r"6 files that its manifest commits .* are "
                                           r"missing \(.* and 2 more\)"):
        open_dataset(run)


# ===========================================================================================
# Item 16: points_per_element changed on --resume; what a refused resume advises
# ===========================================================================================
SCENE = """
[solver]
analysis = "dynamic"
t_end = {t_end}
dt = 1e-3

[sections.wire]
E = 2e11
rho = 7850.0
radius = 1e-3

[[cables]]
name = "wire"
section = "wire"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 3

[[constraints]]
type = "pin"
node = {{ cable = "wire", index = 0 }}

[loads]
gravity = [0, -9.81, 0]

[output]
points_per_element = {ppe}
"""


def test_points_per_element_changed_on_resume_is_refused(tmp_path, capsys):
    """Before: a scene file's ``[output] points_per_element`` changed from 4 to 2 before
    ``--resume`` was accepted (exit 0): the series went on with other samples per element
    than it started with.  Now it is refused as ``--frame`` is, naming both values; the
    store is left as it was, and the same value continues."""
    scene, out = tmp_path / "wire.toml", tmp_path / "run"
    scene.write_text(SCENE.format(t_end=0.01, ppe=4))
    assert cli.main(["run", str(scene), *QUIET, "--out", str(out)]) == 0
    saved = open_dataset(out).sizes["time"]
    scene.write_text(SCENE.format(t_end=0.02, ppe=2))
    capsys.readouterr()
    assert cli.main(["run", str(scene), *QUIET, "--out", str(out), "--resume"]) == 2
    err = capsys.readouterr().err
    assert "written with points_per_element = 4" in err and "not 2" in err
    assert "--overwrite" not in err
    assert open_dataset(out).sizes["time"] == saved
    scene.write_text(SCENE.format(t_end=0.02, ppe=4))
    assert cli.main(["run", str(scene), *QUIET, "--out", str(out), "--resume"]) == 0
    assert open_dataset(out).sizes["time"] > saved


def test_missing_checkpoint_on_resume_advises_no_deletion(finished, tmp_path, capsys):
    """Before: ``--resume`` of a run whose checkpoint was deleted said "its saved steps
    still load (Result.load); run again (--overwrite) to continue": the advice deleted the
    steps it had just said were readable.  Now it advises restoring the file or a new
    directory; the steps load."""
    run = Path(shutil.copytree(finished, tmp_path / "run"))
    for checkpoint in run.glob("checkpoint_*.npz"):
        checkpoint.unlink()
    capsys.readouterr()
    assert _run(run, "--t-end", "0.08", "--resume") == 2
    err = capsys.readouterr().err
    assert "is missing" in err and "--overwrite" not in err and "--resume" not in err
    assert "new directory (--out)" in err
    assert len(sc.Result.load(run, _pendulum())) == 6


# ===========================================================================================
# Item 8: edits after construction and after a run
# ===========================================================================================
def _hub_and_tether():
    """A hub of radius 0.5 m with a 5 m tether pinned to its rim, the system and the
    body-frame point of the pin."""
    hub = sc.RigidBody.cylinder(radius=0.5, height=0.4, density=500.0)
    sec = sc.Section.circular(1e-3, 7e10, 2700.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 5.5, 0], 4, sec)
    rim = [0, 0.5, 0]
    return hub, tether, sc.System([hub, tether]).pin(tether.node(0), hub.point(rim)), rim


def test_rigid_body_base_points_edited_after_construction_are_refused():
    """Before: ``hub.base_points = 2 * hub.base_points`` was taken without a word and the
    run pulled the pin point and the tether's root 0.2 m apart (the hub's coordinates
    ``q0``, its internal constraints and the pin's body point kept the old base points,
    its mass matrix took the new ones).  Now the edit is refused, naming the body and
    what to do; an edit in place is refused by the read-only array; the body simulates
    as built."""
    hub, tether, system, rim = _hub_and_tether()
    before = hub.base_points.copy()
    with pytest.raises(AttributeError, match=r"base_points of the rigid body 'hub' cannot "
                                             r"change after construction.*build another"):
        hub.base_points = 2 * hub.base_points
    with pytest.raises(ValueError, match="read-only"):
        hub.base_points[0] *= 2
    np.testing.assert_array_equal(hub.base_points, before)
    result = sc.simulate(system, t_end=0.01, dt=1e-3)
    pin = hub.positions(result.q[-1, system.dofs(hub)], np.array(rim))
    root = result.position(tether, 0.0)[-1]
    assert np.linalg.norm(pin - root) < 1e-9


def test_base_points_given_stay_the_callers():
    """The body copies the base points it is given: making its own read-only leaves the
    caller's array writable."""
    points = np.array([[-0.2, 0, 0], [0.2, 0, 0], [0, 0.5, 0], [0, 0, 0.5]])
    sc.RigidBody(1.0, np.zeros(3), np.diag([1.0, 1.0, 1.0]), points)
    points[0, 0] = -0.3


def _pendulum_run():
    scene = classics.pendulum(n_elements=4)
    return scene.system, scene.system.bodies[0], sc.simulate(scene.system, t_end=0.05,
                                                             dt=1e-3)


def test_result_after_the_section_was_edited_refuses_what_the_section_changes():
    """Before: ``Result.tension`` after ``cable.section`` was replaced by one of a tenth
    the radius gave 0.0072 N for 0.716 N (the stored motion with the new section's
    stiffness), while the stored energies kept the old ones.  Now ``tension`` and
    ``curvature`` refuse, naming the edit; the stored data (positions, states,
    energies) still answer, and the edited system runs as edited."""
    system, cable, result = _pendulum_run()
    tension = result.tension(cable, 0.6)[-1]
    assert tension == pytest.approx(0.716, abs=1e-3)
    cable.section = sc.Section.circular(radius=0.001, E=7e10, rho=7800.0)
    for read in (result.tension, result.curvature):
        with pytest.raises(sc.SystemChanged, match=r"since this result was simulated: "
                                                   r"bodies\[0\] \(cable\): section\.A"):
            read(cable, 0.6)
    assert result.position(cable, 1.2).shape == (len(result), 3)
    assert result.state(-1).t == pytest.approx(0.05)
    thin = classics.pendulum(n_elements=4).system
    thin.bodies[0].section = cable.section
    np.testing.assert_allclose(
        sc.simulate(system, t_end=0.05, dt=1e-3).tension(cable, 0.6),
        sc.simulate(thin, t_end=0.05, dt=1e-3).tension(thin.bodies[0], 0.6), rtol=0,
        atol=1e-12)


def test_result_multipliers_after_a_constraint_was_added_are_refused():
    """Before: ``multipliers`` after a pin was added sliced the stored multipliers by the
    new constraints (the new pin's entry empty).  Now refused, naming the change."""
    system, cable, result = _pendulum_run()
    assert list(result.multipliers) == ["pin Node(cable, 0)"]
    system.pin(cable.node(-1))
    with pytest.raises(sc.SystemChanged, match="constraints: 2 now, 1 simulated"):
        _ = result.multipliers


def test_evaluate_after_an_edit_sees_the_system_as_edited():
    """Before: ``system.evaluate`` after ``cable.section`` was replaced since the last
    solve used the stale layout (the old stiffness: the residual 7.9 off that of a system
    built with the new section), as did ``f_const`` after ``load.g`` was scaled.  Now
    the public entry points evaluate the system as it is (``current_layout``); a solver
    passes the layout it took at its start."""
    system, cable, result = _pendulum_run()
    q, lam = result.q[-1], result.lam[-1]
    thin = sc.Section.circular(radius=0.001, E=7e10, rho=7800.0)
    cable.section = thin
    fresh = classics.pendulum(n_elements=4).system
    fresh.bodies[0].section = thin
    r, _ = system.evaluate(q, None, 0.0, lam)
    np.testing.assert_allclose(r, fresh.evaluate(q, None, 0.0, lam)[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(system.assemble(q)[0], fresh.assemble(q)[0], rtol=0,
                               atol=1e-12)
    f = system.f_const.copy()
    system.loads[0].g = 10 * system.loads[0].g
    np.testing.assert_allclose(system.f_const, 10 * f, rtol=1e-12, atol=1e-15)
