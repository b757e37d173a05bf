"""The guard against regressions (issue 47, must-show 3): ``skfem-cable bench --against
[REF]`` (``python3 tasks.py bench --against REF``) times the tracked cases of
``benchmarks/commit_compare.py`` here and at a fixed reference commit and flags ratios
above 1.05.  No timing is asserted: the table, the flag, the command line and one quick
run end to end."""

import ast
import importlib.util
import json
import subprocess
from pathlib import Path

import pytest

from skfem_cable.cli import command as cli

ROOT = Path(__file__).parents[1]


def load(path):
    """Import a script by its path."""
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def compare():
    return load(ROOT / "benchmarks" / "commit_compare.py")


def test_the_tracked_cases_and_the_reference(compare):
    """The six cases of issue 47, each a snippet that parses and defines what the timed
    child needs; the reference is a commit of this repository."""
    assert list(compare.CASES) == ["pendulum", "esail", "esail_full", "esail_orbit",
                                   "catenary", "controller"]
    for name, case in compare.CASES.items():
        assigned = {target.id for node in ast.walk(ast.parse(case.build, name))
                    if isinstance(node, ast.Assign) for target in ast.walk(node.targets[0])
                    if isinstance(target, ast.Name)}
        assert {"system", "initial", "dt", "rho"} <= assigned, name
        assert case.steps >= 6 and case.title
    subprocess.run(["git", "rev-parse", "--verify", f"{compare.REFERENCE}^{{commit}}"],
                   cwd=ROOT, check=True, capture_output=True)


def test_ratios_above_the_threshold_are_flagged(compare):
    ours, theirs = {"ms_per_step": 0.1052, "newton_per_step": 1.5}, {"ms_per_step": 0.1,
                                                                     "newton_per_step": 1.5}
    assert compare.flag(compare.ratio(ours, theirs)) == "SLOWER"
    assert compare.flag(1.05) == "" and compare.flag(0.5) == "" and compare.flag(None) == ""
    row = compare.table_row("E-sail", 600, ours, theirs, "abb2314")
    assert row == "| E-sail | 600 | 0.105 | 0.100 | 1.052 | 1.50 / 1.50 | SLOWER |"
    missing = {"error": "AttributeError: no build_orbit"}
    assert compare.ratio(ours, missing) is None
    row = compare.table_row("orbit", 600, ours, missing, "abb2314")
    assert row == "| orbit | 600 | 0.105 | n/a at abb2314 |  | 1.50 / n/a |  |"


def test_the_cost_per_step_takes_the_least_short_and_the_least_long_run(compare):
    """A process whose short run was slowed (the time the difference subtracts) does not
    make the cost per step read low: the least short and the least long run over the
    repeats, each alone."""
    def run(short_ms, long_ms):
        return {"ms_per_step": (long_ms - short_ms) / 500, "wall_ms_per_step": 0.0,
                "newton_per_step": 1.2, "runs_ms": [short_ms, long_ms, short_ms, long_ms],
                "steps": [100, 600]}
    best = compare.fastest([run(45.0, 62.0), run(14.4, 64.8), run(15.0, 66.0)])
    assert best["ms_per_step"] == pytest.approx((62.0 - 14.4) / 500)
    assert best["wall_ms_per_step"] == pytest.approx((62.0 - 14.4) / 500)
    assert best["newton_per_step"] == 1.2
    error = {"error": "AttributeError: no build_orbit"}
    assert compare.fastest([error]) == error


def test_a_case_the_tree_lacks_reads_not_available(compare):
    """A snippet that fails on a tree's API gives its error, not a crash of the report."""
    case = compare.Case("missing", 6, "raise AttributeError('no build_orbit')")
    assert compare.time_case(ROOT, case, 6) == {"error": "AttributeError: no build_orbit"}


def test_the_command_line_passes_the_comparison_on():
    parser = cli.build_parser()
    args = parser.parse_args(["bench", "--against", "abb2314", "--cases", "pendulum",
                              "--repeats", "3"])
    assert cli._against(args) == (["commit_compare"], ["--against", "abb2314", "--cases",
                                                       "pendulum", "--repeats", "3"])
    assert cli._against(parser.parse_args(["bench", "--against", "--quick"])) == (
        ["commit_compare"], [])
    assert cli._against(parser.parse_args(["bench", "step_cost"])) == (["step_cost"], [])
    tasks = load(ROOT / "tasks.py")
    assert tasks.task_arguments(["bench", "--against", "abb2314"]) == (
        "bench", ["--against", "abb2314"])


@pytest.mark.parametrize("argv", [["bench", "step_cost", "--against"],
                                  ["bench", "--cases", "pendulum"],
                                  ["bench", "--repeats", "2"]])
def test_options_that_do_not_go_together_are_refused(argv, capsys):
    assert cli.main(argv) == 2
    assert "--against" in capsys.readouterr().err


def test_quick_comparison_with_head_end_to_end(tmp_path, capsys):
    """``bench --against HEAD --quick --cases pendulum``: the table, exit status 0 and a
    JSON record with the ratio, the flag and the same Newton iterations in both trees."""
    assert cli.main(["bench", "--against", "HEAD", "--quick", "--cases", "pendulum",
                     "--json", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| flexible pendulum (16 elements, dt = 1 ms) | 100 |" in out
    (record,) = tmp_path.glob("*-commit_compare.json")
    (row,) = json.loads(record.read_text())["figures"]
    assert row["case"] == "pendulum" and row["ratio"] > 0 and row["flag"] in ("", "SLOWER")
    assert row["here"]["newton_per_step"] == row["base"]["newton_per_step"]
