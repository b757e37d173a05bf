"""What numba compiles for skfem_cable, and how long it takes: said on stderr, and counted
apart from the work (``seconds``, e.g. ``compile_time`` in ``Result.stats``).

numba compiles a function at its first call, or loads it from its cache; both happen
under numba's compiler lock.  ``install`` (run on importing ``skfem_cable``) listens to
numba's events: the time spent under the lock (compiling or loading) adds up in
``seconds``, and the time of every compilation is charged to the module of the compiled
function (less the functions it compiled in turn).  When the outermost section under the
lock ends, one line per generated module that compiled there (``DESCRIPTIONS``) and one
for the package's own kernels go to stderr; a run that only loads compiled code from the
cache says nothing.  Threads are counted apart.  ``Recorder``, for profiling, lists every
compilation with its CPU seconds and its LLVM part (not installed by default).
"""

import sys
import threading
import time

from numba.core import event

from .cache import cache_dir

#: What the generated module of each name holds (``generated.load``), for the report.
DESCRIPTIONS = {}


class _Books(threading.local):
    """The compiler lock's nesting and timings in one thread."""

    def __init__(self):
        self.depth = 0  # nesting of the compiler lock
        self.start = 0.0  # when the outermost section under the lock began
        self.seconds = 0.0  # total time under the lock
        self.compiling = []  # [start, seconds of nested compilations] of each under way
        self.compiled = {}  # module -> seconds compiling its functions in this section


_books = _Books()


def seconds():
    """Total time (s) this thread spent compiling or loading compiled code with numba,
    since ``install``."""
    return _books.seconds


def report(compiled, where):
    """The lines saying what was compiled: ``compiled`` maps module names to seconds;
    generated modules of ``DESCRIPTIONS`` get a line each, the package's modules one
    together, other modules none."""
    lines = [f"{DESCRIPTIONS[m]} in {s:.1f} s" for m, s in compiled.items() if m in DESCRIPTIONS]
    package = {m.rsplit(".", 1)[-1]: s for m, s in compiled.items()
               if m.startswith("skfem_cable.")}
    if package:
        lines.append(f"kernels ({', '.join(sorted(package))}) in {sum(package.values()):.1f} s")
    return [f"skfem_cable: compiled {line}, once per machine (cached in {where})"
            for line in lines]


class _Lock(event.Listener):
    """Times the outermost sections under numba's compiler lock; reports at their end."""

    def on_start(self, ev):
        if _books.depth == 0:
            _books.start = time.perf_counter()
        _books.depth += 1

    def on_end(self, ev):
        if _books.depth == 0:  # installed while the lock was held
            return
        _books.depth -= 1
        if _books.depth == 0:
            _books.seconds += time.perf_counter() - _books.start
            compiled, _books.compiled = _books.compiled, {}
            for line in report(compiled, cache_dir("numba")) if compiled else ():
                print(line, file=sys.stderr, flush=True)


class _Compile(event.Listener):
    """Charges every compilation to the module of the compiled function."""

    def on_start(self, ev):
        _books.compiling.append([time.perf_counter(), 0.0])

    def on_end(self, ev):
        if not _books.compiling:  # installed during a compilation
            return
        start, nested = _books.compiling.pop()
        spent = time.perf_counter() - start
        if _books.compiling:
            _books.compiling[-1][1] += spent
        py_func = getattr(ev.data.get("dispatcher"), "py_func", None)
        module = getattr(py_func, "__module__", None) or "?"
        _books.compiled[module] = _books.compiled.get(module, 0.0) + spent - nested


_LISTENERS = {"numba:compiler_lock": _Lock(), "numba:compile": _Compile()}


def install():
    """Listen to numba's compiler events (called once: on importing the package)."""
    for kind, listener in _LISTENERS.items():
        event.register(kind, listener)


class Recorder(event.Listener):
    """Every compilation of a dispatcher with its CPU seconds, for profiling what is
    compiled (``tests/compile_recorder.py``, ``benchmarks/compile_cost.py``).

    ``compiles`` lists ``[function, seconds, llvm seconds]`` per compilation: the CPU
    seconds of the compiling thread less those of the compilations nested in it, and of
    those the seconds under numba's LLVM lock (optimisation and machine code); ``take``
    returns them and starts a new list.  ``install`` registers it (and its LLVM clock)."""

    def __init__(self):
        # of each compilation under way: [start, nested seconds, LLVM seconds at its
        # start, nested LLVM seconds]
        self.compiling = []
        self.llvm = 0.0  # seconds under the LLVM lock so far (_LlvmClock)
        self.compiles = []

    def install(self):
        """Listen to numba's compile and LLVM-lock events."""
        event.register("numba:compile", self)
        event.register("numba:llvm_lock", _LlvmClock(self))
        return self

    def take(self):
        """The compilations recorded since the last ``take``."""
        compiles, self.compiles = self.compiles, []
        return compiles

    def on_start(self, ev):
        self.compiling.append([time.thread_time(), 0.0, self.llvm, 0.0])

    def on_end(self, ev):
        if not self.compiling:  # installed during a compilation
            return
        start, nested, llvm_start, nested_llvm = self.compiling.pop()
        spent, llvm = time.thread_time() - start, self.llvm - llvm_start
        if self.compiling:
            self.compiling[-1][1] += spent
            self.compiling[-1][3] += llvm
        py = getattr(ev.data.get("dispatcher"), "py_func", None)
        name = f"{getattr(py, '__module__', '?')}.{getattr(py, '__qualname__', '?')}"
        self.compiles.append([name, spent - nested, llvm - nested_llvm])


class _LlvmClock(event.Listener):
    """The CPU seconds of the thread under numba's LLVM lock (outermost sections), added
    to its ``Recorder``'s ``llvm``."""

    def __init__(self, recorder):
        self.recorder, self.depth, self.start = recorder, 0, 0.0

    def on_start(self, ev):
        if self.depth == 0:
            self.start = time.thread_time()
        self.depth += 1

    def on_end(self, ev):
        self.depth -= 1
        if self.depth == 0:
            self.recorder.llvm += time.thread_time() - self.start
