"""Newton-Raphson corrector shared by every solver, and what makes a step acceptable.

One corrector solves r(q, lambda) = f_int(q) - lambda f_ref(q) = 0 for
    mode 'load':  lambda fixed;                    dq = -K^-1 r
    mode 'disp':  q_c = u_c* (bordered system):    K a = -r, K b = f_ref,
                  dlambda = (u_c* - q_c - a_c)/b_c, dq = a + dlambda b
    mode 'arc':   ||q - q0||_W = dl (Crisfield cylindrical arc length): dlambda is
                  the root of the quadratic constraint whose increment makes the
                  smallest angle with the current one (Crisfield 1991, sec. 9.3.4).
Convergence: |r| <= rtol max(|lambda f_ref|, |f_int|) (+ a rounding floor
~ eps EA), or the energy criterion |dq . r| <= (rtol F)(rtol L_ref) (Bathe),
or corrections below 1e-13 L_ref.

Rotation continuity (a converged residual is not enough: the full-circle
roll-up has spurious equilibria with rotations 4 pi, 6 pi): a converged state
is rejected when an element's end rotations differ from its chord by more
than pi (a 2 pi jump between neighbouring nodes), or when a nodal rotation
changed by more than ``max_rotation_increment`` in the step; the step is then
cut in proportion. Under load control a correction that turns a node by more than
``max_iteration_rotation`` is scaled down to it (a damped Newton step): one step per level
converges from a linear predictor that is far off (a cantilever at PL^2/EI = 10 is predicted at
5 rad) instead of landing on a 2 pi jump.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from . import kernel as cn
from .linear_solver import Factor, SingularMatrix
from .options import NewtonOutcome, SolveOptions
from .types import Evaluation, FloatArray, Loads, SignedFactor

if TYPE_CHECKING:
    from .assembly import System

__all__ = [
    "StepFailed",
    "Path",
    "newton",
    "acceptance_facts",
    "accept_check",
    "snapshot",
    "det_sign",
    "growth",
    "Control",
    "Arc",
]

Control = tuple[int, float, float]  # displacement control: (unknown k, coefficient c, target of c q_k)
Arc = tuple[float, FloatArray, FloatArray]  # arc length: (dl, weights W of ||.||_W, q at the step's start)


class StepFailed(Exception):
    """A Newton step that did not converge or was rejected: why (``reason``), at which iteration, and
    the factor to cut the step by."""

    def __init__(self, reason: str, iteration: int, cut: float = 0.5):
        super().__init__(reason)
        self.reason, self.iteration, self.cut = reason, iteration, cut


def growth(its: int) -> float:
    """Step-size factor after an accepted step that took `its` iterations."""
    return 2.0 if its <= 4 else 1.25 if its <= 6 else 1.0 if its <= 9 else 0.5


class Path:
    """Accepted states, per-step statistics and recorded output levels."""

    def __init__(self) -> None:
        self.snapshots: list[dict[str, Any]] = []  # `snapshot` of each recorded level
        self.residuals: list[FloatArray] = []
        self.iterations: list[int] = []
        self.det_signs: list[int] = []
        self.step_lams: list[float] = []
        self.step_ctrl: list[float] = []
        self.step_s: list[float] = []
        self.step_slope: list[float] = []
        self.cutbacks = 0
        self.stable = True  # last accepted state stable (load/displacement control)
        self.branch_switches: list[tuple[int, str]] = []  # (step index, note)
        self.unassessed: list[int] = []  # step indices: det K < 0 under follower loads
        self.rejected_iterations = 0
        self.precision_checked = False  # `solver._beyond_precision` made its one test

    def record(
        self,
        history: list[float],
        iterations: int,
        sign: int,
        load: float,
        slope: float = np.nan,
        control: float | None = None,
        parameter: float | None = None,
    ) -> None:
        """The per-step statistics of one accepted step (the same for every control mode)."""
        self.residuals.append(np.array(history))
        self.iterations.append(iterations)
        self.det_signs.append(sign)
        self.step_lams.append(load)
        self.step_slope.append(slope)
        if control is not None:
            self.step_ctrl.append(control)
        if parameter is not None:
            self.step_s.append(parameter)

    def mark_start(self) -> None:
        """The unloaded start of an arc-length trace: a state of the path, not a step."""
        self.det_signs.append(1)
        self.step_lams.append(0.0)
        self.step_slope.append(np.nan)
        self.step_ctrl.append(0.0)
        self.step_s.append(0.0)

    def reject(self, iterations: int) -> None:
        """A step that was tried and cut: its iterations count."""
        self.cutbacks += 1
        self.rejected_iterations += iterations


def newton(
    system: System,
    q: FloatArray,
    lam: float,
    beta: FloatArray,
    loads: Loads,
    opts: SolveOptions,
    mode: str = "load",
    ctrl: Control | None = None,
    arc: Arc | None = None,
    q_start: FloatArray | None = None,
) -> NewtonOutcome:
    """Corrector.  mode 'load' (lambda fixed), 'disp' (ctrl=(k, coef, target)),
    'arc' (arc=(dl, w, q0)).  Raises `StepFailed` when it does not converge. Under load control a
    system the compiled corrector handles (`kernel.newton_load`) is solved there, with the same steps."""
    if mode == "load" and system.compiled is not None:
        return _newton_compiled(system, q, lam, beta, loads, opts, q_start)
    F_fixed, F0, presc = loads
    hist: list[float] = []
    dq_small = False
    fac: Factor | None = None
    rot = system.disc.red_is_rotation
    has_rot = bool(rot.any())
    scale = np.where(rot, 1.0, system.L_ref)
    q_start = q.copy() if q_start is None else q_start
    for it in range(opts.maxiter + 1):
        ev = system.evaluate(q, beta, lam, F_fixed, F0, presc, need_K=True)
        r = ev["r"]
        rn = math.sqrt(float(r.dot(r)))  # = np.linalg.norm(r) (its own formula), without its overhead
        floor = system.noise_floor
        tol = opts.rtol * ev["F_scale"] + floor + opts.atol
        hist.append(rn / max(ev["F_scale"], 1e-300))
        if not math.isfinite(rn):
            raise StepFailed("residual is not finite", it)
        # before the first correction the rounding floor does not count: a load below it (4 eps EA) would
        # otherwise leave the unloaded state accepted as converged
        if (rn <= tol or dq_small) and (it > 0 or mode == "load" and rn <= opts.rtol * ev["F_scale"] + opts.atol):
            return NewtonOutcome(q, lam, ev, hist, it, fac)
        if it == opts.maxiter:
            raise StepFailed(f"no convergence in {it} iterations (|r|/F = {hist[-1]:.2e})", it)
        try:
            fac = system.layout.factor(ev["K"])
        except SingularMatrix as exc:
            raise StepFailed(f"{exc}", it) from None
        a = fac.solve(-ev["r"])
        if mode == "load":
            dq, dlam = a, 0.0
            damp = opts.max_iteration_rotation
            if damp and has_rot:  # rotation-limited correction: a far-off predictor is walked in
                big = float(np.abs(dq[rot]).max())
                if big > damp:
                    dq = dq * (damp / big)
        else:
            b = fac.solve(ev["f_ref"])
            if mode == "disp":
                assert ctrl is not None, "mode 'disp' needs ctrl"
                k, coef, target = ctrl
                if b[k] == 0.0:
                    raise StepFailed("control DOF does not respond to the load", it)
                dlam = float((target / coef - q[k] - a[k]) / b[k])
            else:
                assert arc is not None, "mode 'arc' needs arc"
                dl, w, q0 = arc
                Dq = q - q0
                v = Dq + a
                a1 = np.dot(b * w, b)
                a2 = 2 * np.dot(b * w, v)
                a3 = np.dot(v * w, v) - dl * dl
                disc = a2 * a2 - 4 * a1 * a3
                if disc < 0:
                    raise StepFailed("arc-length constraint has no real root", it)
                roots = (-a2 + np.array([1.0, -1.0]) * np.sqrt(disc)) / (2 * a1)
                cosines = [np.dot((v + r_ * b) * w, Dq) for r_ in roots]
                dlam = float(roots[int(np.argmax(cosines))])
            dq = a + dlam * b
        if it > 0 and abs(float(np.dot(dq, ev["r"]))) <= opts.rtol**2 * ev["F_scale"] * system.L_ref:
            # energy criterion |dq . r| <= (rtol F)(rtol L): the remaining correction is
            # negligible; this stops iterating on rounding noise of stiff axial terms
            return NewtonOutcome(q, lam, ev, hist, it, fac)
        q = q + dq
        lam = lam + dlam
        dq_small = bool(np.all(np.abs(dq) <= 1e-13 * scale)) and abs(dlam) <= 1e-13 * max(abs(lam), 1e-300)
        if has_rot:
            dth = float(np.abs(q[rot] - q_start[rot]).max())
            limit = (2 if it == 0 else 4) * opts.max_rotation_increment
            if dth > limit:  # cut now rather than iterate towards a rejected state
                raise StepFailed(
                    f"rotation increment {dth:.3g} rad too large",
                    it + 1,
                    cut=max(0.1, 0.9 * opts.max_rotation_increment / dth),
                )
    raise AssertionError("unreachable")


class _Sign:
    """The sign of det K of the compiled corrector's last factorisation (what load control reads
    of a `linear_solver.Factor`); ``final``: that factorisation is of the converged state itself (a run
    that converged before any Newton correction, or the corrector's own confirmation of a sign not
    positive), so even a negative sign needs no confirmation."""

    def __init__(self, det_sign: int, final: bool = False):
        self.det_sign = det_sign
        self.final = final


class _Evaluation(dict[str, Any]):
    """The evaluation of a compiled Newton run, as `assembly.System.evaluate` gives it; its tangent "K",
    which only the stability checks read, is turned from the kernel's column-major storage into the
    row-major storage of `linear_solver.MatrixLayout` when first read, and with rigid links the
    constraint coefficients "C" are put together from their constant first column and the second
    the kernel turned with the masters (``turned``) likewise."""

    column_major: tuple[cn.CompiledLayout, FloatArray]
    turned: tuple[FloatArray, FloatArray]
    inertia_below: int  # the corrector's inertia test at this state (`kernel.newton_load`), -1: not made

    def __missing__(self, key: str) -> Any:
        if key == "K":
            layout, K = self.column_major
            value = self["K"] = layout.row_major(K)
        elif key == "C":
            C0, second = self.turned
            value = self["C"] = np.column_stack([C0[:, 0], second])
        else:
            raise KeyError(key)
        return value


def _controls(system: System, opts: SolveOptions) -> cn.Controls:
    """The compiled corrector's `kernel.Controls` of a solve: the options' tolerances and limits, the
    system's rounding floor and reference length; the converged sign confirmed where `det_sign` would
    (``opts.watch_det``), the inertia test of `solver._even_crossing` made where it can be asked
    (``opts.check_stability`` and the system's ``inertia_tol``)."""
    return cn.Controls(
        rtol=float(opts.rtol),
        atol=float(opts.atol),
        floor=float(system.noise_floor),
        L_ref=float(system.L_ref),
        maxiter=int(opts.maxiter),
        damp=float(opts.max_iteration_rotation or 0.0),
        max_rot_inc=float(opts.max_rotation_increment),
        confirm_sign=bool(opts.watch_det),
        inertia_tol=float(system.inertia_tol) if opts.check_stability else math.nan,
    )


def _newton_compiled(
    system: System,
    q: FloatArray,
    lam: float,
    beta: FloatArray,
    loads: Loads,
    opts: SolveOptions,
    q_start: FloatArray | None,
) -> NewtonOutcome:
    """`newton` under load control by one call of `kernel.newton_load` on the system's groups: the same
    outcome or failure."""
    F_fixed, _, presc = loads
    c, d, storage = system.compiled, system.disc, system.storage
    assert c is not None and storage is not None  # `newton` calls it only then
    q = np.array(q, dtype=float)
    start = cn.Start(q=q.copy() if q_start is None else q_start, beta=beta)
    load = cn.Load(lam=float(lam), F_fixed=F_fixed, presc=np.asarray(presc, dtype=float))
    work = cn.work_arrays(n=system.n, nf=d.n_full + 1, size=c.size, maxiter=opts.maxiter, links=system.width == 2)
    el = cn.element_outputs(len(d.L0))
    if system.controls is None or system.controls[0] is not opts:  # one solve's options: made once
        system.controls = (opts, _controls(system, opts))
    out = cn.newton_load(
        q, start, load, system.beams, system.dofs, system.couplings, storage, system.controls[1], work, el
    )
    it, dth = out.iterations, out.rotation
    history = work.hist[: it + 1].tolist()
    if out.status == cn.NOT_FINITE:
        raise StepFailed("residual is not finite", it)
    if out.status == cn.NO_CONVERGENCE:
        raise StepFailed(f"no convergence in {it} iterations (|r|/F = {history[-1]:.2e})", it)
    if out.status in (cn.SINGULAR, cn.NON_FINITE_TANGENT):
        raise StepFailed("singular tangent" if out.status == cn.SINGULAR else "non-finite entries in the tangent", it)
    if out.status == cn.ROTATION_TOO_LARGE:
        raise StepFailed(
            f"rotation increment {dth:.3g} rad too large", it, cut=max(0.1, 0.9 * opts.max_rotation_increment / dth)
        )
    ev = _Evaluation(
        u=work.u,
        el=el._asdict(),
        f_int=work.f_int,
        f_ref_full=work.f_ref,
        R_full=work.R,
        r=work.r,
        f_ref=work.fr,
        F_scale=out.scale,
    )
    if system.width == 1:
        ev["C"] = system.C0
    ev.column_major, ev.turned = (c, work.K), (system.C0, work.C1w)
    ev.inertia_below = out.below
    return NewtonOutcome(
        q,
        lam,
        ev,
        history,
        it,
        None if out.sign == 2 else _Sign(out.sign, final=out.final),
        accept=(out.status == cn.CONVERGED_JUMPED, dth),
    )


def acceptance_facts(
    system: System, q_new: FloatArray, q_old: FloatArray, ev: Evaluation, known: tuple[bool, float] | None = None
) -> tuple[bool, float]:
    """(an element's end rotations jumped by about 2 pi, the largest rotation change from q_old to q_new,
    0 without rotations) of the converged state ``ev``: ``known`` when given (`NewtonOutcome.accept`, the
    compiled corrector's own, valid when q_old was its start), else from the evaluation."""
    if known is not None:
        return known
    rot = system.disc.red_is_rotation
    return (bool(ev["el"]["jumped"].any()), float(np.abs(q_new[rot] - q_old[rot]).max()) if rot.any() else 0.0)


def accept_check(
    system: System,
    q_new: FloatArray,
    q_old: FloatArray,
    ev: Evaluation,
    opts: SolveOptions,
    its: int,
    known: tuple[bool, float] | None = None,
) -> None:
    """Raise StepFailed if a converged state must be rejected (`acceptance_facts`, ``known`` as there)."""
    jumped, dth = acceptance_facts(system, q_new, q_old, ev, known)
    if jumped:
        e = int(np.argmax(ev["el"]["jumped"]))
        raise StepFailed(f"rotation jump of about 2 pi between the nodes of element {e}", its)
    if dth > opts.max_rotation_increment:
        raise StepFailed(
            f"rotation increment {dth:.3g} rad exceeds max_rotation_increment",
            its,
            cut=max(0.1, 0.8 * opts.max_rotation_increment / dth),
        )


def snapshot(system: System, q: FloatArray, lam: float, ev: Evaluation, level_param: float) -> dict[str, Any]:
    """The state of a recorded level. The arrays of a compiled corrector's evaluation are its own (made
    for its call, written by nothing after it): kept as they are; those of `assembly.System.evaluate`
    are copied."""
    el = ev["el"]
    kept = _as_it_is if isinstance(ev, _Evaluation) else np.copy
    return dict(
        q=q.copy(),
        lam=lam,
        u=kept(ev["u"]),
        R_full=kept(ev["R_full"]),
        N=kept(el["N"]),
        M=kept(el["M"]),
        L=kept(el["L"]),
        theta_bar=kept(el["theta_bar"]),
        u_bar=kept(el["u_bar"]),
        level=level_param,
    )


def _as_it_is(array: FloatArray) -> FloatArray:
    return array


def det_sign(system: System, ev: Evaluation, fac: SignedFactor | None = None) -> int:
    """Sign of det K at the converged state ``ev``: from the last Newton factorisation ``fac`` when it
    says positive, else from a fresh factorisation at ``ev``. That factorisation is one iterate before
    convergence, which after a long step can lie far from it (Test 2 at 128 elements: |r|/F = 3.2 there
    and det K < 0, while the converged state has det K > 0), so a negative sign is confirmed before it
    counts as lost stability or a critical point; a positive one is taken as it is (no extra
    factorisation on a stable path). A factorisation of the converged state itself (``final``, the
    compiled corrector's when it converged before any correction) is taken whatever its sign."""
    if fac is not None and (fac.det_sign > 0 or fac.final):
        return fac.det_sign
    try:
        return system.layout.factor(ev["K"]).det_sign
    except SingularMatrix:
        return 0
