"""Template of the compiled Newton iteration of one generalized-alpha step.

The one definition of the iteration.  ``newton`` is not compiled here:
``solvers.compiled`` copies its source into one generated module for all linear solvers
(each reached at its address, ``solvers.step_lu``) and compiles it there once per machine
with ``numba.njit(cache=True)``, or imports it interpreted
(``GeneralizedAlpha(compiled=False)``, the debugging mode).  What differs between systems
reaches it through its argument ``terms``: the system's ``evaluate`` and ``constrain``
(numba first-class functions of one signature, compiled per sequence of term kernels:
they call the kernels of the system's terms in order, see ``contract.Term.kernels``, and
call back its Python terms, ``kernels.callbacks``) and the address of their data
(``kernels.erased``).  The integrator keeps the energy books, the instability guard and
the step control in Python, once per step.
"""

import numpy as np

from .books import correct_elastic, csr_product, mass_row3, step_books

#: Return codes of ``newton``.
CONVERGED, NON_FINITE, NO_CONVERGENCE, SINGULAR = 0, 1, 2, 3

#: Smallest error factor ``eta`` of a step's first correction, whose contraction is not
#: measured yet: the first correction ends the iteration only if it is below ten times the
#: tolerance, whatever the last step's contraction (after a fresh tangent Newton contracts
#: quadratically, and its tiny ``eta`` would pass first corrections of thousands of times
#: the tolerance in later steps, which may contract slowly).
ETA_FIRST = 0.1

#: The named slots of ``prm``, the float64 parameter vector of ``newton`` (filled by
#: ``solvers.compiled.CompiledNewton``): the step's end time and size, the method's
#: coefficients (``beta'``, ``gamma'`` of the step), Newton's settings, whether to factor
#: and whether Newton is full (1.0 or 0.0), its contraction estimate (updated by
#: ``newton``), the predictor's coefficients and whether some term writes a damping force
#: and a non-constant external force (1.0 or 0.0, ``Layout.writes``).  The generated
#: module gets them as constants (``solvers.compiled.source``).
PRM_SLOTS = ("T1", "H", "ALPHA_M", "ALPHA_F", "GAMMA", "BETA", "BETA_P", "GAMMA_P", "MBAR",
             "TOL", "CON_WEIGHT", "MAX_ITER", "NEED", "FULL", "TOL_LOCAL", "ERROR_CONSTANT",
             "RATE", "C1", "C0", "DAMPING", "EXTERNAL")
(T1, H, ALPHA_M, ALPHA_F, GAMMA, BETA, BETA_P, GAMMA_P, MBAR, TOL, CON_WEIGHT, MAX_ITER, NEED,
 FULL, TOL_LOCAL, ERROR_CONSTANT, RATE, C1, C0, DAMPING, EXTERNAL) = range(len(PRM_SLOTS))


def pseudo_acceleration(a1, a, abar, am, af):
    """``abar_(n+1)`` of ``(1 - alpha_m) abar_(n+1) + alpha_m abar_n = (1 - alpha_f) a_(n+1)
    + alpha_f a_n`` (scalars or arrays; ``GeneralizedAlpha`` uses it on arrays)."""
    return ((1.0 - af) * a1 + af * a - am * abar) / (1.0 - am)


def forces_written(prm):
    """``(damping, external)``: whether some term writes a damping force and a
    non-constant external force, from their slots of ``prm`` (``PRM_SLOTS``)."""
    return prm[DAMPING] != 0.0, prm[EXTERNAL] != 0.0


def first_error_factor(rate):
    """The error factor ``eta`` of a step's first correction: the last step's ``rate``
    relaxed to ``rate^0.8`` and at least ``ETA_FIRST`` (Hairer & Wanner)."""
    return max(max(rate, 1e-16) ** 0.8, ETA_FIRST)


def error_factor(eta, dx_err, dx_before, it):
    """``eta = theta / (1 - theta)`` of the contraction ``theta = |dx_k| / |dx_(k-1)|``
    after the correction of iteration ``it`` (infinite if it does not contract); the
    given ``eta`` after the first correction (``it == 0``), whose contraction is not
    measured."""
    if it == 0:
        return eta
    theta = dx_err / dx_before
    return theta / (1.0 - theta) if theta < 1.0 else np.inf


def newton(terms, model, lu, state, out, prm):
    """One step: ``_iterate`` and, once converged, ``_finish`` (the arguments and results
    of ``_iterate``)."""
    result = _iterate(terms, model, lu, state, out, prm)
    if result[0] == CONVERGED:
        _finish(model, state, out, prm)
    return result


def newton_held(terms, blob, kind, state, prm):
    """``newton`` with the arguments that stay the same through a run, ``(model, lu,
    out)``, held at the address ``blob`` as a value of the numba type ``kind``
    (``kernels.erased.keep``): the call unboxes the state and ``prm`` alone.  The
    74 arrays of the E-sail rig's arguments took 9 of the 11 us its call spent unboxing
    (``benchmarks/esail_profile.py``)."""
    model, lu, out = held(blob, kind)  # noqa: F821 (names of the generated module)
    return newton(terms, model, lu, state, out, prm)


def _finish(model, state, out, prm):
    """The converged step's pseudo-acceleration ``abar1`` (``GeneralizedAlpha._next_abar``)
    and the sums of its energy books (``kernels.books.step_books``) into ``books``."""
    q, a, abar, before = state[0], state[2], state[3], (state[7], state[8], state[9])
    q1, v1, a1, after = out[0], out[1], out[2], (out[9], out[8], out[10])
    abar1, books, mv = out[22], out[23], out[19]
    am, af = prm[ALPHA_M], prm[ALPHA_F]
    for i in range(q.size):
        abar1[i] = pseudo_acceleration(a1[i], a[i], abar[i], am, af)
    books[0], books[1], books[2], books[3] = step_books(
        q, before, after, model[0], model[2], q1, v1, mv, forces_written(prm))


def _iterate(terms, model, lu, state, out, prm):
    """Predict and iterate one step to convergence (paper Eqs. 12-15).

    Converged: after a correction ``dx_k`` whose error estimate ``eta_k |dx_k|`` is below
    the tolerance, with ``eta_k = theta_k / (1 - theta_k)`` and the contraction ``theta_k =
    |dx_k| / |dx_(k-1)|`` (for the first correction the last step's ``eta``, relaxed to
    ``eta^0.8``, and at least ``ETA_FIRST``; Hairer & Wanner, *Solving Ordinary
    Differential Equations II*, Sect. IV.8), so the iterate is taken
    without evaluating the residual there; or when the scaled residual and the last
    correction are below the tolerance, or at their round-off floor after an exact tangent.

    Parameters
    ----------
    terms : tuple ``(evaluate, constrain, blob)``
        The system's two compiled functions (``solvers.compiled``: of one signature for
        every system, ``EVALUATE`` and ``CONSTRAIN``, given by their addresses,
        ``kernels.erased.address``) and the address of its terms' packed data and tangent
        positions (``kernels.erased``): ``evaluate(blob, ev)`` adds every term's forces
        (and tangents) into ``ev``, ``constrain(blob, cev)`` its nonlinear constraints'
        rows.
    model : tuple
        ``(mass, base, f_const, diag_index, xscale, inv_xscale, c_indptr, c_indices, c_data,
        lin_rows, c_t, constrained)``: the mass matrix
        (``linalg.FastCSR.strided``, read by ``kernels.books.mass_row3``), the constant part
        of the iteration matrix, the constant force, the positions of the diagonal, the
        coordinate scales, the linear constraints' Jacobian (CSR; ``C^T lam`` is scattered
        from its rows), their multiplier rows and offsets at ``t1``, and the coordinates
        some constraint holds (``Layout.constrained``), the only ones where ``C_q^T lam``
        is not zero.
    lu : tuple
        ``(factor, solve, blob)``: the addresses of the linear solver's ``factor`` and
        ``solve`` and of its storage (``solvers.step_lu``; that of ``linalg.PatternSolver``:
        a factor made there is used here and the reverse).
    state : tuple ``(q, v, a, abar, lam, a_prev, da_prev, f_damping, f_nc, f_con)``
        The state at ``t_n``, the accelerations at ``t_(n-1)`` and their change over the
        step before (the predictor's) and the forces of the energy books at ``t_n`` (read
        only).
    out : tuple
        ``(q1, v1, a1, lam1, r, data, nodata, f, f_ext, fd, f_con, energy, power,
        res_weight, history, fq, fv, flam, dx, rhs, s, cs, abar1, books)``: the new
        state, the residual, the matrix values, force accumulators, the scaled-residual
        weights (refreshed at every factorization), the residual history, the state at the
        last factorization, scratch, and (``_finish``) the new pseudo-acceleration and the
        books' sums ``(dissipated, external work, kinetic, potential)`` of the step.
    prm : float ndarray
        ``[t1, h, alpha_m, alpha_f, gamma, beta, beta', gamma', mbar, tol, con_weight,
        max_iter, need, full, tol_local, error_constant, eta, c1, c0, damping, external]``
        (``tol_local = 0``: off; ``c1, c0``: the predictor's,
        ``GeneralizedAlpha.predictor``; ``damping``, ``external``: ``PRM_SLOTS``);
        ``eta``, the contraction estimate of the last step (``GeneralizedAlpha.newton_rate``),
        is replaced by this step's on convergence.

    Returns
    -------
    status, iterations, factorizations, corrections, singular : int
        ``CONVERGED`` (0), ``NON_FINITE``, ``NO_CONVERGENCE`` or ``SINGULAR``; the
        iteration count; the factorizations and Newton corrections made; the unknown
        of a zero pivot (-1 otherwise).
    """
    q, v, a, abar, lam, a_prev, da_prev = state[:7]
    (q1, v1, a1, lam1, r, data, nodata, f, f_ext, fd, f_con, energy, power, res_weight,
     history, fq, fv, flam, dx, rhs, s, cs) = out[:22]
    xscale, inv_xscale = model[4], model[5]
    t1, h, am, af = prm[T1], prm[H], prm[ALPHA_M], prm[ALPHA_F]
    gm, bt, bp, gp = prm[GAMMA], prm[BETA], prm[BETA_P], prm[GAMMA_P]
    mbar, tol_floor, con_weight = prm[MBAR], prm[TOL], prm[CON_WEIGHT]
    tol_local, error_constant = prm[TOL_LOCAL], prm[ERROR_CONSTANT]
    eta = first_error_factor(prm[RATE])
    max_iter, need, full = int(prm[MAX_ITER]), prm[NEED] != 0.0, prm[FULL] != 0.0
    written = forces_written(prm)
    n = q.size
    c1, c0 = prm[C1], prm[C0]
    constant = c1 == 0.0 and c0 == 0.0
    # predictor: GeneralizedAlpha.predicted_acceleration
    for i in range(n):
        a1[i] = a[i] if constant else a[i] + c1 * (a[i] - a_prev[i]) + c0 * da_prev[i]
        abar1 = pseudo_acceleration(a1[i], a[i], abar[i], am, af)
        q1[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * abar[i] + bt * abar1)
        v1[i] = v[i] + h * ((1.0 - gm) * abar[i] + gm * abar1)
    # copies in loops, not slices: numba compiles a formatted error message for a slice
    # copy (seconds of a first run)
    for k in range(lam.size):
        lam1[k] = lam[k]
    s[0], s[1], s[2], s[3] = t1, 1.0 / bp, gp / bp, 1.0
    cs[0], cs[1], cs[2] = t1, 1.0 / bp, mbar
    dq_err = dq_before = dx_err = np.inf
    exact = False
    factorizations = corrections = 0
    for it in range(max_iter + 1):
        tangent = need
        err_q, finite = _residual(terms, model, q1, v1, a1, lam1, r,
                                  data if tangent else nodata, out, mbar, bp, written)
        err_c = 0.0
        for i in range(n, r.size):
            finite = finite and np.isfinite(r[i])
            err_c = max(err_c, abs(r[i]))
            rhs[i] = -r[i]
        err = max(err_q, err_c * con_weight)
        history[it] = err
        if not finite:
            return NON_FINITE, it, factorizations, corrections, -1
        tol = tol_floor
        if tol_local > 0.0:  # GeneralizedAlpha.local_error at the iterate
            e = 0.0
            for i in range(n):
                abar1 = pseudo_acceleration(a1[i], a[i], abar[i], am, af)
                e = max(e, abs(error_constant * h * h * (abar1 - abar[i])) * inv_xscale[i])
            tol = max(tol, tol_local * e)
        if it > 0 and ((err <= tol and dq_err <= tol) or (
                exact and err <= 1e3 * tol and dq_err <= 1e3 * tol
                and (err >= 0.5 * history[it - 1] or dq_err >= 0.5 * dq_before))):
            prm[RATE] = eta
            return CONVERGED, it, factorizations, corrections, -1
        if it > 0 and not exact and err > tol and err >= 0.5 * history[it - 1]:
            need = True  # the stale tangent no longer reduces the residual
        if it == max_iter:
            return NO_CONVERGENCE, it, factorizations, corrections, -1
        exact = need
        if need:
            if not tangent:  # tangent requested after this evaluation: rebuild it
                _residual(terms, model, q1, v1, a1, lam1, rhs, data, out, mbar, bp, written)
                for i in range(r.size):  # (rhs was its scratch)
                    rhs[i] = -r[i]
            singular = _factor(lu, data, model[3], xscale, res_weight)
            if singular != -1:
                return SINGULAR, it, factorizations, corrections, singular
            factorizations += 1
            for i in range(n):
                fq[i] = q1[i]
                fv[i] = v1[i]
            for k in range(lam1.size):
                flam[k] = lam1[k]
            need = full
        lu_solve(lu, rhs, dx)  # noqa: F821
        dq_before = dq_err
        dq_err = 0.0
        for i in range(n):
            q1[i] += dx[i]
            v1[i] += gp * dx[i]
            a1[i] += bp * dx[i]
            dq_err = max(dq_err, abs(dx[i]) * inv_xscale[i])
        dl_err = 0.0
        for k in range(lam1.size):
            lam1[k] += (bp * mbar) * dx[n + k]
            dl_err = max(dl_err, abs(dx[n + k]))
        corrections += 1
        dx_before, dx_err = dx_err, max(dq_err, dl_err * con_weight * mbar)
        eta = error_factor(eta, dx_err, dx_before, it)
        if dq_err > tol and (dq_err > 0.25 * dq_before
                             or (it >= 3 and eta * eta * dx_err > tol_floor)):
            need = True  # modified Newton contracts too slowly: refresh the tangent
        if eta * dx_err <= tol_floor:  # the error left after this correction
            correct_elastic(f, fd, dx[:n], energy, written[0])
            _constraints(terms, model, q1, lam1, r, nodata, f_con, cs, mbar)
            prm[RATE] = eta
            return CONVERGED, it + 1, factorizations, corrections, -1
    return NO_CONVERGENCE, max_iter, factorizations, corrections, -1


def _residual(terms, model, q1, v1, a1, lam1, r, data, out, mbar, bp, written):
    """Evaluate every term and constraint at ``(q1, v1, lam1)`` (and, with ``data`` not
    empty, the iteration matrix) and write the scaled residual into ``r``: dynamic rows
    ``(M a1 + f - f_const - f_ext + C_q^T lam1) / beta'``, constraint rows
    ``mbar (C q1 - c(t1))`` (as ``System.evaluate`` writes them); ``written = (damping,
    external)``: whether some term writes ``fd`` and ``f_ext`` (``Layout.writes``), which
    are cleared only then.  Returns what ``_dynamic_rows`` returns."""
    f, f_ext, fd, energy, power, s = out[7], out[8], out[9], out[11], out[12], out[20]
    f[:] = 0.0
    if written[1]:
        f_ext[:] = 0.0
    if written[0]:
        fd[:] = 0.0
    energy[:] = 0.0
    power[:] = 0.0
    for j in range(data.size):
        data[j] = model[1][j]
    evaluate = function(terms[0], EVALUATE)  # noqa: F821
    evaluate(terms[2], (q1, v1, s, f, f_ext, fd, data, energy, power))
    _constraints(terms, model, q1, lam1, r, data, out[10], out[21], mbar)
    return _dynamic_rows(model, a1, r, out, bp, written[1])


def _dynamic_rows(model, a1, r, out, bp, external):
    """The dynamic rows ``(M a1 + f - f_const - f_ext + C_q^T lam1) / beta'`` of the scaled
    residual into ``r`` and their negation into the right-hand side ``rhs`` (``out[19]``),
    in one pass that also takes ``M a1`` row by row of ``M_s`` for a mass ``M_s ⊗ I_3``
    (``kernels.books.mass_row3``; a general CSR's short rows, a rigid body's, into ``r``
    first) and the largest of them scaled by the residual weights (``out[13]``); returns
    it and whether they are all finite.  Each a pass fewer over the vectors, out of the L2
    cache on large systems."""
    indptr, indices, data, stride = model[0]
    err, finite = 0.0, True
    if stride == 3:
        for row in range(indptr.size - 1):
            m0, m1, m2 = mass_row3(indptr, indices, data, a1, row)
            err, finite = _dynamic_row(3 * row, m0, model, r, out, bp, external, err, finite)
            err, finite = _dynamic_row(3 * row + 1, m1, model, r, out, bp, external, err,
                                       finite)
            err, finite = _dynamic_row(3 * row + 2, m2, model, r, out, bp, external, err,
                                       finite)
    else:  # M a1 into r first: short rows of a general CSR, two tight loops
        csr_product(indptr, indices, data, a1, r)
        for i in range(indptr.size - 1):
            err, finite = _dynamic_row(i, r[i], model, r, out, bp, external, err, finite)
    return err, finite


def _dynamic_row(i, m, model, r, out, bp, external, err, finite):
    """The dynamic row ``i`` of ``_dynamic_rows`` from its entry ``m`` of ``M a1``; returns
    ``err`` and ``finite`` with it.  ``f_ext`` is read only if some term writes it
    (``external``; else its zero is added, the same bits).  ``C_q^T lam1`` is read
    everywhere: a test of the coordinate per row cost the 444 rows of the E-sail rig 1 us
    an evaluation (2.5 %), more than the read saves out of the cache."""
    f_const = model[2]
    f, f_ext, f_con, res_weight, rhs = out[7], out[8], out[10], out[13], out[19]
    fi = (f[i] - (f_const[i] + (f_ext[i] if external else 0.0))) + f_con[i]
    ri = (m + fi) / bp
    r[i] = ri
    rhs[i] = -ri
    e = abs(ri) * res_weight[i]
    return max(err, e), finite and np.isfinite(e)


def _constraints(terms, model, q1, lam1, r, data, f_con, cs, mbar):
    """The constraints at ``(q1, lam1)``: their rows ``mbar (C q1 - c(t1))`` into ``r``,
    ``f_con = C_q^T lam1`` and, with ``data`` not empty, their tangents (``cs = [t1,
    cK, mbar]``).

    Also called on the iterate a step accepts after its last correction without
    evaluating it (``_iterate``): the energy books take the constraint forces' work from
    ``f_con`` (``kernels.books.step_books``), which must be those of the accepted
    multipliers.  The correction's change of ``lam`` can be large in forces and small in
    the convergence test, which measures it as ``dlam / (beta' mbar)`` with ``mbar`` the
    mean nodal mass: a 2.8e5 kg hub holding a 1 m rope of 0.08 kg by a pin (mbar = 3.3e4
    kg) passed corrections of up to 1.3 N at 1e-4 s steps (with the rope's damping, two
    steps in three ended on their first correction), and the books, which took the
    forces before the correction, missed the driven tip's work over it: 2.4e-3 of the
    work, first order in the step (``tests/test_books_hub.py``).  The damping and
    external forces of the books are those before the correction: it moves them by
    ``O(dq)``, held below the tolerance in the coordinates."""
    (c_indptr, c_indices, c_data, lin_rows, c_t, constrained) = model[6:12]
    n = q1.size
    for k in range(constrained.size):  # f_con is zero at the coordinates no constraint holds
        f_con[constrained[k]] = 0.0
    # C_q^T lam scattered from the rows of C, in their order: each f_con[i] takes its
    # terms in the order of the transpose's row (the same sums from the same +0), without
    # a pass over the many coordinates no constraint holds
    for k in range(lin_rows.size):
        acc = 0.0
        lam_k = lam1[lin_rows[k]]
        for j in range(c_indptr[k], c_indptr[k + 1]):
            acc += c_data[j] * q1[c_indices[j]]
            f_con[c_indices[j]] += c_data[j] * lam_k
        r[n + lin_rows[k]] = mbar * (acc - c_t[k])
    constrain = function(terms[1], CONSTRAIN)  # noqa: F821
    constrain(terms[2], (q1, lam1, cs, r[n:], f_con, data))


def _factor(lu, data, diag_index, xscale, res_weight):
    """LU of the matrix values ``data`` (``PatternSolver.factor``) and the new residual
    weights; returns the unknown of a zero pivot (-2: not located), or -1."""
    singular = lu_factor(lu, data)  # noqa: F821
    if singular != -1:
        return singular
    for i in range(res_weight.size):
        res_weight[i] = 1.0 / (abs(data[diag_index[i]]) * xscale[i])
    return -1
