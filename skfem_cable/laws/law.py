"""``CableLaw``: a cable element's physics as an energy density and a dissipation density.

A law is written as a function of ``a = r_x``, ``b = r_xx`` and named parameters that
returns the energy per unit reference length ``W`` (and optionally a second function of
``a, b`` and their rates ``ad, bd`` returning the dissipation density ``D``).  Calling
them once with symbols gives two expressions; everything else is derived:

* the element force density ``G = W_x + D_xd`` (``x = (a, b)``, ``xd`` its rate), the
  stiffness density ``H = W_xx + D_xd,x`` and the damping density ``D_xd,xd``, exactly
  (``sympy``), printed as a compiled kernel (``laws.codegen``) and as vectorised numpy for
  the scikit-fem forms (``forms``);
* the split of the energy (and of the dissipated power ``D_xd . xd``) into an axial part,
  the terms of ``W`` (``D``) that do not involve ``b``, and a bending part, the others;
* the axial part written in the Green strain ``e = (|a|^2 - 1)/2`` and its rate
  ``ed = a . ad`` (``CableLaw.strain``), which the assumed-strain cable interpolates.

Parameters are looked up by name: the law's own values (``with_parameters`` or the
function's defaults) first, then the attributes of the cable's ``Section`` (``EA``,
``EI``, ``gamma_axial``, ...).  ``h``, the element length, is supplied per element.
"""

import copy
import functools
import hashlib
import inspect
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from .symbolic import SLOPE_FLOOR, floored, power

#: Parameter names the framework supplies per element instead of the section.
ELEMENT_PARAMETERS = ("h",)


#: Green strain and its rate as symbols of ``CableLaw.strain`` (named apart from any
#: parameter a law may declare).
STRAIN_SYMBOLS = ("eps_", "epsdot_")


@dataclass(frozen=True)
class Symbolic:
    """The expressions of a law: symbols ``x`` (6: ``a, b``), ``xd`` (6: rates),
    ``params`` (by name) and ``h``; the energy density's axial and bending parts
    ``W = (W_axial, W_bending)`` and the dissipation density's ``D`` likewise."""

    x: tuple
    xd: tuple
    params: dict
    h: sp.Symbol
    W: tuple
    D: tuple

    @functools.cached_property
    def bending(self):
        """True if an expression involves ``b = r_xx`` (``CableLaw.bending``; once per
        expressions: sympy walks them for their symbols at every ``free_symbols``)."""
        return any(e.free_symbols & set(self.x[3:]) for e in (*self.W, *self.D))


@dataclass(frozen=True)
class Strain:
    """The axial part of a law in the Green strain: symbols ``e`` and ``ed`` (its rate),
    ``params`` and ``h`` as in ``Symbolic``; the energy density ``W(e)`` and the
    dissipation density ``D(e, ed)`` per unit reference length."""

    e: sp.Symbol
    ed: sp.Symbol
    params: dict
    h: sp.Symbol
    W: sp.Expr
    D: sp.Expr


def _signature(fn, fields, what):
    """The parameter names of ``fn`` after its ``fields`` field arguments, and the defaults."""
    sig = inspect.signature(fn)
    names = list(sig.parameters)
    if len(names) < fields or any(
            p.kind not in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
            for p in sig.parameters.values()):
        raise TypeError(f"{what} {fn.__name__!r} must take {fields} field arguments "
                        f"({'a, b, ad, bd' if fields == 4 else 'a, b'}) and then named "
                        f"parameters, got ({', '.join(names)})")
    params = names[fields:]
    defaults = {k: sig.parameters[k].default for k in params
                if sig.parameters[k].default is not inspect.Parameter.empty}
    return params, defaults


def _powers(expr, fields):
    """``expr`` with every power whose exponent involves parameters (not the ``fields``)
    written as ``symbolic.power``, whose derivative has no division by the base."""
    return expr.replace(
        lambda e: e.is_Pow and bool(e.exp.free_symbols) and not e.exp.free_symbols & fields,
        lambda e: power(e.base, e.exp))


def _number(expr, point):
    """The value of ``expr`` at ``point`` (symbol -> number), its ``floored`` and
    ``power`` evaluated as what they stand for (numbers put for the symbols by
    ``xreplace``, a tenth of ``subs``'s time and more: no pattern matching)."""
    plain = expr.replace(floored, lambda p: sp.Max(p, SLOPE_FLOOR)).replace(
        power, lambda base, exponent: base**exponent)
    return float(plain.xreplace({k: sp.Float(v) for k, v in point.items()}))


def _split(expr, b_symbols):
    """``(axial, bending)``: the terms of ``expr`` without and with the symbols of ``b``."""
    axial = [t for t in sp.Add.make_args(expr) if not t.free_symbols & b_symbols]
    return sp.Add(*axial), expr - sp.Add(*axial)


class CableLaw:
    """The element law of an ANCF cable: energy density ``W(a, b, params)`` and optional
    dissipation density ``D(a, b, ad, bd, params)`` per unit reference length.

    Use the decorator ``cable_law``; pass the law to ``Cable(..., law=...)``.

    Parameters
    ----------
    energy : callable
        ``energy(a, b, *params) -> expression`` built with ``skfem_cable.laws``.
    dissipation : callable, optional
        ``dissipation(a, b, ad, bd, *params) -> expression``, >= 0 (Rayleigh's
        dissipation function: the damping force is ``D_xd``).
    name : str, optional
        Default: the energy function's name.
    values : dict, optional
        Parameter values that take precedence over the section's attributes.
    """

    def __init__(self, energy, dissipation=None, name=None, values=None):
        self.energy = energy
        self.dissipation = dissipation
        self.name = name or energy.__name__
        names, defaults = _signature(energy, 2, "energy density")
        if dissipation is not None:
            more, more_defaults = _signature(dissipation, 4, "dissipation density")
            names += [k for k in more if k not in names]
            defaults = {**more_defaults, **defaults}
        unknown = set(values or {}) - set(names)
        if unknown:
            raise ValueError(f"law {self.name!r} has no parameter {sorted(unknown)[0]!r}; "
                             f"its parameters are {names}")
        self.parameters = tuple(k for k in names if k not in ELEMENT_PARAMETERS)
        self.values = {**defaults, **(values or {})}
        self._symbolic = None
        self._compiled = {}
        self._key = None
        self._dissipates = {}
        self._parts = {}
        self._strain = None

    def __repr__(self):
        return f"CableLaw({self.name!r})"

    # --- variants -----------------------------------------------------------------------
    def with_dissipation(self, dissipation):
        """The same energy with the dissipation density ``dissipation``."""
        return CableLaw(self.energy, dissipation, self.name, self.values)

    def with_parameters(self, **values):
        """The same law with some parameters given (they then ignore the section): numbers,
        or callables of time ``f(t)`` (a stiffness that softens, a damping switched on),
        which a time integration refreshes once per step (at the step's end time) and
        whose change of the stored energy it books as external work (``varying``).  A
        run store's fingerprint sees a callable's code, its default arguments, what it
        closes over and the numbers it reads from its module (``io.fingerprint``).

        Examples
        --------
        >>> from skfem_cable import laws
        >>> softening = laws.exudyn.with_parameters(EA=lambda t: 1e5 * max(0.02, 2 - t**0.5))
        >>> softening.varies
        ('EA',)
        """
        return CableLaw(self.energy, self.dissipation, self.name, {**self.values, **values})

    @property
    def varies(self):
        """The names of the parameters given as callables of time."""
        return tuple(k for k in self.parameters if callable(self.values.get(k)))

    def part(self, which):
        """The axial (``which = 0``) or bending (1) part of the law alone: the terms of
        ``W`` and ``D`` without (with) ``b``, to integrate with a rule of their own
        (locking-free cables).  A law without the other part is its own part (one
        compiled module, not two of the same expressions)."""
        if which not in self._parts:
            s = self.symbolic
            if s.W[1 - which] == 0 and s.D[1 - which] == 0:
                return self
            keep = [sp.Integer(0), sp.Integer(0)]
            W, D = list(keep), list(keep)
            W[which], D[which] = s.W[which], s.D[which]
            part = copy.copy(self)
            part.name = f"{self.name}-{('axial', 'bending')[which]}"
            part._symbolic = replace(s, W=tuple(W), D=tuple(D))
            part._compiled, part._key, part._dissipates, part._parts = {}, None, {}, {}
            part._strain = None
            self._parts[which] = part
        return self._parts[which]

    # --- expressions ----------------------------------------------------------------------
    @property
    def symbolic(self):
        """The law's ``Symbolic`` expressions (built once)."""
        if self._symbolic is None:
            self._symbolic = self._build()
        return self._symbolic

    def _build(self):
        x = sp.symbols("x0:6", real=True)
        xd = sp.symbols("xd0:6", real=True)
        h = sp.Symbol("h", positive=True)
        params = {k: sp.Symbol(k, real=True) for k in self.parameters}
        args = {**params, "h": h}
        a, b = sp.Matrix(x[:3]), sp.Matrix(x[3:])
        ad, bd = sp.Matrix(xd[:3]), sp.Matrix(xd[3:])
        W = self._scalar(self.energy, (a, b), args, "energy density")
        D = sp.Integer(0) if self.dissipation is None else self._scalar(
            self.dissipation, (a, b, ad, bd), args, "dissipation density")
        allowed = set(x) | set(xd) | set(args.values())
        for label, expr in (("energy", W), ("dissipation", D)):
            stray = expr.free_symbols - allowed
            if stray:
                raise ValueError(f"law {self.name!r}: the {label} density uses unknown "
                                 f"symbols {sorted(map(str, stray))}")
        if W.free_symbols & set(xd):
            raise ValueError(f"law {self.name!r}: the energy density may not depend on rates")
        W, D = _powers(W, set(x) | set(xd)), _powers(D, set(x) | set(xd))
        return Symbolic(x, xd, params, h, _split(W, set(x[3:])), _split(D, set(x[3:])))

    def _scalar(self, fn, fields, args, what):
        names = list(inspect.signature(fn).parameters)[len(fields):]
        expr = fn(*fields, **{k: args[k] for k in names})
        try:
            expr = sp.sympify(expr)
        except (sp.SympifyError, TypeError):
            raise TypeError(f"law {self.name!r}: the {what} must be a scalar expression, "
                            f"got {type(expr).__name__}") from None
        if not isinstance(expr, sp.Expr) or isinstance(expr, sp.MatrixBase):
            raise TypeError(f"law {self.name!r}: the {what} must be a scalar expression, "
                            f"got {type(expr).__name__}")
        return expr

    @property
    def strain(self):
        """The axial part of the law (its terms without ``b``) as a function of the Green
        strain ``e = (|a|^2 - 1)/2`` and its rate ``ed = a . ad`` (a ``Strain``), found by
        putting ``a = (sqrt(1 + 2 e), 0, 0)`` and ``ad = (ed / sqrt(1 + 2 e), 0, 0)``.

        That is the same law when the axial part depends on ``a`` and ``ad`` only through
        the stretch ``|a|`` and its rate, as the law of an isotropic section must (a
        rotated cable stores the same energy, and a rigid rotation dissipates nothing);
        ``check_strain`` verifies it.  The assumed-strain cable evaluates this form."""
        if self._strain is None:
            s = self.symbolic
            e, ed = sp.symbols(STRAIN_SYMBOLS, real=True)
            stretch = sp.sqrt(1 + 2 * e)
            subs = {**dict(zip(s.x[:3], (stretch, 0, 0))),
                    **dict(zip(s.xd[:3], (ed / stretch, 0, 0)))}
            self._strain = Strain(e, ed, s.params, s.h, s.W[0].subs(subs), s.D[0].subs(subs))
        return self._strain

    def check_strain(self, points=3, rtol=1e-9):
        """Verify that the axial part equals its ``strain`` form: at ``points`` random
        stretches, directions and rates of ``a`` (fixed seed), with random parameter
        values in [0.5, 2].

        Raises
        ------
        ValueError
            The axial part depends on the direction of ``a`` (or of its rate): it names
            the formulations that do not need the strain form.
        """
        s, strain = self.symbolic, self.strain
        rng = np.random.default_rng(7)
        for _ in range(points):
            a = rng.standard_normal(3)
            a *= (1.0 + 0.2 * rng.random()) / np.linalg.norm(a)
            ad = rng.standard_normal(3)
            values = {p: 0.5 + 1.5 * rng.random() for p in (*s.params.values(), s.h)}
            point = {**dict(zip(s.x[:3], a)), **dict(zip(s.xd[:3], ad)), **values,
                     strain.e: (a @ a - 1) / 2, strain.ed: a @ ad}
            for label, part, form in (("energy", s.W[0], strain.W),
                                      ("dissipation", s.D[0], strain.D)):
                got, want = _number(form, point), _number(part, point)
                if not abs(got - want) <= rtol * (abs(want) + abs(got)) + 1e-300:
                    raise ValueError(
                        f"law {self.name!r}: the axial part of its {label} density (the "
                        "terms without r_xx) is not a function of the stretch |r_x| and "
                        "its rate alone (it changes when r_x turns); the assumed-strain "
                        "formulation needs one: write it with green_strain(a), norm(a) "
                        "and dot(a, ad), or build the cable with formulation='paper' or "
                        "'lobatto'")

    @property
    def bending(self):
        """True if the law involves ``b = r_xx`` (then it needs the slopes' continuity)."""
        return self.symbolic.bending

    @property
    def vanishes(self):
        """True if the law has neither energy nor dissipation (e.g. the bending part of a
        truss)."""
        s = self.symbolic
        return all(e == 0 for e in (*s.W, *s.D))

    @property
    def damped(self):
        """True if the law has a dissipation density."""
        return self.symbolic.D != (0, 0)

    @property
    def key(self):
        """A digest of the law's expressions: equal for equal physics."""
        if self._key is None:
            s = self.symbolic
            text = sp.srepr((s.W, s.D, tuple(s.params)))
            self._key = hashlib.sha256(text.encode()).hexdigest()[:20]
        return self._key

    # --- values ---------------------------------------------------------------------------
    def parameter_values(self, section, t=0.0):
        """The parameters' values at time ``t`` (s), in the order of ``parameters``: the
        law's own (a callable evaluated at ``t``), else the ``section``'s attribute of the
        same name."""
        out = []
        for k in self.parameters:
            if k in self.values:
                value = self.values[k]
                if callable(value):
                    value = value(t)
            elif hasattr(section, k):
                value = getattr(section, k)
            else:
                raise ValueError(f"law {self.name!r}: parameter {k!r} is neither a Section "
                                 f"attribute nor has a value; give it with "
                                 f"{self.name}.with_parameters({k}=...)")
            try:
                value = float(value)
            except (TypeError, ValueError):
                value = np.nan
            if not np.isfinite(value):
                raise ValueError(f"law {self.name!r}: parameter {k} must be a finite "
                                 f"number, got {value} at t = {t}")
            out.append(value)
        return tuple(out)

    def values_at(self, section, t, ndim):
        """``parameter_values`` for fields of ``ndim`` dimensions at the times ``t``: a
        scalar ``t``, or an array of them leading the fields' shape (a result's rows), for
        which a parameter that varies in time is an array broadcasting against the
        fields (``t.shape`` then ones)."""
        if not self.varies or np.ndim(t) == 0:
            return self.parameter_values(section, float(np.ravel(t)[0]) if np.ndim(t) else t)
        t = np.asarray(t, dtype=float)
        rows = np.array([self.parameter_values(section, ti) for ti in t.ravel()])
        shape = t.shape + (1,) * (ndim - t.ndim)
        return tuple(column.reshape(shape) for column in rows.T)

    def dissipates(self, values):
        """False if the dissipation density vanishes for these parameter values (e.g. zero
        damping coefficients): the kernel then skips it.  Once per law and values, by
        ``xreplace`` (numbers for symbols: about 1 ms, where ``subs`` takes 40)."""
        if values not in self._dissipates:
            s = self.symbolic
            subs = {p: sp.Float(v) for p, v in zip(s.params.values(), values)}
            self._dissipates[values] = any(d.xreplace(subs) != 0 for d in s.D)
        return self._dissipates[values]

    def compiled(self, kind="gauss", orders=(0, 1)):
        """The generated module of this law of ``kind`` (``laws.codegen.TEMPLATES``) for
        the element type with the nodal fields ``orders`` (the kinds whose template is
        sized by the element; the others serve every element): its compiled ``kernel``
        and numpy functions; built once and cached on disk."""
        from .codegen import load, sizing

        key = (kind, sizing(kind, orders))
        if key not in self._compiled:
            self._compiled[key] = load(self, kind, key[1])
        return self._compiled[key]

    def hook(self, kind="gauss", orders=(0, 1), threads=1):
        """``(function, span)``: the compiled hook of the element loop for ``threads`` and
        the address of the ``span`` of this law's module (``compiled``) that the hook's
        pack ends with (``laws.codegen.hook``)."""
        from .codegen import hook

        return hook(self.compiled(kind, orders), threads)


def cable_law(energy=None, *, dissipation=None, name=None):
    """Decorator: an energy density function becomes a ``CableLaw``.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> from skfem_cable import laws
    >>> @sc.cable_law
    ... def biot(a, b, EA, EI):
    ...     e = laws.norm(a) - 1
    ...     return EA * e**2 / 2 + EI * laws.kappa2(a, b) / 2
    >>> biot.parameters
    ('EA', 'EI')
    """
    def make(fn):
        return CableLaw(fn, dissipation, name)

    return make if energy is None else make(energy)
