"""The tension guard of run summaries: a cable whose recovered tension changes sign while
it is not slack, or oscillates from element to element by more than its tension, is named
in the summary's warnings.  Both are what membrane locking looks like (the paper's
formulation reports stripes of tens of times the load on a bending cable,
``docs/locking.md``), whatever formulation a run uses.

Examples
--------
The paper's formulation on a hanging steel wire, 16 elements (``docs/locking.md``):

>>> import skfem_cable as sc
>>> from skfem_cable.runner.tension_guard import tension_warnings
>>> sec = sc.Section.circular(2e-3, 2.1e11, 7850.0)
>>> wire = sc.Cable.straight([0, 0, 0], [12, 0, 0], 16, sec, name="wire", formulation="paper")
>>> system = sc.System([wire]).pin(wire.node(0)).pin(wire.node(-1), [10, 0, 0])
>>> state = sc.solve_static(system.add_gravity([0, 0, -9.81]), load_steps=10)
>>> [w.split(":")[0] for w in tension_warnings(system, state.q)]
["cable 'wire'", "cable 'wire'"]
"""

import numpy as np

#: A cable whose mean tension is below this strain times its axial stiffness ``EA`` is
#: slack: the guard says nothing about it.
SLACK_STRAIN = 1e-6

#: A compression below this fraction of the mean tension is a change of sign.
SIGN_TOLERANCE = 0.05

#: Saved steps evaluated at once (the recovery holds a few arrays of this many steps).
CHUNK = 128


def sample_points(cable):
    """Arc lengths of the nodes and the element midpoints, in order (``2 n + 1``)."""
    x = cable.mesh.p[0]
    s = np.empty(2 * cable.n_elements + 1)
    s[::2] = x
    s[1::2] = 0.5 * (x[1:] + x[:-1])
    return s


def tension_warnings(system, q, t=None):
    """Warnings about the recovered tension of every cable of ``system`` at the
    coordinates ``q`` (``(n_dofs,)``, or one row per saved step at times ``t``; None: a
    static state).

    At the nodes and element midpoints of each state: the mean tension ``T``; a change of
    sign is a least tension below ``-SIGN_TOLERANCE T``; an oscillation is the largest
    distance of a midpoint's tension from the mean of its element's two nodal tensions
    (twice the amplitude of an element-to-element stripe; about ``h^2 T'' / 8`` for a
    resolved field).  Either is reported, at the state where it is largest relative to
    ``T``, for a cable that is not slack (``T > SLACK_STRAIN EA``).

    Returns
    -------
    list of str
        One sentence per finding, naming the cable, the numbers, the time and what to do.
    """
    q = np.atleast_2d(q)
    static = t is None
    t = np.broadcast_to(np.asarray(0.0 if static else t, dtype=float), q.shape[:1])
    out = []
    for cable in system.cables():
        s = sample_points(cable)
        dofs = system.dofs(cable)
        floor = SLACK_STRAIN * cable.section.EA
        worst = {"sign": (0.0, None), "stripes": (0.0, None)}
        for k in range(0, len(q), CHUNK):
            rows, times = q[k:k + CHUNK], t[k:k + CHUNK]
            N = cable.tension(rows[:, dofs], s, system.stretch(cable, times, rows), times)
            mean = N.mean(axis=1)
            taut = mean > floor
            low = np.where(taut, -N.min(axis=1) / np.where(taut, mean, 1.0), 0.0)
            nodes, middles = N[:, ::2], N[:, 1::2]
            wiggle = np.abs(middles - 0.5 * (nodes[:, 1:] + nodes[:, :-1])).max(axis=1)
            high = np.where(taut, wiggle / np.where(taut, mean, 1.0), 0.0)
            for key, ratio, detail in (("sign", low, N.min(axis=1)), ("stripes", high, wiggle)):
                i = int(np.argmax(ratio))
                if ratio[i] > worst[key][0]:
                    worst[key] = (ratio[i], (times[i], mean[i], detail[i], N[i].max()))
        what = (f"(element {cable.element.name!r}, formulation {cable.formulation!r}): "
                "membrane locking or an unresolved tension; refine the mesh, or use the "
                "cubic element's default formulation 'assumed-strain' (docs/locking.md, "
                "docs/elements.md)")
        if worst["sign"][0] > SIGN_TOLERANCE:
            time, mean, least, most = worst["sign"][1]
            when = "" if static else f" at t = {time:.6g} s"
            out.append(f"cable {cable.name!r}: its tension changes sign along the cable "
                       f"(from {least:.3g} N to {most:.3g} N{when}) while it carries a mean "
                       f"tension of {mean:.3g} N {what}")
        if worst["stripes"][0] > 1.0:
            time, mean, wiggle, _ = worst["stripes"][1]
            when = "" if static else f" at t = {time:.6g} s"
            out.append(f"cable {cable.name!r}: its tension oscillates from element to "
                       f"element by {wiggle:.3g} N{when}, more than its mean tension "
                       f"{mean:.3g} N {what}")
    return out
