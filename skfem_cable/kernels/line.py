"""The one loop of the line loads: gather, interpolate, call the load's point, scatter.

A line body declares its quadrature as ``lines.LinePoints``: the global coordinates of
every element's ``nf`` 3-vectors ``edofs`` (ne, 3 nf), the tables ``S`` and ``Sx``
(ne, nq, nf) and the weights ``w`` (ne, nq), so that at point ``g`` of element ``e``

``x = sum_A S[e, g, A] q_A``,  ``a = r_x = sum_A Sx[e, g, A] q_A``,  ``xd = sum_A S[e, g, A] v_A``

(``q_A = q[edofs[e, 3 A : 3 A + 3]]``; ``x`` the position, ``a`` the slope with respect to
the reference arc length, ``xd`` the velocity).  A load gives the force per unit reference
length ``f(x, a, xd)`` at a point and its derivatives ``Fx = df/dx``, ``Fa = df/da`` and
``Fv = df/dxd`` (3 x 3 each); its generalized force and tangent are

``F_A = sum_g w S_A f``,  ``K_AB = -sum_g w S_A (S_B (cK Fx + cC Fv) + Sx_B cK Fa)``

(external force: the iteration matrix receives minus its derivatives, ``contract``).  The
element-wise steps are written once here, as inlined functions (``gather``,
``interpolate``, ``add_point``, ``scatter``), and used by

* the template ``span``: the element loop of a *pointwise* load, whose point function
  ``point`` is a free name.  ``module(point)`` generates, per point function, a module
  with ``point`` bound, this loop and its chunked driver (``kernel``, ``kernel_parallel``,
  the hooks of the evaluation contract) and compiles it once per machine: numba cannot
  cache a loop that receives its point function as an argument (``laws.codegen`` does the
  same for the laws);
* ``points`` and ``assemble``: the two halves of the loop over arrays of points, for a load
  whose force at a point depends on the whole line (the electrodynamic current) or that is
  Python (``LineLoad``).

The point function of a pointwise load has the signature

``point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work)``

with ``params`` the load's own tuple of arrays, ``e`` the element, ``t`` the time, ``xd``
unset for a module generated with ``velocity=False`` (``module``), ``want`` whether the
tangent is wanted (``Fx``, ``Fa``, ``Fv`` may be left unset otherwise) and
``work`` a scratch array (8, 3, 3); it writes ``f``, ``Fx``, ``Fa`` and ``Fv``.  Each
element's force is scaled by ``scale[e]`` (elements with ``scale[e] = 0`` are skipped: a
load on a part of a line), and the loop adds the load's resultant ``sum w scale f`` to
``resultant`` (3,).
"""

import functools
import inspect

import numpy as np
from numba import njit, prange

from . import generated
from .chunks import CHUNK

#: Bump when the generated module changes meaning (part of its digest; a value never used
#: before: caches keep the modules of earlier commits; "7", "8" were used; "10": no Python
#: wrapper of ``span`` and ``loop_parallel``).
GENERATOR = "10"

#: The decorator of a pointwise load's point function (``module``): numba types and lowers
#: it once per process and parameters, apart, and LLVM inlines its code into each
#: generated ``span`` that calls it (``forceinline``; the same instructions).  Numba's own
#: inlining (``inline="always"``) typed and lowered it again in every module, one per load
#: and element type: 29 s of ``span`` in a clean-clone test run, of which 6 s LLVM.
point_function = njit(cache=True, no_cfunc_wrapper=True, forceinline=True)


@njit(cache=True, inline="always")
def gather(edofs, y, e, nf, ye):
    """The ``nf`` 3-vectors of element ``e`` of the global array ``y`` into ``ye``
    (nf, 3)."""
    for A in range(nf):
        for i in range(3):
            ye[A, i] = y[edofs[e, 3 * A + i]]


@njit(cache=True, inline="always")
def interpolate(T, e, g, ye, nf, out):
    """``out = sum_A T[e, g, A] ye[A]`` (3,): the field of the element's vectors ``ye``
    at its point ``g`` with the table ``T`` (``S`` or ``Sx``)."""
    for i in range(3):
        s = 0.0
        for A in range(nf):
            s += T[e, g, A] * ye[A, i]
        out[i] = s


@njit(cache=True, inline="always")
def add_point(S, Sx, e, g, wg, f, Fx, Fa, Fv, cK, cC, want, nf, fe, Ke, G):
    """Add the point's ``wg S_A f`` to the element force ``fe`` (3 nf,) and, if ``want``,
    ``wg S_A (S_B (cK Fx + cC Fv) + Sx_B cK Fa)`` to ``Ke`` (3 nf, 3 nf); ``G`` (3, 3) is
    scratch."""
    for A in range(nf):
        sA = wg * S[e, g, A]
        for i in range(3):
            fe[3 * A + i] += sA * f[i]
    if not want:
        return
    for i in range(3):
        for j in range(3):
            G[i, j] = cK * Fx[i, j] + cC * Fv[i, j]
    for A in range(nf):
        sA = wg * S[e, g, A]
        for B in range(nf):
            sB = S[e, g, B]
            xB = cK * Sx[e, g, B]
            for i in range(3):
                for j in range(3):
                    Ke[3 * A + i, 3 * B + j] += sA * (sB * G[i, j] + xB * Fa[i, j])


@njit(cache=True, inline="always")
def scatter(edofs, index, e, nd, fe, Ke, f_ext, data, want):
    """Add the element force ``fe`` to the external forces ``f_ext`` and, if ``want``,
    minus the element matrix ``Ke`` to ``data`` at ``index[e]`` (external: ``contract``)."""
    for k in range(nd):
        f_ext[edofs[e, k]] += fe[k]
    if want:
        for k in range(nd):
            for m in range(nd):
                data[index[e, k, m]] -= Ke[k, m]


@njit(cache=True, inline="always")
def book_damping(edofs, e, nd, fe, f, f_damping):
    """Add the element force ``fe`` of a dissipative load to the internal forces ``f`` and
    their damping part ``f_damping`` with its sign turned (a damping force resists:
    ``contract``), so that its work is booked as dissipation (``module(dissipative=)``),
    and clear ``fe`` (``scatter`` then adds the tangent only: its sign is the same)."""
    for k in range(nd):
        f[edofs[e, k]] -= fe[k]
        f_damping[edofs[e, k]] -= fe[k]
        fe[k] = 0.0


@njit(cache=True)
def points(edofs, S, Sx, q, v, X, A, V):
    """The positions ``X``, slopes ``A`` and velocities ``V`` (ne, nq, 3) of every point
    of the line: the first half of the loop, for loads whose force at a point depends on
    the whole line or that are Python."""
    ne, nq, nf = S.shape
    qe = np.empty((nf, 3))
    ve = np.empty((nf, 3))
    for e in range(ne):
        gather(edofs, q, e, nf, qe)
        gather(edofs, v, e, nf, ve)
        for g in range(nq):
            interpolate(S, e, g, qe, nf, X[e, g])
            interpolate(Sx, e, g, qe, nf, A[e, g])
            interpolate(S, e, g, ve, nf, V[e, g])


@njit(cache=True)
def assemble(edofs, S, Sx, w, F, Fx, Fa, Fv, cK, cC, f_ext, data, index):
    """The second half: the forces ``F`` (ne, nq, 3) and derivatives ``Fx``, ``Fa``,
    ``Fv`` (ne, nq, 3, 3) at the points into ``f_ext`` and, if ``data`` is not empty,
    the tangent into ``data`` at ``index`` (ne, 3 nf, 3 nf)."""
    ne, nq, nf = S.shape
    nd = 3 * nf
    want = data.size > 0
    fe = np.empty(nd)
    Ke = np.empty((nd, nd))
    G = np.empty((3, 3))
    for e in range(ne):
        fe[:] = 0.0
        Ke[:] = 0.0
        for g in range(nq):
            add_point(S, Sx, e, g, w[e, g], F[e, g], Fx[e, g], Fa[e, g], Fv[e, g], cK, cC,
                      want, nf, fe, Ke, G)
        scatter(edofs, index, e, nd, fe, Ke, f_ext, data, want)


# --- the template of a pointwise load's module (``module``) ---------------------------


def span(first, last, step, t, state, line, params, out, coef, nf, acc):
    """Add the load's force of the elements ``range(first, last, step)`` to ``f_ext`` and
    minus ``cK dF/dq + cC dF/dv`` to ``data``, their resultant to ``acc`` (3,).

    Parameters
    ----------
    first, last, step : int
        The elements ``range(first, last, step)``.
    t : float
        Time (s).
    state : tuple ``(q, v)``
        Global coordinates and velocities (n,).
    line : tuple ``(edofs, S, Sx, w, scale)``
        The line body's points (``lines.LinePoints``) and the factor of each element's
        force (ne,).
    params : tuple
        The load's arrays, passed to ``point``.
    out : tuple ``(f_ext, data, index, f, f_damping)``
        External forces (n,), matrix values and the index of each element-matrix entry in
        them (ne, 3 nf, 3 nf), or an index of length 0 to skip the tangent; internal
        forces and their damping part (n,), which a dissipative load's force goes to
        instead of ``f_ext`` (``module``).
    coef : tuple ``(cK, cC)``
    nf : int
        Functions per element.
    acc : ndarray (3,)
    """
    if first >= last:
        return  # no element: no scratch to allocate (the close of a single chunk)
    q, v = state
    edofs, S, Sx, w, scale = line
    f_ext, data, index, f_int, f_damping = out
    cK, cC = coef
    nq = w.shape[1]
    nd = 3 * nf
    want = index.shape[0] == w.shape[0]
    qe = np.empty((nf, 3))
    ve = np.empty((nf, 3))
    x = np.empty(3)
    a = np.empty(3)
    xd = np.empty(3)
    f = np.empty(3)
    Fx = np.zeros((3, 3))
    Fa = np.zeros((3, 3))
    Fv = np.zeros((3, 3))
    G = np.empty((3, 3))
    work = np.empty((8, 3, 3))
    fe = np.empty(nd)
    Ke = np.empty((nd, nd))
    for e in range(first, last, step):
        c = scale[e]
        if c == 0.0:
            continue
        gather(edofs, q, e, nf, qe)  # noqa: F821 (names of the generated module)
        if VELOCITY:  # noqa: F821 (a constant of the generated module)
            gather(edofs, v, e, nf, ve)  # noqa: F821
        fe[:] = 0.0
        if want:
            Ke[:] = 0.0
        for g in range(nq):
            interpolate(S, e, g, qe, nf, x)  # noqa: F821
            interpolate(Sx, e, g, qe, nf, a)  # noqa: F821
            if VELOCITY:  # noqa: F821
                interpolate(S, e, g, ve, nf, xd)  # noqa: F821
            point(params, e, t, x, a, xd, want, f, Fx, Fa, Fv, work)  # noqa: F821
            wg = c * w[e, g]
            for i in range(3):
                acc[i] += wg * f[i]
            add_point(S, Sx, e, g, wg, f, Fx, Fa, Fv, cK, cC, want, nf, fe, Ke,  # noqa: F821
                      G)
        if DISSIPATIVE:  # noqa: F821 (a constant of the generated module)
            book_damping(edofs, e, nd, fe, f_int, f_damping)  # noqa: F821
        scatter(edofs, index, e, nd, fe, Ke, f_ext, data, want)  # noqa: F821


def chunk(c, t, state, line, params, out, coef, nf, acc):
    """The elements of chunk ``c`` but its first (for ``c > 0``; ``kernels.chunks``),
    their resultant into ``acc[c]``."""
    first = c * CHUNK + (1 if c > 0 else 0)
    last = min(line[4].shape[0], (c + 1) * CHUNK)
    span(first, last, np.int64(1), t, state, line, params, out, coef, nf,  # noqa: F821
         acc[c])


def close(t, state, line, params, out, coef, nf, acc, resultant):
    """The first elements of the chunks after the first, then the chunks' resultants added
    to ``resultant`` in order (the same sums in the same order on any number of threads)."""
    span(np.int64(CHUNK), line[4].shape[0], np.int64(CHUNK), t, state, line, params,  # noqa: F821
         out, coef, nf, acc[-1])
    for c in range(acc.shape[0]):
        for i in range(3):
            resultant[i] += acc[c, i]


def loop(t, state, line, params, out, coef, nf, resultant):
    """All chunks, one after the other."""
    acc = np.zeros(((line[4].shape[0] + CHUNK - 1) // CHUNK + 1, 3))
    for c in range(acc.shape[0] - 1):
        chunk(c, t, state, line, params, out, coef, nf, acc)  # noqa: F821
    close(t, state, line, params, out, coef, nf, acc, resultant)  # noqa: F821


def loop_parallel(t, state, line, params, out, coef, nf, resultant):
    """``loop`` with the chunks on numba's threads."""
    acc = np.zeros(((line[4].shape[0] + CHUNK - 1) // CHUNK + 1, 3))
    for c in prange(acc.shape[0] - 1):
        chunk(c, t, state, line, params, out, coef, nf, acc)  # noqa: F821
    close(t, state, line, params, out, coef, nf, acc, resultant)  # noqa: F821


def arguments(pack, index, ev):
    """The loop's arguments for the packed evaluation ``ev`` and ``pack = (edofs, S, Sx,
    w, scale, params, resultant)`` (``lines.LinePoints.pack``)."""
    q, v, s, f, f_ext, fd, data, energy, power = ev
    edofs, S, Sx, w, scale, params, resultant = pack
    index = index if data.size else index[:0]
    return (s[0], (q, v), (edofs, S, Sx, w, scale), params, (f_ext, data, index, f, fd),
            (s[1], s[2] if s[3] != 0.0 else 0.0), resultant)


def kernel(pack, index, ev):
    """The load's hook of the evaluation contract (``contract.Term.kernels``), with the
    number of functions ``NF`` of the module's element fixed (its loops unrolled)."""
    t, state, line, params, out, coef, resultant = arguments(pack, index, ev)  # noqa: F821
    loop(t, state, line, params, out, coef, NF, resultant)  # noqa: F821


def kernel_parallel(pack, index, ev):
    """``kernel`` on numba's threads."""
    t, state, line, params, out, coef, resultant = arguments(pack, index, ev)  # noqa: F821
    loop_parallel(t, state, line, params, out, coef, NF, resultant)  # noqa: F821


#: The decorator of the template's ``span``: typed and lowered once by numba, which does it
#: again at every call of an ``inline="always"`` function (``span`` was inlined into
#: ``chunk``, itself into ``loop`` and ``loop_parallel``, and into ``close``: 17 s of a
#: cold cache for the Morison drag's module), and inlined by LLVM into each caller
#: (``forceinline``: the machine code of the loops is that of the inlined functions).  No
#: C wrappers here: the module's functions are called by numba (the system's ``evaluate``)
#: or from Python (the hooks, ``HOOK``), never through a C pointer; and ``span`` and
#: ``loop_parallel``, which compiled code alone calls, none of Python either (it would box
#: and unbox their arguments, tuples of arrays; a call from Python would crash).
SHARED = "@njit(cache=True, no_cfunc_wrapper=True, no_cpython_wrapper=True, forceinline=True)"

#: The decorator of the hooks of the evaluation contract, ``kernel`` and
#: ``kernel_parallel`` (see ``SHARED``).
HOOK = "@njit(cache=True, no_cfunc_wrapper=True)"

#: The decorator of the template's small drivers around ``span`` (``chunk``, ``close``,
#: ``loop``, ``arguments``): inlined by numba into the hooks, whose compilation then
#: optimises and emits the loops' code once.  Compiled apart, each was a compilation of
#: its own that LLVM optimised ``span``'s code again for (numba links a callee's code into
#: every caller compiled apart): 1.2 of the 3.7 s of the Morison drag's cubic module.
INLINED = '@njit(cache=True, inline="always")'

#: The template's functions and their decorators in the generated module: the hooks and
#: the threaded loop are compiled (``kernel_parallel`` only when a run uses threads).
TEMPLATE = ((SHARED, span), (INLINED, chunk), (INLINED, close), (INLINED, loop),
            ("@njit(cache=True, parallel=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)",
             loop_parallel),
            (INLINED, arguments), (HOOK, kernel), (HOOK, kernel_parallel))


def _source(point, nf, velocity, dissipative):
    return "\n\n\n".join([
        f'"""Generated by skfem_cable.kernels.line for the point function '
        f'{point.py_func.__module__}.{point.py_func.__qualname__}.  Do not edit."""',
        "import numpy as np\nfrom numba import njit, prange\n\n"
        "from skfem_cable.kernels.chunks import CHUNK\n"
        "from skfem_cable.kernels.line import add_point, book_damping, gather, interpolate, "
        "scatter\n\n"
        f"#: The number of functions of the element.\nNF = {int(nf)}\n"
        f"#: Whether the point function reads the velocity.\nVELOCITY = {bool(velocity)}\n"
        "#: Whether the load's work is booked as dissipation.\n"
        f"DISSIPATIVE = {bool(dissipative)}",
        *(decorator + "\n" + inspect.getsource(fn) for decorator, fn in TEMPLATE)]) + "\n"


@functools.cache
def module(point, nf, velocity=True, dissipative=False):
    """The compiled module of the pointwise load whose point function is ``point``
    (decorated ``point_function``: compiled once per process, inlined by LLVM) on
    elements of ``nf`` functions (a constant of the module: its loops unrolled, and one
    loop compiled, not one per element type it might meet): its hooks ``kernel`` and
    ``kernel_parallel``.  ``velocity=False``: the point function does
    not read the velocity ``xd`` (left unset), whose gather and interpolation the loop
    then skips (on the E-sail rig, 4 % of its step for the solar wind).
    ``dissipative=True``: the force is a resistance (friction, a dashpot) whose work is
    booked as dissipation: its negative goes to the internal forces ``f`` and their
    damping part ``f_damping`` instead of ``f_ext`` (the tangent is the same).
    Generated once per machine, point function, ``nf``, ``velocity`` and ``dissipative`` (its
    name carries a digest of the point's source and of every compiled function it
    calls); remembered per process (its digest reads the sources: 10 ms)."""
    py = point.py_func
    name = "skfem_cable_line_{}_{}".format(
        py.__qualname__.replace(".", "_")[:40],
        generated.digest(GENERATOR, generated.source_id(point), inspect.getsource(span),
                         _source(point, nf, velocity, dissipative)))
    return generated.load("lines", name, lambda: _source(point, nf, velocity, dissipative),
                          namespace={"point": point},
                          description=f"the line loop of {py.__module__}.{py.__qualname__}")
