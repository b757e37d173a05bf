"""The options of a run: the ``skfem-cable run`` flags (``RunOptions``)."""

from dataclasses import dataclass
from pathlib import Path


@dataclass
class RunOptions:
    """Options of a run (the ``skfem-cable run`` flags); ``None`` means the scene's
    default."""

    out: Path | None = None
    t_end: float | None = None
    dt: float | None = None
    elements: int | None = None
    formulation: str | None = None
    alpha: float | None = None
    every: int | None = None
    progress: bool | None = None
    plots: bool = True
    animate: bool = False
    overwrite: bool = False
    resume: bool = False
    frame: str | None = None
    model: str | None = None
    element: str | None = None

    def reject(self, scene, *names):
        """Raise ``ValueError`` if one of the options ``names`` was given: it has no
        meaning for ``scene``."""
        given = [n for n in names if getattr(self, n) is not None]
        if given:
            flags = ", ".join("--" + n.replace("_", "-") for n in given)
            raise ValueError(f"scene {scene!r} does not take {flags}")

    def value(self, name, default):
        """The option ``name``, or ``default`` when it was not given."""
        value = getattr(self, name)
        return default if value is None else value
