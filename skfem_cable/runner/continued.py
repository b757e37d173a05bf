"""A continued run (``--resume``) is the run it continues: the same scene parameters,
system, output frame, samples per element of its series and solver settings
(``resume_checked``), else ``StoreMismatch`` naming what differs."""

import json

from ..io import StoreMismatch
from ..io import resume as resume_run
from ..io.manifest import read_manifest
from ..io.matching import check_fingerprint, stored_version
from ..model.fingerprint import system_fingerprint
from ..util.jsonable import jsonable

#: Scene parameters a continued run may change: where the scene file is.
MOVABLE = ("file",)


def resume_checked(out, system, parameters, frame, solver, points_per_element=8):
    """The ``io.resume`` of the run in ``out``, once it is known to be the run of
    ``system`` with the scene ``parameters`` (``_check_scene``), in the output ``frame``
    (``_check_frame``), with ``points_per_element`` samples per element in its series
    (``_check_samples``) and with the ``simulate`` keywords ``solver``
    (``_check_settings``)."""
    manifest = read_manifest(out)
    _check_scene(out, manifest, system, parameters)
    _check_frame(out, manifest, frame)
    _check_samples(out, manifest, points_per_element)
    resume = resume_run(out)
    _check_settings(out, resume.manifest, solver)
    return resume


def _check_settings(out, manifest, solver):
    """Before a continued run: the solver settings given must be those stored (all but
    ``t_end``), else ``StoreMismatch`` naming them."""
    stored = manifest.get("settings") or {}
    differ = [k for k, v in solver.items()
              if k != "t_end" and k in stored and stored[k] != jsonable(v)]
    if differ:
        raise StoreMismatch(f"{out} was run with other settings ("
                            + ", ".join(f"{k}: stored {stored[k]!r}, given {solver[k]!r}"
                                        for k in differ)
                            + "): continue it with the settings it was started with")


def _check_frame(out, manifest, frame):
    """Before a continued run: its series must go on in the frame it was written in
    (``attrs.frame`` of the manifest, ``"inertial"`` when absent), else
    ``StoreMismatch`` naming both."""
    stored = (manifest.get("attrs") or {}).get("frame", "inertial")
    if stored != frame:
        raise StoreMismatch(f"{out} was written in the frame {stored!r}, not {frame!r}: "
                            f"continue it with --frame {stored}")


def _check_samples(out, manifest, points_per_element):
    """Before a continued run: its series must go on with the samples per element it was
    written with (``attrs.points_per_element`` of the manifest; a store of an earlier
    version records none and is not checked), else ``StoreMismatch`` naming both."""
    stored = (manifest.get("attrs") or {}).get("points_per_element")
    if stored is not None and stored != points_per_element:
        raise StoreMismatch(f"{out} was written with points_per_element = {stored} (the "
                            f"cable samples per element of its series), not "
                            f"{points_per_element}: continue it with points_per_element = "
                            f"{stored} in the [output] table of its scene file")


def _check_scene(out, manifest, system, parameters):
    """Before a continued run: the scene must be the stored one, its parameters (those
    the manifest records, but ``MOVABLE``; a store of an earlier version may record
    fewer) and its system (``check_fingerprint``); else ``StoreMismatch`` naming what
    differs."""
    stored = (manifest.get("attrs") or {}).get("parameters") or {}
    given = json.loads(json.dumps(jsonable(parameters or {})))
    differ = [k for k in sorted(stored) if k not in MOVABLE and stored[k] != given.get(k)]
    if not differ:
        check_fingerprint(out, manifest, system)
        return
    listed = "; ".join(f"{k}: stored {stored[k]!r}, given {given.get(k)!r}" for k in differ)
    same = (manifest.get("fingerprint") or {}).get("system") \
        == system_fingerprint(system, stored_version(manifest))
    raise StoreMismatch(f"{out} was " + ("run with other scene parameters" if same else
                                         "written by another system: its parameters differ")
                        + f" ({listed}): continue it with the scene and options it was "
                        "started with")
