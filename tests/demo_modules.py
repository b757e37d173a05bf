"""Import the runnable scripts of the project (demos, benchmarks) by path, as the tests
do: each demo is checked at reduced size through its own functions."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEMOS = ROOT / "demos"


def load(path, name=None):
    """The module of the script at ``path`` (executed once per call)."""
    path = Path(path)
    spec = importlib.util.spec_from_file_location(name or path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_demo(name):
    """The module of ``demos/NAME.py``."""
    return load(DEMOS / f"{name}.py", f"demo_{name}")
