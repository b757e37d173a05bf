"""The compiled parts of a Newton step, each timed alone, and a probe of the compiled
calls: the timing shared by ``benchmarks/esail_profile.py`` (in a fresh process of this
tree and of the reference commit's, which imports this file by its folder) and
``benchmarks/esail_floor.py`` (a module, not a benchmark script: ``skfem-cable bench``
runs the scripts of ``benchmarks/`` alone, not of its folders).

Only what both trees have is used: ``CompiledNewton.iterate(newton, integrator, ...)``,
its ``arrays`` and ``history``, the terms' ``kernels`` (``contract.Term``) and the
bordered band LU (``kernels.bordered``) on the storage of the integrator's solver
(``integrator.solver.lu``; the step's own ``lu`` is the solver's addresses since the
step became one for every solver, ``solvers.step_lu``).
"""

import time

import numpy as np
from numba import njit

from skfem_cable.kernels import bordered
from skfem_cable.solvers import compiled as compiled_step

#: The index of a term without one (the kernels read none).
NO_INDEX = np.zeros((0, 1, 1), dtype=np.int64)


@njit
def _repeat(function, args, reps):
    for _ in range(reps):
        function(*args)


def cpu_us(function, args, reps=200, repeats=3):
    """CPU us of one call of the compiled ``function(*args)``, in a compiled loop of
    ``reps`` calls (minimum over ``max(repeats, 3)`` loops, after one call)."""
    _repeat(function, args, 1)
    times = []
    for _ in range(max(repeats, 3)):
        start = time.process_time_ns()
        _repeat(function, args, reps)
        times.append(time.process_time_ns() - start)
    return 1e-3 * min(times) / reps


def evaluation(arrays, data):
    """The arrays a term kernel evaluates into, ``ev = (q1, v1, s, f, f_ext, fd, data,
    energy, power)``, with the matrix values ``data`` (empty: no tangent)."""
    a = arrays
    return (a["q1"], a["v1"], a["s"], a["f"], a["f_ext"], a["fd"], data, a["energy"],
            a["power"])


def compiled_parts(newton, integrator, repeats):
    """CPU us of the compiled parts of a Newton iteration of ``integrator`` (its
    ``CompiledNewton`` ``newton``, after a run: its arrays hold the last iterate and
    matrix), each alone: every term kernel without and with its tangent, the bordered
    band factorization and a band solve.

    Returns
    -------
    dict
        ``kernels`` (per kernel, in the order of the step: ``term``, ``residual_us``,
        ``tangent_us``), ``factor_us``, ``solve_us``.
    """
    a = newton.arrays
    matrix = a["data"].copy()
    kernels = []
    for term, index in integrator.lay.body_terms + integrator.lay.load_terms:
        for function, pack in term.kernels or ():
            index = NO_INDEX if index is None else index
            kernels.append({
                "term": term.name,
                "residual_us": cpu_us(function, (pack, index, evaluation(a, a["nodata"])),
                                      repeats=repeats),
                "tangent_us": cpu_us(function, (pack, index, evaluation(a, a["data"])), 20,
                                     repeats)})
    a["data"][:] = matrix  # the tangents added into it
    lu = integrator.solver.lu
    factor_us = cpu_us(bordered.factor, (lu, a["data"]), 20, repeats)
    rhs = np.linspace(-1.0, 1.0, a["r"].size)
    solve_us = cpu_us(bordered.solve, (lu, rhs, a["dx"]), repeats=repeats)
    return {"kernels": kernels, "factor_us": factor_us, "solve_us": solve_us}


class Probe:
    """While entered: counts the residual evaluations of the compiled Newton calls (the
    rows of their history) in ``evaluations``, keeps the last call's ``newton`` and
    ``integrator`` and, if ``timed``, adds the CPU ns spent inside the compiled call
    (its entry point wrapped after each ``CompiledNewton``'s first call) to ``call_ns``.
    """

    def __init__(self, timed=False):
        self.timed = timed
        self.call_ns = self.evaluations = 0
        self.newton = self.integrator = None
        self.original = compiled_step.CompiledNewton.iterate

    def reset(self):
        """Zero the counts of the calls (before a run)."""
        self.call_ns = self.evaluations = 0

    def _timed(self, function):
        def compiled_call(*args):
            start = time.process_time_ns()
            out = function(*args)
            self.call_ns += time.process_time_ns() - start
            return out
        return compiled_call

    def __enter__(self):
        original, probe = self.original, self

        def iterate(newton, g, *args):
            newton.history[:] = -1.0
            out = original(newton, g, *args)
            probe.evaluations += int((newton.history >= 0.0).sum())
            if probe.timed and probe.newton is not newton:  # its entry point is set
                name = "entry" if getattr(newton, "entry", None) is not None else "newton"
                setattr(newton, name, probe._timed(getattr(newton, name)))
            probe.newton, probe.integrator = newton, g
            return out

        compiled_step.CompiledNewton.iterate = iterate
        return self

    def __exit__(self, *exc):
        compiled_step.CompiledNewton.iterate = self.original
