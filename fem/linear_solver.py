"""Factorisation of the reduced tangent: dense LU, banded LU or sparse LU.

The tangent is assembled straight into the storage of the chosen solver
(with precomputed flat indices, `np.bincount`):

* banded LAPACK ``dgbtrf``/``dgbtrs`` when the half-bandwidth is small
  (nodes are numbered in reverse Cuthill-McKee order), cost O(n b^2), however few the unknowns:
  the compiled corrector's band LU beats LAPACK's dense ``dgetrf`` from 6 unknowns up on a beam's
  band (`validation.bench.solver_choice`);
* dense LAPACK ``dgetrf`` (``scipy.linalg.lu_factor``) for wide bands up to 300 unknowns;
* SuperLU (``scipy.sparse.linalg.splu``) for large, wide-band systems.

The sign of det K (product of U's diagonal signs times the permutation
parity) is what the solvers watch for critical points; the factors' estimate of
the reciprocal condition number is what `conditioning` reads.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property
from typing import cast

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import lapack

from .types import FloatArray, Int32Array, IntArray

__all__ = ["MatrixLayout", "SingularMatrix", "inverse_norm1", "weighted_bincount"]


class SingularMatrix(Exception):
    """The tangent cannot be factorised; ``column``: the matrix column of the first zero pivot,
    when known."""

    def __init__(self, message: str, column: int | None = None):
        super().__init__(message)
        self.column = column


def inverse_norm1(solve: Callable[..., FloatArray], n: int) -> float:
    """||A^-1||_1 estimated with n-vector solves ``solve(b)``, ``solve(b, True)`` (A^-1 b, A^-T b): Hager's
    method as refined by Higham, the iteration of LAPACK's ``dlacn2`` (Higham 1988, Algorithm 4.1: at most
    five sign vectors and the alternating test vector, at most eleven solves). Every candidate is
    ||A^-1 x||_1 / ||x||_1 for some x, a lower bound of ||A^-1||_1; the largest is returned."""
    x = solve(np.full(n, 1.0 / n))
    est = float(np.abs(x).sum())
    if n == 1:
        return est
    signs = np.where(x >= 0.0, 1.0, -1.0)
    z = solve(signs, True)
    j = int(np.argmax(np.abs(z)))
    for _ in range(4):
        x = solve(np.eye(1, n, j).ravel())
        previous, est = est, max(est, float(np.abs(x).sum()))
        new_signs = np.where(x >= 0.0, 1.0, -1.0)
        if np.array_equal(new_signs, signs) or est <= previous:  # converged, or cycling
            break
        signs = new_signs
        z = solve(signs, True)
        last, j = j, int(np.argmax(np.abs(z)))
        if z[last] == abs(z[j]):
            break
    alternating = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * (1.0 + np.arange(n) / (n - 1))
    return max(est, 2.0 * float(np.abs(solve(alternating)).sum()) / (3.0 * n))


def weighted_bincount(index: IntArray, weights: FloatArray, minlength: int = 0) -> FloatArray:
    """np.bincount(index, weights, minlength): the sums of ``weights`` per index, float64 (numpy's
    annotations give bincount an integer result whatever the weights)."""
    return cast(FloatArray, np.bincount(index, weights=weights, minlength=minlength))


def _perm_parity(perm: IntArray | Int32Array) -> int:
    """+1 / -1 parity of a permutation array."""
    seen = np.zeros(len(perm), dtype=bool)
    transpositions = 0
    for i in range(len(perm)):
        if not seen[i]:
            j, length = i, 0
            while not seen[j]:
                seen[j] = True
                j = perm[j]
                length += 1
            transpositions += length - 1
    return -1 if transpositions % 2 else 1


class MatrixLayout:
    """Maps (row, col) entries of an n x n matrix to solver storage."""

    def __init__(self, n: int, rows: IntArray, cols: IntArray, kind: str = "auto"):
        self.n = n
        bw = int(np.abs(rows - cols).max()) if len(rows) else 0
        if kind == "auto":  # a band of up to 8 (a beam's 3 DOFs a node, RCM-numbered) is banded at any n
            if bw <= max(8, n // 6):
                kind = "banded"
            elif n <= 300:
                kind = "dense"
            else:
                kind = "sparse"
        self.kind, self.bw = kind, bw
        self.kl = self.ku = self.nrow = 0  # the band's shape (banded storage only)
        if kind == "dense":
            self.size = n * n
        elif kind == "banded":
            kl = ku = bw
            self.kl, self.ku = kl, ku
            self.nrow = 2 * kl + ku + 1
            self.size = self.nrow * n
        else:
            key = cols.astype(np.int64) * n + rows
            uniq, inv = np.unique(key, return_inverse=True)
            self.flat: IntArray = inv
            self.size = len(uniq)
            self.indices = (uniq % n).astype(np.int32)
            self.indptr = np.searchsorted(uniq // n, np.arange(n + 1)).astype(np.int32)
        self._rows, self._cols = rows, cols

    @cached_property
    def flat(self) -> IntArray:
        """The storage index of every (row, col) entry: row-major n x n (dense), LAPACK's band rows
        (banded; as `kernel.CompiledLayout` has them column by column); set in ``__init__`` for sparse
        storage. Worked out when first read (the compiled corrector has its own)."""
        flat: IntArray
        if self.kind == "dense":
            flat = self._rows * self.n + self._cols
        else:
            flat = (self.kl + self.ku + self._rows - self._cols) * self.n + self._cols
        return flat

    @cached_property
    def _entries(self) -> tuple[IntArray, IntArray, IntArray]:
        """One storage index per distinct (row, col) entry (for `to_sparse`, `column_max`)."""
        _, first = np.unique(self._rows.astype(np.int64) * self.n + self._cols, return_index=True)
        return self._rows[first], self._cols[first], self.flat[first]

    @property
    def entry_rows(self) -> IntArray:
        return self._entries[0]

    @property
    def entry_cols(self) -> IntArray:
        return self._entries[1]

    @property
    def entry_flat(self) -> IntArray:
        return self._entries[2]

    def column_max(self, data: FloatArray) -> FloatArray:
        """max_i |A[i, j]| of every column j of the assembled matrix (any storage kind)."""
        out = np.zeros(self.n)
        np.maximum.at(out, self.entry_cols, np.abs(data[self.entry_flat]))
        return out

    def diagonal(self, data: FloatArray) -> FloatArray:
        """A[i, i] of the assembled matrix (any storage kind; 0 where the pattern has no entry)."""
        out = np.zeros(self.n)
        on = self.entry_rows == self.entry_cols
        out[self.entry_rows[on]] = data[self.entry_flat[on]]
        return out

    def scaled(self, data: FloatArray, s: FloatArray) -> FloatArray:
        """The storage of diag(s) A diag(s) (any storage kind)."""
        out = data.copy()
        out[self.entry_flat] *= s[self.entry_rows] * s[self.entry_cols]
        return out

    def norm1(self, data: FloatArray) -> float:
        """||A||_1 = max_j sum_i |A[i, j]| of the assembled matrix (any storage kind)."""
        sums = np.bincount(self.entry_cols, weights=np.abs(data[self.entry_flat]), minlength=self.n)
        return float(sums.max(initial=0.0))

    def assemble(self, values: FloatArray) -> FloatArray:
        return weighted_bincount(self.flat, values, self.size)

    def to_sparse(self, data: FloatArray) -> sp.csc_matrix:
        """The assembled matrix as scipy CSC (any storage kind)."""
        return sp.csc_matrix((data[self.entry_flat], (self.entry_rows, self.entry_cols)), shape=(self.n, self.n))

    def to_dense(self, data: FloatArray) -> FloatArray:
        if self.kind == "dense":
            return data.reshape(self.n, self.n)
        if self.kind == "sparse":
            dense: FloatArray = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.n, self.n)).toarray()
            return dense
        ab = data.reshape(self.nrow, self.n)
        A = np.zeros((self.n, self.n))
        for i in range(self.n):
            for j in range(max(0, i - self.kl), min(self.n, i + self.ku + 1)):
                A[i, j] = ab[self.kl + self.ku + i - j, j]
        return A

    def factor(self, data: FloatArray) -> Factor:
        return Factor(self, data)


class Factor:
    """LU factors of the assembled matrix; ``solve(b)`` and ``det_sign``."""

    final = False  # not known to be of a converged state (`newton.det_sign` confirms a negative sign)

    def __init__(self, layout: MatrixLayout, data: FloatArray):
        self.layout = layout
        n = layout.n
        if n == 0:
            self.kind = "empty"
            return
        self.kind = layout.kind
        if not np.all(np.isfinite(data)):
            raise SingularMatrix("non-finite entries in the tangent")
        if self.kind == "dense":
            A = data.reshape(n, n)
            lu, piv, info = lapack.dgetrf(A)
            if info > 0:
                raise SingularMatrix("singular tangent", column=info - 1)
            self.lu, self.piv = lu, piv
            diag = np.diag(lu)
        elif self.kind == "banded":
            ab = data.reshape(layout.nrow, n)
            lu, piv, info = lapack.dgbtrf(ab, layout.kl, layout.ku)
            if info > 0:
                raise SingularMatrix("singular tangent", column=info - 1)
            self.lu, self.piv = lu, piv
            diag = lu[layout.kl + layout.ku]
        else:
            A = sp.csc_matrix((data, layout.indices, layout.indptr), shape=(n, n))
            try:
                self.lu = spla.splu(A)
            except RuntimeError as exc:
                raise SingularMatrix(str(exc)) from None
            diag = self.lu.U.diagonal()
        self.diag = diag  # the pivots, in elimination order
        # the column of the matrix eliminated at each step (SuperLU permutes the columns)
        self.columns = self.lu.perm_c if self.kind == "sparse" else np.arange(n)
        if np.any(diag == 0.0) or not np.all(np.isfinite(diag)):
            raise SingularMatrix("singular tangent")

    def solve(self, b: FloatArray, transposed: bool = False) -> FloatArray:
        """A^-1 b, or A^-T b when ``transposed``."""
        x: FloatArray
        if self.kind == "empty":
            return np.zeros(0)
        if self.kind == "dense":
            x, info = lapack.dgetrs(self.lu, self.piv, b, trans=int(transposed))
            return x
        if self.kind == "banded":
            x, info = lapack.dgbtrs(self.lu, self.layout.kl, self.layout.ku, b, self.piv, trans=int(transposed))
            return x
        x = self.lu.solve(b, trans="T" if transposed else "N")
        return x

    def rcond(self, anorm: float) -> float:
        """Estimate of the reciprocal condition number 1 / (||A||_1 ||A^-1||_1), ``anorm`` = ||A||_1, with
        ||A^-1||_1 estimated from the factors by `inverse_norm1`: never overestimated, so neither is the
        condition number. (Not LAPACK's ``dgbcon``: its overflow-guarded triangular solves, ``dlatbs``,
        scan the whole solution at every column once the band is ill-conditioned, O(n^2).)"""
        if self.kind == "empty":
            return 1.0
        return 1.0 / (anorm * inverse_norm1(self.solve, self.layout.n))

    @property
    def det_sign(self) -> int:
        if self.kind == "empty":
            return 1
        sign = -1 if np.count_nonzero(self.diag < 0) % 2 else 1
        if self.kind in ("dense", "banded"):
            swaps = int(np.count_nonzero(self.piv != np.arange(len(self.piv))))
            return sign * (-1 if swaps % 2 else 1)
        return sign * _perm_parity(self.lu.perm_r) * _perm_parity(self.lu.perm_c)
