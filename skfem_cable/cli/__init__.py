"""The ``skfem-cable`` command: ``run`` a scene, ``sweep`` it over parameters (on Dask),
``validate`` against references, ``bench``.

Run ``skfem-cable --help`` or ``skfem-cable COMMAND --help``.
"""

from .command import main

__all__ = [
    "main",
]
