"""Incremental-iterative solvers: load control, displacement control, arc-length.

All three solve  r(q, lambda) = f_int(q) - lambda f_ref(q) = 0  on the reduced
unknowns q (`assembly.System`) by Newton-Raphson with the consistent tangent K.

* Load control (lambda = 1, loads and prescribed values interpolated linearly
  between load levels, parameter t in [0, 1] per segment): every level is
  first tried in one step (``initial_step``), then in adaptive substeps,
  cut on failure (halved, or in proportion to an excessive rotation
  increment), grown after easy steps; secant predictor within a segment.
  A step is also cut when its increment points against the previous one
  (it jumped to another branch), and when it lands on an unstable state
  (a step too long for an imperfect path, or several critical loads crossed)
  until it is no longer than ``SWITCH_STEP``; only then is the branch switched.
* Displacement control: one DOF q_c follows prescribed targets, the load
  factor lambda is unknown.  Bordered system solved with two back-solves
  (Batoz & Dhatt 1979; Crisfield 1991 sec. 9.3.3):
      K a = -r,  K b = f_ref,  dlambda = (u_c* - q_c - a_c)/b_c,  dq = a + dlambda b.
* Arc-length (Crisfield 1981 cylindrical; Crisfield 1991 sec. 9.3.4):
  ||Delta q||_W = Delta l, with W weighting rotations by the mean element
  length squared.  Tangent predictor Delta lambda = +-Delta l/||b||_W, b = K^-1 f_ref,
  with the sign of b . Delta q_prev (follows the path through limit points and
  snap-backs), or quadratic extrapolation through the last three states;
  corrector root of the quadratic chosen by the smallest angle with the
  current increment.  Delta l adapts to the iteration count.

The corrector, the convergence tests and the rotation-continuity checks are
in `newton`; limit points and bifurcations are found by `critical`. A model whose
unloaded tangent is singular to working precision (`conditioning`: a mesh too fine
for double precision) is stopped after its first cut step or at its 16th step,
whichever comes first, with a message that says why (a run whose steps converge at
once never pays for the test).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .assembly import System
from .conditioning import beyond_precision
from .critical import critical_points
from .discretise import discretise
from .free_motion import check_held
from .linear_solver import Factor, SingularMatrix
from .model import DOF_NAMES, Model, NodeRef
from .newton import Control, Path, StepFailed, accept_check, acceptance_facts, det_sign, growth, newton, snapshot
from .options import (
    ArcLengthControl,
    DisplacementControl,
    LoadControl,
    NewtonOutcome,
    SolveOptions,
    StepState,
    SwitchStatus,
)
from .result import FemResult, build_result
from .inertia import DENSE_LIMIT, zero_eigenvalue
from .stability import conservative, eigenvalue_below, held_sign, switch_branch
from .types import Evaluation, FloatArray, Loads, SignedFactor
from .warm_start import LevelGuesses, level_guesses

__all__ = ["solve", "solve_load", "solve_displacement", "solve_arclength"]

SWITCH_STEP = 1.0 / 64  # branch switching is tried from steps no longer than this (of a level)
JUMP_CUT_FLOOR = 64  # steps shorter than this many min_step are not cut for turning back


def _path_weights(system: System) -> FloatArray:
    """W of the norm ||dq||_W: rotations weighted by the mean element length squared."""
    return system.path_weights


def _step_state(system: System, opts: SolveOptions, out: NewtonOutcome, beta: FloatArray) -> StepState:
    """A converged step with the sign of det K (`newton.det_sign`) when it is watched."""
    return StepState.of(out, beta, det_sign(system, out.ev, out.factor) if opts.watch_det else 0)


def _try_guess(
    system: System, opts: SolveOptions, path: Path, guesses: LevelGuesses, k: int, loads: Loads
) -> NewtonOutcome | None:
    """Newton from the warm-start guess of level k; None if not acceptable (an element jumped by 2 pi,
    or a rotation moved 0.1 rad or more from the guess: another branch)."""
    q_g, beta_g = guesses.q[k], guesses.beta[k]
    try:
        out = newton(system, q_g, 1.0, beta_g, loads, opts, q_start=q_g)
    except StepFailed as exc:
        path.rejected_iterations += exc.iteration
        return None
    jumped, moved = acceptance_facts(system, out.q, q_g, out.ev, out.accept)  # q_g was its start
    if jumped or not moved < 0.1:
        path.rejected_iterations += out.iterations
        return None
    return out


def _even_crossing(system: System, st: StepState, held: int | None) -> bool:
    """True when det K > 0 hides an unstable state: two (or any even number of) eigenvalues
    crossed zero in one step, which the sign of det K cannot see. Checked by a Cholesky
    factorisation of the shifted, scaled tangent (`stability.eigenvalue_below`), only where it can
    happen (conservative loads, some member in compression) and only for systems small enough for a
    dense eigensolver (larger ones rely on the sign of det K). A state of the compiled corrector
    carries the answer of the same test made there (``inertia_below``, threshold
    ``system.inertia_tol`` = `zero_eigenvalue` (1, n))."""
    if not conservative(system) or system.n > DENSE_LIMIT:
        return False
    known: int = getattr(st.ev, "inertia_below", -1)  # the compiled corrector's own test, made
    if held is None and known >= 0:  # where an element is in compression
        return bool(known)
    if float(st.ev["el"]["N"].min(initial=0.0)) >= 0.0:
        return False
    try:  # Jacobi-scaled: unit diagonal
        return eigenvalue_below(system, st.ev["K"], held, zero_eigenvalue(1.0, system.n))
    except (ValueError, np.linalg.LinAlgError, RuntimeError):
        return False


def _turned_back(system: System, dq: FloatArray, dq_prev: FloatArray) -> bool:
    """True when the increment of a load step points against the previous one (negative
    cosine in the norm ||dq||_W): under load control the path does not turn back within one step,
    the state jumped to another branch (e.g. the buckled state on the far side of an imperfect
    column)."""
    return bool(np.dot(dq * _path_weights(system), dq_prev) < 0.0)


def _lost_stability(system: System, opts: SolveOptions, path: Path, st: StepState, held: int | None = None) -> bool:
    """True when a converged step took the stable path to an unstable state: sign det K (of
    K_ff with the control DOF `held` under displacement control) turned negative, or an even
    number of eigenvalues crossed zero (`_even_crossing`). Dead loads only: under follower
    loads a sign change is recorded as unassessed (the static criterion is not decisive) and
    the path is no longer watched. Arc-length never calls this: it traces unstable branches
    on purpose."""
    if not opts.check_stability or not path.stable:
        return False
    if st.sign >= 0 and not _even_crossing(system, st, held):
        return False
    if not conservative(system):
        path.stable = False
        path.unassessed.append(len(path.step_lams))
        return False
    if held is not None:
        try:
            if held_sign(_solver_factor(system, st.factor, st.ev), st.sign, held) >= 0:
                return False
        except SingularMatrix:
            return False
    return True


def _solver_factor(system: System, factor: SignedFactor | None, ev: Evaluation) -> Factor:
    """The corrector's factorisation ``factor`` of the tangent when it is one that solves (the NumPy
    corrector's, under displacement and arc-length control), else a factorisation of ``ev``'s tangent."""
    return factor if isinstance(factor, Factor) else system.layout.factor(ev["K"])


def _leave_unstable(
    system: System,
    opts: SolveOptions,
    path: Path,
    st: StepState,
    loads: Loads,
    q_prev: FloatArray,
    mode: str = "load",
    ctrl: Control | None = None,
    held: int | None = None,
) -> str | None:
    """Replace the unstable state ``st`` (updated in place) by a stable one on another branch,
    preferably the one on the side of the path's last stable state ``q_prev``
    (`stability.switch_branch`). Returns None, or the reason why no stable state was found."""
    out = switch_branch(
        system, opts, st.q, st.lam, st.beta, st.ev, loads, mode=mode, ctrl=ctrl, held=held, q_prev=q_prev
    )
    if out.status is SwitchStatus.STABLE:  # the eigenvalues (decisive) put it within rounding of stable
        st.sign = 1
        return None
    if out.status is SwitchStatus.FAILED:
        return f"the converged state is unstable: a bifurcation was crossed (det K < 0, {out.reason}); not returned"
    new = out.outcome
    assert new is not None  # SWITCHED carries the stable state
    path.branch_switches.append((len(path.step_lams), out.note))
    st.q, st.lam, st.ev, st.factor = new.q, new.lam, new.ev, new.factor
    st.history, st.iterations = st.history + new.history, st.iterations + new.iterations
    st.sign, st.switched = det_sign(system, new.ev, new.factor), True
    return None


# ---------------------------------------------------------------------------------- load control
def _guessed_level(
    system: System, opts: SolveOptions, path: Path, guesses: LevelGuesses, k: int, beta: FloatArray
) -> StepState | None:
    """The level k solved in one Newton run from its warm-start guess, or None (step to it)."""
    out = _try_guess(system, opts, path, guesses, k, system.loads_at(k - 1, k, 1.0))
    if out is None:
        return None
    st = _step_state(system, opts, out, beta)
    if _lost_stability(system, opts, path, st):
        return None  # not a state of the path: step to the level instead
    path.record(st.history, st.iterations, st.sign if opts.detect_critical else 0, float(k))
    return st


class NoStableBranch(Exception):
    """A converged step is unstable and no stable state was found beside it."""


class StepRetry(Exception):
    """A load step to take again, shorter by ``factor``: it left the path (turned back on it) or lost
    stability over a step long enough to have jumped off it."""

    def __init__(self, factor: float):
        super().__init__(f"retry the step {factor:g} times as long")
        self.factor = factor


class PathStopped(Exception):
    """The path could not be followed further: why, and where (the result's message)."""


def _load_step(
    system: System,
    opts: SolveOptions,
    path: Path,
    q: FloatArray,
    beta: FloatArray,
    k: int,
    t: float,
    t_new: float,
    dt: float,
    prev: tuple[FloatArray, float] | None,
) -> StepState:
    """One load step (length dt) from t to t_new of the segment to level k: the accepted
    `StepState`. Raises StepRetry (with the factor to cut the step by) when the step left the path or
    lost stability over a long step, StepFailed when Newton fails, NoStableBranch when it lands on an
    unstable state with no stable one beside it."""
    loads = system.loads_at(k - 1, k, t_new)
    q_pred = q if prev is None else q + (t_new - t) / prev[1] * prev[0]
    out = newton(system, q_pred, 1.0, beta, loads, opts, q_start=q)
    accept_check(system, out.q, q, out.ev, opts, out.iterations, out.accept)
    if prev is not None and dt > JUMP_CUT_FLOOR * opts.min_step and _turned_back(system, out.q - q, prev[0]):
        path.reject(out.iterations)  # left the path: jumped to another branch
        raise StepRetry(0.25)
    st = _step_state(system, opts, out, beta)
    if _lost_stability(system, opts, path, st):
        if dt > SWITCH_STEP:  # a long step may have jumped off an imperfect path, or
            path.cutbacks += 1  # crossed several critical loads: retry shorter
            raise StepRetry(0.25)
        why = _leave_unstable(system, opts, path, st, loads, q)
        if why:
            raise NoStableBranch(why)
    return st


def _run_load(system: System, opts: SolveOptions, path: Path, guesses: LevelGuesses | None = None) -> None:
    """Load control over the levels; raises PathStopped where it cannot go on."""
    q = np.zeros(system.n)
    beta = system.disc.beta0.copy()
    ev: Evaluation = {}
    for k in range(system.n_levels):
        t = 0.0
        prev: tuple[FloatArray, float] | None = None
        dt = opts.initial_step  # a level that needed cuts does not shorten the first try of the next
        got = None if guesses is None else _guessed_level(system, opts, path, guesses, k, beta)
        if got is not None:
            q, t, beta, ev = got.q, 1.0, got.ev["el"]["beta"].copy(), got.ev
        while t < 1.0:
            _stop_beyond_precision(system, path)
            dt = min(dt, 1.0 - t)
            t_new = 1.0 if 1.0 - (t + dt) < 1e-12 else t + dt
            try:
                st = _load_step(system, opts, path, q, beta, k, t, t_new, dt, prev)
            except StepRetry as retry:
                dt *= retry.factor
                continue
            except NoStableBranch as exc:
                raise PathStopped(
                    f"load level {k}: step from t = {t:.6g} to {t_new:.6g} of the segment from level {k - 1}: {exc}"
                ) from None
            except StepFailed as exc:
                path.reject(exc.iteration)
                dt *= exc.cut
                if dt < opts.min_step:
                    raise PathStopped(
                        f"load level {k}: no convergence between t = {t:.6g} and "
                        f"{t_new:.6g} of the segment from level {k - 1} (step < min_step), "
                        f"iteration {exc.iteration}: {exc.reason}"
                    ) from None
                continue
            secant = opts.predictor == "secant" and not st.switched
            prev = (st.q - q, t_new - t) if secant else None
            q, t, beta, ev = st.q, t_new, st.ev["el"]["beta"].copy(), st.ev
            path.record(st.history, st.iterations, st.sign if opts.detect_critical else 0, k - 1 + t)
            dt *= growth(st.iterations)
        path.snapshots.append(snapshot(system, q, 1.0, ev, float(k)))
    return None


# -------------------------------------------------------------------------- displacement control
def _control_index(system: System, model: Model, control: tuple[NodeRef, str]) -> tuple[int, float]:
    """(reduced unknown, coefficient) of the control DOF ``control`` = (node, 'ux' | 'uy' | 'rz')."""
    name, dof = control
    node = model.node(name)
    d = system.disc
    i = 2 * node + DOF_NAMES[dof] if DOF_NAMES[dof] < 2 else d.rot_dof[node]
    k, c = d.I[i, 0], d.C[i, 0]
    if k >= system.n or c == 0.0 or not d.independent[i]:
        raise ValueError(f"control DOF {control} is constrained or dependent")
    return int(k), float(c)


def _reference_loads(system: System) -> Loads:
    """The load pattern of displacement and arc-length control: the loads at the last level."""
    if system.presc.size and np.any(system.presc != 0.0):
        raise ValueError(
            "displacement/arc-length control needs zero prescribed values; "
            "the load pattern is scaled by the load factor"
        )
    return system.F_fixed[-1], system.F0[-1], system.presc[-1] * 0.0


def _critical_slope(system: System, st: StepState, k: int, coef: float) -> tuple[int, float]:
    """sign det K and d lambda / d u_c = 1 / (K^-1 f_ref)_c at an accepted displacement step."""
    try:
        fac = _solver_factor(system, st.factor, st.ev)
        bb = fac.solve(st.ev["f_ref"])
        return fac.det_sign, (1.0 / (bb[k] * coef) if bb[k] != 0 else np.nan)
    except SingularMatrix:
        return 0, np.nan


def _disp_step(
    system: System,
    opts: SolveOptions,
    path: Path,
    q: FloatArray,
    lam: float,
    beta: FloatArray,
    loads: Loads,
    ctrl: Control,
    prev: tuple[FloatArray, float, float] | None,
) -> StepState:
    """One displacement step to the control value ctrl[2]: the accepted `StepState`. Raises
    StepFailed (Newton) or NoStableBranch."""
    k, coef, u_t = ctrl
    q_pred, lam_pred = q, lam
    if prev is not None and prev[2] != 0.0:
        ratio = (u_t - q[k] * coef) / prev[2]
        q_pred, lam_pred = q + ratio * prev[0], lam + ratio * prev[1]
    out = newton(system, q_pred, lam_pred, beta, loads, opts, mode="disp", ctrl=ctrl, q_start=q)
    accept_check(system, out.q, q, out.ev, opts, out.iterations)
    st = _step_state(system, opts, out, beta)
    if _lost_stability(system, opts, path, st, held=k):
        why = _leave_unstable(system, opts, path, st, loads, q, mode="disp", ctrl=ctrl, held=k)
        if why:
            raise NoStableBranch(why)
    return st


def _run_disp(system: System, model: Model, control: DisplacementControl, opts: SolveOptions, path: Path) -> None:
    """Displacement control over the targets; raises PathStopped where it cannot go on."""
    k, coef = _control_index(system, model, control.control_dof)
    targets = np.atleast_1d(np.asarray(control.targets, dtype=float))
    loads = _reference_loads(system)
    q, lam, beta = np.zeros(system.n), 0.0, system.disc.beta0.copy()
    frac = opts.initial_step
    prev: tuple[FloatArray, float, float] | None = None
    ev: Evaluation = {}
    for lev, target in enumerate(targets):
        u_a, t = q[k] * coef, 0.0
        while t < 1.0:
            _stop_beyond_precision(system, path)
            frac = min(frac, 1.0 - t)
            t_new = 1.0 if 1.0 - (t + frac) < 1e-12 else t + frac
            u_t = u_a + t_new * (target - u_a)
            try:
                st = _disp_step(system, opts, path, q, lam, beta, loads, (k, coef, u_t), prev)
            except NoStableBranch as exc:
                raise PathStopped(f"load level {lev} (control displacement {u_t:.6g}): {exc}") from None
            except StepFailed as exc:
                path.reject(exc.iteration)
                frac *= exc.cut
                if frac < opts.min_step:
                    raise PathStopped(
                        f"load level {lev} (control displacement {u_t:.6g}): no convergence, "
                        f"iteration {exc.iteration}: {exc.reason}"
                    ) from None
                continue
            if opts.predictor == "secant":
                prev = None if st.switched else (st.q - q, st.lam - lam, (st.q[k] - q[k]) * coef)
            q, lam, t, beta, ev = st.q, st.lam, t_new, st.ev["el"]["beta"].copy(), st.ev
            sign, slope = _critical_slope(system, st, k, coef) if opts.detect_critical else (0, np.nan)
            path.record(st.history, st.iterations, sign, lam, slope, control=u_t, parameter=u_t)
            frac *= growth(st.iterations)
        path.snapshots.append(snapshot(system, q, lam, ev, float(lev)))


# ------------------------------------------------------------------------------------ arc length
class _Arc:
    """The state of an arc-length trace between steps."""

    def __init__(self, system: System, model: Model, control: ArcLengthControl):
        self.w = _path_weights(system)
        self.q, self.lam, self.beta = np.zeros(system.n), 0.0, system.disc.beta0.copy()
        self.dl = control.arc_length or 0.05 * system.L_ref
        self.dl_max = control.max_arc_length or 20 * self.dl
        self.dl_min = self.dl * 1e-6
        self.Dq_prev: FloatArray | None = None
        self.sign = float(np.sign(control.direction) or 1.0)
        self.s_total, self.n_limits = 0.0, 0
        self.cached: tuple[Factor, FloatArray] | None = None  # (factor, K^-1 f_ref) at the current state
        self.hist3: list[tuple[float, FloatArray, float]] = [(0.0, self.q.copy(), self.lam)]
        self.stop: tuple[int, float, float] | None = None  # (unknown, coefficient, value) of ``until``
        if control.until is not None:
            self.stop = (*_control_index(system, model, control.until[:2]), float(control.until[2]))


def _arc_predictor(system: System, arc: _Arc, loads: Loads, opts: SolveOptions) -> tuple[FloatArray, float]:
    """Tangent predictor Delta lambda = +-dl/||b||_W (b = K^-1 f_ref, sign following the path), or
    quadratic extrapolation through the last three states."""
    if arc.cached is None:
        ev0 = system.evaluate(arc.q, arc.beta, arc.lam, *loads, need_K=True)
        fac = system.layout.factor(ev0["K"])
        b = fac.solve(ev0["f_ref"])
    else:
        fac, b = arc.cached
    nb = np.sqrt(np.dot(b * arc.w, b))
    if arc.Dq_prev is not None:
        arc.sign = 1.0 if np.dot(b * arc.w, arc.Dq_prev) >= 0 else -1.0
    dlam = arc.sign * arc.dl / nb
    if opts.predictor == "secant" and len(arc.hist3) == 3:
        # quadratic extrapolation along the path (error O(dl^3) instead of
        # O(dl^2)): smaller axial overshoot of slender members
        (s0, q0, l0), (s1, q1, l1), (s2, q2, l2) = arc.hist3
        x = s2 + arc.dl
        c0 = (x - s1) * (x - s2) / ((s0 - s1) * (s0 - s2))
        c1 = (x - s0) * (x - s2) / ((s1 - s0) * (s1 - s2))
        c2 = (x - s0) * (x - s1) / ((s2 - s0) * (s2 - s1))
        return c0 * q0 + c1 * q1 + c2 * q2, float(c0 * l0 + c1 * l1 + c2 * l2)
    return arc.q + dlam * b, float(arc.lam + dlam)


def _arc_accept(system: System, arc: _Arc, out: NewtonOutcome, path: Path) -> None:
    """Move the trace to the converged state and record the step (det K sign and path slope from
    K^-1 f_ref, cached for the next predictor)."""
    Dq = arc.Dq_prev = out.q - arc.q
    arc.q, arc.lam, arc.beta = out.q, out.lam, out.ev["el"]["beta"].copy()
    arc.s_total += float(np.sqrt(np.dot(Dq * arc.w, Dq)))
    arc.hist3 = (arc.hist3 + [(arc.s_total, arc.q.copy(), arc.lam)])[-3:]
    try:
        fac = _solver_factor(system, out.factor, out.ev)
        b = fac.solve(out.ev["f_ref"])
        arc.cached = (fac, b)
        travel = 1.0 if np.dot(b * arc.w, Dq) >= 0 else -1.0
        sign, slope = fac.det_sign, travel / np.sqrt(np.dot(b * arc.w, b))
    except SingularMatrix:
        arc.cached, sign, slope = None, 0, np.nan
    ctrl = arc.q[arc.stop[0]] * arc.stop[1] if arc.stop is not None else np.nan
    path.record(out.history, out.iterations, sign, arc.lam, slope, control=ctrl, parameter=arc.s_total)
    path.snapshots.append(snapshot(system, arc.q, arc.lam, out.ev, float(len(path.snapshots))))


def _arc_stopped(arc: _Arc, control: ArcLengthControl, path: Path) -> bool:
    """The stop crossing, |lambda| >= lambda_max, or the max_limit_points-th limit point."""
    if arc.stop is not None:
        u_stop = arc.stop[2]
        if (path.step_ctrl[-2] - u_stop) * (path.step_ctrl[-1] - u_stop) <= 0 and len(path.iterations) > 1:
            return True
    if control.lambda_max is not None and abs(arc.lam) >= control.lambda_max:
        return True
    if control.max_limit_points is not None and len(path.step_lams) >= 3:
        l3 = path.step_lams[-3:]
        if (l3[1] - l3[0]) * (l3[2] - l3[1]) < 0:
            arc.n_limits += 1
            return arc.n_limits >= control.max_limit_points
    return False


def _run_arc(system: System, model: Model, control: ArcLengthControl, opts: SolveOptions, path: Path) -> None:
    """Arc-length steps until the stop condition; raises PathStopped where it cannot go on (or reach it)."""
    loads = _reference_loads(system)
    arc = _Arc(system, model, control)
    start = system.evaluate(arc.q, arc.beta, arc.lam, *loads, need_K=False)
    path.snapshots.append(snapshot(system, arc.q, arc.lam, start, 0.0))
    if not np.any(start["f_ref"]):  # lambda scales nothing: no path to follow
        raise PathStopped("arc-length control needs a load pattern: the loads at the last level are all zero")
    path.mark_start()
    while len(path.iterations) < control.max_steps:
        _stop_beyond_precision(system, path)
        try:
            q_pred, lam_pred = _arc_predictor(system, arc, loads, opts)
            out = newton(
                system, q_pred, lam_pred, arc.beta, loads, opts, mode="arc", arc=(arc.dl, arc.w, arc.q), q_start=arc.q
            )
            accept_check(system, out.q, arc.q, out.ev, opts, out.iterations)
        except (StepFailed, SingularMatrix) as exc:
            path.reject(getattr(exc, "iteration", 0))
            arc.hist3, arc.cached = arc.hist3[-1:], None
            arc.dl *= getattr(exc, "cut", 0.5)
            if arc.dl < arc.dl_min:
                raise PathStopped(
                    f"arc-length step {len(path.iterations) + 1} (load factor {arc.lam:.6g}): "
                    f"no convergence, iteration {getattr(exc, 'iteration', 0)}: "
                    f"{getattr(exc, 'reason', exc)}"
                ) from None
            continue
        _arc_accept(system, arc, out, path)
        arc.dl = min(arc.dl * float(np.clip(opts.target_iterations / max(out.iterations, 1), 0.5, 2.0)), arc.dl_max)
        if _arc_stopped(arc, control, path):
            return
    if control.has_stop:
        raise PathStopped(f"arc-length: max_steps = {control.max_steps} reached before the stop condition")


# ------------------------------------------------------------------------------- entry points
def _prepare(model: Model, opts: SolveOptions, n_levels: int | None = None, check: bool = True) -> System:
    """The discretised system, tested for free motion (`free_motion`) when ``check``."""
    if n_levels is not None and model.n_levels not in (1, n_levels):
        raise ValueError(f"n_levels={n_levels} but the load histories have {model.n_levels}")
    disc = discretise(model, refine=opts.refine)
    system = System(model, disc, solver_kind=opts.solver, n_levels=n_levels)
    if check:
        check_held(system)
    return system


PRECISION_STEPS = 16  # accepted steps after which a run is tested for precision (`_beyond_precision`)


def _stop_beyond_precision(system: System, path: Path) -> None:
    """Raise PathStopped when the run's model is beyond double precision (`_beyond_precision`)."""
    why = _beyond_precision(system, path)
    if why:
        raise PathStopped(why)


def _beyond_precision(system: System, path: Path) -> str | None:
    """Why the run stops (its model beyond double precision, `conditioning.beyond_precision`), tested
    once, before the next step after the run's first cut step (a failed Newton attempt, a step retried
    shorter) or its PRECISION_STEPS-th accepted step: the two ways a model too fine for double precision
    shows (corrections without correct digits fail, or converge so slowly that the steps shrink). A run
    whose steps converge at once never pays for it."""
    if path.precision_checked or not (path.cutbacks or len(path.iterations) >= PRECISION_STEPS):
        return None
    path.precision_checked = True
    return beyond_precision(system)


def _stopped(run: Callable[[], None]) -> str | None:
    """Follow a path; None when it reached its end, else why it stopped (the result's message)."""
    try:
        run()
    except PathStopped as exc:
        return str(exc)
    return None


def _finish(
    model: Model,
    system: System,
    path: Path,
    opts: SolveOptions,
    failure: str | None,
    control: str,
    t0: float,
    analysis_time: float,
) -> FemResult:
    """The result of a path: critical points, the message (steps, branch switches, unassessed sign
    changes) and the recorded levels; ``analysis_time``: CPU seconds of the load stepping."""
    critical = critical_points(path) if opts.detect_critical else []
    message = failure or f"converged: {len(path.iterations)} steps, {sum(path.iterations)} iterations"
    lams = path.step_lams
    where = "level parameter" if control == "load" else "load factor"
    for i, note in path.branch_switches:
        message += f"; bifurcation at {where} {lams[i] if i < len(lams) else float('nan'):.6g}: {note}"
    for i in path.unassessed:
        message += (
            f"; det K changed sign at step {i + 1} under follower (non-conservative) loads: stability not assessed"
        )
    return build_result(
        model,
        system,
        path,
        converged=failure is None,
        message=message,
        critical_points=critical,
        wall_time=time.perf_counter() - t0,
        control=control,
        refine=opts.refine,
        analysis_time=analysis_time,
    )


def solve_load(model: Model, control: LoadControl = LoadControl(), opts: SolveOptions = SolveOptions()) -> FemResult:
    """Load control: the loads and prescribed values follow their per-level histories."""
    t0 = time.perf_counter()
    system = _prepare(model, opts, control.n_levels, check=not control.held)
    guesses = (
        None
        if control.initial_guess is None
        else level_guesses(control.initial_guess, system.disc, system.X1, system.X2)
    )
    path = Path()
    cpu = time.process_time()
    failure = _stopped(lambda: _run_load(system, opts, path, guesses))
    return _finish(model, system, path, opts, failure, "load", t0, time.process_time() - cpu)


def solve_displacement(model: Model, control: DisplacementControl, opts: SolveOptions = SolveOptions()) -> FemResult:
    """Displacement control: one DOF follows its targets, the load factor is free."""
    t0 = time.perf_counter()
    system = _prepare(model, opts)
    path = Path()
    cpu = time.process_time()
    failure = _stopped(lambda: _run_disp(system, model, control, opts, path))
    return _finish(model, system, path, opts, failure, "displacement", t0, time.process_time() - cpu)


def solve_arclength(
    model: Model, control: ArcLengthControl = ArcLengthControl(), opts: SolveOptions = SolveOptions()
) -> FemResult:
    """Arc-length control of the model's load pattern (its loads at the last level)."""
    t0 = time.perf_counter()
    system = _prepare(model, opts)
    path = Path()
    cpu = time.process_time()
    failure = _stopped(lambda: _run_arc(system, model, control, opts, path))
    return _finish(model, system, path, opts, failure, "arclength", t0, time.process_time() - cpu)


def solve(
    model: Model,
    n_levels: int | None = None,
    control: str = "load",
    *,
    control_dof: Sequence[Any] | None = None,
    targets: ArrayLike | None = None,
    initial_guess: FemResult | None = None,
    arc_length: float | None = None,
    max_arc_length: float | None = None,
    max_steps: int = 2000,
    until: tuple[NodeRef, str, float] | None = None,
    lambda_max: float | None = None,
    direction: float = 1.0,
    max_limit_points: int | None = None,
    held: bool = False,
    **options: Any,
) -> FemResult:
    """Solve the model; returns a `FemResult` (the keyword form of `solve_load`,
    `solve_displacement` and `solve_arclength`; ``options`` are the fields of `SolveOptions`).

    control="load": loads/prescribed values follow their per-level histories.
    ``n_levels`` given for a model whose loads have a single value applies them
    proportionally in n_levels equal levels (k/n_levels, k = 1..n_levels).  control="displacement":
    ``control_dof=(node, 'ux'|'uy'|'rz')`` follows ``targets`` (one per output
    level) and the load pattern (the model's loads at its last level) is scaled
    by the unknown load factor.  control="arclength": the same load pattern,
    traced by arc length ``arc_length`` (consistent length units) until
    ``until=(node, dof, value)`` is crossed, |load factor| >= ``lambda_max``,
    ``max_limit_points`` limit points have been passed, or ``max_steps``
    steps.  ``initial_guess``: a converged load-control `FemResult` of the same
    model with half the elements per member (as many in a member that is not refined), used as
    predictor (`warm_start`). ``held`` (load control): the model is known to have no free motion (a
    coarser mesh of this same model passed the free-motion test; `LoadControl`), the test is skipped.
    ``refine`` multiplies the element count of every member but those added with ``refined=False``.
    Tolerance: |r| <= rtol max(|f_ext|, |f_int|) + atol.
    Step control: each level is tried in one step; a Newton correction that turns a node by more
    than ``max_iteration_rotation`` (rad) is scaled down to it (a far-off linear predictor is walked
    in rather than the step cut), and a converged step is rejected and cut only when a nodal
    rotation changed by more than ``max_rotation_increment`` (default pi: an equilibrium 2 pi away
    at some node, a spurious copy, is then always further than the cap from the last state).
    ``check_stability`` (load and displacement control): a converged state that
    lost stability (a bifurcation was crossed) is not returned; the solve switches
    to a stable branch (noted in the critical point and the message) or returns
    converged=False (`stability`).  Arc-length only reports det K sign changes.
    """
    opts = SolveOptions(**options)
    if control == "load":
        return solve_load(model, LoadControl(n_levels, initial_guess, held), opts)
    if n_levels is not None and model.n_levels not in (1, n_levels):
        raise ValueError(f"n_levels={n_levels} but the load histories have {model.n_levels}")
    if control == "displacement":
        if control_dof is None or targets is None:
            raise ValueError("displacement control needs control_dof and targets")
        node, dof = control_dof
        return solve_displacement(model, DisplacementControl((node, dof), tuple(np.atleast_1d(targets))), opts)
    if control == "arclength":
        return solve_arclength(
            model,
            ArcLengthControl(arc_length, max_arc_length, max_steps, until, lambda_max, direction, max_limit_points),
            opts,
        )
    raise ValueError("control must be 'load', 'displacement' or 'arclength'")
