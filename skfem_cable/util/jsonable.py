"""Python values for JSON files (summaries, manifests, store attributes)."""

from pathlib import Path

import numpy as np


def jsonable(obj):
    """``obj`` with numpy scalars and arrays turned into Python numbers and lists, paths
    into strings, non-finite floats into ``None`` and anything else unknown into its
    ``repr``."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    if isinstance(obj, (float, np.floating)):
        return float(obj) if np.isfinite(obj) else None
    if obj is None or isinstance(obj, (str, int, bool)):
        return obj
    return repr(obj)
