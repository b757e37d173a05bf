"""The Newton step of the generalized-alpha integrator, written once and compiled once.

Two kinds of module are generated, written to the cache of ``kernels.generated`` and
compiled once per machine:

* **The Newton step** (``module``, one): ``newton``, the template ``kernels.step``,
  predicts, evaluates, assembles into the fixed pattern, factors, solves, updates and
  tests convergence in one compiled call, for every system and every linear solver (the
  solver's functions at their addresses, ``solvers.step_lu``, which generates a small
  module per solver).
* **A system's terms** (``system_module``, per sequence of the *slots'* types,
  ``solvers.slots``): ``evaluate`` calls the terms' compiled ``kernels``
  (``contract.Term``) in order, ``constrain`` the nonlinear constraints' ``kernel`` (the
  rigid body's, ``kernels.rigid``; linear constraints, pins to fixed or moving points,
  body points and joints of natural coordinates, are a sparse product in the template, a
  moving point's offset evaluated once per step), each kernel at its machine address,
  held with the packs (its code is not linked in: LLVM would optimise it again in every
  system's module).  Both have one signature for all systems (``EVALUATE``,
  ``CONSTRAIN``) and read the terms' data from an address (``kernels.erased``); the step
  calls them through their machine addresses.  A new system compiles this small module
  alone (a few tenths of a second, against about 10 s for a step module of its own,
  ``benchmarks/compile_cost.py``).

What is Python in a system takes part from inside the compiled call through
``numba.objmode`` blocks, emitted only where the system has such parts
(``PythonParts``): a term with a Python ``add`` hook (called once per evaluation, on an
``Evaluation`` that views the step's arrays), a nonlinear constraint without kernel
(``Layout.python_constraint``), and the sparse LU of an iteration matrix that no band
solver takes (``linalg.PatternSolver``); a fully compiled system's modules have none.

``GeneralizedAlpha(compiled=False)`` runs the same generated modules interpreted
(``numba.config.DISABLE_JIT`` while they are imported; the kernels they call stay
compiled): the debugging mode, with the compiled run's iterates.
``GeneralizedAlpha.step_path`` says which run is used and which parts are Python.
"""

import functools
import inspect
import itertools
import warnings
import weakref

import numba
import numpy as np
from numba.core.compiler_lock import global_compiler_lock
from numba.core.errors import NumbaExperimentalFeatureWarning

from ..core.contract import Evaluation
from ..core.linalg import SingularMatrixError
from ..core.protocols import IntegrableSystem
from ..kernels import books, callbacks, erased, generated, woodbury
from ..kernels import step as template
from . import slots, step_lu
from .slots import PYTHON

#: Bump when the generated code changes meaning (part of every module's digest).
GENERATOR = "20"

_TEMPLATE_FUNCTIONS = ("newton_held", "newton", "_finish", "_iterate", "_residual",
                       "_dynamic_rows", "_dynamic_row", "_constraints", "_factor", "error_factor",
                       "pseudo_acceleration", "forces_written", "first_error_factor")


def python_parts(system: IntegrableSystem, solver):
    """What of ``system`` is Python in its step with ``solver`` (a list of reasons,
    empty for a fully compiled system)."""
    lay = system.layout
    parts = [f"term {term.name!r} has a Python add hook"
             for term, _ in lay.body_terms + lay.load_terms if term.add is not None]
    parts += [f"constraint {c.name!r} is nonlinear and has no compiled kernel"
              for c in system.constraints if not c.linear and getattr(c, "kernel", None) is None]
    if solver.method != "banded":
        parts.append(f"the iteration matrix has band half-width {solver.band}, wider than "
                     "the banded solver's limit: sparse LU")
    return parts


def _calls(prefix, slots, ev, python):
    """The lines calling ``slots`` in order: the compiled function at the address
    ``references[k]``, of the function type ``{prefix}{k}``, or the objmode call ``python``
    (formatted with the slot ``k``) for a ``PYTHON`` slot."""
    return ["    " + python.format(k=k) if f is PYTHON
            else f"    function(references[{k}], {prefix}{k})(packs[{k}], indices[{k}], {ev})"
            for k, f in enumerate(slots)] or ["    pass"]


def _names(prefix, slots):
    return "".join("_, " if f is PYTHON else f"{prefix}{k}, " for k, f in enumerate(slots))


#: The decorator of the generated functions inlined into their one caller by numba (the
#: terms module's ``evaluate_slots`` and ``constrain_slots``; the step's functions called
#: once, and its scalar helpers): a function compiled apart is also optimised by LLVM
#: alone, before numba links its code into its callers'.
_INLINED = '@njit(cache=True, inline="always")'

#: The decorator of the step's entry ``newton_held``: no C wrapper (numba's
#: first-class-function entry, which the step never uses; 750 of the 23,000 lines of LLVM
#: IR of the pendulum's step).
_ENTRY = f"@njit(cache=True, no_cfunc_wrapper=True{step_lu.COUNTLESS})"

#: The decorator of the step's functions with more than one caller (``_residual`` has two,
#: ``_constraints`` three): typed and lowered once by numba, which does it again at every
#: call of an ``inline="always"`` function (its inlining pass took a third of the step's
#: compilation), and inlined by LLVM into each caller (``forceinline``: the step's machine
#: code is that of the inlined functions).
_SHARED = f"@njit(cache=True, no_cfunc_wrapper=True, forceinline=True{step_lu.COUNTLESS})"

#: The decorators of the template's functions other than ``_INLINED`` (all of the step
#: without numba's reference counts, ``step_lu.COUNTLESS``).
_DECORATORS = {"newton_held": _ENTRY, "_residual": _SHARED, "_constraints": _SHARED}


#: The objmode calls (``kernels.callbacks``) a terms module needs for Python terms and
#: Python constraints.
_TERM_CALLS, _CONSTRAINT_CALLS = ("python_term",), ("python_constraint",)

_VECTOR = numba.types.float64[::1]

#: The signatures of a system's ``evaluate(blob, ev)`` and ``constrain(blob, cev)``, the
#: same for every system (``kernels.step._residual``: ``ev = (q1, v1, s, f, f_ext, fd,
#: data, energy, power)``, ``cev = (q1, lam1, cs, r_c, f_con, data)``), so that the step
#: takes them as numba first-class functions and is compiled once for all systems.
EVALUATE = numba.types.void(numba.types.int64, numba.types.UniTuple(_VECTOR, 9))
CONSTRAIN = numba.types.void(numba.types.int64, numba.types.UniTuple(_VECTOR, 6))

#: The functions of a system's module around its slots: its two entries of one signature,
#: reading the terms' data at the address ``blob`` (``kernels.erased``: ``(packs, indices,
#: references, cpacks, cindices, creferences)``, the slots' packs, tangent positions and
#: kernels' addresses, put there by ``kernels.erased.keep``), called at their addresses
#: alone (neither a C nor a Python wrapper); ``{counts}``: without numba's reference counts
#: where no slot is Python (``step_lu.COUNTLESS``; the objmode calls need them).
_SYSTEM_ENTRIES = '''# EVALUATE, CONSTRAIN, TERMS: injected by the loader
@njit(EVALUATE, cache=True, no_cfunc_wrapper=True, no_cpython_wrapper=True{counts})  # noqa: F821
def evaluate(blob, ev):
    terms = held(blob, TERMS)  # noqa: F821
    evaluate_slots(terms[0], terms[1], terms[2], ev)


@njit(CONSTRAIN, cache=True, no_cfunc_wrapper=True, no_cpython_wrapper=True{counts})  # noqa: F821
def constrain(blob, cev):
    terms = held(blob, TERMS)  # noqa: F821
    constrain_slots(terms[3], terms[4], terms[5], cev)
'''


def system_source(kernels, constraint_kernels):
    """Text of the generated module of a system's slots ``kernels`` (the function types
    ``k0 ...`` of its term kernels, taken from the injected tuple ``KERNELS``, or
    ``PYTHON``) and ``constraint_kernels`` (``c0 ...``, from ``CONSTRAINT_KERNELS``): its
    ``evaluate`` and ``constrain`` (``EVALUATE``, ``CONSTRAIN``), which call them in order,
    at the addresses held with the terms of the injected type ``TERMS``."""
    calls = ((_TERM_CALLS if PYTHON in kernels else ())
             + (_CONSTRAINT_CALLS if PYTHON in constraint_kernels else ()))
    imports = (("import numpy as np\n" if calls else "")
               + "from numba import njit" + (", objmode" if calls else "")
               + "\n\nfrom skfem_cable.kernels.erased import function, held\n"
               + ("from skfem_cable.solvers.compiled import python_part\n" if calls else ""))
    parts = [
        '"""Generated by skfem_cable.solvers.compiled: the terms of one sequence of kernels, '
        'for the compiled Newton step.  Do not edit."""',
        imports,
        f"({_names('k', kernels)}) = KERNELS  # noqa: F821 (placed by the loader)"
        if kernels else "",
        f"({_names('c', constraint_kernels)}) = CONSTRAINT_KERNELS  # noqa: F821"
        if constraint_kernels else "",
        # a Python slot's number as an int64: numba compiles a callee once per literal int
        # argument (a module's callback was compiled once per Python slot)
        f"{_INLINED}\ndef evaluate_slots(packs, indices, references, ev):\n"
        + "\n".join(_calls("k", kernels, "ev",
                            "python_term(packs[{k}], np.int64({k}), ev[6].size > 0)")),
        f"{_INLINED}\ndef constrain_slots(packs, indices, references, cev):\n"
        + "\n".join(_calls("c", constraint_kernels, "cev",
                            "python_constraint(packs[{k}], np.int64({k}), cev[3], "
                            "cev[5].size > 0)")),
    ]
    parts += callbacks.source(calls) + [_SYSTEM_ENTRIES.format(
        counts="" if calls else step_lu.COUNTLESS)]
    return "\n\n\n".join(p for p in parts if p)


def source():
    """Text of the generated module of the Newton step (``kernels.step``), its linear
    solver behind an address (``solvers.step_lu``)."""
    parts = [
        '"""Generated by skfem_cable.solvers.compiled: the compiled Newton step.  Do not '
        'edit."""',
        "import numpy as np\nfrom numba import njit\n\n"
        "from skfem_cable.kernels.books import correct_elastic, csr_product, "
        "mass_row3, step_books\nfrom skfem_cable.kernels.erased import function, held",
        f"CONVERGED, NON_FINITE, NO_CONVERGENCE, SINGULAR = {template.CONVERGED}, "
        f"{template.NON_FINITE}, {template.NO_CONVERGENCE}, {template.SINGULAR}\n"
        f"ETA_FIRST = {template.ETA_FIRST!r}\n"
        f"{', '.join(template.PRM_SLOTS)} = range({len(template.PRM_SLOTS)})",
        step_lu.STEP_SOURCE,
    ]
    parts += [_DECORATORS.get(name, _INLINED) + "\n"
              + inspect.getsource(getattr(template, name)) for name in _TEMPLATE_FUNCTIONS]
    return "\n\n\n".join(parts) + "\n"


#: Modules whose compiled functions the generated modules call (linked into them): numba's
#: cache of a module does not notice changes in the functions it calls, so their text is
#: part of the digest.  Not the linear solvers', called at their addresses (``step_lu``).
_CALLED_MODULES = (books, callbacks, erased)


@functools.cache
def _template_id():
    return "".join([inspect.getsource(getattr(template, f)) for f in _TEMPLATE_FUNCTIONS]
                   + [inspect.getsource(m) for m in _CALLED_MODULES])


@functools.cache
def module(jit=True):
    """The generated module of the Newton step (``source``; imported, generated and
    compiled when first needed, then remembered); ``jit=False``: the same module
    interpreted."""
    text = source()
    name = "skfem_cable_step_" + generated.digest(GENERATOR, numba.__version__,
                                                  _template_id(), text)
    return generated.load("steps", name, lambda: text,
                          {"EVALUATE": numba.types.FunctionType(EVALUATE),
                           "CONSTRAIN": numba.types.FunctionType(CONSTRAIN),
                           "AT_FACTOR": numba.types.FunctionType(step_lu.AT_FACTOR),
                           "AT_SOLVE": numba.types.FunctionType(step_lu.AT_SOLVE)},
                          "the Newton step", jit=jit)


@functools.cache
def system_module(kernels, constraint_kernels, kind, jit=True):
    """The generated module of the term and constraint slots (tuples of the kernels' numba
    ``FunctionType``s, or ``PYTHON``) on terms of the numba type ``kind`` (imported,
    generated and compiled when first needed, then remembered); ``jit=False``: the same
    module interpreted.  The kernels are called at their addresses, not linked: the module
    depends on their types alone, and systems whose slots have the same types share it."""
    text = system_source(kernels, constraint_kernels)
    name = "skfem_cable_terms_" + generated.digest(
        GENERATOR, numba.__version__, _template_id(), text, str(kind), repr(kind),
        *map(str, kernels), "constraints", *map(str, constraint_kernels))
    return generated.load("steps", name, lambda: text,
                          {"KERNELS": kernels, "CONSTRAINT_KERNELS": constraint_kernels,
                           "TERMS": kind, "EVALUATE": EVALUATE, "CONSTRAIN": CONSTRAIN},
                          f"the terms of {len(kernels)} term and {len(constraint_kernels)} "
                          "constraint kernels", jit=jit)


_PARTS = {}
_KEYS = itertools.count()


def python_part(key):
    """The ``PythonParts`` registered under ``key`` (the generated modules' objmode calls
    find them so: a number passes through compiled code, a Python object does not)."""
    return _PARTS[key]


class PythonParts:
    """The Python parts of one integrator's compiled step, called back from it: terms with
    an ``add`` hook, on an ``Evaluation`` that views the step's arrays; nonlinear
    constraints without kernel; the sparse LU (``linalg.PatternSolver``).

    Parameters
    ----------
    integrator : GeneralizedAlpha
    arrays : dict
        ``CompiledNewton.arrays``, the step's arrays.
    terms, constraints : dict
        The Python terms ``slot -> (term, index)`` and constraints ``slot -> k`` (the
        constraint's position in the system).
    """

    def __init__(self, integrator, arrays, terms, constraints):
        self.lay, self.solver = integrator.lay, integrator.solver
        self.arrays, self.terms, self.constraints = arrays, terms, constraints
        ev = Evaluation(integrator.system, 0.0, arrays["q1"], arrays["v1"], arrays["lam1"],
                        a=arrays["a1"], cM=1.0)
        ev.f, ev.f_ext, ev.f_damping = arrays["f"], arrays["f_ext"], arrays["fd"]
        ev.energy, ev.power = arrays["energy"], arrays["power"]
        self.ev = ev

    def term(self, slot, tangent):
        """Evaluate the term of ``slot`` at the step's iterate (``s = [t1, cK, cC, 1]``)."""
        ev, s = self.ev, self.arrays["s"]
        ev.t, ev.cK, ev.cC = float(s[0]), float(s[1]), float(s[2])
        ev.data = self.arrays["data"] if tangent else None
        term, index = self.terms[slot]
        term.add(ev, index)

    def constraint(self, slot, r_c, tangent):
        """Evaluate the constraint of ``slot`` into the rows ``r_c`` and the step's
        ``f_con`` (``cs = [t1, cK, scale]``)."""
        a, cs = self.arrays, self.arrays["cs"]
        self.lay.python_constraint(self.constraints[slot], a["q1"], float(cs[0]), a["lam1"],
                                   a["f_con"], r_c, cs[2], a["data"] if tangent else None,
                                   cs[1])

    def factor(self, data):
        """Factor ``data``; the unknown of a zero pivot (-2: not located), or -1."""
        try:
            self.solver.factor(data)
        except SingularMatrixError as exc:
            return exc.index if exc.index >= 0 else -2
        return -1

    def solve(self, rhs, dx):
        dx[:] = self.solver.solve(rhs)


def entry_point(function, args):
    """The machine code of the compiled ``function`` (a numba dispatcher) for the types of
    ``args`` (compiled for them, or read from the cache, first), behind the unboxing of
    its arguments alone; ``function`` itself if it is Python (the interpreted step).  A
    dispatcher types every argument at every call (the Newton step's: 7 us of the E-sail
    rig's 130 us per step; 3 saved).  The caller keeps the types of ``args`` (the
    ``CompiledNewton``'s and its integrator's arrays, float64 and contiguous)."""
    if getattr(function, "overloads", None) is None:
        return function
    signature = tuple(function.typeof_pyval(a) for a in args)
    with warnings.catch_warnings():  # first-class functions are "experimental" in numba
        warnings.simplefilter("ignore", NumbaExperimentalFeatureWarning)
        return erased.entry(function, signature)


def _inner(kernels, inner):
    """The numba type of the storage ``inner`` of the banded LU ``kernels`` (or the
    sparse LU's) and the addresses of its functions (``step_lu.functions``)."""
    kind = numba.typeof(inner)
    return kind, step_lu.functions(kernels, kind)


def _give_back(blob, address, kind):
    """Give back what ``blob`` holds at ``address`` (``kernels.erased.drop``; the buffer
    kept alive until now by this call's reference)."""
    erased.drop(address, kind)


def _hold(kind, value):
    """A buffer holding ``value`` (of numba type ``kind``) for the compiled functions
    (``kernels.erased.keep``); returns the buffer and its address."""
    blob = np.zeros(max(erased.size_of(kind), 8), dtype=np.uint8)
    address = blob.ctypes.data
    erased.keep(address, value, kind)
    return blob, np.int64(address)


class CompiledNewton:
    """The Newton iteration of a ``GeneralizedAlpha`` integrator: the generated module of
    its slots, compiled (``jit``) or interpreted, and the arrays it works in (a factor made
    here serves ``GeneralizedAlpha._factor`` and the reverse)."""

    def __init__(self, integrator, jit=True):
        g = integrator
        lay, n, N = g.lay, g.n, g.lay.N
        key = next(_KEYS)
        (functions, packs, indices), python_terms = slots.term_slots(lay, key)
        (cfunctions, cpacks, cindices), python_constraints = slots.constraint_slots(
            g.system, lay, key)
        sparse = g.solver.method != "banded"
        step = self.step = module(jit)
        self.newton = step.newton_held
        self.entry = None  # entry_point, at the first call
        with global_compiler_lock:  # what it compiles, said on one line (compile_log)
            kind, references, creferences, entries = lay.derived(  # once per layout
                ("terms", jit), lambda: self._terms_module(
                    (functions, packs, indices), (cfunctions, cpacks, cindices), jit))
            self.blob, address = _hold(kind, (packs, indices, references, cpacks, cindices,
                                              creferences))
        weakref.finalize(self, _give_back, self.blob, address, kind).atexit = False
        self.terms = (*entries, address)
        self.prepare = [term.prepare for term, _ in lay.body_terms + lay.load_terms
                        if term.kernels and term.prepare is not None]
        C = lay.C_lin
        lin = (C.indptr, C.indices, C.data) if C is not None else (
            np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0))
        self.lin_rows = np.ascontiguousarray(lay.lin_rows, dtype=np.int64)
        # the linear constraints' offsets: refreshed at every step where a point moves
        # (``iterate``), else set once
        self.c_t = np.zeros(self.lin_rows.size)
        self.driven = bool(lay.driven)
        if self.lin_rows.size:
            self.c_t[:] = lay.linear_offsets(0.0)
        self.model = (lay.mass.strided, g.base, lay.f_const,
                      np.ascontiguousarray(g.diag_index, dtype=np.int64), g.xscale,
                      g.inv_xscale, *lin, self.lin_rows, self.c_t, lay.constrained)
        self.lu_blob, self.lu = self._solver(g, sparse, key, jit)
        self.history = np.zeros(g.max_iter + 1)
        names = ("q1", "v1", "a1", "lam1", "r", "data", "nodata", "f", "f_ext", "fd",
                 "f_con", "energy", "power", "res_weight", "history", "fq", "fv", "flam",
                 "dx", "rhs", "s", "cs", "abar1", "books")
        sizes = {"q1": n, "v1": n, "a1": n, "f": n, "f_ext": n, "fd": n, "f_con": n,
                 "fq": n, "fv": n, "lam1": lay.n_c, "flam": lay.n_c, "r": N, "dx": N,
                 "rhs": N, "data": lay.nnz, "nodata": 0, "energy": 2, "power": 2, "s": 4,
                 "cs": 3, "abar1": n, "books": 4}
        self.arrays = {k: np.zeros(sizes[k]) for k in sizes}
        self.no_change = np.zeros(n)  # da_prev before there is one (its factor c0 is 0)
        self.arrays.update(res_weight=g.res_weight, history=self.history)
        self.out = tuple(self.arrays[k] for k in names)
        self.typed = ("arguments", jit)
        held = (self.model, self.lu, self.out)  # the run's own, held once (step.newton_held)
        self.kind = lay.derived(self.typed, lambda: numba.typeof(held))  # once per layout
        self.held, self.address = _hold(self.kind, held)
        weakref.finalize(self, _give_back, self.held, self.address, self.kind).atexit = False
        if python_terms or python_constraints or sparse:
            _PARTS[key] = PythonParts(g, self.arrays, python_terms, python_constraints)
            weakref.finalize(self, _PARTS.pop, key, None)
        prm = self.prm = np.zeros(len(template.PRM_SLOTS))
        prm[template.ALPHA_M], prm[template.ALPHA_F] = g.alpha_m, g.alpha_f
        prm[template.GAMMA], prm[template.BETA] = g.gamma, g.beta
        prm[template.MBAR], prm[template.TOL] = g.mbar, g.tol
        prm[template.CON_WEIGHT], prm[template.MAX_ITER] = g.con_weight, g.max_iter
        prm[template.TOL_LOCAL], prm[template.ERROR_CONSTANT] = g.tol_local or 0.0, \
            g.error_constant
        prm[template.DAMPING], prm[template.EXTERNAL] = (k in lay.writes
                                                         for k in ("f_damping", "f_ext"))

    @staticmethod
    def _terms_module(terms, constraints, jit):
        """The numba type of the tuple the terms module of the slots ``terms = (functions,
        packs, indices)`` and ``constraints`` reads (``system_module``), the addresses of
        the slots' kernels and those of the module's ``evaluate`` and ``constrain``."""
        (functions, packs, indices), (cfunctions, cpacks, cindices) = terms, constraints
        types = numba.typeof((packs, indices, cpacks, cindices))
        (kinds, ckinds), (references, creferences) = slots.addressed(
            (functions, EVALUATE.args[1]), (cfunctions, CONSTRAIN.args[1]), types)
        kind = numba.typeof((packs, indices, references, cpacks, cindices, creferences))
        own = system_module(kinds, ckinds, kind, jit)
        return kind, references, creferences, (erased.address(own.evaluate, EVALUATE),
                                               erased.address(own.constrain, CONSTRAIN))

    def _solver(self, g, sparse, key, jit):
        """The held storage of the step's linear solver (``solvers.step_lu``, corrected if a
        term asks, ``kernels.woodbury``) and the step's ``lu``: the addresses of the
        solver's ``factor`` and ``solve`` and of the storage."""
        lay = g.lay
        corrections = [term.correction for term, _ in lay.body_terms + lay.load_terms
                       if term.correction is not None]
        if len(corrections) > 1:
            raise ValueError(f"{len(corrections)} terms with a correction of the tangent "
                             "(tangent='woodbury'): the step takes one")
        kernels = None if sparse else g.solver.kernels.__name__.rsplit(".", 1)[-1]
        inner = np.array([key]) if sparse else g.solver.lu
        typed = ("LU", kernels, g.solver.threads, bool(corrections))
        inner_kind, functions = lay.derived((*typed, "inner"), lambda: _inner(kernels, inner))
        self.lu_storage = step_lu.storage(inner, functions, (
            woodbury.storage(corrections[0], lay.N) if corrections else None))
        kind = lay.derived(typed, lambda: numba.typeof(self.lu_storage))
        solver, entries = lay.derived((*typed, "module", jit), lambda: self._lu_module(
            kernels, bool(corrections), inner_kind, kind, jit))
        self._refresh = solver.refresh if corrections else None
        blob, address = _hold(kind, self.lu_storage)
        weakref.finalize(self, _give_back, blob, address, kind).atexit = False
        return blob, (*entries, address)

    @staticmethod
    def _lu_module(kernels, corrected, inner, kind, jit):
        """The module of the step's linear solver (``step_lu.module``) and the addresses
        of its ``factor`` and ``solve``."""
        solver = step_lu.module(kernels, corrected, inner, kind, jit)
        return solver, (erased.address(solver.factor, step_lu.AT_FACTOR),
                        erased.address(solver.solve, step_lu.AT_SOLVE))

    def refresh(self):
        """Correct a factor the step did not make (``GeneralizedAlpha._factor``: a resumed
        run's first) as the step would have (``kernels.woodbury.refresh``), if a term asks."""
        if self._refresh is not None and self._refresh(self.lu_storage) != -1:
            raise SingularMatrixError("singular capacitance of the tangent's correction "
                                      "(tangent='woodbury')", -2)

    def __reduce__(self):
        """Refused: the step holds machine addresses and references of this process (its
        terms behind ``blob``); a copy would read them after the original gave them
        back."""
        raise TypeError("a compiled Newton step cannot be copied or pickled: it holds "
                        "addresses of this process; build a GeneralizedAlpha of the system "
                        "instead")

    def iterate(self, g, h, t1, need, full):
        """Run the Newton iteration of the step ``t_n -> t1 = t_n + h`` of the integrator
        ``g`` (from a fresh tangent if ``need``, in full Newton if ``full``); returns
        ``(status, iterations, factorizations, corrections, singular)`` (the step's
        contraction estimate in ``prm[RATE]``)."""
        lay = g.lay
        for prepare in self.prepare:
            prepare(t1)
        if self.driven:
            self.c_t[:] = lay.linear_offsets(t1)
        prm = self.prm
        prm[template.T1], prm[template.H] = t1, h
        prm[template.BETA_P], prm[template.GAMMA_P] = g._coefficients(h)
        prm[template.NEED], prm[template.RATE] = need, g.newton_rate
        prm[template.FULL] = full
        prm[template.C1], prm[template.C0] = g.predictor(h)
        a_prev = g.a if g.a_prev is None else g.a_prev
        da_prev = self.no_change if g.da_prev is None else g.da_prev
        state = (g.q, g.v, g.a, g.abar, g.lam, a_prev, da_prev, g.fd, g.fnc, g.fcon)
        args = (self.terms, self.address, self.kind, state, self.prm)
        if self.entry is None:  # one per layout and kind of step
            self.entry = lay.derived((*self.typed, "entry"), lambda: entry_point(self.newton, args))
        return self.entry(*args)
