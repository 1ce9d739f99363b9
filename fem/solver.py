"""Incremental-iterative solvers: load control, displacement control, arc-length.

All three solve  r(q, lambda) = f_int(q) - lambda f_ref(q) = 0  on the reduced
unknowns q (`assembly.System`) by Newton-Raphson with the consistent tangent K.

* Load control (lambda = 1, loads and prescribed values interpolated linearly
  between load levels, parameter t in [0, 1] per segment): adaptive substeps,
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
in `newton`; limit points and bifurcations are found by `critical`.
"""
from __future__ import annotations

import time

import numpy as np

from .assembly import System
from .critical import critical_points
from .discretise import discretise
from .free_motion import check_held
from .linear_solver import SingularMatrix
from .model import DOF_NAMES, Model
from .newton import Path, StepFailed, accept_check, det_sign, growth, newton, snapshot
from .result import build_result
from .stability import DENSE_LIMIT, conservative, eigenvalue_below, held_sign, switch_branch, zero_eigenvalue
from .warm_start import chord_angles, guess_states, reduced_from_full

__all__ = ["solve"]


def _try_guess(system, opts, path, u_guess, q, loads):
    """Newton from a warm-start guess of a whole level; None if not acceptable."""
    d = system.disc
    q_g = reduced_from_full(d, u_guess)
    beta_g = chord_angles(d, u_guess, system.X1, system.X2)
    try:
        q_new, lam, ev, hist, its, fac = newton(system, q_g, 1.0, beta_g, loads, opts, q_start=q_g)
    except StepFailed as exc:
        path.rejected_iterations += exc.iteration
        return None
    rot = d.red_is_rotation
    same_branch = not rot.any() or np.abs(q_new[rot] - q_g[rot]).max() < 0.1
    if ev["el"]["jumped"].any() or not same_branch:
        path.rejected_iterations += its
        return None
    return q_new, ev, hist, its, fac


SWITCH_STEP = 1.0 / 64    # branch switching is tried from steps no longer than this (of a level)
JUMP_CUT_FLOOR = 64       # steps shorter than this many min_step are not cut for turning back


def _even_crossing(system, st, held) -> bool:
    """True when det K > 0 hides an unstable state: two (or any even number of) eigenvalues
    crossed zero in one step, which the sign of det K cannot see. Checked by a Cholesky
    factorisation of the shifted, scaled tangent (`stability.eigenvalue_below`), only where it can happen (conservative loads, some member in compression) and only for systems
    small enough for a dense eigensolver (larger ones rely on the sign of det K)."""
    if not conservative(system) or system.n > DENSE_LIMIT:
        return False
    if float(np.min(st["ev"]["el"]["N"], initial=0.0)) >= 0.0:
        return False
    try:   # Jacobi-scaled: unit diagonal
        return eigenvalue_below(system, st["ev"]["K"], held, zero_eigenvalue(1.0, system.n))
    except (ValueError, np.linalg.LinAlgError, RuntimeError):
        return False


def _turned_back(system, dq, dq_prev) -> bool:
    """True when the increment of a load step points against the previous one (negative
    cosine in the norm ||dq||_W, rotations weighted by the mean element length squared):
    under load control the path does not turn back within one step, the state jumped to
    another branch (e.g. the buckled state on the far side of an imperfect column)."""
    d = system.disc
    w = np.where(d.red_is_rotation, float(np.mean(d.L0)) ** 2 if len(d.L0) else 1.0, 1.0)
    return bool(np.dot(dq * w, dq_prev) < 0.0)


def _lost_stability(system, opts, path, st, held=None) -> bool:
    """True when a converged step took the stable path to an unstable state: sign det K (of
    K_ff with the control DOF `held` under displacement control) turned negative, or an even
    number of eigenvalues crossed zero (`_even_crossing`). Dead loads only: under follower
    loads a sign change is recorded as unassessed (the static criterion is not decisive) and
    the path is no longer watched. Arc-length never calls this: it traces unstable branches
    on purpose."""
    if not opts["check_stability"] or not path.stable:
        return False
    if st["sign"] >= 0 and not _even_crossing(system, st, held):
        return False
    if not conservative(system):
        path.stable = False
        path.unassessed.append(len(path.step_lams))
        return False
    if held is not None:
        try:
            fac = st["fac"] or system.layout.factor(st["ev"]["K"])
            if held_sign(fac, st["sign"], held) >= 0:
                return False
        except SingularMatrix:
            return False
    return True


def _leave_unstable(system, opts, path, st, loads, q_prev, mode="load", ctrl=None, held=None):
    """Replace the unstable state ``st`` (q, lam, ev, fac, sign, hist, its; updated in place)
    by a stable one on another branch, preferably the one on the side of the path's last
    stable state ``q_prev`` (`stability.switch_branch`). Returns None, or the reason why no
    stable state was found."""
    status, out = switch_branch(system, opts, st["q"], st["lam"], st["beta"], st["ev"], loads,
                                mode=mode, ctrl=ctrl, held=held, q_prev=q_prev)
    if status == "stable":       # the eigenvalues (decisive) put it within rounding of stable
        st["sign"] = 1
        return None
    if status == "failed":
        return ("the converged state is unstable: a bifurcation was crossed (det K < 0, "
                f"{out}); not returned")
    q, lam, ev, hist, its, fac, note = out
    path.branch_switches.append((len(path.step_lams), note))
    st.update(q=q, lam=lam, ev=ev, fac=fac, hist=st["hist"] + hist, its=st["its"] + its,
              sign=det_sign(system, ev, fac), switched=True)
    return None


def _run_load(system, opts, path):
    n_lev = system.n_levels
    q = np.zeros(system.n)
    beta = system.disc.beta0.copy()
    dt = opts["initial_step"]
    guesses = opts.get("guesses")
    for k in range(n_lev):
        a, b = k - 1, k
        t = 0.0
        prev = None
        if guesses is not None:
            got = _try_guess(system, opts, path, guesses[k], q, system.loads_at(a, b, 1.0))
            if got is not None:
                q_g, ev, hist, its, fac = got
                st = dict(q=q_g, lam=1.0, ev=ev, fac=fac, hist=hist, its=its, beta=beta,
                          sign=det_sign(system, ev, fac) if opts["watch_det"] else 0)
                if _lost_stability(system, opts, path, st):
                    got = None      # not a state of the path: step to the level instead
            if got is not None:
                q, ev, hist, its = st["q"], st["ev"], st["hist"], st["its"]
                t, beta = 1.0, ev["el"]["beta"].copy()
                path.residuals.append(np.array(hist))
                path.iterations.append(its)
                path.det_signs.append(st["sign"] if opts["detect_critical"] else 0)
                path.step_lams.append(float(k))
                path.step_slope.append(np.nan)
        while t < 1.0:
            dt = min(dt, 1.0 - t)
            t_new = 1.0 if 1.0 - (t + dt) < 1e-12 else t + dt
            loads = system.loads_at(a, b, t_new)
            q_pred = q if prev is None else q + (t_new - t) / prev[1] * prev[0]
            try:
                q_new, lam, ev, hist, its, fac = newton(
                    system, q_pred, 1.0, beta, loads, opts, q_start=q)
                accept_check(system, q_new, q, ev, opts, its)
            except StepFailed as exc:
                path.cutbacks += 1
                path.rejected_iterations += exc.iteration
                dt *= exc.cut
                if dt < opts["min_step"]:
                    return (f"load level {k}: no convergence between t = {t:.6g} and "
                            f"{t_new:.6g} of the segment from level {a} (step < min_step), "
                            f"iteration {exc.iteration}: {exc.reason}")
                continue
            if (prev is not None and dt > JUMP_CUT_FLOOR * opts["min_step"]
                    and _turned_back(system, q_new - q, prev[0])):
                path.cutbacks += 1          # left the path: jumped to another branch
                path.rejected_iterations += its
                dt *= 0.25
                continue
            st = dict(q=q_new, lam=1.0, ev=ev, fac=fac, hist=hist, its=its, beta=beta,
                      sign=det_sign(system, ev, fac) if opts["watch_det"] else 0)
            if _lost_stability(system, opts, path, st):
                if dt > SWITCH_STEP:   # a long step may have jumped off an imperfect path, or
                    path.cutbacks += 1  # crossed several critical loads: retry shorter
                    dt *= 0.25
                    continue
                why = _leave_unstable(system, opts, path, st, loads, q)
                if why:
                    return (f"load level {k}: step from t = {t:.6g} to {t_new:.6g} of the "
                            f"segment from level {a}: {why}")
            q_new, ev, hist, its = st["q"], st["ev"], st["hist"], st["its"]
            switched = st.get("switched", False)
            prev = (q_new - q, t_new - t) if opts["predictor"] == "secant" and not switched else None
            q, t, beta = q_new, t_new, ev["el"]["beta"].copy()
            path.residuals.append(np.array(hist))
            path.iterations.append(its)
            path.det_signs.append(st["sign"] if opts["detect_critical"] else 0)
            path.step_lams.append(k - 1 + t)
            path.step_slope.append(np.nan)
            dt *= growth(its)
        path.snapshots.append(snapshot(system, q, 1.0, ev, float(k)))
    return None


def _control_index(system, model, control):
    node, dof = control
    node = model.node(node)
    d = system.disc
    i = 2 * node + DOF_NAMES[dof] if DOF_NAMES[dof] < 2 else d.rot_dof[node]
    k, c = d.I[i, 0], d.C[i, 0]
    if k >= system.n or c == 0.0 or not d.independent[i]:
        raise ValueError(f"control DOF {control} is constrained or dependent")
    return int(k), float(c)


def _reference_loads(system):
    if system.presc.size and np.any(system.presc != 0.0):
        raise ValueError("displacement/arc-length control needs zero prescribed values; "
                         "the load pattern is scaled by the load factor")
    return system.F_fixed[-1], system.F0[-1], system.presc[-1] * 0.0


def _run_disp(system, model, opts, path):
    k, coef = _control_index(system, model, opts["control_dof"])
    targets = np.atleast_1d(np.asarray(opts["targets"], dtype=float))
    loads = _reference_loads(system)
    q = np.zeros(system.n)
    lam = 0.0
    beta = system.disc.beta0.copy()
    frac = opts["initial_step"]
    prev = None
    for lev, target in enumerate(targets):
        u_a = q[k] * coef
        t = 0.0
        while t < 1.0:
            frac = min(frac, 1.0 - t)
            t_new = 1.0 if 1.0 - (t + frac) < 1e-12 else t + frac
            u_t = u_a + t_new * (target - u_a)
            q_pred, lam_pred = q, lam
            if prev is not None and prev[2] != 0.0:
                ratio = (u_t - q[k] * coef) / prev[2]
                q_pred, lam_pred = q + ratio * prev[0], lam + ratio * prev[1]
            try:
                q_new, lam_new, ev, hist, its, fac = newton(
                    system, q_pred, lam_pred, beta, loads, opts, mode="disp",
                    ctrl=(k, coef, u_t), q_start=q)
                accept_check(system, q_new, q, ev, opts, its)
            except StepFailed as exc:
                path.cutbacks += 1
                path.rejected_iterations += exc.iteration
                frac *= exc.cut
                if frac < opts["min_step"]:
                    return (f"load level {lev} (control displacement {u_t:.6g}): no convergence, "
                            f"iteration {exc.iteration}: {exc.reason}")
                continue
            st = dict(q=q_new, lam=lam_new, ev=ev, fac=fac, hist=hist, its=its, beta=beta,
                      sign=det_sign(system, ev, fac) if opts["watch_det"] else 0)
            why = None
            if _lost_stability(system, opts, path, st, held=k):
                why = _leave_unstable(system, opts, path, st, loads, q, mode="disp",
                                      ctrl=(k, coef, u_t), held=k)
            if why:
                return f"load level {lev} (control displacement {u_t:.6g}): {why}"
            q_new, lam_new, ev, hist, its, fac = (st[key] for key in ("q", "lam", "ev", "hist", "its", "fac"))
            if opts["predictor"] == "secant":
                prev = None if st.get("switched") else (q_new - q, lam_new - lam, (q_new[k] - q[k]) * coef)
            q, lam, t, beta = q_new, lam_new, t_new, ev["el"]["beta"].copy()
            path.residuals.append(np.array(hist))
            path.iterations.append(its)
            sign, slope = 0, np.nan
            if opts["detect_critical"]:
                try:
                    fac = fac or system.layout.factor(ev["K"])
                    sign, bb = fac.det_sign, fac.solve(ev["f_ref"])
                    slope = 1.0 / (bb[k] * coef) if bb[k] != 0 else np.nan
                except SingularMatrix:
                    pass
            path.det_signs.append(sign)
            path.step_slope.append(slope)
            path.step_lams.append(lam)
            path.step_ctrl.append(u_t)
            path.step_s.append(u_t)
            frac *= growth(its)
        path.snapshots.append(snapshot(system, q, lam, ev, float(lev)))
    return None


def _run_arc(system, model, opts, path):
    loads = _reference_loads(system)
    d = system.disc
    w = np.where(d.red_is_rotation, float(np.mean(d.L0)) ** 2 if len(d.L0) else 1.0, 1.0)
    stop = opts.get("until")
    if stop is not None:
        k_stop, c_stop = _control_index(system, model, stop[:2])
        u_stop = float(stop[2])
    q = np.zeros(system.n)
    lam = 0.0
    beta = d.beta0.copy()
    dl = opts["arc_length"] or 0.05 * system.L_ref
    dl_max = opts["max_arc_length"] or 20 * dl
    dl_min = dl * 1e-6
    Dq_prev = None
    sign = float(np.sign(opts["direction"]) or 1.0)
    s_total = 0.0
    n_limits = 0
    path.snapshots.append(snapshot(system, q, lam, system.evaluate(q, beta, lam, *loads, need_K=False), 0.0))
    path.step_lams.append(0.0)
    path.step_s.append(0.0)
    path.det_signs.append(1)
    path.step_ctrl.append(0.0)
    path.step_slope.append(np.nan)
    cached = None
    hist3 = [(0.0, q.copy(), lam)]
    while len(path.iterations) < opts["max_steps"]:
        try:
            if cached is None:
                ev0 = system.evaluate(q, beta, lam, *loads, need_K=True)
                fac = system.layout.factor(ev0["K"])
                b = fac.solve(ev0["f_ref"])
            else:
                fac, b = cached
            nb = np.sqrt(np.dot(b * w, b))
            if Dq_prev is not None:
                sign = 1.0 if np.dot(b * w, Dq_prev) >= 0 else -1.0
            dlam = sign * dl / nb
            q_pred, lam_pred = q + dlam * b, lam + dlam
            if opts["predictor"] == "secant" and len(hist3) == 3:
                # quadratic extrapolation along the path (error O(dl^3) instead of
                # O(dl^2)): smaller axial overshoot of slender members
                (s0, q0, l0), (s1, q1, l1), (s2, q2, l2) = hist3
                x = s2 + dl
                c0 = (x - s1) * (x - s2) / ((s0 - s1) * (s0 - s2))
                c1 = (x - s0) * (x - s2) / ((s1 - s0) * (s1 - s2))
                c2 = (x - s0) * (x - s1) / ((s2 - s0) * (s2 - s1))
                q_pred, lam_pred = c0 * q0 + c1 * q1 + c2 * q2, c0 * l0 + c1 * l1 + c2 * l2
            q_new, lam_new, ev, hist, its, fac = newton(
                system, q_pred, lam_pred, beta, loads, opts, mode="arc",
                arc=(dl, w, q), q_start=q)
            accept_check(system, q_new, q, ev, opts, its)
        except (StepFailed, SingularMatrix) as exc:
            path.cutbacks += 1
            path.rejected_iterations += getattr(exc, "iteration", 0)
            hist3 = hist3[-1:]
            cached = None
            dl *= getattr(exc, "cut", 0.5)
            if dl < dl_min:
                it = getattr(exc, "iteration", 0)
                return (f"arc-length step {len(path.iterations) + 1} (load factor {lam:.6g}): "
                        f"no convergence, iteration {it}: {getattr(exc, 'reason', exc)}")
            continue
        Dq_prev = q_new - q
        q, lam, beta = q_new, lam_new, ev["el"]["beta"].copy()
        s_total += float(np.sqrt(np.dot(Dq_prev * w, Dq_prev)))
        hist3 = (hist3 + [(s_total, q.copy(), lam)])[-3:]
        path.residuals.append(np.array(hist))
        path.iterations.append(its)
        try:
            fac = fac or system.layout.factor(ev["K"])
            b = fac.solve(ev["f_ref"])
            cached = (fac, b)
            nb = np.sqrt(np.dot(b * w, b))
            travel = 1.0 if np.dot(b * w, Dq_prev) >= 0 else -1.0
            path.det_signs.append(fac.det_sign)
            path.step_slope.append(travel / nb)
        except SingularMatrix:
            cached = None
            path.det_signs.append(0)
            path.step_slope.append(np.nan)
        path.step_lams.append(lam)
        path.step_s.append(s_total)
        path.step_ctrl.append(q[k_stop] * c_stop if stop is not None else np.nan)
        path.snapshots.append(snapshot(system, q, lam, ev, float(len(path.snapshots))))
        dl = min(dl * float(np.clip(opts["target_iterations"] / max(its, 1), 0.5, 2.0)), dl_max)
        if stop is not None:
            u0 = path.step_ctrl[-2]
            if (u0 - u_stop) * (path.step_ctrl[-1] - u_stop) <= 0 and len(path.iterations) > 1:
                return None
        if opts["lambda_max"] is not None and abs(lam) >= opts["lambda_max"]:
            return None
        if opts["max_limit_points"] is not None and len(path.step_lams) >= 3:
            l3 = path.step_lams[-3:]
            if (l3[1] - l3[0]) * (l3[2] - l3[1]) < 0:
                n_limits += 1
                if n_limits >= opts["max_limit_points"]:
                    return None
    if stop is None and opts["lambda_max"] is None and opts["max_limit_points"] is None:
        return None
    return f"arc-length: max_steps = {opts['max_steps']} reached before the stop condition"


def solve(model: Model, n_levels: int | None = None, control: str = "load", *,
          refine: int = 1, rtol: float = 1e-10, atol: float = 0.0, max_iter: int = 20,
          initial_step: float = 1.0, min_step: float = 1e-7,
          max_rotation_increment: float = np.pi, max_iteration_rotation: float = 1.0,
          detect_critical: bool = True,
          control_dof=None, targets=None,
          arc_length: float | None = None, max_arc_length: float | None = None,
          max_steps: int = 2000, until=None, lambda_max: float | None = None,
          direction: float = 1.0, target_iterations: int = 5, solver: str = "auto",
          predictor: str = "secant", max_limit_points: int | None = None,
          initial_guess=None, check_stability: bool = True):
    """Solve the model; returns a `FemResult`.

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
    model with half the elements per member, used as predictor (`warm_start`).
    ``refine`` multiplies every member's element count.
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
    t0 = time.perf_counter()
    if n_levels is not None and model.n_levels not in (1, n_levels):
        raise ValueError(f"n_levels={n_levels} but the load histories have {model.n_levels}")
    disc = discretise(model, refine=refine)
    system = System(model, disc, solver_kind=solver, n_levels=n_levels)
    check_held(system)
    opts = dict(rtol=rtol, atol=atol, max_iter=max_iter, initial_step=initial_step,
                min_step=min_step, max_rotation_increment=max_rotation_increment,
                max_iteration_rotation=max_iteration_rotation,
                detect_critical=detect_critical, control_dof=control_dof, targets=targets,
                arc_length=arc_length, max_arc_length=max_arc_length, max_steps=max_steps,
                until=until, lambda_max=lambda_max, direction=direction,
                target_iterations=target_iterations, predictor=predictor,
                max_limit_points=max_limit_points, check_stability=check_stability,
                watch_det=detect_critical or check_stability)
    if initial_guess is not None and control == "load":
        opts["guesses"] = guess_states(initial_guess, disc)
    path = Path()
    if control == "load":
        failure = _run_load(system, opts, path)
    elif control == "displacement":
        if control_dof is None or targets is None:
            raise ValueError("displacement control needs control_dof and targets")
        failure = _run_disp(system, model, opts, path)
    elif control == "arclength":
        failure = _run_arc(system, model, opts, path)
    else:
        raise ValueError("control must be 'load', 'displacement' or 'arclength'")
    critical = critical_points(path) if detect_critical else []
    message = failure or f"converged: {len(path.iterations)} steps, {sum(path.iterations)} iterations"
    lams = path.step_lams
    for i, note in path.branch_switches:
        where = "level parameter" if control == "load" else "load factor"
        message += f"; bifurcation at {where} {lams[i] if i < len(lams) else float('nan'):.6g}: {note}"
    for i in path.unassessed:
        message += (f"; det K changed sign at step {i + 1} under follower (non-conservative) "
                    "loads: stability not assessed")
    return build_result(model, system, path, converged=failure is None, message=message,
                        critical_points=critical, wall_time=time.perf_counter() - t0,
                        control=control, refine=refine)
