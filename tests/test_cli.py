"""The skfem-cable command: run directories, TOML scene files, validate, bench."""

import json
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import scene_file
from skfem_cable.analysis.analytic import elastica_tip_load
from skfem_cable.cli import command as cli
from skfem_cable.io import export
from skfem_cable.runner import RunOptions
from skfem_cable.scenes import catalog

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "demos" / "spinning_hub.toml"


def test_toml_scene_run_directory(tmp_path, capsys):
    """The example scene file at reduced size: run store, VTU series, summary and plots;
    the summary's numbers are those of the stored results, and it lists the store."""
    out = tmp_path / "hub"
    rc = cli.main(["run", str(EXAMPLE), "--t-end", "0.05", "--elements", "2", "--every", "5",
                   "--out", str(out), "--no-progress"])
    assert rc == 0
    assert "spinning_hub" in capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == 10 and summary["saved_steps"] == 3
    assert summary["parameters"]["dt"] == 5e-3 and summary["parameters"]["every"] == 5
    assert summary["newton"]["iterations"] >= summary["steps"]
    assert summary["files"]["store"] == "results.zarr" and (out / "results.zarr").is_dir()
    assert summary["store"]["saved_steps"] == 3 and summary["store"]["status"] == "complete"
    spec = scene_file.load(EXAMPLE, elements=2)
    result = sc.Result.load(out, spec.system)
    assert np.allclose(result.t, [0.0, 0.025, 0.05])
    tether = next(b for b in spec.system.bodies if b.name == "tether1")
    tip = summary["outputs"]["cables"]["tether1"]["tip_position"]
    assert np.allclose(tip, result.position(tether, tether.length)[-1])
    assert [t for t, _ in export.read_pvd(out / "series.pvd")] == list(result.t)
    for name in summary["files"]["plots"]:
        assert (out / name).stat().st_size > 1000
    described = summary["files"]["described"]  # every file of the run, described
    on_disk = {p.relative_to(out).as_posix() for p in out.iterdir() if p.is_file()}
    on_disk |= {p.relative_to(out).as_posix() for p in (out / "plots").iterdir()}
    assert on_disk <= set(described) and "results.zarr" in described
    assert "vtu/series_*.vtu" in described and "(3 files)" in described["vtu/series_*.vtu"]
    assert all(len(text) > 20 and text != "written by this package"
               for text in described.values())


def test_static_scene_file_matches_the_elastica(tmp_path):
    text = """
        title = "cantilever"
        [solver]
        analysis = "static"
        load_steps = 20
        [sections.beam]
        E = 1e9
        A = 1e-4
        I = 1e-11
        rho = 7850.0
        [[cables]]
        name = "beam"
        section = "beam"
        start = [0, 0, 0]
        end = [1, 0, 0]
        elements = 16
        [[constraints]]
        type = "clamp"
        node = { cable = "beam", index = 0 }
        [[loads.point]]
        at = { cable = "beam", index = -1 }
        force = [0, -0.05, 0]   # P L^2 / EI = 5
    """
    path = tmp_path / "cantilever.toml"
    path.write_text(text)
    summary = catalog.run_scene(str(path), RunOptions(out=tmp_path / "run", plots=False))
    tip = summary["outputs"]["cables"]["beam"]["tip_position"]
    assert -tip[1] == pytest.approx(elastica_tip_load(5.0)[1], rel=1e-3)
    assert (tmp_path / "run" / "summary.json").exists()


BASE = """
[solver]
t_end = 1.0
dt = 0.01
[sections.s]
E = 1e9
rho = 1000.0
radius = 0.001
[[cables]]
name = "c"
section = "s"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 2
"""


@pytest.mark.parametrize("change, message", [
    (("dt = 0.01", "dt = -0.01"), "solver.dt must be a number > 0, got -0.01"),
    (("elements = 2", "elements = 2.5"), "cables[0].elements must be an integer >= 1, got 2.5"),
    (("section = \"s\"", "section = \"t\""), "cables[0].section names no section"),
    (("radius = 0.001", "radiu = 0.001"),
     "sections.s.radius is required (found the unknown key 'radiu')"),
    (("rho = 1000.0", "rho = 1000.0\ncolour = 3"), "sections.s.colour is not a known key"),
    (("[solver]", "[solver]\nrho_inf = 2"), "solver.rho_inf must lie in [0.0, 1.0], got 2"),
    (("end = [1, 0, 0]", "end = [1, 0]"), "cables[0].end must be a list of 3 numbers"),
    (("elements = 2", "elements = 2\n[[constraints]]\ntype = \"pin\"\n"
      "node = { cable = \"c\", index = 3 }"), "constraints[0].node.index is out of range"),
    (("elements = 2", "elements = 2\n[[constraints]]\ntype = \"weld\"\n"),
     "constraints[0].type must be one of 'pin', 'clamp', got 'weld'"),
    (("elements = 2", "elements = 2\n[loads]\ncentrifugal = [0, 0, 1]"),
     "loads.centrifugal applies to static analyses only"),
    (("t_end = 1.0", "t_end = 1.0\nt_end = 2.0"), "not valid TOML"),
])
def test_scene_file_errors_name_key_and_value(change, message):
    with pytest.raises(scene_file.SceneFileError) as err:
        scene_file.loads_text(BASE.replace(*change), "bad.toml")
    assert str(err.value).startswith("bad.toml: ")
    assert message in str(err.value)


def test_run_rejects_options_a_scene_does_not_take(capsys):
    assert cli.main(["run", "pendulum", "--alpha", "5"]) == 2
    assert "does not take --alpha" in capsys.readouterr().err
    assert cli.main(["run", "no-such-scene"]) == 2
    assert "unknown scene 'no-such-scene'" in capsys.readouterr().err


def test_builtin_scenes_run(tmp_path, capsys):
    assert cli.main(["run", "cantilever", "--elements", "8", "--no-plots",
                     "--out", str(tmp_path / "c")]) == 0
    summary = json.loads((tmp_path / "c" / "summary.json").read_text())
    rows = summary["outputs"]["elastica"]
    assert [r["k"] for r in rows] == [1.0, 2.0, 5.0, 10.0]
    assert max(r["rel_error"] for r in rows) < 2e-2
    assert len(export.read_pvd(tmp_path / "c" / "series.pvd")) == 4
    assert cli.main(["run", "spinning-tether", "--elements", "3", "--t-end", "0.02"]) == 0
    assert "root_tension_rigid" in capsys.readouterr().out


def test_registry_takes_dotted_targets(tmp_path):
    catalog.register("probe-scene", "dataclasses:asdict", "a stand-in runner")
    try:
        assert catalog.run_scene("probe-scene", RunOptions(t_end=2.0))["t_end"] == 2.0
        with pytest.raises(ValueError, match="'probe-scene' does not take --model"):
            catalog.run_scene("probe-scene", RunOptions(model="rodchain"))
    finally:
        del catalog.SCENES["probe-scene"]


def test_validate_prints_the_table(capsys):
    assert cli.main(["validate", "cantilever-frequency", "spinning-tension"]) == 0
    out = capsys.readouterr().out
    assert "cantilever-frequency" in out and "2 passed, 0 failed" in out
    assert cli.main(["validate", "nonsense"]) == 2


def test_bench_lists_the_scripts_and_help_works(capsys):
    assert cli.main(["bench", "--list"]) == 0
    assert "kernel_cost" in capsys.readouterr().out
    assert cli.main(["bench", "nonsense"]) == 2
    with pytest.raises(SystemExit) as exit_:
        cli.main(["run", "--help"])
    assert exit_.value.code == 0
    assert "--t-end" in capsys.readouterr().out


def test_printed_summary_abridges_large_groups_of_bodies():
    from skfem_cable.runner import format_summary

    summary = {"scene": "x", "outputs": {"cables": {f"c{i}": {"L": 1.0} for i in range(10)},
                                         "thrust": 0.5}}
    text = format_summary(summary)
    assert "c2:" in text and "c3:" not in text and "... 7 more in summary.json" in text
    assert "thrust: 0.5" in text
