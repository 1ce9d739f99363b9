"""Warm start of a solve on a refined mesh from a converged coarser result.

With every member of the fine mesh split into twice as many elements, the
fine nodes are the coarse nodes plus one midpoint per coarse element (a member
that is not refined, `Model.add_member`'s ``refined=False``, keeps its nodes and
their states).  At a
midpoint the deformed position is taken from the cubic Hermite curve through
the element's end positions x1, x2 with end tangent angles phi_i = beta0 + theta_i:

    x_mid = (x1 + x2)/2 + L0/8 (t(phi_1) - t(phi_2)),   t(phi) = (cos phi, sin phi),
    theta_mid = (theta_1 + theta_2)/2,

which is O(h^4)-accurate for smooth deformations.  The reduced unknowns follow
by least squares through the constraint map, q_k = sum C_ik u_i / sum C_ik^2
(exact for free DOFs and sliders u = d t).  The solver uses the guess as the
predictor of each load level and checks that the converged state stays on the
same branch; otherwise it falls back to ordinary load stepping.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from dataclasses import dataclass
import numpy as np

from .discretise import Discretisation
from .types import FloatArray, IntArray, Recorded
from .warm_kernel import Coarse, Fine, Refinement, level_guesses_compiled

__all__ = ["guess_states", "LevelGuesses", "level_guesses"]


@dataclass(frozen=True)
class LevelGuesses:
    """The predictor of every load level on the fine mesh: reduced unknowns ``q`` (levels, n) and
    element chord angles ``beta`` (levels, elements)."""

    q: FloatArray
    beta: FloatArray


def level_guesses(coarse: Recorded, disc_fine: Discretisation, X1: FloatArray, X2: FloatArray) -> LevelGuesses:
    """`guess_states` of every level turned into reduced unknowns and chord angles, all levels at once
    (the numbers of `reduced_from_full` and `chord_angles` level by level, to rounding), by the
    compiled `warm_kernel.level_guesses_compiled`. ``X1``, ``X2``: the fine elements' start and end
    nodes (length)."""
    dc: Discretisation = coarse.extra["disc"]
    df = _checked_fine(dc, disc_fine)
    coarse_group = Coarse(
        U=np.ascontiguousarray(coarse.extra["u_full"], dtype=float),
        X=dc.X,
        rot=dc.rot_dof,
        edofs=dc.edofs,
        beta0=dc.beta0,
        L0=dc.L0,
    )
    fine_group = Fine(
        X=df.X,
        rot=df.rot_dof,
        n_released=int(df.n_full - 3 * len(df.X)),
        I0=np.ascontiguousarray(df.I[:, 0]),
        C_independent=df.C[:, 0] * df.independent,
        n_red=int(df.n_red),
        edofs=df.edofs,
        X1=X1,
        X2=X2,
        beta0=df.beta0,
    )
    q, beta = level_guesses_compiled(coarse_group, fine_group, _refinement(dc, df))
    return LevelGuesses(q, beta)


def _checked_fine(dc: Discretisation, disc_fine: Discretisation) -> Discretisation:
    """``disc_fine`` when it refines ``dc`` (each member split in two, or kept), else ValueError."""
    if len(dc.member_elements) != len(disc_fine.member_elements) or any(
        len(b) not in (len(a), 2 * len(a)) for a, b in zip(dc.member_elements, disc_fine.member_elements)
    ):
        raise ValueError(
            "initial_guess must come from the same model with half the elements (or as many, "
            "for a member that is not refined)"
        )
    return disc_fine


def _chain(disc: Discretisation, els: IntArray) -> list[int]:
    """A member's nodes in order: its first element's start, then every element's end."""
    ends: list[int] = disc.conn[els, 1].tolist()
    return [int(disc.conn[els[0], 0])] + ends


def _refinement(dc: Discretisation, df: Discretisation) -> Refinement:
    """`warm_kernel.Refinement` of the fine discretisation ``df`` from the coarse ``dc`` (members in the
    same order), from the members' node chains in plain Python (a few members)."""
    kept_c: list[int] = []
    kept_f: list[int] = []
    mid_el: list[int] = []
    mid_a: list[int] = []
    mid_b: list[int] = []
    mid_f: list[int] = []
    for els_c, els_f in zip(dc.member_elements, df.member_elements):
        cc, cf = _chain(dc, els_c), _chain(df, els_f)
        step = 1 if len(cf) == len(cc) else 2  # 1: a member that is not refined, no midpoints
        kept_c += cc
        kept_f += cf[::step]
        if step == 2:
            mid_el += els_c.tolist()
            mid_a += cc[:-1]
            mid_b += cc[1:]
            mid_f += cf[1::2]

    def ints(v: list[int]) -> IntArray:
        return np.array(v, dtype=np.int64)

    return Refinement(
        kept_c=ints(kept_c),
        kept_f=ints(kept_f),
        mid_el=ints(mid_el),
        mid_a=ints(mid_a),
        mid_b=ints(mid_b),
        mid_f=ints(mid_f),
    )


def guess_states(coarse: Recorded, disc_fine: Discretisation) -> FloatArray:
    """Per level (rows): full displacement vector on the fine mesh from a coarse FemResult (every
    member's nodes and midpoints at once, `_refinement`: each node's and each midpoint's numbers are
    those of the member-by-member formulas above)."""
    dc = coarse.extra["disc"]
    ref = _refinement(dc, _checked_fine(dc, disc_fine))
    nc, nf = len(dc.X), len(disc_fine.X)
    U_c = np.asarray(coarse.extra["u_full"], dtype=float)  # (levels, coarse DOFs): every level at once
    nl = len(U_c)
    U = np.zeros((nl, disc_fine.n_full + 1))
    xc = dc.X + U_c[:, : 2 * nc].reshape(nl, nc, 2)  # node i's (ux, uy) are DOFs 2i, 2i + 1
    th_c = U_c[:, dc.rot_dof]
    xf = np.zeros((nl, nf, 2))
    th_f = np.zeros((nl, nf))
    xf[:, ref.kept_f] = xc[:, ref.kept_c]
    th_f[:, ref.kept_f] = th_c[:, ref.kept_c]
    if len(ref.mid_el):
        # midpoints: Hermite curve of each coarse element (end rotations of the element)
        els = ref.mid_el
        t1 = U_c[:, dc.edofs[els, 2]]
        t2 = U_c[:, dc.edofs[els, 5]]
        p1, p2 = dc.beta0[els] + t1, dc.beta0[els] + t2
        tangents = np.empty(p1.shape + (2,))  # t(phi_1) - t(phi_2)
        tangents[..., 0] = np.cos(p1) - np.cos(p2)
        tangents[..., 1] = np.sin(p1) - np.sin(p2)
        xf[:, ref.mid_f] = (xc[:, ref.mid_a] + xc[:, ref.mid_b]) / 2 + (dc.L0[els] / 8)[None, :, None] * tangents
        th_f[:, ref.mid_f] = (t1 + t2) / 2
    d = xf - disc_fine.X
    U[:, 0 : 2 * nf : 2], U[:, 1 : 2 * nf : 2] = d[..., 0], d[..., 1]
    U[:, disc_fine.rot_dof] = th_f
    n_extra = disc_fine.n_full - 3 * nf
    U[:, 3 * nf : 3 * nf + n_extra] = U_c[:, 3 * nc : 3 * nc + n_extra]  # released member-end rotations
    return U


def reduced_from_full(disc: Discretisation, u: FloatArray) -> FloatArray:
    """Least-squares reduced unknowns q for a full displacement vector u, or for each row of u (levels):
    one bincount over the rows, each row's bins apart, so every unknown sums its terms in the same
    order as for one vector."""
    I, C = disc.I[:, 0], disc.C[:, 0] * disc.independent
    width = disc.n_red + 1
    rows = u.reshape(-1, len(I))
    bins = (np.arange(len(rows)) * width)[:, None] + I
    num = np.bincount(bins.ravel(), weights=(C * rows).ravel(), minlength=len(rows) * width)
    num = num.reshape(len(rows), width)[:, : disc.n_red]
    den = np.bincount(I, weights=C * C, minlength=width)[: disc.n_red]
    q = num / np.where(den > 0, den, 1.0)
    return q.reshape(u.shape[:-1] + (disc.n_red,))


def chord_angles(disc: Discretisation, u: FloatArray, X1: FloatArray, X2: FloatArray) -> FloatArray:
    """Chord angles of the elements, continuous with beta0 + mean end rotation (for u, or each row of u)."""
    p = u[..., disc.edofs]
    dx = X2[:, 0] - X1[:, 0] + p[..., 3] - p[..., 0]
    dy = X2[:, 1] - X1[:, 1] + p[..., 4] - p[..., 1]
    ref = disc.beta0 + (p[..., 2] + p[..., 5]) / 2
    turn = np.arctan2(dy, dx) - ref
    return ref + np.arctan2(np.sin(turn), np.cos(turn))
