"""Scenes described in TOML files: bodies, sections, constraints, loads, initial motion and
solver settings (the schema is documented in ``docs/scene_files.md``), or a rod-chain
tether (a ``[rod_chain]`` table; ``docs/rodchain.md``).

Every value is checked; an error names the file, the key (e.g. ``cables[1].elements``) and
the offending value; an unknown key is named with the closest known one and the keys
allowed in its table (never with its value, which may be a whole table)::

    >>> loads_text('[solver]\\nt_end = -1', "demo.toml")      # doctest: +SKIP
    SceneFileError: demo.toml: solver.t_end must be a number > 0, got -1

The pieces, one job each: ``schema`` (``Table`` and the value checks), ``bodies``
(sections, cables, rigid bodies, point references), ``constraints``, ``loads`` (and point
masses), ``deploy`` (cables leaving a reel), ``environment`` (the epoch and the
environment's models), ``solver`` (solver, initial motion, output),
``system_scene`` (a ``System``
scene in schema order) and ``chain_scene`` (a rod-chain scene).  A new key goes into the
reader of its table; a new constraint type or array of load tables is one entry of
``constraints.CONSTRAINTS`` or ``loads.LOADS``.
"""

import sys
from pathlib import Path

from . import chain_scene, system_scene
from .chain_scene import ChainSceneSpec
from .schema import (
    SceneFileError,
    Table,
    boolean,
    choice,
    count,
    integer,
    interval,
    matrix3,
    non_negative,
    number,
    positive,
    text,
    vector3,
)
from .system_scene import SceneSpec

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["ChainSceneSpec", "SceneFileError", "SceneSpec", "Table", "boolean", "choice",
           "count", "integer", "interval", "load", "loads_text", "matrix3", "non_negative",
           "number", "positive", "run", "text", "vector3"]


def loads_text(content, source="<string>", elements=None, epoch=None):
    """Read a scene from TOML text; ``elements`` overrides every cable's element count (the
    number of rods of a rod chain), ``epoch`` (text, ISO 8601) the ``[environment]``'s
    epoch.  Returns a ``SceneSpec``, or a ``ChainSceneSpec`` for a file with a
    ``[rod_chain]`` table; raises ``SceneFileError``."""
    try:
        data = tomllib.loads(content)
    except tomllib.TOMLDecodeError as err:
        raise SceneFileError(f"{source}: not valid TOML: {err}") from None
    except RecursionError:
        raise SceneFileError(f"{source}: not a scene file: its arrays or tables are nested "
                             "deeper than the TOML reader goes (a scene nests a few "
                             "levels)") from None
    root = Table(data, "", source)
    if "rod_chain" not in data:
        return system_scene.build(root, elements, epoch)
    if epoch is not None:
        raise SceneFileError(f"{source}: a rod-chain scene is never in orbit: --epoch has "
                             "no meaning for it")
    return chain_scene.build(root, elements)


def load(path, elements=None, epoch=None):
    """Read the scene file ``path`` (see ``loads_text``)."""
    path = Path(path)
    if not path.is_file():
        raise SceneFileError(f"{path}: no such scene file")
    data = path.read_bytes()
    try:
        content = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SceneFileError(f"{path}: not a UTF-8 text file (byte {data[err.start]:#04x} "
                             f"at offset {err.start}): a TOML scene file is UTF-8 text; "
                             "convert it (e.g. iconv -f latin1 -t utf-8)") from None
    return loads_text(content, str(path), elements, epoch)


def run(path, options):
    """Run a scene file into the run directory ``options.out``; returns the summary."""
    options.reject(Path(path).name, "formulation")
    spec = load(path, options.elements, options.epoch)
    kind = chain_scene if isinstance(spec, ChainSceneSpec) else system_scene
    return kind.run(path, spec, options)
