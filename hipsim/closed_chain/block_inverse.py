"""Inverses of the small matrices the closure solver meets, compiled with numba.

A block lower triangular matrix block row by block row, a 3×3 in closed form,
a larger block by Gauss–Jordan elimination, and Cramer's rule for a 3×3 system:
LAPACK's inverse costs ~2 µs a call whatever the size, more than this
arithmetic on the hip's matrices (:mod:`hipsim.closed_chain.closure_kernel`
calls them).
"""

from __future__ import annotations

import numpy as np

from ..physics import laws
from ..physics.vectors import cross, dot

__all__ = ["block_lower_inverse", "cramer"]


@laws.jit
def block_lower_inverse(M, starts):
    """The inverse of a block lower triangular matrix, block row by block row.

    With D_b the diagonal blocks, X = M⁻¹ is block lower triangular too:
    X_bb = D_b⁻¹ and, for the columns before block b, X_b,<b = −D_b⁻¹ M_b,<b X_<b,<b.
    A few small inverses instead of one large one (the hip's B: three 3×3
    blocks and a 9×9, against 18×18), and no pivoting across blocks is
    needed: det M is the product of the blocks' determinants. The blocks are
    inverted here, not by LAPACK, whose inverse costs ~2 µs a call whatever
    the size (more than this whole function's arithmetic on the hip): a 3×3
    in closed form, a larger one by Gauss–Jordan elimination with partial
    pivoting. M_b,<b is mostly zeros (a lever couples to few earlier
    coordinates), which the product skips.

    Args:
        M: the matrix, (n, n), zero above its diagonal blocks.
        starts: where each diagonal block starts, and n at the end, (blocks + 1,).

    Raises:
        numpy.linalg.LinAlgError: a diagonal block is singular to machine precision.
    """
    n = M.shape[0]
    X = np.zeros((n, n))
    T = np.empty((n, n))  # M_b,<b X_<b,<b, in its first rows
    for b in range(starts.size - 1):
        s, e = starts[b], starts[b + 1]
        D_inv = X[s:e, s:e]
        if e - s == 3:
            _inverse_3x3(M[s:e, s:e], D_inv)
        else:
            _gauss_jordan_inverse(M[s:e, s:e], D_inv)
        if s == 0:
            continue
        for i in range(e - s):
            for j in range(s):
                T[i, j] = 0.0
            for m in range(s):
                f = M[s + i, m]
                if f != 0.0:
                    for j in range(s):
                        T[i, j] += f * X[m, j]
        for i in range(e - s):
            for j in range(s):
                total = 0.0
                for m in range(e - s):
                    total += D_inv[i, m] * T[m, j]
                X[s + i, j] = -total
    return X


@laws.jit
def _gauss_jordan_inverse(D, out):
    """out = D⁻¹ by Gauss–Jordan elimination with partial pivoting (the textbook algorithm, as LAPACK's getrf + getri).

    Raises:
        numpy.linalg.LinAlgError: a pivot is zero (D singular to machine precision), as LAPACK would.
    """
    m = D.shape[0]
    W = np.empty((m, m))
    for i in range(m):
        for j in range(m):
            W[i, j] = D[i, j]
            out[i, j] = 1.0 if i == j else 0.0
    for col in range(m):
        pivot, largest = col, abs(W[col, col])
        for r in range(col + 1, m):
            if abs(W[r, col]) > largest:
                pivot, largest = r, abs(W[r, col])
        if largest == 0.0:
            raise np.linalg.LinAlgError("Singular matrix")
        if pivot != col:
            for j in range(m):
                W[col, j], W[pivot, j] = W[pivot, j], W[col, j]
                out[col, j], out[pivot, j] = out[pivot, j], out[col, j]
        scale_ = 1.0 / W[col, col]
        for j in range(m):
            W[col, j] *= scale_
            out[col, j] *= scale_
        for r in range(m):
            f = W[r, col]
            if r != col and f != 0.0:
                for j in range(m):
                    W[r, j] -= f * W[col, j]
                    out[r, j] -= f * out[col, j]


@laws.jit
def _inverse_3x3(D, out):
    """out = D⁻¹ of a 3×3 matrix from its cofactors (adjugate over determinant); singular D raises LinAlgError as LAPACK would."""
    rows = ((D[0, 0], D[0, 1], D[0, 2]), (D[1, 0], D[1, 1], D[1, 2]), (D[2, 0], D[2, 1], D[2, 2]))
    # The inverse's columns are the cross products of D's rows over det D.
    c0, c1, c2 = cross(rows[1], rows[2]), cross(rows[2], rows[0]), cross(rows[0], rows[1])
    det = dot(rows[0], c0)
    if det == 0.0:
        raise np.linalg.LinAlgError("Matrix is singular to machine precision.")
    for i in range(3):
        out[i, 0], out[i, 1], out[i, 2] = c0[i] / det, c1[i] / det, c2[i] / det


@laws.jit
def cramer(rows, b):
    """x with M·x = b, M given by its rows, by Cramer's rule."""
    c0 = (rows[0][0], rows[1][0], rows[2][0])
    c1 = (rows[0][1], rows[1][1], rows[2][1])
    c2 = (rows[0][2], rows[1][2], rows[2][2])
    c12 = cross(c1, c2)
    det = dot(c0, c12)
    return (dot(b, c12) / det, dot(c0, cross(b, c2)) / det, dot(c0, cross(c1, b)) / det)
