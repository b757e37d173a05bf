"""Generated modules: source written once to an on-disk cache and imported from there, so
that numba (``cache=True``) compiles it once per machine, not once per run.

The cache folder is ``$SKFEM_CABLE_CACHE`` if set, else ``$XDG_CACHE_HOME/skfem_cable``
(default ``~/.cache/skfem_cable``; ``kernels.cache``), with one subfolder per kind of
module; a module's name carries a digest of everything its text depends on, so a changed
input never meets a stale module.
"""

import hashlib
import importlib.util
import inspect
import sys

import numba

from ..util.atomic import write_atomic
from . import compile_log
from .cache import cache_dir


def digest(*parts):
    """A 16-character digest of the strings ``parts``."""
    return hashlib.sha256("|".join(parts).encode()).hexdigest()[:16]


def load(kind, name, make_source, namespace=None, description=None, jit=True):
    """Import the module ``name`` of ``kind``, writing it first with ``make_source()``
    if it is not in the cache; ``namespace`` (a dict) is placed in the module before its
    text runs (objects its text refers to by name, e.g. compiled kernels); numba's
    compilation of the module is reported as that of ``description`` (``compile_log``;
    default: the module ``name``).  ``jit=False``: the same text imported under
    ``numba.config.DISABLE_JIT`` (its functions stay Python; what it imports compiled
    stays compiled), as the module ``name + "_python"``."""
    module_name = name if jit else name + "_python"
    if module_name in sys.modules:
        return sys.modules[module_name]
    compile_log.DESCRIPTIONS[name] = description or f"module {name}"
    path = cache_dir(kind) / f"{name}.py"
    if not path.exists():
        write_atomic(path, make_source().encode())
    spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(spec)
    module.__dict__.update(namespace or {})
    sys.modules[module_name] = module
    disabled = numba.config.DISABLE_JIT
    numba.config.DISABLE_JIT = disabled or not jit
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[module_name]
        raise
    finally:
        numba.config.DISABLE_JIT = disabled
    return module


def _source_id(py):
    try:
        text = inspect.getsource(py)
    except (OSError, TypeError):
        text = repr(py)
    return f"{py.__module__}.{py.__qualname__}:{text}"


def _compiled_callees(py):
    """The compiled functions that ``py`` names through its globals, directly or as an
    attribute of a module it names (in its code and in the code nested in it)."""
    names, stack = set(), [py.__code__]
    while stack:
        code = stack.pop()
        names.update(code.co_names)
        stack.extend(c for c in code.co_consts if inspect.iscode(c))
    found = []
    for name in sorted(names):
        value = py.__globals__.get(name)
        candidates = [value] if not inspect.ismodule(value) else \
            [getattr(value, attr, None) for attr in sorted(names)]
        found += [c for c in candidates if hasattr(c, "py_func")]
    return found


def source_id(function):
    """The source of a kernel and of every compiled function it calls, transitively:
    numba's cache of the generated module does not notice changes in a callee."""
    ids, seen, stack = [], set(), [function]
    while stack:
        py = getattr(stack.pop(), "py_func", None)
        if py is None or py in seen:
            continue
        seen.add(py)
        ids.append(_source_id(py))
        stack.extend(_compiled_callees(py))
    return "\n".join(ids) if ids else _source_id(function)
