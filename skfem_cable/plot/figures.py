"""Figures of runs (matplotlib, no display needed): time histories (``histories``,
``cable_histories``), power spectral densities (``psd``, from ``spectra.spectrum``), the
energy books (``energies``) and speed-against-error tables of benchmarks (``speed_error``).
A long time history is drawn from the points its pixels show (``thinned``).

matplotlib is imported on first use, not with the module.
"""

from itertools import cycle
from pathlib import Path

import numpy as np

from ..analysis.spectra import spectrum, welch_note
from .cameras import spin_axis


def _figure(n_panels, width=7.0, height_per_panel=2.2):
    from matplotlib.figure import Figure  # imported on first use: a second off every import

    fig = Figure(figsize=(width, max(2.5, height_per_panel * n_panels)), layout="constrained")
    axes = fig.subplots(n_panels, 1, sharex=True, squeeze=False)[:, 0]
    return fig, axes


def _finish(fig, path):
    if path is not None:
        fig.savefig(Path(path), dpi=120)
    return fig


#: Columns of ``thinned``: more than a figure's pixels across (840 at 7 in and 120 dpi).
COLUMNS = 2000


def thinned(t, y, columns=COLUMNS):
    """The points of the time history ``(t, y)`` that a drawing ``columns`` pixels wide
    shows: in each of ``columns`` equal spans of ``t``, its first, last, lowest and highest
    point, in order (each column's vertical extent and its joins to the next are drawn as
    from every point; a figure of a noisy 470,000-step history takes 0.6 s, not 5.6).  A
    history of at most ``4 * columns`` points, not of numbers, with a value that is not
    finite, or whose times do not grow, is returned as it is."""
    t, y = np.asarray(t), np.asarray(y)
    if (len(t) <= 4 * columns or not all(np.issubdtype(a.dtype, np.number) for a in (t, y))
            or not (np.isfinite(t).all() and np.isfinite(y).all())
            or not t[-1] > t[0] or np.any(np.diff(t) < 0)):
        return t, y
    column = np.minimum(((t - t[0]) * (columns / (t[-1] - t[0]))).astype(np.intp),
                        columns - 1)
    first = np.flatnonzero(np.diff(column, prepend=-1))
    count = np.diff(first, append=len(t))
    keep = [first, first + count - 1]
    for extreme in (np.minimum, np.maximum):
        at = np.flatnonzero(y == np.repeat(extreme.reduceat(y, first), count))
        keep.append(at[np.diff(column[at], prepend=-1) > 0])  # the first in its column
    keep = np.unique(np.concatenate(keep))
    return t[keep], y[keep]


#: Most curves of a panel told apart by the default colour cycle and named in a legend;
#: more are coloured from ``CURVE_CMAP`` and named on a colour bar (``curve_colours``).
MAX_LEGEND = 10

#: Colour map of panels with more than ``MAX_LEGEND`` curves (one hue per curve, in order).
CURVE_CMAP = "turbo"


def curve_colours(n):
    """Colours of ``n`` curves of a panel: the default cycle up to ``MAX_LEGEND`` curves,
    else ``n`` samples of ``CURVE_CMAP`` (its darkest ends left out), all distinct."""
    if n <= MAX_LEGEND:
        return [f"C{i}" for i in range(n)]
    from matplotlib import colormaps

    return [tuple(c) for c in colormaps[CURVE_CMAP](np.linspace(0.08, 0.92, n))]


def _curve_key(axes, labels, colours, **legend):
    """Name the curves ``labels`` drawn in ``colours`` on the panels ``axes``: a legend
    on the first panel (keywords ``legend``) up to ``MAX_LEGEND`` curves, else one colour
    bar beside all the panels with a tick per curve, the first at the top."""
    if len(labels) <= MAX_LEGEND:
        axes[0].legend(fontsize="small", **legend)
        return
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import BoundaryNorm, ListedColormap

    n = len(labels)
    mappable = ScalarMappable(BoundaryNorm(np.arange(n + 1) - 0.5, n), ListedColormap(colours))
    bar = axes[0].figure.colorbar(mappable, ax=list(axes), ticks=np.arange(n), pad=0.01,
                                  aspect=12 * len(axes), fraction=0.04)
    bar.ax.set_yticklabels(labels, fontsize="x-small")
    bar.ax.invert_yaxis()
    for ax in axes:  # other named lines (frequency marks) keep a legend
        others = [line for line in ax.get_lines()
                  if line.get_label() not in labels and not line.get_label().startswith("_")]
        if others:
            ax.legend(handles=others, fontsize="small", **legend)


def _plain_numbers(ax):
    """Tick labels of ``ax``'s linear y axis as plain numbers (no ``1e-5 + 1.0008``)."""
    if ax.get_yscale() == "linear":
        ax.ticklabel_format(axis="y", useOffset=False)


def histories(t, panels, path=None, title=None, xlabel="t [s]", drawstyle="default"):
    """Time histories, one panel per entry (as the E-sail paper's figures of coning and
    lagging angles, hub rates, thrust and reactions), with plain tick labels (no offset).

    Parameters
    ----------
    t : ndarray (nt,)
    panels : dict
        ``{panel label: {curve label: ndarray (nt,)}}``, or ``{panel label: ndarray}`` for
        a single curve; the panel label is the y-axis label.  Named curves get a legend,
        or beyond ``MAX_LEGEND`` distinct colours named on a colour bar (``_curve_key``).
    path : path, optional
        Save the figure there (``.png``, ``.pdf``, ``.svg``).
    title : str, optional
    drawstyle : str
        Matplotlib's ``drawstyle`` of the curves (``"steps-post"`` for values held from
        each time to the next).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = _figure(len(panels))
    for ax, (ylabel, curves) in zip(axes, panels.items()):
        if not isinstance(curves, dict):
            curves = {None: curves}
        colours = curve_colours(len(curves))
        for (label, y), colour in zip(curves.items(), colours):
            ax.plot(*thinned(t, y), label=label, lw=1.0, color=colour, drawstyle=drawstyle)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        _plain_numbers(ax)
        if any(label is not None for label in curves):
            _curve_key([ax], list(curves), colours, loc="best")
    axes[-1].set_xlabel(xlabel)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _psd_unit(unit):
    """Unit of the PSD of a signal in ``unit`` (``""``, "1" or None: dimensionless)."""
    return "1/Hz" if unit in (None, "", "1") else f"{unit}$^2$/Hz"


def psd(t, signals, path=None, title=None, markers=None, units=None, f_min=None):
    """Power spectral densities of several signals on log axes (the paper's PSD figures),
    one panel per unit, with vertical marks at known frequencies.

    Parameters
    ----------
    t : ndarray (nt,)
        Uniform sample times.
    signals : dict
        ``{label: ndarray (nt,)}``.
    markers : dict, optional
        ``{label: frequency in Hz}`` (a dashed line named on the top axis, e.g. the spin
        or a tabulated mode), or ``{label: sequence of frequencies}`` (dotted lines with
        one legend entry, e.g. computed modes).  Frequencies outside the plotted band are
        left out.
    units : str or dict, optional
        Unit of every signal, or ``{label: unit}`` (``""``: dimensionless); the y label
        is ``PSD [unit^2/Hz]``.  Default: ``"unit"``.
    f_min : float, optional
        Lowest frequency to resolve (Hz), which sets the segments (``welch_plan``);
        default: 4 half-overlapping segments.  The segments and bin width are printed
        on the figure.
    """
    units = units if isinstance(units, dict) else dict.fromkeys(signals, units or "unit")
    panels = {}
    for label, x in signals.items():
        panels.setdefault(units[label], {})[label] = x
    fig, axes = _figure(len(panels), height_per_panel=3.0 if len(panels) > 1 else 3.5)
    for ax, (unit, group) in zip(axes, panels.items()):
        for (label, x), colour in zip(group.items(), curve_colours(len(group))):
            f, p = spectrum(t, x, f_min=f_min)
            ax.loglog(f[1:], p[1:], label=label, lw=1.0, color=colour)
        ax.set_xlim(f[1], f[-1])
        ax.set_ylim(bottom=max(ax.get_ylim()[0], 1e-12 * ax.get_ylim()[1]))
        ax.set_ylabel(f"PSD [{_psd_unit(unit)}]")
        ax.grid(True, which="both", alpha=0.3)
    _frequency_marks(axes, markers or {}, (f[1], f[-1]))
    for ax, group in zip(axes, panels.values()):
        _curve_key([ax], list(group), curve_colours(len(group)), loc="lower left")
    axes[-1].set_xlabel("frequency [Hz]")
    fig.supxlabel(welch_note(t, next(iter(signals.values())), f_min), fontsize="x-small",
                  color="dimgray")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


#: Colours of the dotted frequency marks (``psd``).
_MARK_COLOURS = ("tab:red", "tab:purple", "tab:brown", "tab:olive")


def _frequency_marks(axes, markers, band):
    """Dashed lines at single frequencies (named on a top axis) and dotted ones at
    sequences (one legend entry each), inside ``band``."""
    named, groups = {}, {}
    for label, value in markers.items():
        fs = np.atleast_1d(np.asarray(value, dtype=float))
        fs = fs[(fs >= band[0]) & (fs <= band[1])]
        if fs.size:
            (named if np.ndim(value) == 0 else groups)[label] = fs
    for ax in axes:
        for (f0,) in named.values():
            ax.axvline(f0, color="dimgray", ls="--", lw=0.9)
        for (label, fs), colour in zip(groups.items(), cycle(_MARK_COLOURS)):
            for i, f0 in enumerate(fs):
                ax.axvline(f0, color=colour, ls=":", lw=1.0, alpha=0.7,
                           label=None if i else label)
    if named:
        top = axes[0].secondary_xaxis("top")
        top.set_xticks([f0 for (f0,) in named.values()], list(named), fontsize="small")
        top.minorticks_off()
        top.tick_params(colors="dimgray")


#: Energy terms of ``energies``' first panel.
ENERGY_TERMS = ("kinetic", "axial", "bending", "potential", "dissipated", "external_work")

#: A term whose change over the run stays within this fraction of the energy in play
#: (``energy_scale``) is constant to rounding and named, not drawn: a pin's reaction
#: does no work, but the LU's rounding leaves the pinned node's corrections tiny,
#: not exactly zero (the flexible pendulum's pin 9e-25 m from its point after 50 steps,
#: external work 1e-25 J in a run of 1 J).
ROUNDING = 1e-12


def energy_scale(E):
    """Energy in play in a run (J): the largest ``kinetic + axial + bending +
    |potential change| + dissipated + |external work|`` over its saved steps."""
    content = (np.abs(E["kinetic"]) + np.abs(E["axial"]) + np.abs(E["bending"])
               + np.abs(E["potential"] - E["potential"][0]) + np.abs(E["dissipated"])
               + np.abs(E["external_work"]))
    return float(content.max())


def energy_figure(t, E, path=None, title="Energy"):
    """``energies`` from the times and the energy dict (``Result.energy``'s keys)."""
    fig, (terms, balance, drift) = _figure(3, width=8.5)
    scale = energy_scale(E)
    constant = [k for k in ENERGY_TERMS
                if not np.any(np.abs(E[k] - E[k][0]) > ROUNDING * scale)]
    for k in ENERGY_TERMS:
        if k not in constant:
            change = E[k] - E[k][0]
            terms.plot(*thinned(t, change), **_energy_style(k),
                       label=f"{k.replace('_', ' ')}\n(max |Δ| {np.abs(change).max():.2g} J)")
    terms.set_ylabel("change since\nfirst step [J]")
    terms.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.01, 0.5),
                 title=_constant_note(constant), title_fontsize="small")
    balance.plot(*thinned(t, E["balance"]), color="k", lw=1.0)
    balance.set_ylabel("balance\nresidual [J]")
    rel = np.abs(E["balance"]) / scale if scale > 0 else np.zeros_like(t)
    drift.semilogy(*thinned(t, np.where(rel > 0, rel, np.nan)), color="tab:red", lw=1.0)
    if not np.any(rel > 0):
        drift.text(0.5, 0.5, "balance exactly zero", transform=drift.transAxes, ha="center")
    drift.set_ylabel("|balance| / E_scale")
    drift.set_title(f"E_scale = max(K + V_axial + V_bending + |ΔV_pot| + D + |W|) = "
                    f"{scale:.4g} J", fontsize="small", loc="left")
    for ax in (terms, balance, drift):
        ax.grid(True, which="both", alpha=0.3)
    _plain_numbers(balance)
    drift.set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _energy_style(term):
    """Line style of an energy term: the works (dissipated energy, external work) wide,
    pale and dashed under the energies they feed, which stay visible on top."""
    colour = f"C{ENERGY_TERMS.index(term)}"
    if term in ("dissipated", "external_work"):
        return {"color": colour, "lw": 3.0, "ls": "--", "alpha": 0.5, "zorder": 1}
    return {"color": colour, "lw": 1.0, "zorder": 3}


def _constant_note(constant):
    """Legend title naming the energy terms left out because they never change."""
    if not constant:
        return None
    names = ", ".join(k.replace("_", " ") for k in constant)
    return f"constant over the run (to rounding)\n(not drawn): {names}"


def energies(result, path=None, title="Energy"):
    """Energy books of a run in three panels: the terms (kinetic, axial, bending,
    potential energy; dissipated energy and external work) as changes since the first
    saved step, the balance residual (J), and the relative drift ``|balance| / E_scale``
    (``energy_scale``) on a log axis."""
    return energy_figure(result.t, result.energy, path, title)


def speed_error(rows, path=None, group="elements", cost="wall", error="error", title=None):
    """Speed against error of a benchmark: one log-log curve per value of ``group``.

    Parameters
    ----------
    rows : iterable of dict
        Each with the keys ``group``, ``cost`` (e.g. wall time in s) and ``error``.
    """
    rows = list(rows)
    fig, (ax,) = _figure(1, height_per_panel=3.5)
    for g in sorted({r[group] for r in rows}):
        sel = sorted((r for r in rows if r[group] == g), key=lambda r: r[cost])
        ax.loglog([r[cost] for r in sel], [r[error] for r in sel], "o-", label=f"{group} = {g}")
    ax.set_xlabel(cost)
    ax.set_ylabel(error)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def rigid_fit(points):
    """Rigid motions that best carry the first row of ``points`` (nt, m, 3) onto each
    row (least squares, Kabsch): rotations ``R`` (nt, 3, 3) and centroids ``c`` (nt, 3)
    with ``points[k] ~ c[k] + (points[0] - c[0]) @ R[k].T``."""
    points = np.asarray(points, dtype=float)
    c = points.mean(axis=1)
    rel = points - c[:, None]
    U, _, Vt = np.linalg.svd(np.einsum("mi,tmj->tij", rel[0], rel))
    V = np.swapaxes(Vt, -1, -2)
    d = np.sign(np.linalg.det(V @ np.swapaxes(U, -1, -2)))
    D = np.broadcast_to(np.eye(3), V.shape).copy()
    D[:, 2, 2] = d
    return V @ D @ np.swapaxes(U, -1, -2), c


def corotated(result, x):
    """Points ``x`` (nt, ..., 3) of a run carried back by the rigid motion fitted to all
    its positions (``rigid_fit``) into where they would be at the first saved step: their
    motion relative to the frame that moves (spins) with the system as a whole."""
    system = result.system
    R, c = rigid_fit(result.q[:, system.vectors[system.vector_is_position]])
    rel = np.asarray(x, dtype=float) - c.reshape((len(c),) + (1,) * (np.ndim(x) - 2) + (3,))
    back = np.einsum("tji,t...j->t...i", R, rel)
    return back + c[0]


def orbiting(result, x):
    """Points ``x`` (nt, ..., 3) of a run in orbit relative to the system's centre of
    mass, in the orbiting frame (``Orbit.to_lvlh``) at each saved time: their motion as
    seen from the orbiting frame, free of the orbit's turn and of the reference point's
    rebases."""
    system = result.system
    centre = system.centre_of_mass(result.q)
    rel = np.asarray(x, dtype=float) - centre.reshape(
        (len(centre),) + (1,) * (np.ndim(x) - 2) + (3,))
    return result.reference.to_lvlh(result.t, rel)


def tip_frame(result):
    """How ``cable_histories`` measures tip displacements: ``(label, carry)`` with
    ``carry(result, x)`` taking points into that frame: the orbiting (LVLH) frame about
    the centre of mass for a system in orbit (``orbiting``), else the frame spinning with
    a spinning system (``corotated``, ``spin_axis`` of the first saved step), else the
    coordinates as computed (None)."""
    system = result.system
    if system.orbit is not None:
        return "in the LVLH frame", orbiting
    if spin_axis(system, result.q[0], result.v[0]) is not None:
        return "in the spinning frame", corotated
    return None, None


def cable_histories(result, path=None, title=None):
    """Tip displacement, root tension and peak tension of every cable of a run, one colour
    per cable (``curve_colours``; a colour bar names them beyond ``MAX_LEGEND``).  The tip
    displacement of a run in orbit is measured in the orbiting (LVLH) frame about the
    centre of mass, of a spinning run in the frame spinning with the system
    (``tip_frame``), so that it shows the tethers' motion rather than the orbit's or the
    rotation's chord."""
    system = result.system
    cables = system.cables()
    tips = np.stack([result.position(c, c.length) for c in cables], axis=1)
    frame, carry = tip_frame(result)
    if carry is not None:
        tips = carry(result, tips)
    panels = {"\n".join(filter(None, ["tip displacement", frame])) + " [m]":
              np.linalg.norm(tips - tips[0], axis=-1),
              "root tension [N]": np.stack([result.tension(c, 0.0) for c in cables], axis=1),
              "peak tension [N]": np.stack([result.tension(c, c.mesh.p[0]).max(axis=-1)
                                            for c in cables], axis=1)}
    fig, axes = _figure(len(panels))
    colours = curve_colours(len(cables))
    for ax, (ylabel, values) in zip(axes, panels.items()):
        for k, (cable, colour) in enumerate(zip(cables, colours)):
            ax.plot(*thinned(result.t, values[:, k]), lw=1.0, color=colour, label=cable.name)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        _plain_numbers(ax)
    if len(cables) > 1:
        _curve_key(axes, [c.name for c in cables], colours, loc="best")
    axes[-1].set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)
