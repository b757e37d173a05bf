"""The package's import graph, the facts of its layout, and its picture.

Reads every module of ``skfem_cable`` with ``ast`` (nothing is imported) and takes the
package-internal imports at any depth (a function-level import ties two modules as much as
a top-level one).  It prints

* the modules over a size limit (500 lines);
* the import cycles: strongly connected components of the module graph with more than
  one module;
* the violations of the layer rules (``LAYERS``: the model imports nothing from the
  output and driving layers, the solvers nothing from output), each with file:line;
* the command-line flags spelled in more than one module (an option is declared once);
* the packages' own graph: its cycles (an import that goes down the house and back up)
  and its layers (a package stands one floor above the highest package it imports),

and draws the house (``--picture``, ``docs/img/architecture.png``)::

    python scripts/import_graph.py                     # the facts; exit 1 on a cycle
    python scripts/import_graph.py --sizes 0           # every module's size
    python scripts/import_graph.py --picture docs/img/architecture.png
"""

import argparse
import ast
import functools
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

PACKAGE = Path(__file__).resolve().parents[1] / "skfem_cable"
LIMIT = 500

MODEL = ("skfem_cable.model.system", "skfem_cable.model.layout", "skfem_cable.bodies.cable",
         "skfem_cable.constraints", "skfem_cable.loads", "skfem_cable.model.motion",
         "skfem_cable.core.node", "skfem_cable.bodies.rigid")
#: (name, importers, what they may not import): module-name prefixes.
LAYERS = [
    ("model", MODEL, ("skfem_cable.io", "skfem_cable.runner", "skfem_cable.plot",
                      "skfem_cable.io.export", "skfem_cable.analysis.analytic")),
    ("solvers", ("skfem_cable.solvers",), ("skfem_cable.io.export", "skfem_cable.io",
                                          "skfem_cable.runner", "skfem_cable.plot")),
]
#: Not floors of the house: the public API imports every floor, the old paths none.
OUTSIDE = ("skfem_cable", "skfem_cable._moved")


def module_name(path):
    """``skfem_cable.a.b`` of ``skfem_cable/a/b.py`` (a package is its ``__init__``)."""
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def within(name, prefixes):
    """True if module ``name`` is one of ``prefixes`` or inside one."""
    return any(name == p or name.startswith(p + ".") for p in prefixes)


def _is_flag(node):
    return (isinstance(node, ast.Constant) and isinstance(node.value, str)
            and node.value.startswith("--") and node.value[2:3].isalpha()
            and " " not in node.value)


@functools.cache
def _scanned(path, mtime_ns, size):
    statements, spelled = [], set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            statements.append((node.lineno, None, [a.name for a in node.names]))
        elif isinstance(node, ast.ImportFrom):
            statements.append((node.lineno, (node.level, node.module or ""),
                               [a.name for a in node.names]))
        elif _is_flag(node):
            spelled.add(node.value.split("=")[0])
    return statements, spelled


def scan(path):
    """One walk of the syntax tree of the module ``path``: its import statements ``(line,
    None, names)`` (``import``) or ``(line, (level, module), names)`` (``from``), and the
    command-line flags it spells (``flags``).  Kept per process while the file keeps its
    time and size: ``imports`` and ``flags`` read the same modules (the trees themselves
    are not kept: a few hundred of them slow every later garbage collection)."""
    stat = path.stat()
    return _scanned(path, stat.st_mtime_ns, stat.st_size)


def imports(path, modules):
    """The package modules that ``path`` imports, each with the line of its first import
    (relative imports resolved)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = {}
    for line, source, names in scan(path)[0]:
        if source is None:
            targets = names
        else:
            level, base = source
            if level:
                anchor = package.split(".")[:len(package.split(".")) - level + 1]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{a}" for a in names] + [base]
        for target in targets:
            while target and target not in modules:  # a name inside a module
                target = target.rpartition(".")[0]
            if target and target != name:
                out[target] = min(out.get(target, line), line)
    return out


def graph():
    """The package's modules with their line counts, and the imports between them:
    ``{(importer, imported): line}``."""
    paths = {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}
    lines = {name: len(path.read_text().splitlines()) for name, path in paths.items()}
    # a package's __init__ re-exporting its modules is not a dependency of them
    edges = {(name, target): line for name, path in paths.items()
             for target, line in imports(path, paths).items()
             if not name.startswith(target + ".") and not target.startswith(name + ".")}
    return lines, edges, paths


def components(names, edges):
    """The strongly connected components of the directed graph ``edges`` on ``names``."""
    at = {n: i for i, n in enumerate(names)}
    ij = np.array([(at[a], at[b]) for a, b in edges], dtype=int).reshape(-1, 2)
    adjacency = coo_matrix((np.ones(len(ij)), (ij[:, 0], ij[:, 1])),
                           shape=(len(names), len(names)))
    _, label = connected_components(adjacency, directed=True, connection="strong")
    return [[n for n, k in zip(names, label) if k == c] for c in np.unique(label)]


def cycles(lines, edges):
    """The strongly connected components of more than one module: the import cycles."""
    return [g for g in components(list(lines), edges) if len(g) > 1]


def oversized(lines, limit=LIMIT):
    """``(lines, module)`` of the modules longer than ``limit`` lines, longest first."""
    return sorted(((n, name) for name, n in lines.items() if n > limit), reverse=True)


def violations(edges, paths):
    """The imports that break ``LAYERS``: ``(rule, importer, imported, "file:line")``."""
    root = PACKAGE.parent
    return sorted((rule, a, b, f"{paths[a].relative_to(root)}:{line}")
                  for (a, b), line in edges.items() for rule, who, banned in LAYERS
                  if within(a, who) and within(b, banned))


def flags(paths):
    """The command-line flags (string constants ``--name``) spelled in more than one
    module: ``{flag: [modules]}``."""
    where = defaultdict(set)
    for name, path in paths.items():
        for flag in scan(path)[1]:
            where[flag].add(name)
    return {f: sorted(m) for f, m in sorted(where.items()) if len(m) > 1}


def package_of(name):
    """The floor of a module: its top-level subpackage (``skfem_cable.loads``)."""
    return ".".join(name.split(".")[:2])


def packages(lines, edges):
    """The package graph: ``{package: (modules, lines)}`` and its edges
    ``{(a, b): number of module imports}`` (the public API and the old paths left out)."""
    size = defaultdict(lambda: [0, 0])
    for name, n in lines.items():
        if name not in OUTSIDE:
            size[package_of(name)][0] += 1
            size[package_of(name)][1] += n
    pedges = defaultdict(int)
    for a, b in edges:
        pa, pb = package_of(a), package_of(b)
        if pa != pb and a not in OUTSIDE and b not in OUTSIDE:
            pedges[pa, pb] += 1
    return dict(size), dict(pedges)


def floors(names, pedges):
    """The floor of each package: 0 for a package that imports no other, else one above
    the highest it imports (a cycle's packages share a floor); and the package cycles."""
    groups = components(names, list(pedges))
    group = {n: i for i, g in enumerate(groups) for n in g}
    floor = {}

    def visit(i, seen=()):
        if i not in floor:
            below = {group[b] for a, b in pedges if group[a] == i and group[b] != i}
            floor[i] = 1 + max((visit(j, seen + (i,)) for j in below), default=-1)
        return floor[i]

    for i in range(len(groups)):
        visit(i)
    return {n: floor[group[n]] for n in names}, [g for g in groups if len(g) > 1]


def draw(size, pedges, floor, path):
    """The house: packages as boxes on their floors, imports as arrows (grey down, red
    up: a package cycle), written to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch

    rows = defaultdict(list)
    for name in sorted(size):
        rows[floor[name]].append(name)
    width = max(3, max(len(r) for r in rows.values()))
    fig, ax = plt.subplots(figsize=(2.6 * width + 1, 0.8 * len(rows) + 1))
    xy = {}
    for f, names in rows.items():
        for k, name in enumerate(names):  # a lone package stands left or right by turns
            x = (k + 0.5) * width / len(names) if len(names) > 1 else width * (0.3 + 0.4 * (f % 2))
            xy[name] = (x, f)
    for (a, b), n in pedges.items():
        (xa, ya), (xb, yb) = xy[a], xy[b]
        up = yb >= ya
        ax.annotate("", xy=(xb, yb + 0.2), xytext=(xa, ya - 0.2),
                    arrowprops=dict(arrowstyle="-|>", lw=0.4 + 0.15 * min(n, 8),
                                    color="tab:red" if up else "0.6",
                                    alpha=0.9 if up else 0.35,
                                    connectionstyle="arc3,rad=0.08"))
    for name, (x, y) in xy.items():
        modules, n = size[name]
        label = name.removeprefix("skfem_cable.")
        ax.add_patch(FancyBboxPatch((x - 0.4, y - 0.2), 0.8, 0.4,
                                    boxstyle="round,pad=0.02", fc="#e8eef7", ec="#34558b"))
        ax.text(x, y + 0.06, label, ha="center", va="center", fontsize=9, weight="bold")
        ax.text(x, y - 0.1, f"{modules} modules, {n} lines", ha="center", va="center",
                fontsize=6.5, color="0.3")
    ax.set_xlim(-0.1, width + 0.1)
    ax.set_ylim(-0.6, max(rows) + 0.6)
    ax.set_yticks(sorted(rows))
    ax.set_yticklabels([f"floor {f}" for f in sorted(rows)], fontsize=8)
    ax.set_xticks([])
    for side in ("top", "right", "bottom"):
        ax.spines[side].set_visible(False)
    ax.set_title("skfem_cable: packages by floor (each imports the floors below; red: an "
                 "import that is not down, a package cycle)", fontsize=10)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, default=LIMIT,
                        help=f"list the modules longer than this many lines (default {LIMIT})")
    parser.add_argument("--picture", help="draw the package graph to this file (png, svg)")
    args = parser.parse_args(argv)
    lines, edges, paths = graph()
    found = cycles(lines, edges)
    print(f"{len(lines)} modules, {len(edges)} imports, {len(found)} import cycles")
    for c in found:
        print("  cycle: " + " <-> ".join(c))
    big = oversized(lines, args.sizes)
    print(f"{len(big)} modules over {args.sizes} lines")
    for n, name in big:
        print(f"  {n:5d}  {name}")
    bad = violations(edges, paths)
    print(f"{len(bad)} layer violations")
    for rule, a, b, where in bad:
        print(f"  {rule}: {a} imports {b} ({where})")
    twice = flags(paths)
    print(f"{len(twice)} command-line flags spelled in more than one module")
    for flag, modules in twice.items():
        print(f"  {flag}: {', '.join(modules)}")
    size, pedges = packages(lines, edges)
    floor, pcycles = floors(sorted(size), pedges)
    print(f"{len(size)} packages on {max(floor.values()) + 1} floors, "
          f"{len(pcycles)} package cycles")
    for c in pcycles:
        up = [f"{a} -> {b}" for (a, b) in pedges if a in c and b in c]
        print("  package cycle: " + ", ".join(sorted(up)))
    for f in sorted(set(floor.values()), reverse=True):
        names = [n.removeprefix("skfem_cable.") for n in sorted(size) if floor[n] == f]
        print(f"  floor {f}: {', '.join(names)}")
    if args.picture:
        draw(size, pedges, floor, args.picture)
        print(f"drawn: {args.picture}")
    return 1 if found or bad else 0


if __name__ == "__main__":
    sys.exit(main())
