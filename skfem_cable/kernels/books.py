"""Numba kernel of the energy books of a time step (``GeneralizedAlpha``, ``docs/theory``):
the sums of a step in one pass, without temporaries."""

import numpy as np
from numba import njit

#: Unsigned indices: numba tests a signed index for wrap-around (a negative one counts
#: from the end) at every read, an unsigned one not; a CSR's column indices are >= 0.
ONE, TWO, THREE = np.uint64(1), np.uint64(2), np.uint64(3)


@njit(cache=True)
def step_books(q0, before, after, mass, f_const, q, v, mv, written):
    """Work of the damping and of the external and constraint forces over a step from
    ``q0`` to ``q`` by the trapezoidal rule, and the kinetic and potential energy at its
    end.

    Parameters
    ----------
    q0 : ndarray (n,)
        The coordinates at the step's start (its change ``dq = q - q0`` is taken here, in
        the same pass).
    before, after : tuple ``(f_damping, f_nc, f_con)``
        Damping force, non-constant external force and ``C_q^T lambda`` at the step's
        start and end.
    mass : tuple ``(indptr, indices, data, k)``
        The mass matrix ``M = M_s ⊗ I_k`` (``linalg.FastCSR.strided``: ``M_s`` in CSR).
    f_const : ndarray (n,)
        Constant external force (its potential is ``-f_const . q``).
    q, v : ndarray (n,)
        Coordinates and velocities at the step's end.
    mv : ndarray (n,)
        Scratch: ``M v``.
    written : tuple ``(damping, external)``
        Whether some term writes a damping force and a non-constant external force
        (``Term.writes``): a force no term writes is zero and not read (the same sums, bit
        for bit).

    Returns
    -------
    dissipated, external_work, kinetic, potential : float
        ``dq . (fd_0 + fd_1) / 2``, ``dq . (fnc_0 + fnc_1 - fcon_0 - fcon_1) / 2``,
        ``v . M v / 2`` and ``-f_const . q`` (J).
    """
    damping, external = written
    fd0, fnc0, fcon0 = before
    fd1, fnc1, fcon1 = after
    mass_product(mass, v, mv)
    dissipated = work = kinetic = potential = 0.0
    for i in range(q.size):
        dq = q[i] - q0[i]
        if damping:
            dissipated += dq * (fd0[i] + fd1[i])
        nc = fnc0[i] + fnc1[i] if external else 0.0
        work += dq * (nc - fcon0[i] - fcon1[i])
        kinetic += v[i] * mv[i]
        potential -= f_const[i] * q[i]
    return 0.5 * dissipated, 0.5 * work, 0.5 * kinetic, potential


@njit(cache=True, forceinline=True)
def mass_product(mass, x, out):
    """``out[:n] = M x`` for the mass ``M = M_s ⊗ I_k`` given as ``mass = (indptr,
    indices, data, k)``, ``k`` 3 or 1 (``linalg.FastCSR.strided``): each entry the sum
    over ``M``'s row in the order of its columns (``mass_row3``, ``csr_product``)."""
    indptr, indices, data, stride = mass
    if stride == 3:
        for row in range(indptr.size - 1):
            out[3 * row], out[3 * row + 1], out[3 * row + 2] = mass_row3(
                indptr, indices, data, x, row)
    else:
        csr_product(indptr, indices, data, x, out)


@njit(cache=True, forceinline=True)
def mass_row3(indptr, indices, data, x, row):
    """The three entries of ``M x`` of the row ``row`` of ``M_s`` (``M = M_s ⊗ I_3``):
    the three components of a row in one pass over it (its values and indices read
    once)."""
    values, columns = _row(indptr, indices, data, row)
    m0 = m1 = m2 = 0.0
    for k in range(values.size):
        d, j = values[k], THREE * np.uint64(columns[k])
        m0 += d * x[j]
        m1 += d * x[j + ONE]
        m2 += d * x[j + TWO]
    return m0, m1, m2


@njit(cache=True, forceinline=True)
def _row(indptr, indices, data, row):
    """The values and column indices of ``row`` of a CSR matrix, as slices (read from 0:
    without the wrap-around test of an index from ``indptr``): the rig's ``M a`` 1.25 ->
    0.96 us with the unsigned columns."""
    start, end = indptr[row], indptr[row + 1]
    return data[start:end], indices[start:end]


@njit(cache=True, forceinline=True)
def csr_product(indptr, indices, data, x, out):
    """``out[:n] = A x`` for the CSR matrix ``A = (indptr, indices, data)``, each entry the
    sum over its row in the order of its columns; returns ``out``."""
    for row in range(indptr.size - 1):
        values, columns = _row(indptr, indices, data, row)
        m = 0.0
        for k in range(values.size):
            m += values[k] * x[np.uint64(columns[k])]
        out[row] = m
    return out


@njit(cache=True)
def correct_elastic(f, fd, dq, energy, damping):
    """Carry the elastic energy ``energy`` (axial, bending) of an evaluation over a Newton
    correction ``dq`` taken after it, to first order: ``dE = (f - f_damping) . dq`` (the
    elastic force is the energy's gradient), shared between axial and bending in proportion
    to their magnitudes.  A step that converges on a correction (``kernels.step``) then
    books the energy of the state it accepts to ``O(dq^2)``, not ``O(dq)``.  ``fd`` is
    read only if some term writes a damping force (``damping``)."""
    de = 0.0
    for i in range(dq.size):
        de += ((f[i] - fd[i]) if damping else f[i]) * dq[i]
    total = abs(energy[0]) + abs(energy[1])
    share = abs(energy[0]) / total if total > 0.0 else 1.0
    energy[0] += share * de
    energy[1] += (1.0 - share) * de
