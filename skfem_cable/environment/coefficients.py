"""The coefficient files of the field's libraries read once per process.

ppigrf (``read_shc``) and PyIRI (``read_ccir_ursi_coeff``) parse their coefficient files
at every model call, and a load calls a model once per step (or block of knots).
``read_once`` puts a memo of such a reader in its module's place, which the library looks
up at each call: ``environment.igrf.ppigrf`` and ``environment.iri.pyiri`` install theirs.
"""

import functools


def read_once(module, name, maxsize, kept=None, handed=None):
    """Replace ``module.<name>``, a reader of coefficient files, by its memo per arguments
    (once in a process: a memo in place is kept), and return it.

    Parameters
    ----------
    module : module
        The library's module that holds the reader and looks it up at each call.
    name : str
        The reader's name in ``module``.
    maxsize : int
        The files (arguments) remembered.
    kept, handed : callable, optional
        ``kept(result)`` is what the memo stores of a read (e.g. its arrays made
        read-only, so that a write raises instead of changing later calls);
        ``handed(stored)`` what each call receives (e.g. copies of frames that cannot be
        made read-only).  Default: the result itself.

    The memo is the reader's attribute ``memoized`` (an ``functools.lru_cache``, for its
    ``cache_info``); ``__wrapped__`` is the library's own reader.
    """
    read = getattr(module, name)
    if hasattr(read, "memoized"):
        return read

    @functools.lru_cache(maxsize=maxsize)
    def memoized(*args, **named):
        result = read(*args, **named)
        return result if kept is None else kept(result)

    @functools.wraps(read)
    def coefficients(*args, **named):
        stored = memoized(*args, **named)
        return stored if handed is None else handed(stored)

    coefficients.memoized = memoized
    setattr(module, name, coefficients)
    return coefficients
