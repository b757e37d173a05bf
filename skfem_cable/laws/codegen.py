"""Code generation of an element law: derivatives by ``sympy``, modules per law written to
an on-disk cache and compiled by numba (``cache=True``), so that a law is derived and
compiled once per machine, not once per run.

A law has a module of each kind (``TEMPLATES``) it is used with, and its point functions
in a module of their own (``points``, one per expressions and damping):

* ``point_g(x, prm, h, G) -> (W_axial, W_bending)`` writing ``G = W_x``;
* ``point_gh(x, prm, h, G, H)`` also writing ``H = W_xx``;
* ``point_gd(x, xd, prm, h, G, Gd) -> (W_axial, W_bending, P_axial, P_bending)`` with
  ``G = W_x + D_xd``, ``Gd = D_xd`` and the dissipated power ``P = D_xd . xd``;
* ``point_ghd(x, xd, prm, h, G, H, Gd, Hc)`` also writing ``H = W_xx + D_xd,x`` and
  ``Hc = D_xd,xd``;
* ``numpy_point(x, xd, prm, h)``, the same quantities vectorised over points (numpy);
* ``numpy_gradient(x, xd, prm, h)``, its ``G`` alone, stacked (6, ...): what a section
  force reads, without the Hessians.

The ``"gauss"`` module imports the law's point functions and holds ``span``, the loop of
``kernels.cable`` over a range of elements compiled around them.  The element loop of
``kernels.chunks``, ``kernel`` and ``kernel_parallel`` (on numba's threads), the hooks of
the evaluation contract (``contract.Term.kernels``), is one module for every law
(``loop``): it calls a law's ``span`` at the address its pack ends with (``hook``).

The ``"assumed-strain"`` module imports the point functions of the law's bending part
(``CableLaw.part(1)``; with the law's damping: the module that part's ``"gauss"`` module
imports when both damp or neither does, so that a process compiling both, or the modules
of two element sizes, compiles them once), and
holds for its axial part in the Green strain (``CableLaw.strain``): ``strain_point(e, prm,
h) -> (W, s, k)`` (energy, stress ``s = W'`` and ``k = W''``), ``strain_point_d(e, ed,
prm, h) -> (W, P, s, k, c, sd)`` with ``s = W' + D_ed``, ``k = ds/de``, ``c = ds/ded``,
the damping stress ``sd = D_ed`` and the power ``P = D_ed ed``, and ``numpy_strain(e,
prm, h)`` (``W`` and ``s``, vectorised); its ``span`` is that of
``kernels.assumed_strain``, in the same loop.

Each is common-subexpression eliminated (``sympy.cse``) and compiled apart, then inlined
into ``span`` by LLVM (``POINT``).  The modules live in the
``laws`` folder of the cache of ``kernels.generated``; a module's name carries a digest of
the law's expressions, its kind, the templates and this generator, so a changed law or
template never meets a stale module.
"""

import functools
import inspect
import re
import sys

import numba
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import PythonCodePrinter

from ..kernels import assumed_strain, chunks, erased, generated
from ..kernels import cable as template
from .symbolic import SLOPE_FLOOR

#: Bump when the generated code changes meaning (part of every module's digest), to a value
#: never used before: a cache may hold the modules of any earlier commit ("8" was used,
#: then reverted to "7"; "10": the point functions in modules of their own; "11": the element
#: loop one function, ``kernel``; "13": ``numpy_gradient``, and no numba wrappers where
#: compiled code alone calls; "12" was used by the two branches that made them; "14": the
#: element loop in one module for every law, ``loop``).  The
#: digest also holds this module's own text (``_generator_id``), so an edit of the
#: generator never meets a module of the text before.
GENERATOR = "14"

#: The decorator of the point functions: numba types and lowers each once, apart, and
#: LLVM inlines its code into ``span`` (``forceinline``; the same instructions).  Numba's
#: own inlining (``inline="always"``) made ``span`` one large function, which numba
#: compiles more slowly than its parts apart: four law modules 34-35 -> 28 s of CPU.  Not
#: cached: ``span``'s cached code holds theirs.  Called by ``span`` alone: without numba's
#: Python and C wrappers (``SPAN``; a call from Python would crash).
POINT = "@njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, forceinline=True)"

#: The decorator of ``strain_point_d``, also called from Python (``bodies.forms``; one
#: compiles there): ``POINT`` with numba's Python wrapper.
CALLED = "@njit(no_cfunc_wrapper=True, forceinline=True)"


class _ScalarPrinter(PythonCodePrinter):
    """Scalar code for numba: ``math`` functions, ``max`` for the slope floor."""

    def _print_floored(self, expr):
        return f"max({self._print(expr.args[0])}, SLOPE_FLOOR)"

    def _print_sign(self, expr):
        return f"np.sign({self._print(expr.args[0])})"

    def _print_power(self, expr):
        return f"({self._print(expr.args[0])})**({self._print(expr.args[1])})"


class _VectorPrinter(NumPyPrinter):
    """Vectorised numpy code for the scikit-fem forms."""

    def _print_floored(self, expr):
        return f"numpy.maximum({self._print(expr.args[0])}, SLOPE_FLOOR)"

    def _print_power(self, expr):
        return f"({self._print(expr.args[0])})**({self._print(expr.args[1])})"


def _smooth(expr):
    """Derivatives of ``Abs``/``Piecewise`` laws carry ``DiracDelta`` terms (zero almost
    everywhere, the consistent tangent of a kink is its one-sided one): drop them."""
    return expr.replace(sp.DiracDelta, lambda *args: sp.Integer(0)).replace(
        sp.Heaviside, lambda arg, *rest: sp.Piecewise((1, arg > 0), (0, True)))


def derivatives(sym, damped):
    """Named output expressions of a point function: ``[(target, expr), ...]`` with targets
    ``"ea"``, ``"eb"``, ``"pa"``, ``"pb"``, ``"G[i]"``, ``"H[i, j]"``, ``"Gd[i]"``,
    ``"Hc[i, j]"`` (and ``"H"`` without the dissipation part if not ``damped``); the
    Hessian ``H`` is a dict ``(i, j) -> expr`` (all 36)."""
    x, xd = sym.x, sym.xd
    W = sym.W[0] + sym.W[1]
    G = [sp.diff(W, xi) for xi in x]
    H = {}
    for i in range(6):
        for j in range(i, 6):
            H[i, j] = H[j, i] = sp.diff(G[i], x[j])
    out = {"ea": sym.W[0], "eb": sym.W[1]}
    if damped:
        D = sym.D[0] + sym.D[1]
        Gd = [sp.diff(D, v) for v in xd]
        out["pa"] = sum(sp.diff(sym.D[0], v) * v for v in xd)
        out["pb"] = sum(sp.diff(sym.D[1], v) * v for v in xd)
        G = [g + d for g, d in zip(G, Gd)]
        H = {(i, j): H[i, j] + sp.diff(Gd[i], x[j]) for i in range(6) for j in range(6)}
        out.update({f"Gd[{i}]": Gd[i] for i in range(6)})
        out.update({f"Hc[{i}, {j}]": sp.diff(Gd[i], xd[j])
                    for i in range(6) for j in range(6)})
    out.update({f"G[{i}]": G[i] for i in range(6)})
    out.update({f"H[{i}, {j}]": H[i, j] for i in range(6) for j in range(6)})
    return {k: _smooth(v) for k, v in out.items()}


def strain_derivatives(strain, damped):
    """Named output expressions of the strain point functions: ``W``, ``s``, ``k`` (and,
    if ``damped``, with the dissipation: ``P``, ``c``, ``sd``)."""
    e, ed = strain.e, strain.ed
    s = sp.diff(strain.W, e)
    out = {"W": strain.W, "s": s, "k": sp.diff(s, e)}
    if damped:
        sd = sp.diff(strain.D, ed)
        out.update(P=sd * ed, s=s + sd, k=sp.diff(s + sd, e), c=sp.diff(sd, ed), sd=sd)
    return {k: _smooth(v) for k, v in out.items()}


def _unpack(sym, used, rates):
    """Lines unpacking the inputs of a point function (6 fields ``x``, ``xd``) that the
    expressions use."""
    lines = [f"{s} = x[{i}]" for i, s in enumerate(sym.x) if s in used]
    if rates:
        lines += [f"{s} = xd[{i}]" for i, s in enumerate(sym.xd) if s in used]
    return lines


def _body(outputs, sym, printer, indent, rates, unpack=_unpack):
    """Lines computing ``outputs`` (target -> expr) after unpacking the inputs."""
    used = set().union(*(e.free_symbols for e in outputs.values()))
    lines = unpack(sym, used, rates)
    lines += [f"{k} = prm[{i}]" for i, (k, s) in enumerate(sym.params.items()) if s in used]
    targets = list(outputs)
    # equal entries (a symmetric Hessian) are computed once
    unique, first = [], {}
    for t in targets:
        key = outputs[t]
        if key not in first:
            first[key] = t
            unique.append(t)
    subs, reduced = sp.cse([outputs[t] for t in unique],
                           symbols=sp.numbered_symbols("c_"), order="none")
    for s, e in subs:
        lines.append(f"{s} = {printer.doprint(e)}")
    for t, e in zip(unique, reduced):
        lines.append(f"{t} = {printer.doprint(e)}")
    for t in targets:
        if first[outputs[t]] != t:
            lines.append(f"{t} = {first[outputs[t]]}")
    return [indent + line for line in lines]


def _scalar_function(name, args, outputs, returns, sym, rates, unpack=_unpack,
                     decorator=POINT):
    lines = [decorator, f"def {name}({', '.join(args)}):"]
    lines += _body(outputs, sym, _ScalarPrinter({"standard": "python3"}), "    ", rates,
                   unpack)
    lines.append(f"    return {', '.join(returns)}")
    return "\n".join(lines)


def _select(outputs, prefixes):
    return {t: e for t, e in outputs.items() if t.split("[")[0] in prefixes}


def _numpy_functions(outputs, sym):
    """``numpy_point(x, xd, prm, h)`` returning a dict of arrays (vectorised), and
    ``numpy_gradient(x, xd, prm, h)`` returning its ``G`` alone, stacked (6, ...), by the
    lines of ``numpy_point`` that ``G`` needs (the same arithmetic, bit for bit)."""
    flat = {re.sub(r"[\[\], ]+", "_", t).rstrip("_"): e for t, e in outputs.items()}
    body = _body(flat, sym, _VectorPrinter({"standard": "python3"}), "    ", True)
    point = ["def numpy_point(x, xd, prm, h):",
             '    """Energy and power parts, G, H, Gd, Hc at points (leading axes of x)."""',
             *body, "    shape = numpy.shape(x[0])", "    out = {}",
             *(f"    out[{t!r}] = numpy.broadcast_to({t}, shape) * 1.0" for t in flat),
             "    return out"]
    G = [f"G_{i}" for i in range(6)]
    gradient = ["def numpy_gradient(x, xd, prm, h):",
                '    """G = W_x + D_xd at points (leading axes of x), stacked (6, ...)."""',
                *_needed(body, G), "    shape = numpy.shape(x[0])",
                f"    return numpy.stack([numpy.broadcast_to(G, shape) * 1.0 for G in "
                f"({', '.join(G)})])"]
    return "\n".join(point), "\n".join(gradient)


def _needed(lines, targets):
    """The lines of the straight-line code ``lines`` (``name = expr``) that computing
    ``targets`` needs (a name read is a word of an expression)."""
    need, kept = set(targets), []
    for line in reversed(lines):
        name, expr = line.strip().split(" = ", 1)
        if name in need:
            need.update(re.findall(r"[A-Za-z_]\w*", expr))
            kept.append(line)
    return kept[::-1]


def _unpack_strain(strain, used, rates):
    """Lines naming the strain point functions' inputs ``e``, ``ed`` as the symbols."""
    lines = [f"{strain.e} = e"] if strain.e in used else []
    if rates and strain.ed in used:
        lines.append(f"{strain.ed} = ed")
    return lines


def _strain_functions(strain):
    """The strain point functions and ``numpy_strain`` of the axial part ``strain``."""
    elastic = strain_derivatives(strain, damped=False)
    lines = ["def numpy_strain(e, prm, h):",
             '    """Axial energy W and stress s = dW/de at Green strains e (numpy)."""']
    lines += _body({t: elastic[t] for t in ("W", "s")}, strain,
                   _VectorPrinter({"standard": "python3"}), "    ", False, _unpack_strain)
    lines += ["    shape = numpy.shape(e)",
              "    return {'W': numpy.broadcast_to(W, shape) * 1.0,",
              "            's': numpy.broadcast_to(s, shape) * 1.0}"]
    return [
        _scalar_function("strain_point", ("e", "prm", "h"), elastic, ("W", "s", "k"),
                         strain, False, _unpack_strain),
        _scalar_function("strain_point_d", ("e", "ed", "prm", "h"),
                         strain_derivatives(strain, damped=True),
                         ("W", "P", "s", "k", "c", "sd"), strain, True, _unpack_strain,
                         CALLED),
        "\n".join(lines),
    ]


def _point_functions(sym, damped):
    """The scalar point functions ``point_g``, ``point_gh``, ``point_gd``, ``point_ghd`` of
    the expressions ``sym`` (the damped ones with zero dissipation if not ``damped``), and
    the output expressions of the damped ones (for ``numpy_point``)."""
    undamped = derivatives(sym, damped=False)
    d = derivatives(sym, damped=True) if damped else {
        **undamped, **{k: sp.Integer(0) for k in ("pa", "pb")},
        **{f"Gd[{i}]": sp.Integer(0) for i in range(6)},
        **{f"Hc[{i}, {j}]": sp.Integer(0) for i in range(6) for j in range(6)}}
    return [
        _scalar_function("point_g", ("x", "prm", "h", "G"), _select(undamped, ("ea", "eb", "G")),
                         ("ea", "eb"), sym, False),
        _scalar_function("point_gh", ("x", "prm", "h", "G", "H"),
                         _select(undamped, ("ea", "eb", "G", "H")), ("ea", "eb"), sym, False),
        _scalar_function("point_gd", ("x", "xd", "prm", "h", "G", "Gd"),
                         _select(d, ("ea", "eb", "pa", "pb", "G", "Gd")),
                         ("ea", "eb", "pa", "pb"), sym, True),
        _scalar_function("point_ghd", ("x", "xd", "prm", "h", "G", "H", "Gd", "Hc"),
                         _select(d, ("ea", "eb", "pa", "pb", "G", "H", "Gd", "Hc")),
                         ("ea", "eb", "pa", "pb"), sym, True),
    ], d


#: The decorator of a template's ``span``: called by the element loop alone, so without
#: numba's wrappers, which a call from compiled code does not use (the Python one boxes and
#: unboxes its nine arguments, tuples of arrays; the C one serves numba's first-class
#: functions, ``kernels.erased`` calls at the function's own address).  With ``POINT`` and
#: ``LOOP``, a law's functions compile in 4.4 s of CPU instead of 5.2 (Gauss rule; 8.3
#: instead of 9.3 at the assumed strain), with the same machine code.  A call from Python
#: would crash.
SPAN = "@njit(cache=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)"

#: The element loop (``kernels.chunks``) around the laws' ``span``: its ``kernel`` under
#: the names of the hooks and with their decorators, in one module for every law and
#: template (``loop``), which calls a law's ``span`` at its address (``hook``).  Numba
#: compiles each at its first call, so the threaded loop only where a system runs on
#: threads.  Called from Python (``contract.Term.evaluate``) and at their machine
#: addresses (``kernels.erased``), never through a C pointer: no C wrapper (why one module
#: for every law: ``kernels.chunks``).
LOOP = (("kernel", "@njit(cache=True, no_cfunc_wrapper=True)"),
        ("kernel_parallel", "@njit(cache=True, parallel=True, no_cfunc_wrapper=True)"))


#: The kinds of generated module of a law and the template each compiles: ``"gauss"``,
#: the law on a Gauss (or any) rule (``kernels.cable``; the paper's and the Lobatto
#: formulations), and ``"assumed-strain"``, the axial part at the assumed strain and the
#: bending part on a Gauss rule (``kernels.assumed_strain``).
TEMPLATES = {"gauss": template, "assumed-strain": assumed_strain}


def sizing(kind, orders):
    """The element type (its nodal fields ``orders``) that the module of ``kind`` is
    compiled for, when its template takes the element's sizes as constants
    (``constants``: ``kernels.assumed_strain``); None when one module serves every
    element (``kernels.cable`` reads them from the tables)."""
    return tuple(orders) if hasattr(TEMPLATES[kind], "constants") else None


#: The names of the point functions a points module holds (``points``).
POINTS = ("point_g", "point_gh", "point_gd", "point_ghd")


def _header(what):
    """The docstring and imports of a generated module (``what`` it holds)."""
    return [f'"""Generated by skfem_cable.laws.codegen: {what}.  Do not edit: regenerated '
            'when the law or the generator changes."""',
            "import math  # noqa: F401\n\nimport numpy  # noqa: F401\nimport numpy as np\n"
            "from numba import njit, prange"]


def points_source(law, damped):
    """The text of the points module of ``law`` (a law or a part of one, ``damped`` or
    not): its point functions (``POINTS``), ``numpy_point`` and ``numpy_gradient``."""
    points, d = _point_functions(law.symbolic, damped)
    return "\n\n\n".join([
        *_header(f"the point functions of the law {law.name!r} (parameters "
                 f"{', '.join(law.parameters) or 'none'}, damped {damped})"),
        f"SLOPE_FLOOR = {SLOPE_FLOOR!r}", *points, *_numpy_functions(d, law.symbolic)]) + "\n"


def points_name(law, damped):
    """Module name of the points module of ``law`` (``damped`` or not): its name and a
    digest of its expressions and the generator."""
    return _name(law, "_points" + ("_damped" if damped else ""),
                 law.key, "points", str(damped))


def points(law, damped):
    """Import (generating it first if needed) the points module of ``law``: one per
    expressions in a process, whichever modules call its functions (the law's Gauss
    module and, for a law's bending part, the assumed-strain modules of every element
    size), so that numba compiles each point function once, not once per caller."""
    return generated.load("laws", points_name(law, damped), lambda: points_source(law, damped),
                          description=f"the point functions of the law {law.name!r}")


def _shared(law, kind):
    """The expressions and damping of the points module that ``law``'s module of ``kind``
    calls: the law's own (``"gauss"``), or its bending part's (``"assumed-strain"``)."""
    return (law if kind == "gauss" else law.part(1)), law.damped


def source(law, kind="gauss", orders=None):
    """The text of the generated module of ``law`` of ``kind`` (``TEMPLATES``) for the
    element type of nodal fields ``orders`` (``sizing``): the point functions of the law
    (``"gauss"``) or of its bending part (``"assumed-strain"``), imported from their
    points module (``points``), the strain functions of the axial part
    (``"assumed-strain"``), the element type's constants and the template's ``span`` (the
    element loop is ``loop``'s)."""
    module = TEMPLATES[kind]
    names = (*POINTS, "numpy_point", "numpy_gradient") if kind == "gauss" else POINTS
    parts = [
        *_header(f"the law {law.name!r} (parameters {', '.join(law.parameters) or 'none'}), "
                 f"module kind {kind!r}"),
        f"from {points_name(*_shared(law, kind))} import {', '.join(names)}  # noqa: F401"
        + ("" if orders is None else f"\nfrom {module.__name__} import rule"),
        f"BENDING = {law.bending}\nDAMPED = {law.damped}\nSLOPE_FLOOR = {SLOPE_FLOOR!r}"
        + ("" if orders is None else "\n" + module.constants(orders)),
        f"PARAMETERS = {law.parameters!r}",
        *([] if kind == "gauss" else _strain_functions(law.strain)),
        SPAN + "\n" + inspect.getsource(module.span),
    ]
    return "\n\n\n".join(parts) + "\n"


def loop_source():
    """The text of the element loop's module (``loop``): ``kernels.chunks.kernel`` as each
    hook of ``LOOP``."""
    return "\n\n\n".join([
        *_header("the element loop of every law (kernels.chunks)"),
        "from skfem_cable.kernels.chunks import CHUNK  # noqa: F401\n"
        "from skfem_cable.kernels.erased import function  # noqa: F401",
        *(decorator + "\n" + inspect.getsource(chunks.kernel).replace("def kernel(", f"def {name}(")
          for name, decorator in LOOP)]) + "\n"


@functools.cache
def loop():
    """Import (generating it first if needed) the element loop's module: its hooks
    ``kernel`` and ``kernel_parallel`` serve every law, each calling the law's ``span`` at
    the address its pack ends with (``hook``)."""
    name = "skfem_cable_law_loop_" + generated.digest(GENERATOR, _generator_id(),
                                                      inspect.getsource(chunks))
    return generated.load("laws", name, loop_source,
                          namespace={"SPAN": numba.types.FunctionType(chunks.SPAN)},
                          description="the element loop of the laws")


def hook(module, threads):
    """``(function, span)``: the element loop's hook for ``threads`` (``kernel``, or
    ``kernel_parallel`` on more than one) and the address of the ``span`` of the law's
    ``module`` (``load``), compiled for ``chunks.SPAN``, that the pack of ``function``
    ends with (``bodies.cable_term``)."""
    functions = loop()
    function = functions.kernel_parallel if threads > 1 else functions.kernel
    return function, erased.address(module.span, chunks.SPAN)


@functools.cache
def _generator_id():
    """The text of this module, which writes the generated modules (their digests hold
    it: the generated text itself is known only after the law's derivatives, which the
    cache is there to skip)."""
    return inspect.getsource(sys.modules[__name__])


def _name(law, suffix, *parts):
    """``skfem_cable_law_<law's name><suffix>_<digest>``: a digest of ``parts``, the
    generator (its version and text) and sympy's version."""
    digest = generated.digest(*parts, GENERATOR, _generator_id(), sp.__version__)
    safe = re.sub(r"\W", "_", law.name)[:40]
    return f"skfem_cable_law_{safe}{suffix}_{digest}"


def module_name(law, kind="gauss", orders=None):
    """Module name of ``law`` of ``kind`` for the element type of nodal fields ``orders``
    (``sizing``): its name and a digest of its expressions, the template, the element type
    and the generator (its version and text)."""
    suffix = "" if kind == "gauss" else "_" + re.sub(r"\W", "_", kind)
    suffix += "" if orders is None else f"_{2 * len(orders)}"
    return _name(law, suffix, law.key, kind, inspect.getsource(TEMPLATES[kind]),
                 inspect.getsource(chunks), repr(law.parameters), repr(orders))


def load(law, kind="gauss", orders=None):
    """Import (generating it first if needed) the module of ``law`` of ``kind`` for the
    element type of nodal fields ``orders`` (``sizing``), after the points module it
    imports (``points``)."""
    points(*_shared(law, kind))
    return generated.load("laws", module_name(law, kind, orders),
                          lambda: source(law, kind, orders),
                          description=f"the kernel of the law {law.name!r} ({kind}"
                          + ("" if orders is None else f", {2 * len(orders)} functions")
                          + ")")
