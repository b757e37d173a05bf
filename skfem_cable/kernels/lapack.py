"""LAPACK's banded and dense LU (``dgbtrf``/``dgbtrs``, ``dgetrf``/``dgetrs``) callable
from numba-compiled code.

The routines are scipy's own (``scipy.linalg.cython_lapack``), called through their
addresses.  The addresses are passed at run time (``ADDRESSES``), never frozen into
compiled code, so the kernels that use them can be cached on disk: an address differs
between processes.

The band storage is LAPACK's: column-major ``(2 kl + ku + 1, n)``, held here as a
C-ordered ``(n, 2 kl + ku + 1)`` array whose row ``j`` is column ``j`` of the band;
pivots are 32-bit Fortran integers (1-based).
"""

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import get_cython_function_address, intrinsic

#: ``(dgbtrf, dgbtrs, dgetrf, dgetrs)`` addresses in this process.
ADDRESSES = np.array([get_cython_function_address("scipy.linalg.cython_lapack", name)
                      for name in ("dgbtrf", "dgbtrs", "dgetrf", "dgetrs")], dtype=np.int64)


@intrinsic
def _call(typingctx, address, pointers):
    """``_call(address, (p_1, ..., p_k))``: call the C function ``void f(void *, ...)`` at
    ``address`` with the pointers ``p_i`` (given as integers)."""

    def codegen(context, builder, signature, args):
        ptr = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [ptr] * len(pointers))
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        builder.call(fn, [builder.inttoptr(builder.extract_value(args[1], k), ptr)
                          for k in range(len(pointers))])

    return types.void(address, pointers), codegen


@njit(cache=True)
def band_factor(addresses, ab, kl, ku, ipiv, ints):
    """LU-factor the band ``ab`` in place (``dgbtrf``); ``ints`` is int32 scratch of
    length 8.  Returns LAPACK's ``info`` (``> 0``: zero pivot at that 1-based column)."""
    n, ldab = ab.shape
    ints[0] = n
    ints[1] = kl
    ints[2] = ku
    ints[3] = ldab
    ints[4] = 0
    _call(addresses[0], (ints[0:].ctypes.data, ints[0:].ctypes.data, ints[1:].ctypes.data,
                         ints[2:].ctypes.data, ab.ctypes.data, ints[3:].ctypes.data,
                         ipiv.ctypes.data, ints[4:].ctypes.data))
    return ints[4]


@njit(cache=True)
def band_solve(addresses, ab, kl, ku, ipiv, b, ints):
    """Solve ``A X = B`` in place with the factor of ``band_factor`` (``dgbtrs``): ``b``
    of shape ``(n,)``, or ``(nrhs, n)`` holding the right-hand sides as rows."""
    n, ldab = ab.shape
    ints[0] = n
    ints[1] = kl
    ints[2] = ku
    ints[3] = b.size // max(n, 1)
    ints[4] = ldab
    ints[5] = 0
    ints[6] = 78  # 'N': no transpose
    _call(addresses[1], (ints[6:].ctypes.data, ints[0:].ctypes.data, ints[1:].ctypes.data,
                         ints[2:].ctypes.data, ints[3:].ctypes.data, ab.ctypes.data,
                         ints[4:].ctypes.data, ipiv.ctypes.data, b.ctypes.data,
                         ints[0:].ctypes.data, ints[5:].ctypes.data))
    return ints[5]


@njit(cache=True)
def dense_factor(addresses, a, ipiv, ints):
    """LU-factor the square matrix ``a`` in place (``dgetrf``; ``a`` C-ordered holds the
    transpose, LAPACK's column-major storage).  Returns ``info``."""
    ints[0] = a.shape[0]
    ints[1] = 0
    _call(addresses[2], (ints[0:].ctypes.data, ints[0:].ctypes.data, a.ctypes.data,
                         ints[0:].ctypes.data, ipiv.ctypes.data, ints[1:].ctypes.data))
    return ints[1]


@njit(cache=True)
def dense_solve(addresses, a, ipiv, b, ints):
    """Solve ``A x = b`` in place with the factor of ``dense_factor`` (``dgetrs``)."""
    ints[0] = a.shape[0]
    ints[1] = 1
    ints[2] = 0
    ints[6] = 78  # 'N'
    _call(addresses[3], (ints[6:].ctypes.data, ints[0:].ctypes.data, ints[1:].ctypes.data,
                         a.ctypes.data, ints[0:].ctypes.data, ipiv.ctypes.data,
                         b.ctypes.data, ints[0:].ctypes.data, ints[2:].ctypes.data))
    return ints[2]

