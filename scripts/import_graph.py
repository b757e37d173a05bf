"""The package's import graph: its cycles and its module sizes.

Reads every module of ``skfem_cable`` with ``ast`` (nothing is imported), takes the
package-internal imports at any depth (a function-level import ties two modules as much as
a top-level one), and prints the strongly connected components with more than one module
(the import cycles) and the modules over a size limit::

    python scripts/import_graph.py            # cycles, then modules over 500 lines
    python scripts/import_graph.py --sizes 0  # every module's size

Exits 1 if there is a cycle.
"""

import argparse
import ast
import sys
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

PACKAGE = Path(__file__).resolve().parents[1] / "skfem_cable"


def module_name(path):
    """``skfem_cable.a.b`` of ``skfem_cable/a/b.py`` (a package is its ``__init__``)."""
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path, modules):
    """The package modules that ``path`` imports (relative imports resolved)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        for target in targets:
            while target and target not in modules:  # a name inside a module
                target = target.rpartition(".")[0]
            if target and target != name:
                out.add(target)
    return out


def graph():
    """The package's modules with their line counts, and the imports between them
    (``(importer, imported)`` pairs)."""
    paths = {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}
    lines = {name: len(path.read_text().splitlines()) for name, path in paths.items()}
    # a package's __init__ re-exporting its modules is not a dependency of them
    edges = [(name, target) for name, path in paths.items()
             for target in imports(path, paths)
             if not name.startswith(target + ".") and not target.startswith(name + ".")]
    return lines, edges


def cycles(lines, edges):
    """The strongly connected components of more than one module: the import cycles."""
    names = list(lines)
    at = {n: i for i, n in enumerate(names)}
    ij = np.array([(at[a], at[b]) for a, b in edges], dtype=int).reshape(-1, 2)
    adjacency = coo_matrix((np.ones(len(ij)), (ij[:, 0], ij[:, 1])),
                           shape=(len(names), len(names)))
    _, label = connected_components(adjacency, directed=True, connection="strong")
    groups = [[n for n, k in zip(names, label) if k == c] for c in np.unique(label)]
    return [g for g in groups if len(g) > 1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, default=500,
                        help="list the modules longer than this many lines (default 500)")
    args = parser.parse_args(argv)
    lines, edges = graph()
    found = cycles(lines, edges)
    print(f"{len(lines)} modules, {len(edges)} imports, {len(found)} import cycles")
    for c in found:
        print("  cycle: " + " <-> ".join(c))
    big = sorted(((n, name) for name, n in lines.items() if n > args.sizes), reverse=True)
    print(f"{len(big)} modules over {args.sizes} lines")
    for lines, name in big:
        print(f"  {lines:5d}  {name}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
