"""The ``[environment]`` table of a scene file: the epoch of the run's ``t = 0`` and the
models of the near-Earth environment (``environment``): the geomagnetic field
(``field``), the neutral atmosphere (``atmosphere``) and the ionosphere (``plasma``).

The models are made without an epoch: they take the system's, ``System.add_orbit(orbit,
epoch=...)`` (``environment.bound_model``), which is the table's ``epoch`` or the run's
``--epoch`` (it overrides the file's).  The table needs an ``[orbit]``.  Loads that take
a density model read ``atmosphere`` when they give no ``density`` of their own
(``[[loads.atmospheric_drag]]``, ``[[loads.free_molecular]]``)."""

from dataclasses import dataclass

from ..environment.epoch import as_epoch
from ..environment.iri import IRI
from ..environment.msis import MSIS
from ..environment.plasma import UniformPlasma
from ..loads.electrodynamic import MagneticDipole
from .schema import choice, interval, positive, text

#: The field models: ``field = "igrf"`` or ``"dipole"`` (``sc.MagneticDipole()``).
FIELDS = ("igrf", "dipole")


@dataclass
class EnvironmentSpec:
    """What ``[environment]`` says: the epoch (an ``Epoch``, or None) and the models
    (None where not given)."""

    epoch: object = None
    field: object = None
    atmosphere: object = None
    plasma: object = None


def epoch_value(v):
    """An ``Epoch`` of a TOML date-time or an ISO 8601 string."""
    try:
        return as_epoch(v)
    except ValueError:
        raise ValueError("must be a TOML date-time or an ISO 8601 string "
                         "(2026-01-01T00:00:00Z, UTC)") from None


def read_field(t):
    """``field``: ``"igrf"`` (``environment.IGRF``) or ``"dipole"``; None if absent."""
    from ..environment.igrf import IGRF

    name = t.get("field", choice(*FIELDS), None)
    return None if name is None else IGRF() if name == "igrf" else MagneticDipole()


def read_atmosphere(t):
    """``atmosphere = { model = "msis", f107, f107a, ap }`` (sfu, sfu, Ap index)."""
    if not t.has("atmosphere"):
        return None
    a = t.inline("atmosphere")
    a.get("model", choice("msis"))
    out = MSIS(f107=a.get("f107", interval(0.0, 500.0)),
               f107a=a.get("f107a", interval(0.0, 500.0)), ap=a.get("ap", interval(0.0, 400.0)))
    a.finish()
    return out


def read_plasma(t):
    """``plasma = { model = "iri", f107, temperature }`` or ``{ model = "uniform",
    density, temperature }`` (m^-3, K)."""
    if not t.has("plasma"):
        return None
    p = t.inline("plasma")
    model = p.get("model", choice("iri", "uniform"))
    temperature = p.get("temperature", positive, 1500.0)
    if model == "iri":
        out = IRI(f107=p.get("f107", interval(0.0, 500.0)), temperature=temperature)
    else:
        out = UniformPlasma(p.get("density", positive), temperature=temperature)
    p.finish()
    return out


def read_environment(t, epoch=None):
    """The ``[environment]`` table (empty: no environment); ``epoch`` (the run's
    ``--epoch``, text) overrides its ``epoch``.  Returns an ``EnvironmentSpec``."""
    out = EnvironmentSpec(t.get("epoch", epoch_value, None), read_field(t),
                          read_atmosphere(t), read_plasma(t))
    t.finish()
    if epoch is not None:
        out.epoch = epoch_value(text(epoch))
    if out.epoch is None and (out.atmosphere or out.plasma or out.field) is not None:
        t.missing("epoch", "is required by the models (an ISO 8601 date-time such as "
                  "2026-01-01T00:00:00), or give --epoch")
    return out


def check_orbit(root, environment):
    """An epoch (of ``[environment]`` or ``--epoch``) needs an ``[orbit]``: fail naming
    the table otherwise."""
    if environment.epoch is not None and "orbit" not in root.data:
        root.fail("environment", "(or --epoch) needs an [orbit]: the epoch is the t = 0 of "
                  "a system in orbit")
