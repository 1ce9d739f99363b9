"""``prbm-validate stress``: push every method to its edges and count what happens.

Categories (each check is a function returning ``Check`` records; nothing passes vacuously:
every check asserts an agreement or a specific error):

- ``agreement``: random cantilevers (load direction anywhere, PL^2/EI up to 50, end moments up to
  4 pi EI/L, slenderness 10..1e5, E 1e3..1e12) - the FEM agrees with the exact elastica within its
  own error estimate plus the axial-stretch bound P L/EA (the elastica is inextensible), or it
  says converged = False or that its estimate is unreliable.
- ``invariance``: rotating, mirroring, changing units; the linear limit; mesh refinement.
- ``hard paths``: limit points, rotations past 2 pi, load reversal.
- ``bad input``: NaN, zero or negative sizes, coincident nodes, zero-length members, a
  structure with a zero-stiffness mode: each a specific error or converged = False with a message.
- ``fuzz`` (``mutants`` > 0): mutated shipped case files through ``solve`` and ``run``, each within its
  time bound with exit 0, 1 or 2 and one-line messages (``validation.stress.fuzz_run``).

The cases are built as case data and run through the same adapters as the validation cases.
"""

from __future__ import annotations

import cmath
import hashlib
import html
import json
import math
import random
import time
import tomllib
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import tomli_w
from pydantic import ValidationError
from scipy.optimize import brentq
from scipy.special import ellipk

from prbm import FourBar
from prbm.fits import PAULY_MIDHA, FitRangeError
from validation.case.loader import case_by_id, describe
from validation.case.schema import Case, without_checks
from validation.methods.base import Request
from validation.run.exit_status import decide
from validation.run.output_set import OutputSet
from validation.run.runner import run_method
from validation.stress.contract_run import run_contract_stress
from validation.stress.fuzz_run import fuzz_checks

IN, LBF, PSI = 0.0254, 4.4482216152605, 6894.757293168361


@dataclass
class Check:
    category: str
    name: str
    passed: bool
    detail: str

    def __post_init__(self):
        self.passed = bool(self.passed)


def cantilever(
    length=1.0,
    E=1.0,
    width=1.0,
    thickness=0.01,
    alpha=1.0,
    angle_deg=90.0,
    moment=0.0,
    units="dimensionless",
    elements=16,
    levels=1,
    follower=False,
    methods=("fem",),
    error_estimate=True,
    kappa=0.0,
    reverse=False,
) -> Case:
    """A fixed-free segment with a tip force of P L^2/EI = alpha at angle_deg and/or a tip moment."""
    I = width * thickness**3 / 12.0
    EI = E * I
    P = alpha * EI / length**2
    ramp = [P * (k + 1) / levels for k in range(levels)]
    if reverse:
        ramp = ramp + [-v for v in ramp]
    loads = []
    if alpha:
        a = math.radians(angle_deg)
        loads.append(
            dict(kind="force", point="tip", direction=[math.cos(a), math.sin(a)], values=ramp, follower=follower)
        )
    if moment:
        mvals = [moment * EI / length * (k + 1) / levels for k in range(levels)]
        loads.append(dict(kind="moment", point="tip", values=mvals if not reverse else mvals + [-v for v in mvals]))
    data = dict(
        case=dict(id="stress", title="stress cantilever", group="stress", units=units),
        segment=dict(
            boundary="fixed-free",
            length=length,
            E=E,
            curvature=kappa,
            section=dict(kind="rectangle", width=width, thickness=thickness),
        ),
        loads=loads,
        outputs=[dict(quantity=q) for q in ("x", "y", "rotation")],
        methods={m: ({"elements": elements, "error_estimate": error_estimate} if m == "fem" else {}) for m in methods},
    )
    return Case.model_validate(data)


def tip(run, level=-1):
    reqs = sorted({r.level for r in run.values})
    lv = reqs[level]
    return np.array([run.values[Request(q, "tip", lv)] for q in ("x", "y", "rotation")])


def _estimate(run, level=-1):
    reqs = sorted({r.level for r in run.values})
    lv = reqs[level]
    return max(run.error_estimate.get(Request(q, "tip", lv), 0.0) for q in ("x", "y"))


# --- agreement -----------------------------------------------------------------------------------


def random_cantilever_params(rng: random.Random) -> dict:
    moment = rng.random() < 0.3
    return dict(
        length=10 ** rng.uniform(-2, 2),
        E=10 ** rng.uniform(3, 12),
        slenderness=10 ** rng.uniform(1, 5),
        alpha=0.0 if moment else rng.uniform(0.05, 50.0),
        angle_deg=rng.uniform(0, 360),
        moment=rng.uniform(0.1, 4 * math.pi) if moment else 0.0,
    )


def agreement_check(params: dict) -> Check:
    """FEM against the exact elastica for one cantilever; passes on agreement or an honest failure."""
    L, slender = params["length"], params["slenderness"]
    h = L / slender
    case = cantilever(
        length=L,
        E=params["E"],
        width=h,
        thickness=h,
        alpha=params["alpha"],
        angle_deg=params["angle_deg"],
        moment=params["moment"],
        levels=1,
        methods=("fem", "elastica"),
        elements=16,
    )
    name = ", ".join(f"{k}={v:.4g}" for k, v in params.items())
    fem = run_method(case, "fem")
    exact = run_method(case, "elastica")
    if not exact.converged:
        return Check("agreement", name, True, f"elastica gave no reference ({exact.message}); not compared")
    if not fem.converged:
        ok = bool(fem.message)
        return Check("agreement", name, ok, f"FEM says converged=False: {fem.message}")
    doubtful = [r for r in fem.unreliable_estimate if r.point == "tip" and r.quantity in ("x", "y")]
    if doubtful:
        return Check(
            "agreement",
            name,
            True,
            f"FEM says its estimate is unreliable: {fem.unreliable_estimate[doubtful[0]]}; not compared",
        )
    diff = np.hypot(*(tip(fem)[:2] - tip(exact)[:2]))
    I = h**4 / 12
    stretch = params["alpha"] * (params["E"] * I / L**2) * L / (params["E"] * h * h)  # P L / EA
    allowed = 3.0 * _estimate(fem) + stretch + 1e-9 * L
    return Check(
        "agreement",
        name,
        diff <= allowed,
        f"|FEM - exact| = {diff / L:.3g} L, allowed {allowed / L:.3g} L "
        f"(3 x estimate {3 * _estimate(fem) / L:.2g} L + stretch {stretch / L:.2g} L)",
    )


# --- invariances ---------------------------------------------------------------------------------


def rotated_cantilever(phi_deg: float, alpha: float, angle_deg: float, length=1.0, E=1.0, h=0.01, mirror=False) -> Case:
    phi = math.radians(phi_deg)
    sign = -1.0 if mirror else 1.0
    tipx, tipy = length * math.cos(phi), sign * length * math.sin(phi)
    I = h**4 / 12
    P = alpha * E * I / length**2
    a = math.radians(angle_deg + phi_deg)
    data = dict(
        case=dict(id="stress_rotated", title="rotated cantilever", group="stress", units="SI"),
        mechanism=dict(
            nodes=[dict(name="root", x=0.0, y=0.0), dict(name="tip", x=tipx, y=tipy)],
            beams=[dict(name="b", start="root", end="tip", E=E, section=dict(kind="rectangle", width=h, thickness=h))],
            supports=[dict(node="root", kind="fixed")],
        ),
        loads=[dict(kind="force", point="tip", direction=[math.cos(a), sign * math.sin(a)], values=[P])],
        outputs=[dict(quantity=q, point="tip") for q in ("x", "y", "rotation")],
        methods={"fem": {"elements": 16}},
    )
    return Case.model_validate(data)


def invariance_checks() -> list[Check]:
    checks = []
    base = run_method(rotated_cantilever(0.0, 3.0, 100.0), "fem")
    p0 = tip(base)
    for phi in (30.0, 135.0, -100.0):
        run = run_method(rotated_cantilever(phi, 3.0, 100.0), "fem")
        c, s = math.cos(math.radians(phi)), math.sin(math.radians(phi))
        expected = np.array([c * p0[0] - s * p0[1], s * p0[0] + c * p0[1]])
        err = np.hypot(*(tip(run)[:2] - expected))
        checks.append(
            Check(
                "invariance",
                f"rotation by {phi} deg",
                run.converged and err < 1e-9,
                f"tip differs from the rotated answer by {err:.2e} L",
            )
        )
        drot = abs(tip(run)[2] - p0[2])
        checks.append(
            Check(
                "invariance",
                f"rotation by {phi} deg: tip angle",
                run.converged and drot < 1e-7,
                f"tip rotation differs by {drot:.2e} deg",
            )
        )
    mirrored = run_method(rotated_cantilever(0.0, 3.0, 100.0, mirror=True), "fem")
    pm = tip(mirrored)
    err = abs(pm[0] - p0[0]) + abs(pm[1] + p0[1]) + abs(pm[2] + p0[2]) * 1e-3
    checks.append(
        Check(
            "invariance", "mirror y -> -y", mirrored.converged and err < 1e-9, f"mirrored answer differs by {err:.2e}"
        )
    )
    # unit systems: the same beam in inch-pound and SI
    inch = cantilever(
        length=20.0, E=30e6, width=0.5, thickness=0.0625, alpha=4.0, angle_deg=80.0, units="in-lb", error_estimate=False
    )
    si = cantilever(
        length=20.0 * IN,
        E=30e6 * PSI,
        width=0.5 * IN,
        thickness=0.0625 * IN,
        alpha=4.0,
        angle_deg=80.0,
        units="SI",
        error_estimate=False,
    )
    a, b = tip(run_method(inch, "fem")), tip(run_method(si, "fem"))
    err = max(abs(a[0] / 20.0 - b[0] / (20.0 * IN)), abs(a[1] / 20.0 - b[1] / (20.0 * IN)))
    checks.append(Check("invariance", "inch-pound vs SI", err < 1e-9, f"dimensionless tip differs by {err:.2e}"))
    # linear limit: tip deflection P L^3 / 3EI and rotation P L^2 / 2EI
    tiny = 1e-7
    run = run_method(cantilever(alpha=tiny, angle_deg=90.0, error_estimate=False, elements=4), "fem")
    y, rot = tip(run)[1], math.radians(tip(run)[2])
    rel = max(abs(y / (tiny / 3) - 1), abs(rot / (tiny / 2) - 1))
    checks.append(
        Check(
            "invariance",
            "linear limit PL^3/3EI, PL^2/2EI",
            rel < 1e-6 and run.converged,
            f"relative difference {rel:.2e} (nonlinear terms are O(alpha^2) = 1e-14)",
        )
    )
    # refinement moves the answer by no more than the estimate said: values on the estimate's finest mesh
    # (16 elements, or finer where 4/8/16 are not in the asymptotic range), a plain run on twice as many
    for alpha in (2.0, 10.0):
        est = run_method(cantilever(alpha=alpha, elements=8), "fem")
        fine = 8 * est.extras["refine"]
        finer = run_method(cantilever(alpha=alpha, elements=2 * fine, error_estimate=False), "fem")
        move = np.hypot(*(tip(finer)[:2] - tip(est)[:2]))
        checks.append(
            Check(
                "invariance",
                f"refinement {fine} -> {2 * fine} elements, alpha = {alpha}",
                move <= _estimate(est) * 1.5,
                f"moved {move:.2e}, estimate {_estimate(est):.2e}",
            )
        )
    return checks


# --- hard paths ----------------------------------------------------------------------------------


def hard_path_checks() -> list[Check]:
    checks = []
    for turns in (1, 2):
        run = run_method(
            cantilever(alpha=0.0, moment=2 * math.pi * turns, levels=1, error_estimate=False, elements=32), "fem"
        )
        x, y, rot = tip(run)
        ok = run.converged and abs(rot - 360.0 * turns) < 1e-4 and math.hypot(x, y) < 1e-6
        checks.append(
            Check(
                "hard paths",
                f"end moment {2 * turns} pi EI/L in one level",
                ok,
                f"tip rotation {rot:.6f} deg, tip at {math.hypot(x, y):.2e} L from the root",
            )
        )
    run = run_method(cantilever(alpha=5.0, levels=3, reverse=True, error_estimate=False), "fem")
    up, down = tip(run, 2), tip(run, -1)
    ok = run.converged and abs(up[0] - down[0]) < 1e-9 and abs(up[1] + down[1]) < 1e-9
    checks.append(
        Check("hard paths", "load reversal +P then -P", ok, f"+P tip {up[:2].round(6)}, -P tip {down[:2].round(6)}")
    )
    return checks


def column_check() -> list[Check]:
    checks = []
    # a column with a small imperfection, loaded past its Euler load: the post-buckled elastica
    # (fixed-free, tip angle a, k = sin(a/2)): P/P_cr = (2K(k)/pi)^2 and lateral tip deflection 2k/K(k) L

    ratio = 1.5
    k = brentq(lambda k: (2 * ellipk(k * k) / math.pi) ** 2 - ratio, 1e-9, 0.999999)
    exact_delta = 2 * k / ellipk(k * k)
    P_cr = math.pi**2 / 4  # EI = L = 1
    run = run_method(_imperfect_column(P_cr, 1e-5), "fem")  # levels up to 1.5 P_cr
    delta = abs(tip(run)[1]) if run.converged else math.nan
    checks.append(
        Check(
            "hard paths",
            "column past its Euler load (1.5 P_cr, imperfection 1e-5 P)",
            run.converged and abs(delta - exact_delta) < 2e-3,
            f"lateral tip deflection {delta:.5f} L, post-buckled elastica {exact_delta:.5f} L",
        )
    )
    return checks


def bistable_check() -> list[Check]:
    """The bistable partially-compliant four-bar of chapter 6 Example 2, driven through both stable
    positions by its output rotation in small steps: the FEM path must be continuous (no jump
    between steps), the strain energy must rise to a maximum and fall to the second well, and the
    driving torque must change sign at that maximum (the snap-through a torque-driven test would show)."""

    loaded = case_by_id("bapat2015_ch6_ex2")
    data = tomllib.loads(loaded.text)
    angles = [float(a) for a in np.linspace(0.0, 60.0, 31)]
    data["loads"] = [dict(data["loads"][0], values=angles)]
    data["outputs"] = [
        dict(quantity="strain_energy"),
        dict(quantity="input_torque"),
        dict(quantity="x", point="B"),
        dict(quantity="y", point="B"),
    ]
    data["methods"] = {"fem": dict(data["methods"]["fem"], error_estimate=False)}
    without_checks(data, ["fem"])
    data.pop("level_labels", None)
    run = run_method(Case.model_validate(data), "fem")
    if not run.converged:
        return [Check("hard paths", "bistable four-bar (ch. 6 Ex. 2) through both wells", False, run.message[:200])]
    U = np.array([run.values[Request("strain_energy", "", k)] for k in range(len(angles))])
    T = np.array([run.values[Request("input_torque", "", k)] for k in range(len(angles))])
    A = np.array([[run.values[Request(q, "B", k)] for q in ("x", "y")] for k in range(len(angles))])
    jumps = np.hypot(*np.diff(A, axis=0).T)
    peak = int(np.argmax(U))
    sign_changes = int(np.sum(np.sign(T[1:-1]) != np.sign(T[2:])))
    ok = 0 < peak < len(U) - 1 and U[-1] < U[peak] and sign_changes >= 1 and jumps.max() < 5.0 * np.median(jumps)
    return [
        Check(
            "hard paths",
            "bistable four-bar (ch. 6 Ex. 2) through both wells",
            ok,
            f"energy peak {U[peak]:.4g} in-lb at {angles[peak]:.0f} deg, {U[-1]:.4g} at 60 deg; torque changes "
            f"sign {sign_changes}x; largest step of B {jumps.max():.3g} in (median {np.median(jumps):.3g})",
        )
    ]


def prbm_edge_checks() -> list[Check]:
    """PRBM at its edges: fits at and beyond their ranges, four-bars at and past toggle, loops that
    cannot close."""

    checks = []
    for n, inside in ((10.0, True), (-3.999, True), (10.5, False), (-4.5, False)):
        try:
            gamma = PAULY_MIDHA.parameters(n)[0]
            checks.append(
                Check(
                    "prbm edges",
                    f"fit at n = {n}",
                    inside and math.isfinite(gamma),
                    f"gamma = {gamma:.6f}" + ("" if inside else " returned outside the range"),
                )
            )
        except FitRangeError as exc:
            checks.append(Check("prbm edges", f"fit at n = {n}", not inside, str(exc)))
    # a crank-rocker-like linkage that cannot turn fully: finite up to toggle, NaN past it
    Z1, Z2 = 4.0 + 0j, cmath.rect(2.5, math.radians(60))
    B = Z1 + cmath.rect(2.0, math.radians(100))
    fb = FourBar(Z1, Z2, B - Z2, B - Z1)
    grid = np.radians(np.linspace(60.0, 300.0, 24001))
    t3, t4 = fb.angles(grid)
    ok = np.isfinite(t3)
    edge = np.nonzero(ok[:-1] & ~ok[1:])[0]
    if len(edge):
        i = edge[0]
        A = fb.R2 * np.exp(1j * grid[i])
        closure = abs(A + fb.R3 * np.exp(1j * t3[i]) - (fb.Z1 + fb.R4 * np.exp(1j * t4[i])))
        checks.append(
            Check(
                "prbm edges",
                "four-bar at its toggle position",
                closure < 1e-9 and not ok[i + 1],
                f"loop closes to {closure:.1e} at {np.degrees(grid[i]):.3f} deg; NaN past it",
            )
        )
    else:
        checks.append(Check("prbm edges", "four-bar at its toggle position", False, "no toggle found"))
    # a loop that cannot close: a clear error, not NaN positions
    try:
        FourBar(Z1, Z2, 0.1 * (B - Z2), B - Z1)
        checks.append(Check("bad input", "four-bar loop that cannot close", False, "accepted"))
    except ValueError as exc:
        checks.append(Check("bad input", "four-bar loop that cannot close", "close" in str(exc), str(exc)))
    return checks


def _imperfect_column(P: float, imperfection: float) -> Case:
    levels = [P * f for f in (0.5, 0.9, 0.98, 1.02, 1.1, 1.25, 1.4, 1.5)]
    data = dict(
        case=dict(id="stress_column", title="imperfect column", group="stress", units="dimensionless"),
        segment=dict(boundary="fixed-free", length=1.0, E=1.0, section=dict(kind="inertia", I=1.0, A=1e6)),
        loads=[dict(kind="force", point="tip", direction=[-1.0, imperfection], values=levels)],
        outputs=[dict(quantity=q) for q in ("x", "y", "rotation")],
        methods={"fem": {"elements": 32}},
    )
    return Case.model_validate(data)


# --- bad input -----------------------------------------------------------------------------------


def bad_input_checks() -> list[Check]:
    checks = []
    base = cantilever().model_dump(mode="json")
    mutations = {
        "NaN load": lambda d: d["loads"][0].__setitem__("values", [float("nan")]),
        "infinite E": lambda d: d["segment"].__setitem__("E", float("inf")),
        "zero thickness": lambda d: d["segment"]["section"].__setitem__("thickness", 0.0),
        "negative length": lambda d: d["segment"].__setitem__("length", -1.0),
    }
    for name, mutate in mutations.items():
        data = json.loads(json.dumps(base))
        mutate(data)
        try:
            Case.model_validate(data)
            checks.append(Check("bad input", name, False, "accepted"))
        except ValidationError as exc:
            field, message = describe(exc)
            checks.append(
                Check("bad input", name, "greater than 0" in message or "finite" in message, f"{field}: {message}")
            )
    mech = rotated_cantilever(0.0, 1.0, 90.0).model_dump(mode="json")
    coincident = json.loads(json.dumps(mech))
    coincident["mechanism"]["nodes"].append(dict(name="again", x=0.0, y=0.0))
    zero = json.loads(json.dumps(mech))
    zero["mechanism"]["beams"][0]["end"] = "root"
    for name, data, words in (
        ("coincident nodes", coincident, "coincident"),
        ("zero-length member", zero, "zero length"),
    ):
        try:
            Case.model_validate(data)
            checks.append(Check("bad input", name, False, "accepted"))
        except ValidationError as exc:
            field, message = describe(exc)
            checks.append(Check("bad input", name, words in message, f"{field}: {message}"))
    # a mechanism with a zero-stiffness mode: a beam pinned at its root, no spring, transverse load
    free = json.loads(json.dumps(mech))
    free["mechanism"]["supports"][0]["kind"] = "pinned"
    free["loads"][0]["direction"] = [0.0, 1.0]
    run = run_method(Case.model_validate(free), "fem")
    checks.append(
        Check(
            "bad input",
            "zero-stiffness mode (pinned beam, no spring)",
            not run.converged and bool(run.message),
            f"converged={run.converged}: {run.message[:160]}",
        )
    )
    return checks


SIMPLE = {"length": [1.0], "E": [1.0e6], "slenderness": [100.0], "angle_deg": None, "alpha": None, "moment": None}


def shrink(params: dict) -> dict:
    """A simpler failing case: each parameter moved to a round value while the check still fails."""
    current = dict(params)
    for key, choices in SIMPLE.items():
        value = current[key]
        if choices is None:  # round to fewer digits, coarsest first
            choices = [round(value, -1), round(value), round(value, 1)] if value else []
        for choice in choices:
            if choice == value or (key in ("alpha", "moment") and choice <= 0 < value):
                continue
            trial = current | {key: float(choice)}
            if not agreement_check(trial).passed:
                current = trial
                break
    return current


def write_regression(params: dict, folder: Path) -> Path:
    """Keep a shrunk failure as a case file (FEM and elastica side by side) for a developer to adopt."""

    h = params["length"] / params["slenderness"]
    case = cantilever(
        length=params["length"],
        E=params["E"],
        width=h,
        thickness=h,
        alpha=params["alpha"],
        angle_deg=params["angle_deg"],
        moment=params["moment"],
        methods=("fem", "elastica"),
    )
    data = case.model_dump(mode="json", exclude_none=True, exclude_defaults=True)
    tag = hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()[:8]
    data["case"] |= {
        "id": f"stress_regression_{tag}",
        "title": "shrunk stress failure: FEM vs exact elastica",
        "description": "Found by prbm-validate stress; parameters " + json.dumps(params),
    }
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"stress_regression_{tag}.toml"
    path.write_text(tomli_w.dumps(data))
    return path


STRESS_FILES = ("stress.json", "index.html", "regressions", "fuzz.json", "fuzz_regressions")  # what stress writes


def run_stress(
    out: Path,
    long: bool = False,
    seed: int = 20261122,
    *,
    configurations: int = 10_000,
    executor: str = "process",
    workers: int | None = None,
    scheduler: str | None = None,
    mutants: int = 0,
    mutant_timeout: float = 20.0,
) -> int:
    """The checks below; with ``long``, also the quantity contract on ``configurations`` generated
    configurations on the sweep executors (``validation.stress.contract_run``); ``mutants`` mutated case
    files, each within ``mutant_timeout`` seconds (``validation.stress.fuzz_run``). Written into ``out`` as
    one output set (``validation.run.output_set``), the earlier runs' shrunk regressions kept."""
    with OutputSet(out, owned=STRESS_FILES, seed=("regressions", "fuzz_regressions")) as output:
        status = _stress_into(
            output.path,
            long,
            seed,
            configurations=configurations,
            executor=executor,
            workers=workers,
            scheduler=scheduler,
            mutants=mutants,
            mutant_timeout=mutant_timeout,
        )
        output.commit()
    return status


def _stress_into(
    out: Path,
    long: bool,
    seed: int,
    *,
    configurations: int,
    executor: str,
    workers: int | None,
    scheduler: str | None,
    mutants: int = 0,
    mutant_timeout: float = 20.0,
) -> int:
    """The stress run written in ``out``; its exit status."""
    started = time.perf_counter()
    checks: list[Check] = []
    contract = None
    if long:
        rows, contract = run_contract_stress(
            out, seed=seed, count=configurations, executor=executor, workers=workers, scheduler=scheduler
        )
        checks.extend(Check(r["category"], r["name"], r["passed"], r["detail"]) for r in rows)
    rng = random.Random(seed)
    n_random = 200 if long else 25
    for _ in range(n_random):
        params = random_cantilever_params(rng)
        check = agreement_check(params)
        if not check.passed:
            small = shrink(params)
            path = write_regression(small, out / "regressions")
            check.detail += f"; shrunk to {json.dumps({k: round(v, 6) for k, v in small.items()})}, kept as {path.name}"
        checks.append(check)
    for block in (
        invariance_checks,
        hard_path_checks,
        column_check,
        bistable_check,
        prbm_edge_checks,
        bad_input_checks,
    ):
        checks.extend(block())
    if mutants:
        checks.extend(
            Check(*row) for row in fuzz_checks(out, mutants, seed, long=long, workers=workers, timeout=mutant_timeout)
        )
    categories: dict[str, dict[str, int]] = {}
    for c in checks:
        tally = categories.setdefault(c.category, {"tried": 0, "passed": 0, "failed": 0})
        tally["tried"] += 1
        tally["passed" if c.passed else "failed"] += 1
    document = {
        "seed": seed,
        "long": long,
        "wall_time_s": time.perf_counter() - started,
        "categories": categories,
        "contract": contract,
        "checks": [asdict(c) for c in checks],
    }
    (out / "stress.json").write_text(json.dumps(document, indent=2))
    _write_page(out, document)
    for cat, t in categories.items():
        print(f"{cat:<18} tried {t['tried']:5d}  passed {t['passed']:5d}  failed {t['failed']:5d}")
    if contract:
        print(
            f"contract: {contract['configurations']} configurations, {contract['compared_values']} values compared, "
            f"{contract['wall_time_s']:.0f} s on {contract['executor']} ({contract['workers']} workers)"
        )
    for c in checks:
        if not c.passed:
            print(f"FAILED {c.category}: {c.name}: {c.detail}")
    return int(decide(failed=not all(c.passed for c in checks)))


def _write_page(out: Path, document: dict) -> None:

    rows = "".join(
        f"<tr class='{'good' if c['passed'] else 'bad'}'><td>{html.escape(c['category'])}</td>"
        f"<td>{html.escape(c['name'])}</td><td>{'pass' if c['passed'] else 'FAIL'}</td>"
        f"<td>{html.escape(c['detail'])}</td></tr>"
        for c in document["checks"]
    )
    tally = "".join(
        f"<tr><td>{k}</td><td>{v['tried']}</td><td>{v['passed']}</td><td>{v['failed']}</td></tr>"
        for k, v in document["categories"].items()
    )
    page = (
        f"<!doctype html><html><head><meta charset='utf-8'><title>Stress report</title><style>"
        f"body{{font-family:system-ui,sans-serif;margin:2em}}td,th{{border:1px solid #ccc;padding:3px 6px}}"
        f"table{{border-collapse:collapse}}.bad{{background:#fdd}}.good{{background:#dfd}}</style></head><body>"
        f"<p><a href='../index.html'>report</a></p><h1>Stress report</h1>"
        f"<p>seed {document['seed']}, {'long' if document['long'] else 'short'} mode, "
        f"{document['wall_time_s']:.1f} s</p><table><tr><th>category</th><th>tried</th><th>passed</th>"
        f"<th>failed</th></tr>{tally}</table><h2>Every check</h2><table><tr><th>category</th><th>check</th>"
        f"<th>result</th><th>detail</th></tr>{rows}</table></body></html>"
    )
    (out / "index.html").write_text(page)
