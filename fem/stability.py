"""Stability of converged equilibria, and branch switching to a stable state.

Dead (conservative) loads: an equilibrium q* of the total potential

    Pi(q) = U(q) - lambda f_ref . u(q)

is stable iff the reduced tangent K = d2 Pi / dq2 is positive definite (Lagrange-
Dirichlet; prescribed DOFs are already eliminated from q, and under displacement
control the control DOF q_c is held too, so K_ff = K without row and column c).

Watching it costs nothing extra: the sign of det K comes from the LU factors the
solvers already have (Sylvester: one eigenvalue through zero flips it), and under
displacement control  sign det K_ff = sign det K * sign (K^-1)_cc  (Cramer), one
back-solve.  When a step takes a stable state to sign det < 0, the lowest
eigenpairs of K (dense `eigh` for small systems, shift-invert Lanczos about 0
otherwise) confirm it, and the branch is switched (Riks 1984; Wagner & Wriggers
1988): starting from  q* +- a phi_1  (phi_1 the eigenvector of the most negative
eigenvalue, amplitudes a growing), Newton is rerun at the same load; a candidate
counts when it converged, passes the rotation-continuity checks, left q*, and is
stable itself.  Of the stable candidates on the two sides, the one connected to the path
is kept: the side s with  s phi_1 . (q_prev - q*) > 0, towards the last stable state of the
path q_prev.  Above a critical load the near-straight equilibrium q* of an imperfect member
is deflected against the imperfection (w = e / (1 - P/P_cr) < 0), so the connected branch,
bent the way the imperfection pushes, lies back towards q_prev.  Neither the lower total
potential Pi (a column pushed to +y far past its critical load has a deeper minimum at -y)
nor the work of the loads at q*, f . phi_1 = f_int(q*) . phi_1 (it points to the side q*
is already deflected to, against the imperfection), says which branch is connected.  Only
when phi_1 . (q_prev - q*) vanishes (a perfect bifurcation) the lower Pi decides.  The
solvers cut a long step that lands on an unstable state before switching: a step too long
for an imperfect path is cured by a shorter one.

Follower loads make K unsymmetric and the static criterion incomplete (flutter):
there a sign change is reported, not acted on.  Limitation: two eigenvalues
crossing zero within one step leave sign det K unchanged and go unnoticed.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.linalg import lapack

from .corotational import strain_energy
from .inertia import DENSE_LIMIT, zero_eigenvalue
from .linear_solver import Factor, SingularMatrix
from .newton import Control, StepFailed, accept_check, newton
from .options import BranchSwitch, NewtonOutcome, SolveOptions, SwitchStatus
from .types import BoolArray, Evaluation, FloatArray, IntArray, Loads

if TYPE_CHECKING:
    from .assembly import System

__all__ = [
    "conservative",
    "eigenvalue_below",
    "held_sign",
    "lowest_modes",
    "potential",
    "switch_branch",
    "DENSE_LIMIT",
    "zero_eigenvalue",
]

AMPLITUDE = 1e-3  # of L_ref: largest translation of the perturbation (no stretching)
SIDE_TOL = 1e-8  # |phi . (q_prev - q*)| / (|phi| |q_prev - q*|) below this: no side


def conservative(system: System) -> bool:
    """Dead loads only (no followers, no force at an angle to the line to a fixed point): K is
    symmetric, K = d2 Pi / dq2 (a rope force toward a fixed point and a dead distributed load are
    conservative)."""
    return system.dead_loads


def held_sign(fac: Factor, det_sign: int, held: int | None) -> int:
    """sign det K_ff with DOF `held` removed: sign det K * sign (K^-1)_hh (Cramer)."""
    if held is None:
        return det_sign
    e = np.zeros(fac.layout.n)
    e[held] = 1.0
    x = float(fac.solve(e)[held])
    return det_sign * (1 if x > 0 else -1 if x < 0 else 0)


def lowest_modes(
    system: System, K: FloatArray, held: int | None = None, count: int = 2
) -> tuple[FloatArray, FloatArray]:
    """The `count` lowest eigenvalues of the Jacobi-scaled K (or K_ff, DOF `held` removed),
    S K S with S = diag(|K_ii|)^(-1/2), ascending, and the directions S psi in reduced coordinates
    (unit length).

    The scaling is a congruence, so it keeps the inertia (the signs of the eigenvalues, Sylvester)
    while putting axial and bending terms on one scale: in a slender beam they differ by (L/h)^2,
    which in unscaled form hides a negative bending eigenvalue below the rounding of the axial
    ones. Eigenvalues are therefore relative to a unit diagonal (see ``zero_eigenvalue``)."""
    A = system.layout.to_sparse(K)
    keep = np.arange(system.n) if held is None else np.delete(np.arange(system.n), held)
    A = A[keep][:, keep]
    A = 0.5 * (A + A.T)
    d = np.sqrt(np.abs(A.diagonal()))
    d[d == 0.0] = 1.0
    S = sp.diags(1.0 / d)
    A = (S @ A @ S).tocsr()
    m = A.shape[0]
    count = max(1, min(count, m - 1)) if m > 1 else 1
    if m <= DENSE_LIMIT:
        vals, vecs = sla.eigh(A.toarray(), subset_by_index=[0, count - 1])
    else:  # eigenvalues nearest zero: the ones that just crossed
        vals, vecs = spla.eigsh(A.tocsc(), k=count, sigma=0.0, which="LM")
        order = np.argsort(vals)
        vals, vecs = vals[order], vecs[:, order]
    vecs = vecs / d[:, None]
    vecs = vecs / np.linalg.norm(vecs, axis=0)
    full = np.zeros((system.n, len(vals)))
    full[keep] = vecs
    return vals, full


@lru_cache(maxsize=32)
def _upper_band(n: int, ku: int) -> tuple[BoolArray, IntArray, IntArray]:
    """The entries of the upper band storage (ku + 1, n) that lie in the matrix (row i = j + r - ku >= 0),
    as a mask, and their rows i and columns j (read-only: the same for every step of a system)."""
    j = np.broadcast_to(np.arange(n), (ku + 1, n))
    i = j + np.arange(-ku, 1)[:, None]
    inside = i >= 0
    rows: IntArray = i[inside]
    cols: IntArray = j[inside]
    for a in (inside, rows, cols):
        a.flags.writeable = False
    return inside, rows, cols


def eigenvalue_below(system: System, K: FloatArray, held: int | None, tol: float) -> bool:
    """True when the Jacobi-scaled K (K_ff with DOF ``held`` removed, see `lowest_modes`) has an
    eigenvalue below -tol, without an eigensolver: Cholesky of  S K S + tol I  succeeds iff every
    eigenvalue of S K S exceeds -tol (Sylvester's law of inertia). The held DOF's row and column are
    replaced by a unit diagonal (one positive eigenvalue, the others those of K_ff). Banded storage
    is factorised as a band (LAPACK dpbtrf, O(n b^2)), dense storage by dpotrf; sparse storage by
    the lowest eigenvalue (`lowest_modes`). K is symmetric (dead loads): its upper triangle is used."""
    layout, n = system.layout, system.n
    if layout.kind == "banded":
        ab = K.reshape(layout.nrow, n)
        ku = layout.ku
        upper = ab[layout.kl : layout.kl + ku + 1].copy()  # upper[ku + i - j, j] = K[i, j], i <= j
        d = np.sqrt(np.abs(upper[ku]))
        d[d == 0.0] = 1.0
        inside, i, j = _upper_band(n, ku)
        upper[inside] /= d[i] * d[j]
        if held is not None:
            upper[inside] = np.where((i == held) | (j == held), 0.0, upper[inside])
            upper[ku, held] = 1.0
        upper[ku] += tol
        _, info = lapack.dpbtrf(upper, lower=0, overwrite_ab=1)
        return bool(info > 0)
    if layout.kind == "dense":
        A = K.reshape(n, n)
        A = A + A.T  # a new array, scaled in place: the same floats as
        A *= 0.5  # 0.5 (A + A^T) / d_i / d_j in new arrays
        d = np.sqrt(np.abs(A.diagonal()))
        d[d == 0.0] = 1.0
        A /= d[:, None]
        A /= d
        if held is not None:
            A[held, :] = 0.0
            A[:, held] = 0.0
            A[held, held] = 1.0
        A.flat[:: n + 1] += tol  # the diagonal
        _, info = lapack.dpotrf(A, lower=0, overwrite_a=1)
        return bool(info > 0)
    vals, _ = lowest_modes(system, K, held, count=1)
    return bool(vals[0] < -tol)


def potential(system: System, ev: Evaluation, lam: float) -> float:
    """Total potential Pi = U - lambda f_ref . u of a state (dead loads)."""
    d = system.disc
    el, u = ev["el"], ev["u"]
    energy = float(strain_energy(d.ka, d.kb, el["u_bar"], el["theta_bar"]).sum())
    if len(d.springs):
        dth = u[d.springs[:, 0]] - u[d.springs[:, 1]]
        energy += 0.5 * float(np.sum(d.spring_k * dth**2))
    return energy - lam * float(np.dot(ev["f_ref_full"][: d.n_full], u[: d.n_full]))


def _lowest(A: sp.csr_matrix) -> float:
    """Lowest eigenvalue of a symmetric sparse matrix."""
    if A.shape[0] <= DENSE_LIMIT:
        return float(sla.eigh(A.toarray(), eigvals_only=True, subset_by_index=[0, 0])[0])
    vals = spla.eigsh(A.tocsc(), k=min(3, A.shape[0] - 1), sigma=0.0, which="LM", return_eigenvectors=False)
    return float(np.min(vals))


def _descend(
    system: System,
    q: FloatArray,
    lam: float,
    beta: FloatArray,
    loads: Loads,
    free: IntArray,
    tol: float,
    scale: float,
    maxiter: int = 200,
) -> tuple[FloatArray, float] | None:
    """Minimise Pi over the DOFs `free` from q: Newton on K + mu I (mu = 1.5 |mu_min| while
    K_ff is indefinite, Levenberg-Marquardt) with a backtracking line search on Pi.
    Leaves a saddle along negative curvature; ends near a minimum (a stable state).
    Returns (q, lowest eigenvalue) or None."""
    eye = sp.identity(len(free), format="csc")
    ev = system.evaluate(q, beta, lam, *loads, need_K=True)
    pi = potential(system, ev, lam)
    for _ in range(maxiter):
        r = ev["r"][free]
        A = system.layout.to_sparse(ev["K"])[free][:, free]
        A = 0.5 * (A + A.T)
        mu_min = _lowest(A)
        if np.linalg.norm(r) <= tol and mu_min > -zero_eigenvalue(scale, len(q)):
            return q, mu_min
        mu = 1.5 * max(-mu_min, 0.0)
        dq = np.zeros_like(q)
        try:
            dq[free] = spla.spsolve((A + mu * eye).tocsc(), -r)
        except RuntimeError:
            return None
        for _ls in range(40):
            ev_t = system.evaluate(q + dq, beta, lam, *loads, need_K=True)
            pi_t = potential(system, ev_t, lam) if np.all(np.isfinite(ev_t["r"])) else np.inf
            if pi_t <= pi + 1e-14 * abs(pi) or np.linalg.norm(ev_t["r"][free]) <= tol:
                break
            dq *= 0.5
        else:
            return None
        q, ev, pi = q + dq, ev_t, pi_t
        beta = ev["el"]["beta"]
    return None


def _follow_mode(
    system: System, opts: SolveOptions, q_u: FloatArray, phi: FloatArray, side: float, beta: FloatArray, loads: Loads
) -> tuple[FloatArray | None, str, int]:
    """Follow the branch leaving q_u along phi, with its largest component q_c held at
    q_u,c + xi (displacement control on the mode, load factor lambda free, xi growing),
    until lambda = 1 (the load of the step) is crossed; returns the state interpolated
    there (a Newton start), or None with the reason, and the iterations spent."""
    rot = system.disc.red_is_rotation
    kc = int(np.argmax(np.where(rot, 0.0, np.abs(phi)) if (~rot).any() else np.abs(phi)))
    phi = phi / phi[kc]
    unit = system.L_ref if not rot[kc] else 1.0
    xi, dxi = 0.0, 2e-3 * side * unit
    q, lam, its_total = q_u, 1.0, 0
    prev: tuple[FloatArray, float, float] | None = None
    while abs(xi) < 2.0 * unit:
        xi_new = xi + dxi
        q_pred = q_u + xi_new * phi if prev is None else q + dxi / prev[2] * prev[0]
        lam_pred = lam if prev is None else lam + dxi / prev[2] * prev[1]
        try:
            out = newton(
                system, q_pred, lam_pred, beta, loads, opts, mode="disp", ctrl=(kc, 1.0, q_u[kc] + xi_new), q_start=q
            )
            q_x, lam_x, ev, its = out.q, out.lam, out.ev, out.iterations
            its_total += its
            accept_check(system, q_x, q, ev, opts, its)
        except (StepFailed, SingularMatrix) as exc:
            dxi *= 0.5
            if abs(dxi) < 1e-6 * unit:
                return None, f"mode control stalled at xi = {xi:.3g}: {getattr(exc, 'reason', exc)}", its_total
            continue
        if prev is not None and lam <= 1.0 <= lam_x:
            w = (1.0 - lam) / (lam_x - lam)
            return q + w * (q_x - q), "", its_total
        if lam_x <= 0.0:
            return None, "the branch unloads (lambda <= 0): no stable state near", its_total
        prev = (q_x - q, lam_x - lam, dxi)
        q, lam, xi, beta = q_x, lam_x, xi_new, ev["el"]["beta"].copy()
        dxi *= 1.5 if its <= 6 else 1.0
    return None, "no crossing of the step's load within |xi| < 2 L_ref", its_total


def _stable(system: System, K: FloatArray, held: int | None, scale: float) -> tuple[bool, float]:
    try:
        vals, _ = lowest_modes(system, K, held, count=1)
    except (ValueError, np.linalg.LinAlgError, RuntimeError):
        return False, np.nan
    return bool(vals[0] > -zero_eigenvalue(1.0, system.n)), float(vals[0])


def switch_branch(
    system: System,
    opts: SolveOptions,
    q_u: FloatArray,
    lam: float,
    beta: FloatArray,
    ev_u: Evaluation,
    loads: Loads,
    mode: str = "load",
    ctrl: Control | None = None,
    held: int | None = None,
    q_prev: FloatArray | None = None,
) -> BranchSwitch:
    """Leave the unstable equilibrium q_u along its critical eigenvector, preferably to the
    side of ``q_prev`` (the last stable state of the path; see the module docstring).

    Returns a `BranchSwitch`: STABLE when the eigenvalues say q_u is stable after all, SWITCHED
    with the stable state found, or FAILED with the reason."""
    vals, vecs = lowest_modes(system, ev_u["K"], held)
    scale = float(np.abs(system.layout.to_sparse(ev_u["K"]).diagonal()).max())
    if vals[0] > -zero_eigenvalue(1.0, system.n):  # scaled eigenvalues: unit diagonal
        return BranchSwitch(SwitchStatus.STABLE, float(vals[0]))
    phi = vecs[:, 0]
    rot = system.disc.red_is_rotation
    big = np.abs(phi[~rot]).max() / system.L_ref if (~rot).any() else 0.0
    phi = phi / (big if big > 1e-12 else np.abs(phi).max())
    free = np.arange(system.n) if held is None else np.delete(np.arange(system.n), held)
    tol = opts.rtol * ev_u["F_scale"] + system.noise_floor + opts.atol
    pi_u = potential(system, ev_u, lam)
    found: dict[float, tuple[NewtonOutcome, float]] = {}
    tried: list[str] = []
    its_total = 0
    for side in (1.0, -1.0):
        label = "+" if side > 0 else "-"
        if mode == "load":
            start_q, why, its = _follow_mode(system, opts, q_u, phi, side, beta, loads)
        else:
            down = _descend(system, q_u + side * AMPLITUDE * system.L_ref * phi, lam, beta, loads, free, tol, scale)
            start_q, why, its = (None, "the descent of Pi stalled", 0) if down is None else (down[0], "", 0)
        its_total += its
        if start_q is None:
            tried.append(f"{label}: {why}")
            continue
        try:  # the solver's own corrector and convergence test, at the same load
            out = newton(system, start_q, lam, beta, loads, opts, mode=mode, ctrl=ctrl, q_start=start_q)
            its_total += out.iterations
            accept_check(system, out.q, start_q, out.ev, replace(opts, max_rotation_increment=np.inf), out.iterations)
        except (StepFailed, SingularMatrix) as exc:
            tried.append(f"{label}: {getattr(exc, 'reason', exc)}")
            continue
        moved = np.abs(out.q - q_u).max(initial=0.0) > 1e-6 * max(system.L_ref, 1.0)
        ok, mu = _stable(system, out.ev["K"], held, scale)
        if moved and ok:
            found[side] = (out, potential(system, out.ev, out.lam))
        else:
            tried.append(
                f"{label}: "
                + ("returned to the unstable state" if not moved else f"unstable (lowest eigenvalue {mu:.3g})")
            )
    if not found:
        return BranchSwitch(
            SwitchStatus.FAILED,
            float(vals[0]),
            reason=(
                f"lowest eigenvalue {vals[0]:.3g}; no stable state found by Newton from "
                f"the unstable one perturbed along the critical eigenvector ({'; '.join(tried)})"
            ),
        )
    side = min(found, key=lambda s: found[s][1])
    back = 0.0 if q_prev is None else float(np.dot(phi, q_prev - q_u))
    toward = (
        float(np.sign(back))
        if q_prev is not None and abs(back) > SIDE_TOL * (np.linalg.norm(phi) * np.linalg.norm(q_prev - q_u))
        else 0.0
    )
    if toward in found:
        side = toward
    out, pi = found[side]
    other = found.get(-side)
    why_side = "the side of the path's last stable state" if toward == side else "the lower total potential"
    note = (
        f"branch switch: unstable state (lowest eigenvalue {vals[0]:.3g}, Pi = {pi_u:.6g}) "
        f"left along the critical eigenvector, side {'+' if side > 0 else '-'}, "
        f"{why_side}; stable "
        f"state Pi = {pi:.9g}" + (f" (other side Pi = {other[1]:.9g})" if other else "")
    )
    return BranchSwitch(
        SwitchStatus.SWITCHED,
        float(vals[0]),
        note=note,
        outcome=NewtonOutcome(out.q, out.lam, out.ev, out.history, its_total, out.factor),
    )
