"""Residual and consistent tangent of the reduced (constraint-free) system.

With the full DOFs u(q) given by the constraint map of `discretise`
(u_i = sum_w C_iw q_{I_iw} + u_p,i, rigid-link slaves x_s = x_m + R(theta_m) d0),
and the full residual R(u) = f_int(u) - lambda f_ext(u), the reduced system is

    r(q) = J^T R,        J = du/dq,
    K_r  = J^T (K_int - lambda K_load) J + sum_s R_s . d2x_s/dtheta_m^2 ,

with d2x_s/dtheta_m^2 = -(x_s - x_m) for every rigid-link slave s.
External loads: fixed forces and moments F, follower forces
F_i = R(theta_i) F0_i that turn with the node (or member-end) rotation (load
stiffness dF/dtheta = [-F_y, F_x], unsymmetric), forces of magnitude T toward a
fixed point P turned by alpha, F = T R(alpha) e, e = (P - x)/l, l = |P - x|
(load stiffness dF/dx = -T R(alpha)(I - e e^T)/l; symmetric for a rope, alpha = 0),
and uniform distributed loads (consistent nodal loads and load stiffness of
`distributed.element_loads`).  The configuration-dependent intensities (follower
F0, pointed magnitudes [T, 0], distributed q) are the rows of ``F0`` in that
order, so they follow the load path like every other load.  f_int comes from the corotational
elements (`corotational.element_state`) and torsional springs
M = k (theta_a - theta_b).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Any

import numpy as np

from .corotational import element_state
from .distributed import element_loads
from .discretise import Discretisation
from .kernel import Beams, CompiledLayout, Controls, Couplings, DofMap, Storage, scatter
from .linear_solver import MatrixLayout, weighted_bincount
from .model import Model
from .inertia import DENSE_LIMIT, EPS, zero_eigenvalue
from .types import BoolArray, Evaluation, FloatArray, IntArray, Loads

__all__ = ["System"]

SPRING_SIGN = np.array([[1.0, -1.0], [-1.0, 1.0]])  # d(k (theta_a - theta_b)) / d(theta_a, theta_b)
SPRING_SIGN.flags.writeable = False
# the (empty) arrays of what a system lacks, shared; writeable like the others (numba types a read-only
# array apart, and would compile the corrector for it again)
_NO_INTS, _NO_FLOATS, _NO_FLAGS = np.zeros(0, np.int64), np.zeros(0), np.zeros(0, bool)
_NO_POINTS = np.zeros((0, 2))
_NO_LINKS, _NO_LINK_X = np.zeros((0, 4), np.int64), np.zeros((0, 4))


class System:
    """Everything that does not change between Newton iterations."""

    def __init__(self, model: Model, disc: Discretisation, solver_kind: str = "auto", n_levels: int | None = None):
        self.model, self.disc = model, disc
        d = disc
        self.fol_nodes: IntArray
        self.fol_rot: IntArray
        self.pt_nodes: IntArray
        self.pt_toward: FloatArray
        self.pt_angle: FloatArray
        self.dist_follower: BoolArray
        self.dist_members: FloatArray
        self.F0: FloatArray
        self.rows_full: IntArray
        self.cols_full: IntArray
        self.valid: BoolArray
        self.valid_src: IntArray
        self.valid_pair: IntArray
        self.coef_const: FloatArray
        self.n_levels = model.n_levels
        self.X1 = d.X[d.conn[:, 0]]
        self.X2 = d.X[d.conn[:, 1]]
        self.n = d.n_red
        self.width = 2 if len(d.slaves) else 1
        self.I = d.I[:, : self.width]
        self.C0 = d.C[:, : self.width].copy()
        self.I0 = np.ascontiguousarray(d.I[:, 0])
        self.C0_flat = np.ascontiguousarray(self.C0[:, 0])
        # rigid links for the compiled corrector: the second constraint column, the slave and master
        # nodes and rotation DOFs, their reference positions (no rows, none read, without links)
        self.I1: IntArray = _NO_INTS
        self.C1_flat: FloatArray = _NO_FLOATS
        self.links: IntArray = _NO_LINKS
        self.links_X: FloatArray = _NO_LINK_X
        if self.width == 2:
            s, m = d.slaves, d.masters
            self.I1, self.C1_flat = np.ascontiguousarray(d.I[:, 1]), np.ascontiguousarray(d.C[:, 1])
            self.links = np.empty((len(s), 4), np.int64)  # = np.stack([s, m, rot s, rot m], axis=1)
            self.links[:, 0], self.links[:, 1], self.links[:, 2], self.links[:, 3] = s, m, d.rot_dof[s], d.rot_dof[m]
            self.links_X = np.concatenate([d.X[s], d.X[m]], axis=1)
        self._load_tables(model, n_levels)
        rows, cols = self._sparsity()
        self.layout = MatrixLayout(self.n, rows, cols, kind=solver_kind)
        self.spring_sign = SPRING_SIGN
        self.I_flat = self.I.ravel()
        self.L_ref = model.characteristic_length()
        # residual noise from rounding positions: ~ eps * EA per element
        self.noise_floor = 4 * EPS * float((d.ka * d.L0).max(initial=0.0))
        # the compiled corrector's controls of the last options object it ran with (`newton._controls`)
        self.controls: tuple[object, Controls] | None = None
        self.dead_loads = (
            len(self.fol_nodes) == 0
            and not (len(self.pt_angle) and self.pt_angle.any())
            and not (len(self.dist_follower) and self.dist_follower.any())
        )  # `stability.conservative`
        self.beams = Beams(X1=self.X1, X2=self.X2, L0=d.L0, beta0=d.beta0, ka=d.ka, kb=d.kb)
        # the compiled load-control corrector (`kernel.newton_load`), where it applies, and its groups
        self.compiled: CompiledLayout | None = (
            CompiledLayout(self.layout, rows, cols) if CompiledLayout.applies(self) else None
        )
        self.dofs, self.couplings, self.storage = self._kernel_groups()

    def _kernel_groups(self) -> tuple[DofMap, Couplings, Storage | None]:
        """The compiled corrector's groups of this system (`kernel.DofMap`, `kernel.Couplings`,
        `kernel.Storage`; no storage where the corrector does not apply)."""
        d = self.disc
        dofs = DofMap(
            I0=self.I0,
            C0=self.C0_flat,
            I1=self.I1,
            C1=self.C1_flat,
            edofs=d.edofs,
            prescribed=d.prescribed_dofs,
            ground=int(d.ground),
            rotation=d.red_is_rotation,
        )
        couplings = Couplings(links=self.links, links_X=self.links_X, springs=d.springs, spring_k=d.spring_k)
        if self.compiled is None:
            return dofs, couplings, None
        storage = Storage(
            band=self.compiled.band,
            flat=self.compiled.flat,
            source=self.valid_src,
            coef=self.coef_const,
            pair=self.valid_pair,
            rows_full=self.rows_full,
            cols_full=self.cols_full,
        )
        return dofs, couplings, storage

    @cached_property
    def inertia_tol(self) -> float:
        """The threshold of the compiled corrector's inertia test, `stability.zero_eigenvalue` (1, n), where
        `solver._even_crossing` can ask for it (dead loads, n <= DENSE_LIMIT); NaN (no test) elsewhere."""
        return zero_eigenvalue(1.0, self.n) if self.dead_loads and self.n <= DENSE_LIMIT else math.nan

    @cached_property
    def path_weights(self) -> FloatArray:
        """W of the path norm ||dq||_W: rotations weighted by the mean element length squared (read only
        by steps after the first of a level, and by arc length)."""
        d = self.disc
        return np.where(d.red_is_rotation, float(d.L0.sum() / len(d.L0)) ** 2 if len(d.L0) else 1.0, 1.0)

    def _load_tables(self, model: Model, n_levels: int | None) -> None:
        """Fixed forces and moments as full vectors per level (``F_fixed``), the configuration-dependent
        intensities per level (``F0``: followers, pointed magnitudes, distributed loads), prescribed
        values per level, scaled in ``n_levels`` equal levels when asked."""
        d = self.disc
        nf = d.n_full + 1
        # loads: fixed forces/moments as full vectors per level, followers as F0 per level
        nl = self.n_levels
        self.F_fixed = np.zeros((nl, nf))
        fol_nodes: list[int] = []
        fol_vals: list[FloatArray] = []
        for ld in model.loads:
            vals = ld.values
            if len(vals) != nl:  # a single value: same at every level
                vals = np.broadcast_to(vals, (nl,) + vals.shape[1:])
            if ld.kind == "moment":
                dof = d.rot_dof[ld.node] if ld.member is None else d.member_end_dof(ld.member, ld.node)
                self.F_fixed[:, dof] += vals
            elif ld.follower:
                fol_nodes.append(ld.node)
                fol_vals.append(vals)
            else:
                self.F_fixed[:, 2 * ld.node] += vals[:, 0]
                self.F_fixed[:, 2 * ld.node + 1] += vals[:, 1]
        n_el = len(d.L0)
        if not (fol_nodes or model.pointed or model.distributed):  # dead point loads only: the empty tables
            self.fol_nodes = self.fol_rot = self.pt_nodes = _NO_INTS
            self.pt_toward, self.pt_angle, self.dist_follower = _NO_POINTS, _NO_FLOATS, _NO_FLAGS
            self.dist_members, self.F0 = np.zeros((0, n_el)), np.zeros((nl, 0, 2))
        else:
            self._configuration_loads(model, fol_nodes, fol_vals, nl, n_el)
        self.presc = d.prescribed_values.T.copy()  # (nl, n_p)
        if n_levels is not None and n_levels != nl:  # proportional ramp
            ramp = np.arange(1, n_levels + 1) / n_levels
            self.F_fixed = ramp[:, None] * self.F_fixed[-1]
            self.F0 = ramp[:, None, None] * self.F0[-1]
            self.presc = ramp[:, None] * self.presc[-1]
            self.n_levels = n_levels

    def _configuration_loads(
        self, model: Model, fol_nodes: list[int], fol_vals: list[FloatArray], nl: int, n_el: int
    ) -> None:
        """The tables of the loads that depend on the configuration: followers (their nodes, the rotation
        each turns with), forces toward points, distributed loads (the elements each covers); their
        intensities per level in ``F0``."""
        d = self.disc
        self.fol_nodes = np.array(fol_nodes, dtype=int)
        self.fol_rot = np.array(
            [
                d.rot_dof[ld.node] if ld.member is None else d.member_end_dof(ld.member, ld.node)
                for ld in model.loads
                if ld.kind == "force" and ld.follower
            ],
            dtype=int,
        )
        if model.pointed:
            self.pt_nodes = np.array([ld.node for ld in model.pointed], dtype=int)
            self.pt_toward = np.array([ld.toward for ld in model.pointed], dtype=float).reshape(-1, 2)
            self.pt_angle = np.array([ld.angle for ld in model.pointed], dtype=float)
        else:
            self.pt_nodes, self.pt_toward, self.pt_angle = _NO_INTS, _NO_POINTS, _NO_FLOATS
        for pointed in model.pointed:
            fol_vals.append(np.column_stack([np.broadcast_to(pointed.values, (nl,)), np.zeros(nl)]))
        self.dist_members = np.zeros((len(model.distributed), n_el))  # which elements each load covers
        self.dist_follower = np.array([dl.follower for dl in model.distributed], dtype=bool)
        for k, dl in enumerate(model.distributed):
            self.dist_members[k, d.member_elements[dl.member] if dl.member is not None else slice(None)] = 1.0
            fol_vals.append(np.broadcast_to(dl.values, (nl, 2)))
        self.F0 = np.array(fol_vals).reshape(len(fol_vals), nl, 2).transpose(1, 0, 2)

    def _sparsity(self) -> tuple[IntArray, IntArray]:
        """Rows and columns of the reduced tangent's entries (elements, springs, follower and pointed
        loads, rigid links), with which full entry feeds each and the constant factor without rigid
        links."""
        d = self.disc
        # full-level sparsity pattern: elements, springs, follower, rigid links (only the parts present)
        e = d.edofs
        rows = [np.repeat(e, 6, axis=1).ravel()]  # entry (i, j) of element k at 36 k + 6 i + j
        cols = [np.concatenate([e] * 6, axis=1).ravel()]  # = np.tile(e, (1, 6)), without tile's overhead
        if len(d.springs):
            rows.append(np.repeat(d.springs, 2, axis=1).ravel())
            cols.append(np.tile(d.springs, (1, 2)).ravel())
        if len(self.fol_nodes):
            rows.append(np.concatenate([2 * self.fol_nodes, 2 * self.fol_nodes + 1]))
            cols.append(np.concatenate([self.fol_rot] * 2))
        if len(self.pt_nodes):
            pt = np.column_stack([2 * self.pt_nodes, 2 * self.pt_nodes + 1])  # 2x2 block per pointed force
            rows.append(np.repeat(pt, 2, axis=1).ravel())
            cols.append(np.tile(pt, (1, 2)).ravel())
        if len(d.masters):
            mr = d.rot_dof[d.masters]
            rows.append(mr)
            cols.append(mr)
        self.rows_full = np.concatenate(rows) if len(rows) > 1 else rows[0]
        self.cols_full = np.concatenate(cols) if len(cols) > 1 else cols[0]
        w = self.width
        if w == 1:  # one column per row: the same arrays as the broadcast below, without it
            R, Cc = self.I0[self.rows_full], self.I0[self.cols_full]
            prod = self.C0_flat[self.rows_full] * self.C0_flat[self.cols_full]
        else:  # entry (k, a, b) at w^2 k + w a + b: row column a of entry k, column column b
            # (np.broadcast_arrays of [:, :, None] against [:, None, :], without its overhead)
            R = np.repeat(self.I[self.rows_full], w, axis=1).ravel()
            Cc = np.concatenate([self.I[self.cols_full]] * w, axis=1).ravel()
            prod = (
                np.repeat(self.C0[self.rows_full], w, axis=1).ravel()
                * np.concatenate([self.C0[self.cols_full]] * w, axis=1).ravel()
            )
        self.valid = (R < self.n) & (Cc < self.n)
        # without rigid links the constraint coefficients are constant: precompute
        # which full entry feeds each reduced entry, and with what factor
        self.valid_src = self.valid.nonzero()[0]
        self.valid_pair = _NO_INTS  # with them: which two columns, 2 w1 + w2, of each entry
        if w != 1:
            self.valid_pair = self.valid_src % (w * w)
            self.valid_src //= w * w
        self.coef_const = prod[self.valid]
        return R[self.valid], Cc[self.valid]

    # -- loads along a path ------------------------------------------------
    def loads_at(self, level_a: int, level_b: int, t: float) -> Loads:
        """Fixed vector, follower F0 and prescribed values between two levels.

        level_a = -1 means the unloaded state.
        """
        return (
            _between(self.F_fixed, level_a, level_b, t),
            _between(self.F0, level_a, level_b, t),
            _between(self.presc, level_a, level_b, t),
        )

    # -- kinematics -----------------------------------------------------------
    def full_displacements(self, q: FloatArray, presc: FloatArray) -> tuple[FloatArray, FloatArray]:
        """u (n_full+1,) and the current constraint coefficients C."""
        d = self.disc
        qx = np.append(q, 0.0)
        C = self.C0
        u = (C * qx[self.I]).sum(axis=1)
        u[d.prescribed_dofs] = presc
        if len(d.slaves):
            C = C.copy()
            s, m = d.slaves, d.masters
            th = u[d.rot_dof[m]]
            d0 = d.X[s] - d.X[m]
            cs, sn = np.cos(th), np.sin(th)
            Rd = np.column_stack([cs * d0[:, 0] - sn * d0[:, 1], sn * d0[:, 0] + cs * d0[:, 1]])
            u[2 * s] = u[2 * m] + Rd[:, 0] - d0[:, 0]
            u[2 * s + 1] = u[2 * m + 1] + Rd[:, 1] - d0[:, 1]
            u[d.rot_dof[s]] = th
            C[2 * s, 1] = -Rd[:, 1]
            C[2 * s + 1, 1] = Rd[:, 0]
        return u, C

    def _pointed(self, u: FloatArray, magnitude: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Forces toward fixed points, F = T R(alpha) e, and their stiffness dF/dx (n_pt, 2, 2)."""
        n = self.pt_nodes
        x = self.disc.X[n] + np.column_stack([u[2 * n], u[2 * n + 1]])
        r = self.pt_toward - x
        length = np.hypot(r[:, 0], r[:, 1])
        if np.any(length == 0.0):
            raise ValueError("a force toward a fixed point reached that point (direction undefined)")
        e = r / length[:, None]
        cs, sn = np.cos(self.pt_angle), np.sin(self.pt_angle)
        rot = np.stack([np.column_stack([cs, -sn]), np.column_stack([sn, cs])], axis=1)  # R(alpha)
        F: FloatArray = magnitude[:, None] * np.einsum("kij,kj->ki", rot, e)
        proj = np.eye(2)[None] - e[:, :, None] * e[:, None, :]
        K = -(magnitude / length)[:, None, None] * np.matmul(rot, proj)
        return F, K

    def reduce(self, v_full: FloatArray, C: FloatArray) -> FloatArray:
        """J^T v."""
        return weighted_bincount(self.I_flat, (C * v_full[:, None]).ravel(), self.n + 1)[: self.n]

    def evaluate(
        self,
        q: FloatArray,
        beta_prev: FloatArray,
        lam: float,
        F_fixed: FloatArray,
        F0: FloatArray,
        presc: FloatArray,
        need_K: bool = True,
    ) -> Evaluation:
        """Residual, tangent and element state at q for load factor lam."""
        d = self.disc
        u, C = self.full_displacements(q, presc)
        p = u[d.edofs]
        el = element_state(self.beams, p, beta_prev, need_K)
        nf = d.n_full + 1
        f_int = np.bincount(d.edofs.ravel(), weights=el["f"].ravel(), minlength=nf).astype(float)
        if len(d.springs):
            m_sp = d.spring_k * (u[d.springs[:, 0]] - u[d.springs[:, 1]])
            f_int += np.bincount(d.springs.ravel(), weights=np.column_stack([m_sp, -m_sp]).ravel(), minlength=nf)
        f_ref = F_fixed.copy()
        n_fol, n_pt = len(self.fol_nodes), len(self.pt_nodes)
        if n_fol:
            th = u[self.fol_rot]
            cs, sn = np.cos(th), np.sin(th)
            Fx = cs * F0[:n_fol, 0] - sn * F0[:n_fol, 1]
            Fy = sn * F0[:n_fol, 0] + cs * F0[:n_fol, 1]
            np.add.at(f_ref, 2 * self.fol_nodes, Fx)
            np.add.at(f_ref, 2 * self.fol_nodes + 1, Fy)
        if n_pt:
            F_pt, K_pt = self._pointed(u, F0[n_fol : n_fol + n_pt, 0])
            np.add.at(f_ref, 2 * self.pt_nodes, F_pt[:, 0])
            np.add.at(f_ref, 2 * self.pt_nodes + 1, F_pt[:, 1])
        K_el = el["K"] if need_K else _NO_FLOATS
        if len(self.dist_follower):
            q_dist = F0[n_fol + n_pt :]
            q_dead = self.dist_members[~self.dist_follower].T @ q_dist[~self.dist_follower]
            q_fol = self.dist_members[self.dist_follower].T @ q_dist[self.dist_follower]
            f_q, K_q = element_loads(self.beams, p, el["beta"], q_dead, q_fol)
            f_ref += np.bincount(d.edofs.ravel(), weights=f_q.ravel(), minlength=nf)
            if need_K:
                K_el = K_el - lam * K_q
        f_ref[d.ground] = 0.0
        f_int[d.ground] = 0.0
        R_full = f_int - lam * f_ref
        out: dict[str, Any] = dict(
            u=u,
            C=C,
            el=el,
            f_int=f_int,
            f_ref_full=f_ref,
            R_full=R_full,
            r=self.reduce(R_full, C),
            f_ref=self.reduce(f_ref, C),
        )
        f_ext = lam * f_ref  # norms as np.linalg.norm computes them, sqrt(x . x), without its overhead
        out["F_scale"] = max(math.sqrt(float(f_ext.dot(f_ext))), math.sqrt(float(f_int.dot(f_int))))
        if need_K:
            vals = [K_el.ravel(), (d.spring_k[:, None, None] * self.spring_sign).ravel()]
            if n_fol:
                vals.append(lam * np.concatenate([Fy, -Fx]))
            if n_pt:
                vals.append(-lam * K_pt.ravel())
            if len(d.slaves):
                s, m = d.slaves, d.masters
                xs = d.X[s, 0] + u[2 * s] - d.X[m, 0] - u[2 * m]
                ys = d.X[s, 1] + u[2 * s + 1] - d.X[m, 1] - u[2 * m + 1]
                vals.append(-(R_full[2 * s] * xs + R_full[2 * s + 1] * ys))
            v = np.concatenate(vals)
            if len(d.slaves):
                Cr = C[self.rows_full][:, :, None]
                Ccol = C[self.cols_full][:, None, :]
                red = (v[:, None, None] * Cr * Ccol).ravel()[self.valid]
                out["K"] = self.layout.assemble(red)
            else:  # constant constraint coefficients: one compiled scatter into solver storage
                out["K"] = scatter(self.layout.flat, self.valid_src, self.coef_const, v, self.layout.size)
        return out


def _between(table: FloatArray, level_a: int, level_b: int, t: float) -> FloatArray:
    """(1 - t) table[level_a] + t table[level_b], a new array (level_a = -1: the unloaded state, zero),
    exact at t = 0 and t = 1."""
    b: FloatArray = table[level_b]
    if t == 1.0:  # (1 - t) a + t b = b exactly
        return b.copy()
    if level_a < 0:  # (1 - t) 0 + t b = t b exactly
        return np.zeros_like(table[0]) if t == 0.0 else t * b
    a: FloatArray = table[level_a]
    return a.copy() if t == 0.0 else (1.0 - t) * a + t * b
