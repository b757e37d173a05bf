"""Round three of "never a silent wrong answer" (issue 45), the command line's items:
failures a user could not read, checks that took a wrong value for 1, and the default
output of scene files."""

import importlib.util
import inspect
import json
import sys

import pytest

from skfem_cable import bench, cli


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


def test_bench_quick_runs_the_rectification_benchmark(tmp_path, capsys):
    """``skfem-cable bench --quick rectification``: one day with and without rectification
    (about 3 s), its rows in the record."""
    assert cli.main(["bench", "--quick", "--json", str(tmp_path), "rectification"]) == 0
    assert "1 days, dt = 60 s" in capsys.readouterr().out
    (path,) = tmp_path.glob("*-rectification.json")
    rows = json.loads(path.read_text())["figures"]
    assert [row["rectify"] for row in rows] == [1e-4, None] and rows[0]["rebases"] > 0
