"""The figures of a run in its run directory: the standard ones of a dynamic run
(``run_figures``: energies, cable histories, root-tension spectra, the rendered final
state, the animation on request), a rendered snapshot (``snapshot``) and the list of a
run's figures for its summary (``plot_files``).  The files it writes are described in
``directory.DESCRIPTIONS``."""

from pathlib import Path

import numpy as np

from .. import plot
from ..io import export
from ..util.atomic import is_temporary
from .summary import warn


def snapshot(out, system, state, name="final.png", title=None, frame="inertial"):
    """Render ``state`` (in the output ``frame``, ``export.FRAMES``) into
    ``out/plots/name`` when off-screen rendering works; returns the path, or None (with a
    warning on stderr) when it does not."""
    ok, reason = plot.rendering_available()
    if not ok:
        warn(f"skipping the 3-D snapshot: {reason}")
        return None
    path = Path(out) / "plots" / name
    path.parent.mkdir(parents=True, exist_ok=True)
    plot.render(system, state, path, title=title, frame=frame)
    return path


def framed_title(title, frame):
    """``title`` with the line that names the output ``frame`` (``export.FRAMES``; none
    for the inertial one), or None when both are empty."""
    return "\n".join(filter(None, [title, export.FRAMES[frame].label])) or None


def run_figures(out, result, animate=False, title=None, frame="inertial"):
    """The standard figures of a dynamic run in ``out/plots`` (energies, cable histories,
    root-tension spectra, the inputs' histories when the system has any, final snapshot)
    and ``out/animation.gif`` if ``animate``; the snapshot and the animation show
    ``title`` (a scene file's) above the time and are drawn in the output ``frame``
    (``export.FRAMES``; ``"lvlh"`` says so on them).
    Returns the paths written."""
    plots = Path(out) / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    paths = [plots / "energies.png", plots / "cables.png"]
    plot.energies(result, paths[0])
    plot.cable_histories(result, paths[1])
    if len(result) >= 16 and result.system.cables():
        signals = {c.name: result.tension(c, 0.0) for c in result.system.cables()}
        paths.append(plots / "tension_psd.png")
        plot.psd(result.t, signals, paths[-1], title="root tension", units="N")
    if result.inputs:
        paths.append(plots / "inputs.png")
        plot.histories(result.t, {name: _components(name, values)
                                  for name, values in result.inputs.items()},
                       paths[-1], title="inputs (held from each saved step to the next)",
                       drawstyle="steps-post")
    title = framed_title(title, frame)
    final = snapshot(out, result.system, result.state(len(result) - 1),
                     title="\n".join(filter(None, [title, f"t = {result.t[-1]:.4g} s"])),
                     frame=frame)
    if final is not None:
        paths.append(final)
        if animate:
            paths.append(Path(out) / "animation.gif")
            plot.animate(result, paths[-1], title=title, frame=frame)
    elif animate:
        warn("skipping the animation (no off-screen rendering)")
    return paths


def _components(name, values):
    """The curves of an input's history ``values`` (nt, ...): itself for a number, one
    per component (``name[k]``) for a vector."""
    values = np.asarray(values)
    if values.ndim == 1:
        return values
    flat = values.reshape(len(values), -1)
    return {f"{name}[{k}]": flat[:, k] for k in range(flat.shape[1])}


def plot_files(out, written=()):
    """Paths (relative to the run directory ``out``, as text) of the run's figures: the
    paths ``written`` in their order, then every other file of ``out/plots`` (a scene's
    own figures, written by its ``outputs``), temporary files left out."""
    out = Path(out)
    folder = out / "plots"
    present = sorted(p for p in folder.iterdir() if p.is_file() and not is_temporary(p)
                     and not p.name.endswith(".tmp")) if folder.is_dir() else []
    return list(dict.fromkeys(p.relative_to(out).as_posix() for p in [*written, *present]))
