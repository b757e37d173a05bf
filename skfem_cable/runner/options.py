"""The options of a run, each declared once: its field of ``RunOptions`` carries its flag
(``Flag``: the ``skfem-cable run`` spelling, value type, help), from which the command
line is built (``add_flags``) and read back (``RunOptions.from_args``); a flag that only
some scenes accept is ``opt_in`` and the scene catalog refuses it for the others
(``opt_in``, ``scenes.catalog.register(..., takes=...)``)."""

from dataclasses import dataclass, field, fields
from pathlib import Path

from . import values


@dataclass(frozen=True)
class Flag:
    """How an option is given on the command line.

    Attributes
    ----------
    help : str or callable
        The help text, or a function returning it (called when the help is shown).
    type : callable, optional
        Converts and checks the text (``values``); None for a switch.
    metavar : str, optional
    choices : callable, optional
        Returns the accepted values (called when a value is checked or listed).
    negated : bool
        A switch ``--no-NAME`` that sets the option to False (given) or leaves its default
        (the parsed value is then None).
    opt_in : bool
        Only the scenes that name the option in their ``takes`` accept it.
    """

    help: str
    type: object = None
    metavar: str | None = None
    choices: object = None
    negated: bool = False
    opt_in: bool = False


def _option(default, *args, **kwargs):
    return field(default=default, metadata={"flag": Flag(*args, **kwargs)})


def _formulations():
    from ..bodies.formulation import FORMULATIONS

    return tuple(FORMULATIONS)


def _elements():
    from ..elements import ELEMENTS

    return tuple(ELEMENTS)


def _frames():
    from ..io.export import FRAMES

    return tuple(FRAMES)


def _formulation_help():
    from ..bodies.formulation import DEFAULT, FORMULATIONS

    return (f"formulation of the cables of a built-in scene: {', '.join(FORMULATIONS)} "
            f"(default {DEFAULT}: locking-free with the paper's accuracy on taut cables; "
            "paper: the paper's own, whose tension locks in bending; docs/locking.md)")


def _element_help():
    from ..elements import DEFAULT_ELEMENT, ELEMENTS

    return (f"element type of the cables of the cantilever, pendulum and spinning-tether "
            f"scenes: {', '.join(ELEMENTS)} (default {DEFAULT_ELEMENT}; docs/elements.md)")


@dataclass
class RunOptions:
    """Options of a run (the ``skfem-cable run`` flags); ``None`` means the scene's
    default."""

    t_end: float | None = _option(
        None, "end time: seconds, or with a suffix s, min, h, d (30d) (default: the "
        "scene's)", values.duration, "T")
    dt: float | None = _option(
        None, "time step in s (hanging-chain: output spacing; default: the scene's)",
        values.duration, "DT")
    elements: int | None = _option(
        None, "elements per cable (hanging-chain: number of rods)", values.positive_int,
        "N")
    formulation: str | None = _option(None, _formulation_help, metavar="NAME",
                                      choices=_formulations)
    element: str | None = _option(None, _element_help, metavar="NAME", choices=_elements,
                                  opt_in=True)
    model: str | None = _option(
        None, "model of a scene that has several (tss: ancf, the default, or rodchain)",
        metavar="NAME", opt_in=True)
    alpha: float | None = _option(
        None, "sailing angle in degrees (the E-sail scenes)", values.finite_float, "DEG",
        opt_in=True)
    out: Path | None = _option(None, "run directory to write", values.directory, "DIR")
    every: int | None = _option(None, "save every K-th step (default: the scene's)",
                                values.positive_int, "K")
    progress: bool | None = _option(
        None, "no progress bar (default: shown when stderr is a terminal)", negated=True)
    plots: bool = _option(True, "write no figures or snapshot into the run directory",
                          negated=True)
    animate: bool = _option(False, "also render animation.gif of the run (needs OpenGL)")
    epoch: str | None = _option(
        None, "UTC instant of the run's t = 0, ISO 8601 (2026-01-01 or "
        "2026-01-01T12:00:00): a system in orbit at that epoch, the environment models "
        "(IGRF, MSIS, IRI) at it; overrides a scene file's [environment] epoch "
        "(docs/environment.md)", values.epoch, "UTC", opt_in=True)
    frame: str | None = _option(
        None, "frame of the ParaView series and the renders: inertial (default) or lvlh, "
        "the orbiting frame of a system in orbit (x radial, y along-track, z orbit "
        "normal; velocities relative to it)", metavar="FRAME", choices=_frames)
    overwrite: bool = _option(
        False, "replace the run already in --out DIR (removes only the files skfem-cable "
        "wrote)")
    resume: bool = _option(
        False, "continue the interrupted (or finished) run in --out DIR, with the same "
        "scene and options (--t-end may grow)")

    @classmethod
    def from_args(cls, args):
        """The options of parsed arguments ``args`` (``add_flags``)."""
        given = {}
        for f in fields(cls):
            value = getattr(args, f.name, None)
            given[f.name] = f.default if value is None else value
        return cls(**given)

    def reject(self, scene, *names):
        """Raise ``ValueError`` if one of the options ``names`` was given: it has no
        meaning for ``scene``."""
        given = [n for n in names if getattr(self, n) != DEFAULTS[n]]
        if given:
            raise ValueError(f"scene {scene!r} does not take {', '.join(map(flag, given))}")

    def value(self, name, default):
        """The option ``name``, or ``default`` when it was not given."""
        value = getattr(self, name)
        return default if value is None else value


#: The flag of every option, by field name.
FLAGS = {f.name: f.metadata["flag"] for f in fields(RunOptions)}

#: The default of every option, by field name.
DEFAULTS = {f.name: f.default for f in fields(RunOptions)}

#: The options only the scenes naming them accept (``scenes.catalog.register``).
OPT_IN = tuple(name for name, f in FLAGS.items() if f.opt_in)


def flag(name):
    """The command-line spelling of the option ``name``: ``--t-end``, ``--no-progress``."""
    return ("--no-" if FLAGS[name].negated else "--") + name.replace("_", "-")


class Choices:
    """The accepted values of a flag, asked of ``names()`` only when a value is checked
    or listed: building the parser (``skfem-cable --help``) imports none of the
    registries that name them (the formulations, the element types: scikit-fem; the
    output frames: the run store)."""

    def __init__(self, names):
        self.names = names

    def __contains__(self, value):
        return value in self.names()

    def __iter__(self):
        return iter(self.names())


def add_flags(parser, names=None, **overrides):
    """Add the flags of the options ``names`` (default: all) to the ``argparse`` parser
    or group ``parser``; ``overrides``: keywords of ``add_argument`` for all of them (a
    command that gives an option another meaning, e.g. ``help``, ``required``).  A help
    given as a function stays one: the parser calls it when it shows the help
    (``cli.command``)."""
    for name in names or FLAGS:
        spec = FLAGS[name]
        kwargs = {"help": spec.help, "dest": name}
        if spec.negated:
            kwargs.update(action="store_const", const=False, default=None)
        elif spec.type is None and spec.choices is None and spec.metavar is None:
            kwargs["action"] = "store_true"
        else:
            kwargs.update(type=spec.type, metavar=spec.metavar)
            if spec.choices is not None:
                kwargs["choices"] = Choices(spec.choices)
        parser.add_argument(flag(name), **{**kwargs, **overrides})
