"""The cache folder of skfem_cable, and where numba caches the package's compiled kernels.

Everything compiled is cached once per machine under one folder: ``$SKFEM_CABLE_CACHE``
if set, else ``$XDG_CACHE_HOME/skfem_cable`` (default ``~/.cache/skfem_cable``), with one
subfolder per kind (``laws`` and ``steps``: generated modules, ``kernels.generated``;
``numba``: numba's cache of every ``cache=True`` function of the package and of the
generated modules).  ``install`` (run on importing ``skfem_cable``, before any kernel is
defined) puts ``PackageLocator`` first among numba's cache locators; it claims only those
functions, so that numba caches nothing in the installed package and keeps the user's own
functions where numba's settings (``NUMBA_CACHE_DIR``) put them.

numba's own stamp of a cached function is its source file's alone, so a kernel whose callee
in another module was edited would load its stale machine code (numba links the callee
into it).  ``PackageLocator``'s stamp is the file's and those of the package modules it
imports, transitively (``dependencies``): an edit recompiles every kernel that can call the
edited code, and no other.
"""

import ast
import functools
import hashlib
import os
import re
import tempfile
from pathlib import Path

from numba.core import caching

#: The folder of the skfem_cable package.
PACKAGE = Path(__file__).resolve().parent.parent

#: Folders handed out by ``cache_dir`` (resolved): generated modules live there.
_FOLDERS = set()


def cache_root():
    """The configured cache folder (``$SKFEM_CABLE_CACHE``, else
    ``$XDG_CACHE_HOME/skfem_cable``, default ``~/.cache/skfem_cable``)."""
    env = os.environ.get("SKFEM_CABLE_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "skfem_cable"


def cache_dir(kind):
    """Folder of the cached files of ``kind`` (created if missing; a private temporary
    folder if the configured one cannot be written)."""
    folder = cache_root() / kind
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError:
        folder = Path(tempfile.gettempdir()) / f"skfem_cable-{os.getuid()}" / kind
        folder.mkdir(parents=True, exist_ok=True)
    _FOLDERS.add(folder.resolve())
    return folder


def owns(py_file):
    """Whether the source file ``py_file`` is the package's or a generated module's."""
    path = Path(py_file).resolve()
    return path.is_relative_to(PACKAGE) or path.parent in _FOLDERS


class PackageLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """numba cache locator of the functions of ``owns``: ``cache_dir("numba")``, one
    subfolder per source folder (as numba's own ``NUMBA_CACHE_DIR`` locator)."""

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        subfolder = self.get_suitable_cache_subpath(py_file)
        self._cache_path = str(cache_dir("numba") / subfolder)

    def get_cache_path(self):
        """The folder of the function's index and compiled code."""
        return self._cache_path

    def get_source_stamp(self):
        """The digest of the sources of the function's file and of the package modules
        it imports, transitively (``dependencies``): numba recompiles when it changes."""
        digest = hashlib.sha256()
        for path in sorted(dependencies(Path(self._py_file).resolve())):
            stat = path.stat()
            digest.update(caching._hash_source_file(str(path), stat.st_mtime, stat.st_size))
        return digest.hexdigest()

    @classmethod
    def from_function(cls, py_func, py_file):
        """A locator for ``py_func`` of ``py_file`` if the package owns it, else None
        (numba's next locator decides)."""
        if not owns(py_file):
            return None
        return super().from_function(py_func, py_file)


def install():
    """Put ``PackageLocator`` first among numba's cache locators (once)."""
    locators = caching.FunctionCache._impl_class._locator_classes
    if PackageLocator not in locators:
        locators.insert(0, PackageLocator)


def dependencies(py_file):
    """``py_file`` and the package's source files it imports, transitively (a set of
    paths): its own imports (``imports``), theirs, and so on."""
    seen, todo = set(), [Path(py_file)]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        stat = path.stat()
        todo.extend(imports(path, stat.st_mtime, stat.st_size))
    return seen


#: An import statement at the start of a line, at any indentation (function-level imports
#: count): ``import a.b as c, d``, or ``from .a import b`` with the names in parentheses
#: over several lines or not.  A docstring's line of that form counts too (a dependency
#: too many, harmless).
_IMPORT = re.compile(r"^[ \t]*(?:import[ \t][^\n]*|from[ \t]+[\w.]+[ \t]+import[ \t]*"
                     r"(?:\([^)]*\)|[^\n]*))", re.MULTILINE)


@functools.cache
def imports(path, mtime, size):
    """The package's source files that the module at ``path`` imports (relative imports,
    and absolute ones of ``skfem_cable``), memoised per version (mtime, size) of the
    file.  Its import statements are found by ``_IMPORT`` and parsed alone: parsing the
    whole module cost every process 0.2 s for the 30 modules of a run's kernels."""
    inside = path.is_relative_to(PACKAGE)
    package = path.relative_to(PACKAGE.parent).parent.parts if inside else ()
    found = []
    for statement in _IMPORT.findall(path.read_text()):
        try:
            node = ast.parse(statement.strip()).body[0]
        except SyntaxError:  # a docstring's line, not a statement
            continue
        if isinstance(node, ast.Import):
            found += [_source(alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level and not inside:
                continue
            base = package[:len(package) - node.level + 1] if node.level else ()
            name = ".".join([*base, *([node.module] if node.module else [])])
            found.append(_source(name))
            found += [_source(f"{name}.{alias.name}") for alias in node.names]
    return tuple(f for f in found if f is not None)


def _source(name):
    """The package's source file of the dotted module name ``name``, or None."""
    if name.split(".")[0] != PACKAGE.name:
        return None
    path = PACKAGE.parent.joinpath(*name.split("."))
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate.resolve()
    return None
