"""The memory guard of cable sizes: a cable, a scene or a system that cannot be built and
simulated in this machine's memory is refused before any work, with the largest size that
fits."""

import os

#: Memory (bytes) per element to build a cable, its system layout and a time
#: integration (measured: 4.7 kB, 12 kB and 8 kB at 1e5 elements).
MEMORY_PER_ELEMENT = 25e3


def check_memory(n_elements, what=None):
    """Refuse ``n_elements`` cable elements that cannot be built and simulated in this
    machine's memory: one cable's, or all the cables of a scene or system (``what`` says
    which, default ``"n_elements = N: a cable of that size"``)."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):  # not a POSIX system: no estimate
        return
    need = MEMORY_PER_ELEMENT * n_elements
    if need > total:
        what = what or f"n_elements = {n_elements}: a cable of that size"
        raise ValueError(f"{what} needs about {need / 1e9:.3g} GB to build and simulate, "
                         f"and this machine has {total / 1e9:.3g} GB; at most about "
                         f"{int(total / MEMORY_PER_ELEMENT)} elements fit")


def check_total_memory(counts):
    """``check_memory`` of the cables with the element ``counts`` together (a system's
    or a scene's; the guard of each cable alone lets 30 cables of 900,000 elements
    through on 24 GB)."""
    total = int(sum(counts))
    check_memory(total, f"a system of {len(counts)} cables with {total} elements in all")
