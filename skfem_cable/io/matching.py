"""Whether a run store was written by a system (and with settings): its manifest's
fingerprints against the system's, ``StoreMismatch`` naming what differs."""

from ..core.protocols import SystemView
from ..model.fingerprint import (
    changed_parts,
    describe_system,
    part_digests,
    settings_fingerprint,
    system_fingerprint,
)
from ..util.jsonable import jsonable
from .manifest import StoreMismatch


def stored_version(manifest):
    """The version of the fingerprints of a store's ``manifest`` (1: recorded none)."""
    return (manifest.get("fingerprint") or {}).get("version", 1)


def outline(system: SystemView):
    """A short readable description of ``system`` for error messages: bodies with their
    sizes, constraint equations, loads."""
    bodies = ", ".join(f"{getattr(b, 'name', '?')} ({type(b).__name__}, {b.n_dofs} dofs)"
                       for b in system.bodies[:4])
    if len(system.bodies) > 4:
        bodies += f", ... ({len(system.bodies)} bodies)"
    loads = ", ".join(sorted({type(x).__name__ for x in system.loads})) or "none"
    return (f"{system.n_dofs} dofs: {bodies}; {system.n_constraints} constraint equations; "
            f"loads: {loads}; {len(system.point_masses)} point masses")


def parts(system: SystemView):
    """What a store's manifest keeps of the parts of ``system`` to name what changed
    (``model.fingerprint.part_digests``)."""
    return part_digests(describe_system(system))


def _changed(manifest, system):
    """The parts of ``system`` whose parameters differ from the store's (a store that
    recorded them, of the current fingerprint version), as a clause of a message."""
    if "parts" not in manifest or stored_version(manifest) != 2:
        return ""
    changed = changed_parts(manifest["parts"], describe_system(system))
    return f"; what differs: {'; '.join(changed)}" if changed else ""


def check_fingerprint(path, manifest, system: SystemView, settings=None):
    """Raise ``StoreMismatch`` unless the store of ``path`` (its ``manifest``) was written
    by ``system`` (and with ``settings``, when given), naming the parts and parameters
    that differ when the store recorded them (``parts``)."""
    fp = manifest.get("fingerprint") or {}
    if fp.get("system") != system_fingerprint(system, stored_version(manifest)):
        raise StoreMismatch(
            f"{path} was written by another system: stored {manifest.get('system')}; "
            f"given {outline(system)}"
            + ("" if manifest.get("system") != outline(system) else
               " (same bodies and sizes: sections, masses, constraints or loads differ)")
            + _changed(manifest, system)
            + ": load or continue it with the system that wrote it (or write a new run)")
    if settings is not None and fp.get("settings") != settings_fingerprint(settings):
        stored = manifest.get("settings") or {}
        given = jsonable(settings)
        differ = [k for k in sorted(set(stored) | set(given))
                  if k not in ("t_end", "n_steps") and stored.get(k) != given.get(k)]
        details = ", ".join(f"{k}: stored {stored.get(k)!r}, given {given.get(k)!r}"
                            for k in differ) or "they differ"
        raise StoreMismatch(f"{path} was run with other solver settings ({details}): "
                            "continue it with the settings it was started with")
