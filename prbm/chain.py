"""The Chain Algorithm (Midha, Her et al.; [bapat2015, §2.2, eqs 26-40]) for a cantilevered segment.

The segment is cut into N elements; element i runs from node i-1 to node i, has length L_i, stiffness
E_i I_i and undeformed orientation theta_i.  Marching from the clamp, each element is deflected as a
small-deflection cantilever clamped at the deflected node i-1, and every element beyond it is given the
rigid rotation of that node:

    psi_i = theta_i + Dtheta_{i-1}                                                          (29)
    (P_ax)_i = Fx cos psi_i + Fy sin psi_i,   (P_tr)_i = -Fx sin psi_i + Fy cos psi_i         (26), (27)
    M_i = sum_j m_j + sum_j [(f_y)_j (x_j - x_i) - (f_x)_j (y_j - y_i)]                        (28)
    (P_tr)_eq = (P_tr)_i / (1 - alpha_i),  alpha_i = 4 C_i L_i^2 / (E_i I_i pi^2)              (30), (31)
    delta_tr = [(P_tr)_eq L^3/3 + M_i L^2/2] / EI,  dtheta_i = [(P_tr)_eq L^2/2 + M_i L] / EI  (32), (33)
    X_i = X_{i-1} + L_i (cos psi_i, sin psi_i) + delta_tr (-sin psi_i, cos psi_i)            (34)-(40)
    Dtheta_i = Dtheta_{i-1} + dtheta_i                                                       (36)

with (Fx, Fy) = sum over the loads outboard of node i (j >= i), the moments m_j and the lever arms
(x_j - x_i, y_j - y_i) taken on the deformed chain (global frame O-X-Y).  The element is inextensible
(delta_ax = 0, as the dissertation says is typical).

Readings where the printed equations are incomplete (notes seed-ch2-4 section 3):

* The sums of (26)-(28) run over the loads outboard of node i (j >= i): printed j = 1..n, which would
  load every element with every load, including loads applied inboard of it.
* (29) mixes the indices i and j; read psi_i = theta_i + Dtheta_{i-1}.  (36) uses Dtheta_i for both the
  cumulative and the elemental rotation; read as above.
* (31) amplifies the transverse load by 1/(1 - alpha_i): the beam-column magnification under
  *compression* (a cantilever element buckles at pi^2 EI/(4 L^2)), while (26) gives tension positive.
  Here C_i = -(P_ax)_i is the compressive axial force, so tension reduces the element's deflection.
* The deformed-geometry loop of (28) (the lever arms depend on the deflected shape) is not described;
  here it is one nonlinear system in the node positions, X = G(X; loads), solved by Powell's hybrid
  method with the loads applied in steps (continuation from the previous step's shape), with the exact
  Jacobian of G (``march_jacobian``: G sees X only through the moments (28), linear in X).
* The shooting method of Her et al. [24] for displacement boundary conditions is not given; here the
  unknown tip loads join the node positions in the same system, with the end position/angle
  conditions as extra equations, continued in steps from the unloaded shape.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Literal, overload

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import root

from prbm.result import PRBMResult


@dataclass(frozen=True)
class ChainBeam:
    """A cantilevered segment cut into ``elements`` equal elements, clamped at the origin.

    ``orientations``: the undeformed element angles theta_i (rad), one per element (default: a straight
    beam along +x).  EI may vary per element (a sequence of N values)."""

    length: float
    EI: float | tuple[float, ...]
    elements: int = 40
    orientations: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if not (self.length > 0 and math.isfinite(self.length)):
            raise ValueError(f"ChainBeam: length must be finite and > 0, got {self.length}")
        if self.elements < 1:
            raise ValueError(f"ChainBeam: elements must be >= 1, got {self.elements}")
        if np.any(np.asarray(self.EI, float) <= 0) or not np.all(np.isfinite(self.EI)):
            raise ValueError(f"ChainBeam: EI must be finite and > 0, got {self.EI}")
        if np.size(self.EI) not in (1, self.elements):
            raise ValueError(f"ChainBeam: EI has {np.size(self.EI)} values for {self.elements} elements")
        if self.orientations is not None and len(self.orientations) != self.elements:
            raise ValueError(f"ChainBeam: {len(self.orientations)} orientations for {self.elements} elements")

    @property
    def element_length(self) -> float:
        return self.length / self.elements

    def theta(self) -> NDArray[np.float64]:
        return np.zeros(self.elements) if self.orientations is None else np.asarray(self.orientations, float)

    def stiffness(self) -> NDArray[np.float64]:
        return np.broadcast_to(np.asarray(self.EI, float), (self.elements,))

    def undeformed(self) -> NDArray[np.float64]:
        """Node positions (N+1, 2) of the unloaded chain."""
        t = self.theta()
        steps = self.element_length * np.column_stack([np.cos(t), np.sin(t)])
        return np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)])


@dataclass(frozen=True)
class NodalLoads:
    """Dead loads at the nodes in the global frame: arrays of N+1 values (node 0 is the clamp)."""

    fx: NDArray[np.float64]
    fy: NDArray[np.float64]
    m: NDArray[np.float64]

    @classmethod
    def at_tip(cls, beam: ChainBeam, fx: float = 0.0, fy: float = 0.0, m: float = 0.0) -> "NodalLoads":
        z = np.zeros(beam.elements + 1)
        fxa, fya, ma = z.copy(), z.copy(), z.copy()
        fxa[-1], fya[-1], ma[-1] = fx, fy, m
        return cls(fxa, fya, ma)

    def scaled(self, s: float) -> "NodalLoads":
        return NodalLoads(self.fx * s, self.fy * s, self.m * s)

    def plus(self, other: "NodalLoads") -> "NodalLoads":
        return NodalLoads(self.fx + other.fx, self.fy + other.fy, self.m + other.m)


def lumped_uniform_load(beam: ChainBeam, qx: float, qy: float) -> NodalLoads:
    """A dead load (qx, qy) per unit undeformed length along the whole chain, lumped at the element ends:
    each element's q L_i goes half to each of its nodes (node 0, the clamp, takes its half into the
    support), so the nodal loads keep the resultant q l; the moment of the lumped loads about any node
    differs from the distributed one by O(L_i^2) (the trapezoid rule).  The dissertation's chain takes loads at
    its nodes only (eqs 26-28: (f_x)_j, (f_y)_j, m_j at node j)."""
    weights = np.full(beam.elements + 1, beam.element_length)
    weights[0] = weights[-1] = 0.5 * beam.element_length
    return NodalLoads(qx * weights, qy * weights, np.zeros(beam.elements + 1))


@dataclass
class ChainState:
    nodes: NDArray[np.float64]  # (N+1, 2) deformed node positions
    rotations: NDArray[np.float64]  # (N+1,) cumulative rotation Dtheta at each node (node 0: 0)
    extras: dict[str, Any] = field(default_factory=dict)


def march(beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64]) -> ChainState:
    """One pass of eqs (26)-(40): the chain deflected under ``loads`` with lever arms taken on ``nodes``."""
    return _march(beam, loads, nodes, False)[0]


def march_jacobian(beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64]) -> NDArray[np.float64]:
    """d X_out / d X_in of one march at ``nodes`` (2N x 2N, nodes 1..N as x1, y1, x2, y2, ...).

    The march sees the node positions only through the moments (28), which are linear in them,
    M = M_0 + A X; so dX_out/dX = (dX_out/dM) A, with dX_out/dM carried through (29)-(40) alongside the
    march for all N moments at once (forward-mode differentiation of the same loop)."""
    dxy, _, through = _march_derivatives(beam, loads, nodes)
    return through(dxy)


MomentMap = Callable[[NDArray[np.float64]], NDArray[np.float64]]
"""D -> D A: a derivative with respect to the moments (28) turned into one with respect to the nodes."""


def _march_derivatives(
    beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], MomentMap]:
    """(dX_out/dM (2N x N), d Dtheta_N/dM (N,), D -> D A) of one march at ``nodes``: the output positions'
    and the tip rotation's derivatives with respect to the N moments (28), and the product with the
    moments' derivative with respect to the input positions, A = dM/dX_in (linear: M = M_0 + A X).

    A's columns are a triangle and a diagonal, dM_i/dx_j = fy_j [j >= i] - Fy_i [j = i] and
    dM_i/dy_j = -fx_j [j >= i] + Fx_i [j = i], so (D A)[:, x_j] = S_j fy_j - D_j Fy_j with S the running
    sum of D's columns (and likewise for y_j): O(N^2), no N^3 matrix product."""
    _, (dxy, dtip) = _march(beam, loads, nodes, True)
    Fx, Fy, _ = _outboard(loads, nodes)
    fx, fy = loads.fx[1:], loads.fy[1:]

    def through(D: NDArray[np.float64]) -> NDArray[np.float64]:
        S = np.cumsum(D, axis=-1)
        out = np.empty(D.shape[:-1] + (2 * D.shape[-1],))
        out[..., 0::2] = S * fy - D * Fy
        out[..., 1::2] = D * Fx - S * fx
        return out

    return dxy, dtip, through


def _outboard(
    loads: NodalLoads, nodes: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(Fx, Fy, M) per element i = 0..N-1: the loads outboard of its end node i+1 and their moment about
    that node (eqs 26-28), lever arms on ``nodes``."""
    Fx = np.cumsum(loads.fx[:0:-1])[::-1]
    Fy = np.cumsum(loads.fy[:0:-1])[::-1]
    m_out = np.cumsum(loads.m[:0:-1])[::-1]
    # eq (28) about node i: sum_j fy_j x_j - fx_j y_j over j >= i, minus (Fx, Fy) x position of node i
    mom_j = loads.fy[1:] * nodes[1:, 0] - loads.fx[1:] * nodes[1:, 1]
    M = m_out + np.cumsum(mom_j[::-1])[::-1] - (Fy * nodes[1:, 0] - Fx * nodes[1:, 1])
    return Fx, Fy, M


@overload
def _march(
    beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64], tangent: Literal[False]
) -> tuple[ChainState, None]: ...


@overload
def _march(
    beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64], tangent: Literal[True]
) -> tuple[ChainState, tuple[NDArray[np.float64], NDArray[np.float64]]]: ...


def _march(
    beam: ChainBeam, loads: NodalLoads, nodes: NDArray[np.float64], tangent: bool
) -> tuple[ChainState, tuple[NDArray[np.float64], NDArray[np.float64]] | None]:
    """The march, and with ``tangent`` its derivatives with respect to the N moments M_i: of the output
    positions (rows x1, y1, ...) and of the tip rotation (``_moment_derivative``)."""
    N, L = beam.elements, beam.element_length
    EI, theta = beam.stiffness(), beam.theta()
    Fx, Fy, M = _outboard(loads, nodes)
    # plain floats in the sequential march (numpy scalar indexing costs more than the arithmetic)
    Fx, Fy, M, EI, theta = Fx.tolist(), Fy.tolist(), M.tolist(), EI.tolist(), theta.tolist()
    x, y, rot = [0.0] * (N + 1), [0.0] * (N + 1), [0.0] * (N + 1)
    terms: list[tuple[float, ...]] = []  # with ``tangent``: each element's (c, s, P_ax, P_tr, alpha, P_eq, d_tr)
    for i in range(N):
        psi = theta[i] + rot[i]  # (29)
        c, s = math.cos(psi), math.sin(psi)
        P_ax = Fx[i] * c + Fy[i] * s  # (26), tension positive
        P_tr = -Fx[i] * s + Fy[i] * c  # (27)
        alpha = -4.0 * P_ax * L * L / (EI[i] * math.pi**2)  # (31), compression positive
        P_eq = P_tr / (1.0 - alpha)  # (30)
        d_tr = (P_eq * L**3 / 3.0 + M[i] * L * L / 2.0) / EI[i]  # (32)
        d_th = (P_eq * L * L / 2.0 + M[i] * L) / EI[i]  # (33)
        x[i + 1] = x[i] + L * c - d_tr * s  # (34), (37), (39)
        y[i + 1] = y[i] + L * s + d_tr * c  # (35), (38), (40)
        rot[i + 1] = rot[i] + d_th  # (36)
        if tangent:
            terms.append((c, s, P_ax, P_tr, alpha, P_eq, d_tr))
    state = ChainState(np.column_stack([x, y]), np.array(rot))
    return state, (_moment_derivative(np.array(terms).reshape(N, 7), L, np.array(EI)) if tangent else None)


@lru_cache(maxsize=16)
def _triangles(N: int) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """The strictly lower triangle of an N x N matrix (bool) and the lower one with the diagonal (float),
    read-only (the chain's length changes little between calls)."""
    below, lower = np.tri(N, k=-1, dtype=bool), np.tri(N)
    below.flags.writeable = lower.flags.writeable = False
    return below, lower


def _moment_derivative(
    terms: NDArray[np.float64], L: float, EI: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """d(x_i, y_i)/dM_k of the march (rows x1, y1, x2, y2, ...; columns k = 0..N-1), and d Dtheta_N/dM_k
    of its tip rotation (r_N, the last row of the running product below), from each element's
    (c, s, P_ax, P_tr, alpha, P_eq, d_tr) (``terms``, one row an element).

    The march's lines differentiated: with r_i = d Dtheta_{i-1}/dM the rotation before element i (r_0 = 0),
    dc = -s r_i, ds = c r_i, d alpha = kappa P_tr r_i (kappa = -4 L^2/(EI pi^2)) and
    dP_eq = g_i r_i, g_i = (-P_ax + P_eq kappa P_tr)/(1 - alpha); so every derivative is linear in r_i:

        r_{i+1} = (1 + g_i L^2/(2 EI)) r_i + (L/EI) e_i,
        dx_{i+1} = dx_i - (L s + s g_i L^3/(3 EI) + d_tr c) r_i - s L^2/(2 EI) e_i,
        dy_{i+1} = dy_i + (L c + c g_i L^3/(3 EI) - d_tr s) r_i + c L^2/(2 EI) e_i,

    with e_i the unit row of M_i (eqs (32)-(33) read M_i directly).  So r_{i+1, k} = (L/EI_k) prod_{k<j<=i}
    (1 + g_j L^2/(2 EI_j)) for k <= i (0 beyond): one running product down the columns of a triangular
    matrix, then the positions' rows as running sums (numpy over the whole matrix, not a loop of
    length-N vector operations per element)."""
    c, s, P_ax, P_tr, alpha, P_eq, d_tr = terms.T
    N = len(c)
    below, lower = _triangles(N)
    kappa = -4.0 * L * L / (EI * math.pi**2)
    g = (-P_ax + P_eq * kappa * P_tr) / (1.0 - alpha)
    factor: NDArray[np.float64] = np.where(below, (1.0 + g * (L * L / 2.0) / EI)[:, None], 1.0)  # rows j, columns k
    np.fill_diagonal(factor, L / EI)
    after = np.cumprod(factor, axis=0)
    after *= lower  # row i: r_{i+1}
    before = np.zeros((N, N))
    before[1:] = after[:-1]  # row i: r_i
    bend = g * (L**3 / 3.0) / EI
    half = (L * L / 2.0) / EI
    dxy = np.empty((2 * N, N))
    dxy[0::2] = np.cumsum(-(L * s + s * bend + d_tr * c)[:, None] * before - np.diag(s * half), axis=0)
    dxy[1::2] = np.cumsum((L * c + c * bend - d_tr * s)[:, None] * before + np.diag(c * half), axis=0)
    return dxy, after[-1].copy()


def _forward_step(
    beam: ChainBeam, loads: NodalLoads, guess: NDArray[np.float64], tol: float
) -> tuple[NDArray[np.float64], bool, int, str]:
    def residual(x: NDArray[np.float64]) -> NDArray[np.float64]:
        nodes: NDArray[np.float64] = np.vstack([[0.0, 0.0], x.reshape(-1, 2)])
        return (march(beam, loads, nodes).nodes[1:] - nodes[1:]).ravel()

    def jacobian(x: NDArray[np.float64]) -> NDArray[np.float64]:
        nodes = np.vstack([[0.0, 0.0], x.reshape(-1, 2)])
        return march_jacobian(beam, loads, nodes) - np.eye(x.size)

    sol = root(residual, guess[1:].ravel(), jac=jacobian, method="hybr", tol=tol)
    nodes = np.vstack([[0.0, 0.0], sol.x.reshape(-1, 2)])
    ok = bool(sol.success) and float(np.max(np.abs(residual(sol.x)))) < 1e-8 * beam.length
    return nodes, ok, int(sol.nfev) + int(sol.njev), sol.message


def _beyond_reach(beam: ChainBeam, a: float, b: float) -> str | None:
    """Why a chain solution is not an answer when its tip (a, b) lies farther from the root than the beam's
    length: an inextensible beam cannot get there; the chain's elements stretched (their chords lengthen
    with the transverse deflection, eq 34).  None when the tip is within reach (1e-9 relative)."""
    reach = math.hypot(a, b)
    if reach <= beam.length * (1.0 + 1e-9):
        return None
    return (
        f"the chain's tip is {reach / beam.length:.4g} lengths from the root, beyond an inextensible "
        f"beam's reach: the elements stretched (eq 34)"
    )


CHAIN_MODEL = "Chain Algorithm, seed 000 eqs (26)-(40)"


def _level_result(
    model: str,
    beam: ChainBeam,
    ok: bool,
    message: str,
    out: dict[str, Any],
    t0: float,
    nfev: int,
    nodes: NDArray[np.float64] | None = None,
) -> PRBMResult:
    """One chain solve's result: its outputs as float64, its element count, the wall time since ``t0``, and
    its deformed nodes where they stand."""
    return PRBMResult(
        ok,
        message,
        {k: np.float64(v) for k, v in out.items()},
        {"elements": beam.elements},
        model,
        time.perf_counter() - t0,
        nfev,
        np.array([ok]),
        extras={} if nodes is None else {"nodes": nodes},
    )


def _failed_level(model: str, beam: ChainBeam, message: str) -> PRBMResult:
    """A level after the first that failed: the same message, no tip, no time."""
    return PRBMResult(
        False,
        message,
        {k: np.float64(np.nan) for k in ("a", "b", "theta0")},
        {"elements": beam.elements},
        model,
        0.0,
        0,
        np.array([False]),
    )


def chain_tip(beam: ChainBeam, loads: NodalLoads, *, steps: int = 10, tol: float = 1e-12) -> PRBMResult:
    """Forward analysis: the deflected chain under dead nodal loads, applied in ``steps`` equal increments.
    Outputs a, b (tip position), theta0 (tip rotation, rad), and the node positions in ``extras``."""
    t0 = time.perf_counter()
    nodes = beam.undeformed()
    nfev, ok, message = 0, True, "converged"
    for k in range(1, steps + 1):
        nodes, ok, n, msg = _forward_step(beam, loads.scaled(k / steps), nodes, tol)
        nfev += n
        if not ok:
            message = f"load step {k}/{steps}: " + " ".join(str(msg).split())
            break
    state = march(beam, loads, nodes)
    out = {"a": state.nodes[-1, 0], "b": state.nodes[-1, 1], "theta0": state.rotations[-1]}
    stretched = _beyond_reach(beam, out["a"], out["b"]) if ok else None
    if stretched:
        ok, message = False, stretched
    return _level_result(CHAIN_MODEL, beam, ok, message, out, t0, nfev, state.nodes)


def chain_path(
    beam: ChainBeam, loads: NodalLoads, factors: Iterable[float], *, tol: float = 1e-12, max_step: float = 0.25
) -> list[PRBMResult]:
    """The chain under ``loads`` scaled by each of the increasing ``factors``, each level solved from the
    previous one's nodes (continuation), with sub-steps of at most ``max_step`` times the largest factor
    so that the solve follows the branch a slowly loaded beam takes; a level whose solve stalls is tried
    again from the previous level in twice as many sub-steps (four times at most).  One ``PRBMResult`` per factor; after
    the first level that fails, the rest fail with the same message."""
    factors = [float(f) for f in factors]
    nodes, previous = beam.undeformed(), 0.0
    results: list[PRBMResult] = []
    step_cap = max_step * max(abs(f) for f in factors) if factors else 0.0
    failed: str | None = None
    for factor in factors:
        t0 = time.perf_counter()
        if failed is not None:
            results.append(_failed_level(CHAIN_MODEL, beam, failed))
            continue
        substeps = max(1, math.ceil(abs(factor - previous) / step_cap)) if step_cap > 0 else 1
        nfev, ok, message = 0, False, "converged"
        for _ in range(5):  # a stalled solve is retried from the last level's nodes in twice as many steps
            trial = nodes
            for k in range(1, substeps + 1):
                level = previous + (factor - previous) * k / substeps
                trial, ok, n, msg = _forward_step(beam, loads.scaled(level), trial, tol)
                nfev += n
                if not ok:
                    message = f"load factor {level:.6g}: " + " ".join(str(msg).split())
                    break
            if ok:
                nodes, message = trial, "converged"
                break
            substeps *= 2
        state = march(beam, loads.scaled(factor), nodes)
        out = {"a": state.nodes[-1, 0], "b": state.nodes[-1, 1], "theta0": state.rotations[-1]}
        stretched = _beyond_reach(beam, out["a"], out["b"]) if ok else None
        if stretched:
            ok, message = False, stretched
        if not ok:
            failed = message
        results.append(_level_result(CHAIN_MODEL, beam, ok, message, out, t0, nfev, state.nodes))
        previous = factor
    return results


def chain_from_tip(
    beam: ChainBeam, *, b: float, theta0: float, n: float = 0.0, steps: int = 10, tol: float = 1e-12
) -> PRBMResult:
    """Displacement boundary conditions (Table 3.1's Chain row): the tip force (-nP, P) and tip moment M
    (CCW) that put the tip at height b with rotation theta0 (rad), for a given load ratio n.  Unknowns
    are the node positions and (P, M); the targets are reached in ``steps`` increments from zero.
    Outputs a, b, theta0, P, M (CCW)."""
    t0 = time.perf_counter()
    if not all(math.isfinite(v) for v in (b, theta0, n)):
        raise ValueError(f"chain_from_tip: b, theta0, n must be finite, got {b}, {theta0}, {n}")
    x = np.concatenate([beam.undeformed()[1:].ravel(), [0.0, 0.0]])
    nfev, ok, message = 0, True, "converged"

    def residual(x: NDArray[np.float64], b_k: float, th_k: float) -> NDArray[np.float64]:
        P, M = x[-2], x[-1]
        nodes = np.vstack([[0.0, 0.0], x[:-2].reshape(-1, 2)])
        st = march(beam, NodalLoads.at_tip(beam, -n * P, P, M), nodes)
        scale = beam.length
        return np.concatenate(
            [(st.nodes[1:] - nodes[1:]).ravel(), [(st.nodes[-1, 1] - b_k) / scale, st.rotations[-1] - th_k]]
        )

    for k in range(1, steps + 1):
        sol = root(residual, x, args=(b * k / steps, theta0 * k / steps), method="hybr", tol=tol)
        nfev += int(sol.nfev)
        ok = bool(sol.success) and float(np.max(np.abs(residual(sol.x, b * k / steps, theta0 * k / steps)))) < 1e-8
        if not ok:
            message = f"displacement step {k}/{steps}: " + " ".join(str(sol.message).split())
            break
        x = sol.x
    P, M = float(x[-2]), float(x[-1])
    state = march(beam, NodalLoads.at_tip(beam, -n * P, P, M), np.vstack([[0.0, 0.0], x[:-2].reshape(-1, 2)]))
    out = {"a": state.nodes[-1, 0], "b": state.nodes[-1, 1], "theta0": state.rotations[-1], "P": P, "nP": n * P, "M": M}
    stretched = _beyond_reach(beam, out["a"], out["b"]) if ok else None
    if stretched:
        ok, message = False, f"{stretched} to meet b = {b:g}"
    model = "Chain Algorithm with tip displacement conditions, seed 000 eqs (26)-(40)"
    return _level_result(model, beam, ok, message, out, t0, nfev, state.nodes)


HELD_FREEDOMS = ("ux", "uy", "rz")


def _held_jacobian(
    beam: ChainBeam,
    applied: NodalLoads,
    tip_loads: Callable[[NDArray[np.float64]], NodalLoads],
    kept: list[int],
    z: NDArray[np.float64],
    residual: Callable[[NDArray[np.float64], float], NDArray[np.float64]],
    level: float,
) -> NDArray[np.float64]:
    """The Jacobian of ``chain_held_path``'s residual at z = (nodes 1..N, the kept tip loads).

    Node columns: the march sees the nodes only through the moments, so the positions' rows are
    (dX_out/dM) A - I and a held freedom's row is its own derivative times A (``_march_derivatives``;
    the tip's x and y over L, its rotation d Dtheta_N/dM). A tip moment adds 1 to every M_i: its column
    is the derivatives summed over the moments. A tip force also enters every element's axial and
    transverse force (26)-(27), which the moment derivative does not carry: its column is a central
    difference of the residual (two marches), with a step of sqrt(eps) times the larger of the force
    and EI/L^2."""
    N = beam.elements
    nodes = np.vstack([[0.0, 0.0], z[: 2 * N].reshape(-1, 2)])
    dxy, dtip, through = _march_derivatives(beam, applied.plus(tip_loads(z[2 * N :])), nodes)
    by_moment = (dxy[2 * N - 2] / beam.length, dxy[2 * N - 1] / beam.length, dtip)  # d(end condition)/dM
    J = np.zeros((z.size, z.size))
    J[: 2 * N, : 2 * N] = through(dxy) - np.eye(2 * N)
    force_scale = float(np.max(beam.stiffness())) / beam.length**2
    for row, k in enumerate(kept):
        J[2 * N + row, : 2 * N] = through(by_moment[k])
    for col, k in enumerate(kept):
        j = 2 * N + col
        if k == 2:
            J[: 2 * N, j] = dxy.sum(axis=1)
            J[2 * N :, j] = [by_moment[kk].sum() for kk in kept]
        else:
            h = math.sqrt(np.finfo(float).eps) * max(abs(float(z[j])), force_scale)
            step = np.zeros(z.size)
            step[j] = h
            J[:, j] = (residual(z + step, level) - residual(z - step, level)) / (2.0 * h)
    return J


def chain_held_path(
    beam: ChainBeam,
    loads: NodalLoads,
    held: Iterable[str],
    factors: Iterable[float],
    *,
    tol: float = 1e-12,
    max_step: float = 0.25,
) -> list[PRBMResult]:
    """The chain under ``loads`` scaled by each of the increasing ``factors``, its tip held in the freedoms
    ``held`` (a subset of 'ux', 'uy', 'rz': the tip's x, its y, its rotation kept where the unloaded chain
    has them; a fixed-guided segment holds 'rz').

    The tip loads the held freedoms need (Fx, Fy, M at the tip node, global frame, CCW) are unknowns beside
    the node positions, with one end condition each, as ``chain_from_tip`` poses its displacement
    conditions; each level is continued from the previous one in sub-steps of at most ``max_step`` times
    the largest factor. Outputs a, b, theta0 (the tip), and Fx, Fy, M (the held freedoms' tip loads, 0 for
    a free one). After the first level that fails, the rest fail with the same message."""
    kept = [HELD_FREEDOMS.index(h) for h in dict.fromkeys(held)]
    if any(h not in HELD_FREEDOMS for h in held):
        raise ValueError(f"chain_held_path: held freedoms {sorted(held)} not among {HELD_FREEDOMS}")
    if beam.orientations is None and 0 in kept:
        raise ValueError(
            "chain_held_path: a straight chain with its tip's x held cannot bend (its elements "
            "are inextensible: a bent chain's chord is shorter)"
        )
    factors = [float(f) for f in factors]
    model = "Chain Algorithm with a held tip, seed 000 eqs (26)-(40)"
    rest = beam.undeformed()
    target = (rest[-1, 0], rest[-1, 1], 0.0)
    N = beam.elements
    x = np.concatenate([rest[1:].ravel(), np.zeros(len(kept))])

    def tip_loads(reactions: NDArray[np.float64]) -> NodalLoads:
        components = [0.0, 0.0, 0.0]
        for k, r in zip(kept, reactions):
            components[k] = float(r)
        return NodalLoads.at_tip(beam, *components)

    def residual(z: NDArray[np.float64], level: float) -> NDArray[np.float64]:
        nodes = np.vstack([[0.0, 0.0], z[: 2 * N].reshape(-1, 2)])
        st = march(beam, loads.scaled(level).plus(tip_loads(z[2 * N :])), nodes)
        tip = (st.nodes[-1, 0], st.nodes[-1, 1], st.rotations[-1])
        ends = [(tip[k] - target[k]) / (beam.length if k < 2 else 1.0) for k in kept]
        return np.concatenate([(st.nodes[1:] - nodes[1:]).ravel(), ends])

    def jacobian(z: NDArray[np.float64], level: float) -> NDArray[np.float64]:
        return _held_jacobian(beam, loads.scaled(level), tip_loads, kept, z, residual, level)

    results: list[PRBMResult] = []
    previous, failed = 0.0, None
    step_cap = max_step * max(abs(f) for f in factors) if factors else 0.0
    for factor in factors:
        t0 = time.perf_counter()
        if failed is None:
            substeps = max(1, math.ceil(abs(factor - previous) / step_cap)) if step_cap > 0 else 1
            nfev, ok = 0, True
            for k in range(1, substeps + 1):
                level = previous + (factor - previous) * k / substeps
                sol = root(residual, x, args=(level,), jac=jacobian, method="hybr", tol=tol)
                nfev += int(sol.nfev) + int(sol.njev)
                ok = bool(sol.success) and float(np.max(np.abs(residual(sol.x, level)))) < 1e-8
                if not ok:
                    failed = f"load factor {level:.6g}: " + " ".join(str(sol.message).split())
                    break
                x = sol.x
            previous = factor
        if failed is not None:
            results.append(_failed_level(model, beam, failed))
            continue
        reactions = x[2 * N :]
        state = march(
            beam, loads.scaled(factor).plus(tip_loads(reactions)), np.vstack([[0.0, 0.0], x[: 2 * N].reshape(-1, 2)])
        )
        tip = tip_loads(reactions)
        out = {
            "a": state.nodes[-1, 0],
            "b": state.nodes[-1, 1],
            "theta0": state.rotations[-1],
            "Fx": tip.fx[-1],
            "Fy": tip.fy[-1],
            "M": tip.m[-1],
        }
        stretched = _beyond_reach(beam, out["a"], out["b"])
        if stretched:
            failed = stretched
            results.append(_level_result(model, beam, False, stretched, out, t0, nfev))
            continue
        results.append(_level_result(model, beam, True, "converged", out, t0, nfev, state.nodes))
    return results
