"""The cache folder of skfem_cable, and where numba caches the package's compiled kernels.

Everything compiled is cached once per machine under one folder: ``$SKFEM_CABLE_CACHE``
if set, else ``$XDG_CACHE_HOME/skfem_cable`` (default ``~/.cache/skfem_cable``), with one
subfolder per kind (``laws`` and ``steps``: generated modules, ``kernels.generated``;
``numba``: numba's cache of every ``cache=True`` function of the package and of the
generated modules).  ``install`` (run on importing ``skfem_cable``, before any kernel is
defined) puts ``PackageLocator`` first among numba's cache locators; it claims only those
functions, so that numba caches nothing in the installed package and keeps the user's own
functions where numba's settings (``NUMBA_CACHE_DIR``) put them.
"""

import os
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
