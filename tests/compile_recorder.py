"""What numba compiles during the test suite, test by test (a pytest plugin of
``conftest.py``, on only with ``SKFEM_CABLE_COMPILE_LOG=DIR``).

Every compilation of a dispatcher is charged to the test running it
(``kernels.compile_log.Recorder``: CPU seconds of the compiling thread, less nested
compilations, and of those the seconds under numba's LLVM lock).  Each worker appends one
JSON line per test to ``DIR/compile-<worker>.jsonl``: ``{"test", "cpu", "children",
"wall", "compiles": [[function, seconds, llvm seconds], ...]}`` (at the test's end:
``cpu``, the worker's process CPU seconds; ``children``, those of the child processes it
waited for, the CLI and dask runs the workers' count misses; ``wall``, the clock's
seconds since the epoch, of which the workers' last records tell whether they ended
together).  ``python benchmarks/compile_cost.py --suite DIR`` sums them up.
"""

import json
import os
import time
from pathlib import Path

#: The environment variable naming the folder of the records.
LOG = "SKFEM_CABLE_COMPILE_LOG"

#: The recorder of this process, once listening (``pytest_configure``).
_listening = {}


def pytest_configure(config):
    """Listen to numba's compilations (only with ``SKFEM_CABLE_COMPILE_LOG``: otherwise
    the package is not imported here, where xdist's controller, which runs no test, would
    import it for nothing: 1.5-1.9 CPU s)."""
    if os.environ.get(LOG):
        from skfem_cable.kernels.compile_log import Recorder

        _listening["recorder"] = Recorder()
        _listening["recorder"].install()


def pytest_runtest_teardown(item, nextitem):
    """Append the test's compilations to this worker's records (in the process that ran
    it: xdist's controller does not run this hook)."""
    folder = os.environ.get(LOG)
    if not folder:
        return
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    times = os.times()
    line = {"test": item.nodeid, "cpu": time.process_time(),
            "children": times.children_user + times.children_system, "wall": time.time(),
            "compiles": _listening["recorder"].take()}
    Path(folder).mkdir(parents=True, exist_ok=True)
    with open(Path(folder) / f"compile-{worker}.jsonl", "a") as out:
        out.write(json.dumps(line) + "\n")
