"""The documentation: docstring examples run, the API page covers the public API, the
tutorial uses documented attributes only, papers are cited by reference, and the gallery
has an entry, a small picture and an existing test for every demo."""

import ast
import doctest
import importlib
import importlib.util
import inspect
import re
from pathlib import Path

import pytest

import skfem_cable as sc

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

#: Modules whose docstring examples (``>>>``) run here.
DOCTEST_MODULES = [
    "skfem_cable",
    "skfem_cable.bodies.section",
    "skfem_cable.bodies.cable",
    "skfem_cable.model.system",
    "skfem_cable.model.state",
    "skfem_cable.results.result",
    "skfem_cable.loads",
    "skfem_cable.constraints",
    "skfem_cable.bodies.rigid",
    "skfem_cable.loads.coulomb",
    "skfem_cable.analysis.analytic",
    "skfem_cable.bodies.forms",
    "skfem_cable.laws",
]


def gallery():
    spec = importlib.util.spec_from_file_location("gallery", ROOT / "scripts" / "gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", DOCTEST_MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    result = doctest.testmod(module, optionflags=flags, verbose=False)
    assert result.attempted > 0, f"{name} has no docstring examples"
    assert result.failed == 0


def api_page():
    return (DOCS / "api.md").read_text()


def test_api_page_lists_every_export():
    text = api_page()
    missing = [name for name in sc.__all__ if f"`{name}`" not in text]
    assert not missing, f"docs/api.md does not mention {missing}"


def test_api_page_targets_exist():
    """Every ``::: dotted.path`` of the API page names a module or an object in one."""
    targets = re.findall(r"^::: ([\w.]+)", api_page(), flags=re.M)
    assert len(targets) > 40
    for target in targets:
        parts = target.split(".")
        for k in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:k]))
            except ModuleNotFoundError:
                continue
            for attr in parts[k:]:
                obj = getattr(obj, attr)
            break
        else:
            pytest.fail(f"docs/api.md: {target} cannot be imported")


def test_api_page_covers_the_subpackages_users_import():
    text = api_page()
    for module in ("skfem_cable.scenes.esail", "skfem_cable.rodchain", "skfem_cable.loads",
                   "skfem_cable.constraints", "skfem_cable.bodies.forms", "skfem_cable.laws",
                   "skfem_cable.io"):
        assert f"::: {module}\n" in text, module


def documented_attributes(cls):
    """Names in the numpydoc ``Attributes`` section of ``cls`` (``a, b : type`` lines)."""
    doc = inspect.getdoc(cls)
    section = re.search(r"^Attributes\n-+\n(.*?)(?:\n\S[^\n]*\n-+\n|\Z)", doc, flags=re.M | re.S)
    assert section, f"{cls.__name__} has no Attributes section"
    names = set()
    for line in section.group(1).splitlines():
        if line and not line.startswith(" "):
            names.update(n.strip() for n in line.split(" : ")[0].split(","))
    return names


def code_blocks(path):
    return re.findall(r"```(?:python|py)\n(.*?)```", path.read_text(), flags=re.S)


def test_tutorial_uses_documented_cable_attributes_only():
    """``cable.<name>`` in the code of the docs and the README: an entry of the
    ``Attributes`` section of ``Cable`` or a method with a docstring."""
    attributes = documented_attributes(sc.Cable)
    sources = [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]
    used = {}
    for path in sources:
        for block in code_blocks(path):
            for name in re.findall(r"\bcable\.([A-Za-z_]\w*)", block):
                used.setdefault(name, path.name)
    assert {"node"} <= set(used)
    for name, where in used.items():
        member = getattr(sc.Cable, name, None)
        method = callable(member) and not isinstance(member, property)
        ok = name in attributes or (method and inspect.getdoc(member))
        assert ok, f"{where} uses cable.{name}, which Cable does not document"


def test_cable_attributes_exist():
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    for name in documented_attributes(sc.Cable):
        assert hasattr(cable, name), name


def test_papers_are_cited_by_reference():
    """No page, README or docstring cites the papers by a path outside the repository."""
    files = [ROOT / "README.md", ROOT / "mkdocs.yml", *DOCS.rglob("*.md"),
             *(ROOT / "skfem_cable").rglob("*.py")]
    offenders = [str(p.relative_to(ROOT)) for p in files if "shared/papers" in p.read_text()]
    assert not offenders
    assert "shared/papers" not in gallery().page()
    theory = (DOCS / "theory.md").read_text()
    assert "Pacheco-Ramos" in theory and "10.1007/s42423-018-0025-1" in theory


def test_readme_keeps_its_two_setup_commands():
    readme = (ROOT / "README.md").read_text()
    assert "python3 tasks.py demo" in readme and "python3 tasks.py test" in readme


def test_gallery_has_every_demo_with_picture_and_test():
    g = gallery()
    demos = sorted(p.name for p in (ROOT / "demos").iterdir() if p.suffix in (".py", ".toml"))
    assert sorted(e.demo for e in g.ENTRIES) == demos
    for entry in g.ENTRIES:
        picture = DOCS / entry.picture
        assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", picture
        assert picture.stat().st_size < g.MAX_BYTES, picture
        test_file, function = entry.test.split("::")
        tree = ast.parse((ROOT / test_file).read_text())
        names = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
        assert function in names, entry.test
        assert callable(g.DRAW[entry.name])


def test_each_demo_script_draws_its_own_gallery_picture():
    """A demo script holds the code of its picture (``gallery_figure(path)``), which the
    gallery only runs; the gallery draws the pictures of the scene files (no code)."""
    g = gallery()
    for entry in g.ENTRIES:
        if entry.demo.endswith(".py"):
            tree = ast.parse((ROOT / "demos" / entry.demo).read_text())
            names = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
            assert "gallery_figure" in names, entry.demo
            assert not hasattr(g, f"draw_{entry.name}"), entry.demo
        else:
            assert g.DRAW[entry.name] is getattr(g, f"draw_{entry.name}"), entry.demo


def test_gallery_page_is_built_from_the_docstrings():
    g = gallery()
    text = g.page()
    for entry in g.ENTRIES:
        title = g.docstring(ROOT / "demos" / entry.demo).partition("\n")[0].strip().rstrip(".")
        assert f"## {title}\n" in text
        assert f"]({entry.picture})" in text and entry.command in text
    assert "\n-------\n" not in text  # numpydoc underlines are not turned into headings
    config = (ROOT / "mkdocs.yml").read_text()
    assert "scripts/gallery.py" in config and "gallery.md" in config
    assert not (DOCS / "gallery.md").exists()  # generated at build time only
