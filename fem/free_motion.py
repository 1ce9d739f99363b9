"""A model that can move without deforming: the last line of defence before any Newton step.

A structure held by its supports has a non-singular reduced stiffness at the unloaded state
(q = 0, lambda = 0, no prescribed motion), K_0 = J^T K_int(0) J (`assembly.System`): every motion
of the free DOFs stretches or bends some member or turns some spring. A body that can move as a
rigid body (too few supports, a revolute joint with nothing to turn against) has a motion v with
K_0 v = 0, and Gaussian elimination of K_0 then meets a pivot that is zero up to rounding:

    |u_kk| <= PIVOT_TOL * max_i |K_0[i, k]|        (column k of the LU factors, k = 0 .. n-1).

Rounding leaves such a pivot at about eps times the column's largest entry; a held structure's
smallest pivot is at least its softest stiffness over its stiffest one, which for a beam of
thickness h and element length l_e is of order (h / l_e)^2 / n^2 -- far above 1e-13 for the
meshes the models use. The DOF of that column (node and 'ux' | 'uy' | 'rz') is named in the
error, before any Newton correction. A load-controlled run on the compiled corrector that starts from
the unloaded state with nothing prescribed and no force on a rigid link's slave makes the test on the
factors of its first iteration, whose tangent is exactly the unloaded one (`kernel.newton_load`'s
``check``, `refusal`), instead of a factorisation of its own; every other run is tested here first
(`check_held`).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import numpy as np

from .linear_solver import SingularMatrix
from .newton import PIVOT_TOL, Unheld, unloaded_check

__all__ = ["FreeMotion", "check_held", "refusal", "PIVOT_TOL"]


class FreeMotion(ValueError):
    """The model can move as a rigid body (or a mechanism) at the unloaded state."""


def _dof_label(system, k: int) -> str:
    """'node <name> <dof>' of reduced DOF k (the first full DOF that maps to it)."""
    d = system.disc
    names = system.model.node_names
    full = int(np.nonzero(d.I[:, 0] == k)[0][0])
    n_en = len(d.X)
    if full < 2 * n_en:
        node, dof = full // 2, ("ux", "uy")[full % 2]
    elif full < 3 * n_en:
        node, dof = full - 2 * n_en, "rz"
    else:      # a released member-end rotation: the joint node that owns it
        node = int(np.nonzero((d.edofs[:, [2, 5]] == full).any(axis=1))[0][0])
        ends = d.conn[node]
        node, dof = int(ends[np.argmax(d.edofs[node, [2, 5]] == full)]), "rz (member end at a joint)"
    where = names[node] if node < d.n_model_nodes else _interior(system, node)
    return f"{where} {dof}"


def _interior(system, node: int) -> str:
    d = system.disc
    e = int(np.nonzero((d.conn == node).any(axis=1))[0][0])
    member = system.model.members[int(d.el_member[e])]
    return f"an interior node of member {member.name!r}"


def refusal(system, unheld: Unheld) -> FreeMotion:
    """The error naming the free DOF of a failed compiled test (`kernel.newton_load`'s ``check``: made
    beforehand by `check_held`, or on a run's own first factors by `solver.solve_load`): an empty
    column first (a DOF nothing touches), else the smallest pivot ratio (an exactly zero pivot's is 0)."""
    column = unheld.column
    k = np.argmin(column) if column.min() == 0.0 else np.argmin(unheld.ratios)
    return FreeMotion(_message(system, int(k)))


def check_held(system) -> None:
    """Raise `FreeMotion` naming the free DOF when the unloaded reduced stiffness is singular."""
    if system.n == 0:
        return
    if system.compiled is not None:     # the compiled corrector's factors of the unloaded tangent
        unheld = unloaded_check(system)
        if unheld is not None:
            raise refusal(system, unheld)
        return
    zero = system.loads_at(-1, 0, 0.0)
    ev = system.evaluate(np.zeros(system.n), system.disc.beta0.copy(), 0.0, *zero, need_K=True)
    column = system.layout.column_max(ev["K"])
    try:
        fac = system.layout.factor(ev["K"])
    except SingularMatrix as exc:
        k = exc.column if exc.column is not None else int(np.argmin(column))
    else:
        held = column[fac.columns]
        ratio = np.abs(fac.diag) / np.where(held > 0.0, held, 1.0)
        k = int(fac.columns[int(np.argmin(ratio))])
        if ratio.min() > PIVOT_TOL and column.min() > 0.0:
            return
    if column.min() == 0.0:      # a DOF nothing touches
        k = int(np.argmin(column))
    raise FreeMotion(_message(system, k))


def _message(system, k: int) -> str:
    return (f"the model can move without deforming (a rigid-body motion or a mechanism): "
            f"no stiffness holds {_dof_label(system, k)} at the unloaded state; "
            "add a support, a joint spring or a member there")
