"""Soft modes of a mechanism's tangent stiffness condensed to its actuation points: an FEM count of
the degrees of freedom that the PRBM's Grubler count [bapat2015, ch. 8, eq 208] predicts.

At a state q (default: unloaded), the reduced tangent K (`assembly.System`) gives the flexibility of
the chosen actuation DOFs u_a = T q (T the rows of du/dq for those DOFs, rigid-link slaves included):

    C_a = T K^-1 T^T,     K_a = C_a^-1     (the stiffness seen at the actuation points, Guyan),

with rotations scaled by a length ``length_scale`` (u = L theta) so that every entry is a force per
length. Its eigenvalues k_1 <= ... <= k_m split into soft (bending) and stiff (stretching) motions;
a mode is *soft* when k_i / k_ref < ``ratio``, k_ref the stretching stiffness of the members
(``reference_stiffness``, e.g. the largest EA/l of the flexible members; default k_m, which is wrong
when artificially stiff bars stand in for rigid links). Bending to stretching stiffness of a beam of thickness t
and length l is of order (t/l)^2, so ``ratio = 1e-2`` separates them for t/l < 0.1 (stated with every
count). The count is the number of independent ways the actuation points can be moved without
stretching a member: the mechanism's mobility as the FEM sees it.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .assembly import System
from .discretise import discretise
from .model import DOF_NAMES, Model, NodeRef
from .types import FloatArray

__all__ = ["SoftModes", "soft_modes"]


@dataclass
class SoftModes:
    count: int  # eigenvalues below ratio x the reference stiffness
    stiffness: FloatArray  # eigenvalues of K_a, ascending (force/length)
    ratios: FloatArray  # stiffness / reference stiffness
    ratio: float  # the threshold used
    dofs: list[tuple[NodeRef, str]]  # the actuation DOFs, (node, 'ux' | 'uy' | 'rz')
    modes: FloatArray  # (m, m) eigenvectors (columns), in the scaled actuation DOFs


def _actuation_rows(system: System, model: Model, dofs: list[tuple[NodeRef, str]], length_scale: float) -> FloatArray:
    """T (m x n): du_a/dq at the unloaded state, rotations times ``length_scale``."""
    d = system.disc
    _, C = system.full_displacements(np.zeros(system.n), system.presc[0] * 0.0)
    T = np.zeros((len(dofs), system.n))
    for row, (node, dof) in enumerate(dofs):
        i = model.node(node)
        k = DOF_NAMES[dof]
        full = 2 * i + k if k < 2 else d.rot_dof[i]
        for w in range(system.width):
            col = system.I[full, w]
            if col < system.n:
                T[row, col] += C[full, w] * (length_scale if k == 2 else 1.0)
    if np.any(~T.any(axis=1)):
        bad = [dofs[r] for r in np.nonzero(~T.any(axis=1))[0]]
        raise ValueError(f"actuation DOFs held by supports or unused: {bad}")
    return T


def soft_modes(
    model: Model,
    dofs: Iterable[tuple[NodeRef, str]],
    ratio: float = 1e-2,
    length_scale: float | None = None,
    reference_stiffness: float | None = None,
) -> SoftModes:
    """Soft modes of the unloaded mechanism at the actuation DOFs ``dofs`` ((node, 'ux'|'uy'|'rz'), ...)."""
    disc = discretise(model)
    system = System(model, disc, solver_kind="dense")
    L = float(length_scale) if length_scale is not None else model.characteristic_length()
    zero = system.loads_at(-1, 0, 0.0)
    ev = system.evaluate(np.zeros(system.n), disc.beta0.copy(), 0.0, *zero)
    K = system.layout.to_dense(ev["K"])
    dofs = list(dofs)
    T = _actuation_rows(system, model, dofs, L)
    flexibility = T @ np.linalg.solve(K, T.T)
    stiffness_matrix = np.linalg.inv(0.5 * (flexibility + flexibility.T))
    values, vectors = np.linalg.eigh(0.5 * (stiffness_matrix + stiffness_matrix.T))
    ratios = values / (float(reference_stiffness) if reference_stiffness is not None else values[-1])
    return SoftModes(int(np.count_nonzero(ratios < ratio)), values, ratios, float(ratio), dofs, vectors)
