"""A new user's first hour: errors that name the parameter and its range instead of a
traceback or a misleading message, a progress bar and a quick benchmark that never show NaN
or a negative time, and documentation that lists what the command knows."""

import argparse
import importlib.util
import inspect
import io
import math
import os
import re
import sys
from pathlib import Path

import pytest

import skfem_cable as sc
from skfem_cable import study
from skfem_cable.cli import bench
from skfem_cable.cli import command as cli
from skfem_cable.io.progress import Progress
from skfem_cable.runner import values
from skfem_cable.scenes import catalog

ROOT = Path(__file__).resolve().parents[1]
DEMO = ROOT / "demos" / "spinning_hub.toml"

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib


def _error(capsys):
    """The standard error of the last command: one line of ours (after argparse's usage
    lines, if any), without a traceback."""
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if "error:" in line]
    assert len(lines) == 1, err
    return lines[0]


def _numeric_options():
    """``(command, option, check)`` of every option of every subcommand whose value is
    checked by one of the command's number types."""
    parser = cli.build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    checks = (values.positive_int, values.finite_float, values.duration)
    return [(name, action.option_strings[0], action.type)
            for name, sub in commands.choices.items() for action in sub._actions
            if action.type in checks]


def _base(command):
    """A command line of ``command`` that every option can be added to."""
    return {"run": ["run", "pendulum"],
            "sweep": ["sweep", "pendulum", "--param", "elements=2", "--out", "unused"],
            "bench": ["bench", "--against", "HEAD", "--cases", "pendulum"]}[command]


# --- --out that cannot be made ------------------------------------------------------------------
@pytest.fixture
def blocked(tmp_path, monkeypatch):
    """Fail the test if a run, sweep or benchmark starts; returns a regular file."""
    monkeypatch.setattr(catalog, "run_scene", lambda *a: pytest.fail("the scene ran"))
    monkeypatch.setattr(study, "sweep", lambda *a, **k: pytest.fail("the sweep ran"))
    monkeypatch.setattr(bench, "run", lambda *a, **k: pytest.fail("the benchmarks ran"))
    path = tmp_path / "file"
    path.write_text("not a folder")
    return path


@pytest.mark.parametrize("command", [
    ["run", "pendulum", "--out"],
    ["sweep", "pendulum", "--param", "elements=2", "--out"],
    ["bench", "step_cost", "--out"],
    ["bench", "step_cost", "--json"],
])
def test_out_under_a_file_is_refused_naming_it(blocked, command, capsys):
    """Before: ``sweep`` ran every point into a failed study and ended in ``[Errno 20] Not
    a directory``, ``bench`` ran the benchmark first; ``run`` already said it."""
    out = blocked / "sub"
    assert cli.main([*command, str(out)]) == 2
    line = _error(capsys)
    assert f"{command[-1]} {out}: {blocked} is a file, not a directory" in line


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
@pytest.mark.parametrize("command", [
    ["sweep", "pendulum", "--param", "elements=2", "--out"],
    ["bench", "step_cost", "--out"],
])
def test_out_in_a_read_only_folder_is_refused_naming_it(blocked, tmp_path, command,
                                                        capsys):
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        assert cli.main([*command, str(folder / "sub")]) == 2
    finally:
        folder.chmod(0o755)
    assert f"{command[-1]} {folder / 'sub'}: {folder} is read-only" in _error(capsys)


def test_out_in_a_read_only_folder_is_refused_as_any_user(blocked, tmp_path, monkeypatch,
                                                          capsys):
    """The same as another user than root sees it (``os.access`` says no)."""
    monkeypatch.setattr(os, "access", lambda path, mode, **kw: Path(path) != tmp_path)
    assert cli.main(["sweep", "pendulum", "--param", "elements=2", "--out",
                     str(tmp_path / "study")]) == 2
    assert f"--out {tmp_path / 'study'}: {tmp_path} is read-only" in _error(capsys)


# --- negative numbers ---------------------------------------------------------------------------
def test_every_numeric_option_is_found():
    found = {(command, option) for command, option, _ in _numeric_options()}
    assert {("run", "--dt"), ("run", "--t-end"), ("run", "--elements"), ("run", "--every"),
            ("run", "--alpha"), ("sweep", "--t-end"), ("sweep", "--workers")} <= found


@pytest.mark.parametrize("value", ["-1e-3", "-1E+2", "-.5", "-2", "-inf", "nan"])
def test_negative_numbers_reach_the_range_check(value, capsys):
    """Before: ``--dt -1e-3`` got argparse's ``expected one argument`` (its pattern of a
    negative number has no exponent), ``--dt=-1e-3`` the range check."""
    for command, option, check in _numeric_options():
        if check is values.finite_float and value not in ("-inf", "nan"):
            continue  # a finite negative number is a valid value there
        with pytest.raises(SystemExit) as info:
            cli.main([*_base(command), option, value])
        assert info.value.code == 2
        line = _error(capsys)
        assert re.search(rf"argument {option}: must be (a finite number|an integer)", line)
        assert line.endswith(f"got {value}")


def test_negative_values_are_accepted_where_they_are_valid(monkeypatch, capsys):
    """``--alpha -1e1`` is a sailing angle of -10 degrees."""
    seen = []

    def scene(name, options):
        seen.append(options.alpha)
        raise ValueError("stop here")

    monkeypatch.setattr(catalog, "run_scene", scene)
    assert cli.main(["run", "esail", "--alpha", "-1e1"]) == 2
    assert seen == [-10.0] and "stop here" in _error(capsys)


def test_words_are_refused_with_the_range_not_the_type_name(capsys):
    """Before: ``invalid _positive_int value: '2.5'``."""
    for option, value in (("--elements", "2.5"), ("--dt", "abc")):
        with pytest.raises(SystemExit):
            cli.main(["run", "pendulum", option, value])
        line = _error(capsys)
        assert "_positive" not in line and f"argument {option}: must be" in line


# --- Cable.straight ------------------------------------------------------------------------------
SECTION = sc.Section.circular(1e-3, 2e11, 7850.0)


@pytest.mark.parametrize("start, end, n, message", [
    ([0, math.nan, 0], [1, 0, 0], 2, "start must be 3 finite coordinates"),
    ([0, 0, 0], [math.inf, 0, 0], 2, "end must be 3 finite coordinates"),
    ([0, 0, 0], [1, 0], 2, "end must be 3 finite coordinates"),
    ([0, 0, 0], [1, 0, 0], math.nan, "n_elements must be a positive integer"),
    ([0, 0, 0], [1, 0, 0], math.inf, "n_elements must be a positive integer"),
    ([0, 0, 0], [0, 0, 0], 2, "start and end must differ"),
])
def test_straight_cable_names_the_argument_that_is_not_finite(start, end, n, message):
    """Before: a NaN coordinate said ``start and end must differ``, an infinite count raised
    ``OverflowError``."""
    with pytest.raises(ValueError, match=message):
        sc.Cable.straight(start, end, n, SECTION)


# --- scene files: unknown keys -----------------------------------------------------------------
@pytest.mark.parametrize("old, new, key, guess", [
    ("[[constraints]]", "[[constraint]]", "constraint", "constraints"),
    ("rho_inf = 0.8", "rho_in = 0.8", "solver.rho_in", "rho_inf"),
])
def test_unknown_key_is_named_with_the_closest_known_one(tmp_path, old, new, key, guess,
                                                         capsys):
    """Before: ``constraint is not a known key (...), got [{'type': 'pin', ...}]``: the
    whole table, and no suggestion."""
    scene = tmp_path / "typo.toml"
    scene.write_text(DEMO.read_text().replace(old, new))
    assert cli.main(["run", str(scene), "--no-progress"]) == 2
    line = _error(capsys)
    assert f"{scene}: {key} is not a known key: did you mean {guess!r}?" in line
    assert "{" not in line and "got" not in line


# --- progress bar -------------------------------------------------------------------------------
def test_first_frame_of_the_progress_bar_shows_no_nan():
    """Before: ``ETA nans`` until a step was done."""
    stream = io.StringIO()
    bar = Progress(0.0, 2.0, enabled=True, stream=stream)
    bar.update(0.0)
    assert "nan" not in stream.getvalue() and "ETA      --" in stream.getvalue()
    bar.last = -1.0
    bar.update(1.0)
    assert "nan" not in stream.getvalue().lower()


def test_progress_over_an_empty_span_is_complete():
    stream = io.StringIO()
    Progress(1.0, 1.0, enabled=True, stream=stream).update(1.0)
    assert "100.0%" in stream.getvalue()


# --- quick benchmark ----------------------------------------------------------------------------
def _step_cost():
    path = ROOT / "benchmarks" / "step_cost.py"
    spec = importlib.util.spec_from_file_location("step_cost", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_step_cost_fit_refuses_times_that_are_not_positive():
    """Before: a negative time went into ``np.log``: a ``RuntimeWarning`` and ``nan``."""
    step_cost = _step_cost()
    assert step_cost.exponent([10, 100, 1000], [-0.8, 0.1, 1.0], half=False) is None
    assert step_cost.verdict(None, True, True) == "not fitted (a time is not positive)"
    assert step_cost.exponent([10, 100, 1000], [0.01, 0.1, 1.0], half=False) == \
        pytest.approx(1.0)


def test_step_cost_takes_more_steps_until_the_difference_is_measurable(monkeypatch):
    """A difference of runs lost in the scatter of their setup (here negative) is measured
    again over more steps, never printed."""
    step_cost = _step_cost()
    spans = iter([-1e-3, 0.05, 0.3])

    def walls(system, compiled, steps, repeats):
        span = next(spans) if compiled else 1.0
        return {1: 0.01, 1 + steps: 0.01 + span}, {1: 3, 1 + steps: 3 + 2 * steps}

    monkeypatch.setattr(step_cost, "best_walls", walls)
    fast, slow, newton, setup, steps = step_cost.cost_per_step(2, steps=10, repeats=1)
    assert steps > 100 and fast == pytest.approx(300 / steps) and newton == 2.0
    assert step_cost.more_steps(10, 0.0, 0.2) == 100
    assert 24 <= step_cost.more_steps(10, 0.1, 0.2) <= 25  # 1.2 x the span
    assert step_cost.more_steps(10, 0.3, 0.2) == 11  # at least one more


def test_quick_step_cost_says_its_exponents_are_indicative(capsys):
    figures = _step_cost().table((4, 8), steps=5, repeats=1, quick=True, span=0.02)
    out = capsys.readouterr().out
    assert "nan" not in out and "indicative (quick mode)" in out
    assert all(r["compiled_ms"] > 0 and r["python_ms"] > 0 for r in figures["rows"])
    assert not re.search(r"\s-\d", out.split("growth exponent")[0])  # no negative time


# --- documentation ------------------------------------------------------------------------------
def _help(capsys, *argv):
    with pytest.raises(SystemExit):
        cli.main([*argv, "--help"])
    return capsys.readouterr().out


def test_cli_docs_list_every_scene_of_run_help(capsys):
    """Before: ``docs/cli.md`` left out ``esail``."""
    epilog = _help(capsys, "run").split("scenes:\n", 1)[1]
    listed = set(re.findall(r"^  (\S+) ", epilog, re.M)) - {"FILE.toml"}
    assert listed == set(catalog.SCENES)
    docs = (ROOT / "docs" / "cli.md").read_text().split("## `run`", 1)[1].split("###", 1)[0]
    documented = set(re.findall(r"^\| `([^`]+)` \|", docs, re.M)) - {"FILE.toml"}
    assert documented == listed


def _build_parameters():
    """``{scene: [(parameter, repr of its default)]}`` of the sweepable scenes."""
    return {name: [(p.name, repr(p.default))
                   for p in inspect.signature(entry.builder()).parameters.values()]
            for name, entry in catalog.SCENES.items() if entry.build is not None}


def test_sweep_help_lists_each_scenes_parameters(capsys):
    """Before: only the names of the sweepable scenes."""
    out = _help(capsys, "sweep")
    for name, params in _build_parameters().items():
        block = out.split(f"  {name} ", 1)[1]
        assert all(f"{p}={default}" in block for p, default in params)


def test_cli_docs_list_each_sweepable_scenes_parameters():
    """Before: ``spinning-tether`` was documented without ``spin`` and ``tip_mass``."""
    docs = (ROOT / "docs" / "cli.md").read_text().split("## `sweep`", 1)[1]
    rows = dict(re.findall(r"^\| `([^`]+)` \| (.*) \|$", docs, re.M))
    for name, params in _build_parameters().items():
        assert re.findall(r"`(\w+)=([^`]*)`", rows[name]) == params


def test_licence_is_an_spdx_expression():
    """Before: ``license = { text = ... }``, which setuptools >= 77 reports as deprecated."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["license"] == "BSD-3-Clause"
    assert not any(c.startswith("License ::") for c in project["project"].get(
        "classifiers", []))
    assert "setuptools>=77" in project["build-system"]["requires"]


def test_scenes_register_their_files_and_overwrite_removes_only_the_runs(tmp_path,
                                                                          monkeypatch):
    """A scene registers the files it writes (``register_files``, listed ``after`` a named
    one); ``--overwrite`` (``remove_run``) removes the files a run's summary describes
    even when the scene that registered them is not imported in this process, and never
    a user's file, the store's lock or a path outside the directory."""
    import json

    from skfem_cable.runner import directory

    monkeypatch.setattr(directory, "DESCRIPTIONS", dict(directory.DESCRIPTIONS))
    directory.register_files({"plots/probe.png": "a probe's figure"}, after="summary.json")
    names = list(directory.DESCRIPTIONS)
    assert names[names.index("summary.json") + 1] == "plots/probe.png"
    with pytest.raises(ValueError, match="no run file 'nothing.txt' is registered"):
        directory.register_files({"x.png": "x"}, after="nothing.txt")
    out = tmp_path / "run"
    (out / "plots").mkdir(parents=True)
    (out / "plots" / "chain.png").write_bytes(b"png")   # a scene not imported here
    (out / "notes.txt").write_text("mine")
    (tmp_path / "outside.txt").write_text("not the run's")
    (out / "summary.json").write_text(json.dumps({"files": {"described": {
        "plots/chain.png": "figure", "../outside.txt": "escape", "/etc/hosts": "escape",
        "summary.json": "the summary"}}}))
    assert [p.name for p in directory.recorded_files(out)] == ["chain.png", "summary.json"]
    directory.remove_run(out)
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]
    assert (tmp_path / "outside.txt").exists()


def test_printed_summary_keeps_a_matrix_on_its_line():
    """Before: a rigid body's rotation printed its rows on lines of their own, out of the
    summary's indentation."""
    from skfem_cable.runner import format_summary

    text = format_summary({"scene": "s", "outputs": {"bodies": {"hub": {
        "rotation": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}}}})
    line = next(row for row in text.splitlines() if "rotation" in row)
    assert line.strip() == "rotation: [[1. 0. 0.] [0. 1. 0.] [0. 0. 1.]]"
