"""Mission-length runs (issue 31): durations with suffixes, the progress bar's simulated
time per wall second, and the full-size E-sail preset."""

import io
import time
from pathlib import Path

import pytest

from skfem_cable import cli, durations
from skfem_cable.io.progress import Progress
from skfem_cable.scene_file import loads_text
from skfem_cable.scenes import catalog, esail

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("text, seconds", [("30d", 2592000.0), ("12h", 43200.0),
                                           ("90min", 5400.0), ("0.5s", 0.5), ("2.5", 2.5),
                                           (" 1e3 s ", 1000.0), (4, 4.0)])
def test_durations_take_the_suffixes(text, seconds):
    assert durations.parse(text) == seconds


@pytest.mark.parametrize("text", ["30 days", "h", "1.2.3h", "inf", "nan", None, "5y"])
def test_a_bad_duration_names_the_accepted_forms(text):
    with pytest.raises(ValueError, match="t_end must be a finite number of seconds or a "
                                         "number with a suffix s, min, h or d"):
        durations.parse(text, "t_end")


def test_the_cli_and_scene_files_read_durations():
    args = cli.build_parser().parse_args(["run", "esail-full", "--t-end", "30d", "--dt", "2min"])
    assert (args.t_end, args.dt) == (2592000.0, 120.0)
    with pytest.raises(SystemExit):
        cli.build_parser().parse_args(["run", "esail-full", "--t-end", "-1d"])
    text = (ROOT / "demos" / "reel_brake.toml").read_text()
    spec = loads_text(text.replace("t_end = 1.0 ", 't_end = "1s"').replace(
        "dt = 1e-3 ", 'dt = "0.001s"'), "reel_brake.toml")
    assert (spec.solver["t_end"], spec.solver["dt"]) == (1.0, 1e-3)


def test_the_progress_bar_shows_simulated_time_per_wall_second():
    stream = io.StringIO()
    bar = Progress(0.0, 30 * 86400.0, enabled=True, stream=stream)
    time.sleep(0.05)
    bar.update(2.5 * 86400.0)
    line = stream.getvalue()
    assert "t=2.5 d, " in line and " d/s" in line and "ETA" in line


def test_the_full_size_sail_meets_the_spin_criterion():
    """Janhunen and Toivanen's criterion: centrifugal tension at the root at least 5 times
    the Coulomb force on the tether (the paper's baseline has 59)."""
    cfg = esail.FULL_SIZE
    assert (cfg.n_tethers, cfg.tether_length) == (100, 20e3)
    assert 5.0 <= cfg.centrifugal_ratio < 6.0
    tether = cfg.tether_density * cfg.tether_area * cfg.tether_length
    force = cfg.wind.force_per_length(cfg.voltage) * cfg.tether_length
    assert cfg.centrifugal_ratio == pytest.approx(
        cfg.spin_rate**2 * cfg.tether_length * (cfg.remote_mass + tether / 2) / force)
    assert esail.BaselineConfig().centrifugal_ratio == pytest.approx(59.2, abs=0.1)


def test_the_esail_full_scene_runs_with_adaptive_steps():
    scene = catalog.esail_full_scene(elements=2, t_end=5.0)
    assert scene.settings["rtol"] == esail.MISSION_RTOL
    assert len(scene.system.cables()) == 100
    from skfem_cable import simulate

    settings = {k: v for k, v in scene.settings.items() if k != "series_every"}
    result = simulate(scene.system, initial=scene.initial, **settings)
    assert result.t[-1] == 5.0 and result.stats["path"] == "compiled"
    assert scene.outputs(result)["thrust_mean_N"] == pytest.approx(0.89, rel=0.02)  # 1 AU
