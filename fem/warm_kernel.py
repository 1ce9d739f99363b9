"""The warm start's guess of every load level compiled (numba, ``cache=True``): `warm_start.guess_states`
turned into reduced unknowns (`warm_start.reduced_from_full`) and element chord angles
(`warm_start.chord_angles`) in one call.

The NumPy functions of `warm_start` are the definition (their docstrings give the formulas); this is
the same arithmetic, in the same order, element by element: the positions, midpoints, least-squares
unknowns and chord angles agree with theirs to rounding (the sines, cosines and arctangents are the C
library's here and may differ from NumPy's SIMD ones in the last bit). On the small meshes of an
n/2n error estimate the NumPy version is some thirty NumPy calls on arrays of a few dozen entries,
whose fixed per-call overhead outweighs their arithmetic; this is one call.

The arrays come in three named groups (named tuples, each field read by its name; defined here, as
numba's cache is keyed on this file): `Coarse` (the converged coarse solution and its mesh), `Fine`
(the refined mesh) and `Refinement` (where each fine node comes from).

One module, no call into another file's compiled code: numba's cache is keyed on the defining file
only (`kernel` explains it; `tests/project/test_compiled_cache.py` checks it).

Angles (the chord angles, the end rotations, the tangent angles of the midpoints) are in radians.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from .types import FloatArray, IntArray

__all__ = ["level_guesses_compiled", "Coarse", "Fine", "Refinement"]


class Coarse(NamedTuple):
    """The converged coarse solution (levels rows) and its mesh (nc element nodes, n_el_c elements).

    U     : (levels, coarse full DOFs) full displacements of each level (length, rad)
    X     : (nc, 2) the element nodes' reference positions (length)
    rot   : (nc,) each node's rotation DOF (int)
    edofs : (n_el_c, 6) each element's full DOFs (int)
    beta0 : (n_el_c,) reference chord angles (rad)
    L0    : (n_el_c,) reference lengths (length)
    """

    U: FloatArray
    X: FloatArray
    rot: IntArray
    edofs: IntArray
    beta0: FloatArray
    L0: FloatArray


class Fine(NamedTuple):
    """The refined mesh (nf element nodes, n_el elements, n_red reduced unknowns).

    X             : (nf, 2) the element nodes' reference positions (length)
    rot           : (nf,) each node's rotation DOF (int)
    n_released    : released member-end rotations, full DOFs after the node rotations (as many on
                    the coarse mesh)
    I0            : (fine full DOFs + 1,) the constraint map's first column (int; n_red: no unknown)
    C_independent : (fine full DOFs + 1,) its coefficients times the independence mask
    n_red         : number of reduced unknowns
    edofs         : (n_el, 6) each element's full DOFs (int)
    X1, X2        : (n_el, 2) reference positions of each element's start and end nodes (length)
    beta0         : (n_el,) reference chord angles (rad)
    """

    X: FloatArray
    rot: IntArray
    n_released: int
    I0: IntArray
    C_independent: FloatArray
    n_red: int
    edofs: IntArray
    X1: FloatArray
    X2: FloatArray
    beta0: FloatArray


class Refinement(NamedTuple):
    """Where the fine mesh's nodes come from, every member at once: the nodes both meshes have (coarse
    ``kept_c`` -> fine ``kept_f``), and each coarse element of a refined member (``mid_el``, its start
    and end nodes ``mid_a``, ``mid_b``) with the fine node at its midpoint (``mid_f``); all int."""

    kept_c: IntArray
    kept_f: IntArray
    mid_el: IntArray
    mid_a: IntArray
    mid_b: IntArray
    mid_f: IntArray


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def level_guesses_compiled(coarse: Coarse, fine: Fine, refinement: Refinement) -> tuple[FloatArray, FloatArray]:
    """(q, beta): per level (rows of the coarse full displacements ``coarse.U``) the fine mesh's reduced
    unknowns (levels, n_red) and element chord angles (levels, elements) of the warm-start guess."""
    U_c, Xc, rot_c, edofs_c, beta0_c, L0_c = coarse.U, coarse.X, coarse.rot, coarse.edofs, coarse.beta0, coarse.L0
    Xf, rot_f, n_extra, I0, C_independent = fine.X, fine.rot, fine.n_released, fine.I0, fine.C_independent
    n_red, edofs_f, X1, X2, beta0_f = fine.n_red, fine.edofs, fine.X1, fine.X2, fine.beta0
    kept_c, kept_f = refinement.kept_c, refinement.kept_f
    mid_el, mid_a, mid_b, mid_f = refinement.mid_el, refinement.mid_a, refinement.mid_b, refinement.mid_f
    nl = U_c.shape[0]
    nc, nf = Xc.shape[0], Xf.shape[0]
    n_full = I0.shape[0]  # fine full DOFs with the ground entry
    n_el = edofs_f.shape[0]
    q = np.empty((nl, n_red))
    beta = np.empty((nl, n_el))
    den = np.empty(n_red + 1)
    for i in range(n_red + 1):
        den[i] = 0.0
    for i in range(n_full):
        c = C_independent[i]
        den[I0[i]] += c * c
    U = np.empty(n_full)
    xf = np.empty((nf, 2))
    th_f = np.empty(nf)
    num = np.empty(n_red + 1)
    for lv in range(nl):
        u = U_c[lv]
        for j in range(nf):
            xf[j, 0] = 0.0
            xf[j, 1] = 0.0
            th_f[j] = 0.0
        for k in range(kept_c.shape[0]):
            i, j = kept_c[k], kept_f[k]
            xf[j, 0] = Xc[i, 0] + u[2 * i]
            xf[j, 1] = Xc[i, 1] + u[2 * i + 1]
            th_f[j] = u[rot_c[i]]
        for k in range(mid_el.shape[0]):
            e, a, b, j = mid_el[k], mid_a[k], mid_b[k], mid_f[k]
            t1, t2 = u[edofs_c[e, 2]], u[edofs_c[e, 5]]
            p1, p2 = beta0_c[e] + t1, beta0_c[e] + t2
            h = L0_c[e] / 8
            xf[j, 0] = ((Xc[a, 0] + u[2 * a]) + (Xc[b, 0] + u[2 * b])) / 2 + h * (math.cos(p1) - math.cos(p2))
            xf[j, 1] = ((Xc[a, 1] + u[2 * a + 1]) + (Xc[b, 1] + u[2 * b + 1])) / 2 + h * (math.sin(p1) - math.sin(p2))
            th_f[j] = (t1 + t2) / 2
        for i in range(n_full):
            U[i] = 0.0
        for j in range(nf):
            U[2 * j] = xf[j, 0] - Xf[j, 0]
            U[2 * j + 1] = xf[j, 1] - Xf[j, 1]
            U[rot_f[j]] = th_f[j]
        for k in range(n_extra):
            U[3 * nf + k] = u[3 * nc + k]
        for i in range(n_red + 1):
            num[i] = 0.0
        for i in range(n_full):
            num[I0[i]] += C_independent[i] * U[i]
        for j in range(n_red):
            q[lv, j] = num[j] / (den[j] if den[j] > 0 else 1.0)
        for e in range(n_el):
            dx = X2[e, 0] - X1[e, 0] + U[edofs_f[e, 3]] - U[edofs_f[e, 0]]
            dy = X2[e, 1] - X1[e, 1] + U[edofs_f[e, 4]] - U[edofs_f[e, 1]]
            ref = beta0_f[e] + (U[edofs_f[e, 2]] + U[edofs_f[e, 5]]) / 2
            turn = math.atan2(dy, dx) - ref
            beta[lv, e] = ref + math.atan2(math.sin(turn), math.cos(turn))
    return q, beta
