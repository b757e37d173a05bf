"""The thread count of the bordered LU's blocks set for a block of a benchmark."""

import os
from contextlib import contextmanager

from skfem_cable.core.linalg import THREADS


@contextmanager
def thread_count(count):
    """``SKFEM_CABLE_THREADS`` set to ``count`` inside the block, as it was after it."""
    previous = os.environ.get(THREADS)
    os.environ[THREADS] = str(count)
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop(THREADS)
        else:
            os.environ[THREADS] = previous
