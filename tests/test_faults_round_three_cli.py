"""Round three of "never a silent wrong answer" (issue 45), the command line's items:
failures a user could not read, checks that took a wrong value for 1, and the default
output of scene files."""

import importlib.util
import inspect
import json
import sys
from pathlib import Path

import pytest

from skfem_cable import bench, cli

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


def test_bench_quick_runs_the_rectification_benchmark(tmp_path, capsys):
    """``skfem-cable bench --quick rectification``: one day with and without rectification
    (about 3 s), its rows in the record."""
    assert cli.main(["bench", "--quick", "--json", str(tmp_path), "rectification"]) == 0
    assert "1 days, dt = 60 s" in capsys.readouterr().out
    (path,) = tmp_path.glob("*-rectification.json")
    rows = json.loads(path.read_text())["figures"]
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
