"""The house (issue 46): the facts ``scripts/import_graph.py`` prints, asserted.

No import cycle (function-level imports count), no module above 500 lines, the layer rules
(the model imports nothing from io, runner, plot, export or analytic; the solvers nothing
from export, io, runner or plot), the root holding the public API only (``docs/architecture.md``).
"""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("import_graph", ROOT / "scripts/import_graph.py")
import_graph = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(import_graph)

@pytest.fixture(scope="module")
def graph():
    return import_graph.graph()


def test_no_import_cycle(graph):
    lines, edges, _ = graph
    assert import_graph.cycles(lines, edges) == []


def test_no_module_over_500_lines(graph):
    lines, _, _ = graph
    assert import_graph.oversized(lines) == []


def test_no_layer_violation(graph):
    _, edges, paths = graph
    assert import_graph.violations(edges, paths) == []


def test_no_option_spelled_twice(graph):
    """A command-line option is declared in one module (``runner.options``, ``bench``)."""
    _, _, paths = graph
    assert import_graph.flags(paths) == {}


def test_package_floors(graph):
    lines, edges, _ = graph
    size, pedges = import_graph.packages(lines, edges)
    _, cycles = import_graph.floors(sorted(size), pedges)
    assert cycles == []


def test_root_holds_the_api():
    root = {p.name for p in (ROOT / "skfem_cable").glob("*.py")}
    assert root == {"__init__.py", "_moved.py"}


def test_rules_name_existing_modules(graph):
    """A rule on a module that no longer exists would pass silently."""
    lines, _, _ = graph
    for _, who, banned in import_graph.LAYERS:
        for prefix in who + banned:
            assert any(import_graph.within(m, (prefix,)) for m in lines), prefix
