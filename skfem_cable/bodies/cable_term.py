"""The term of the cables' elastic and damping forces: one compiled call per pass of each
law, the elements of all cables that share a law, its values and quadrature merged into
one call (an E-sail's tethers are one)."""

import numpy as np

from ..core.contract import Term


def cable_term(edofs, passes, key, name):
    """The term of the elastic and damping forces of the elements of one or more cables
    that share a law, its parameter values and quadrature (see ``contract``): one
    compiled kernel call per pass.  Cables with the same ``key`` are merged
    (``merge_cable_terms``), so an E-sail's tethers are one call.

    Parameters
    ----------
    edofs : int ndarray (ne, 3 n_functions)
        Global coordinates of each element (``n_functions`` of its element type).
    passes : sequence of ``(function, tables, values, damped, span)``
        One kernel call each: a compiled hook of the element loop of the laws and the
        address of the ``span`` of a law (or of a part of it, ``CableLaw.part``) that it
        calls (``CableLaw.hook``), its tables ``(Sx, Sxx, weights, h)``
        (shape-function derivatives and weights of its own rule, element lengths), its
        parameter values and whether its dissipation is active (the assumed strain's
        tables end with its map, ``kernels.assumed_strain.Rule.map``, which no stretch changes).
        The formulation (``formulation``) decides the passes: the paper's and the assumed
        strain have one, the Lobatto formulation two (the axial and the bending part).
    key : hashable
    name : str
    """
    edofs = np.ascontiguousarray(edofs, dtype=np.int64)
    kernels = tuple((function, (edofs, *(np.ascontiguousarray(t) for t in tables),
                                np.array(values, dtype=float), bool(damped), span))
                    for function, tables, values, damped, span in passes)
    damped = any(damped for _, _, _, damped, _ in passes)
    return Term(kernels=kernels, rows=edofs[:, :, None], cols=edofs[:, None, :], key=key,
                merge=merge_cable_terms, name=name,
                writes=("f", "f_damping") if damped else ("f",))


def merge_cable_terms(terms):
    """One term for the concatenated elements of ``terms`` (same key: same passes)."""
    kernels = []
    for k, (function, pack) in enumerate(terms[0].kernels):
        packs = [t.kernels[k][1] for t in terms]
        tables = tuple(np.concatenate(parts) for parts in zip(*(p[:5] for p in packs)))
        kernels.append((function, (*tables, *pack[5:])))
    edofs = kernels[0][1][0]
    return Term(kernels=tuple(kernels), rows=edofs[:, :, None], cols=edofs[:, None, :],
                key=terms[0].key, merge=merge_cable_terms,
                name=" + ".join(t.name for t in terms), writes=terms[0].writes)
