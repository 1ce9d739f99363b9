"""``prbm-validate stress --long``: the quantity contract on thousands of generated configurations.

Three categories, each configuration regenerated on the worker from its seed (so a task carries a
few integers, not case data):

* ``contract linear``: every method against linear beam theory at a small load
  (``validation.stress.contract.linear_limit_check``: all boundaries, straight and curved, every load kind
  and unit system);
* ``contract large``: the FEM against the exact elastica at a large deflection, the PRBM recorded
  and held to the conventions (``large_deflection_check``);
* ``contract mechanism``: the same segment written as a one-beam ``[mechanism]`` turned by an angle
  phi in the global frame: the FEM's positions, rotation and root reactions must be the segment's,
  turned by phi (linear theory at a small load, the elastica at a large one), each quantity within 3x
  the FEM's own estimate of that quantity; where the elastica stalls (a limit point under load
  control, where the FEM too reports no convergence) nothing is judged.

Tasks run on the sweep executors (``validation.sweep.run.completed``: local processes, a local Dask
cluster, or a Dask scheduler). Each failure is shrunk (unit system, size, slenderness, curvature,
load rounded, one at a time while it still fails) and kept as a case file under ``regressions/``,
stating the failure in ``case.findings`` and its configuration and status in the description (the
ones kept in ``cases/regressions/`` are re-run by ``tests/validation/test_contract_regressions.py``).
"""

from __future__ import annotations

import hashlib
import json
import math
import random
import time
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import tomli_w
from numpy.typing import NDArray

from validation.stress.contract import (
    Configuration,
    ContractResult,
    applicable,
    build_case,
    large_deflection_check,
    linear_limit_check,
    linear_reference,
    random_configuration,
)
from validation.methods.base import Request
from validation.run.runner import run_method
from validation.case.schema import Case
from validation.sweep.run import _chunk_size, completed

CATEGORIES = ("contract linear", "contract large", "contract mechanism")
LARGE_BOUNDARIES = ("fixed-free", "fixed-pinned", "fixed-guided")
LARGE_LOADS = ("transverse", "oblique", "moment", "force_moment", "follower", "displacement_y", "rotation")
MECHANISM_LOADS = ("transverse", "oblique", "moment", "force_moment", "follower")


def configuration_for(category: str, seed: int) -> tuple[Configuration, float]:
    """The configuration (and, for a mechanism, its turn phi in degrees) of one seed."""
    rng = random.Random(seed)
    if category == "contract linear":
        return random_configuration(rng, small=True), 0.0
    if category == "contract large":
        return random_configuration(rng, small=False, boundaries=LARGE_BOUNDARIES, loads=LARGE_LOADS), 0.0
    small = rng.random() < 0.5
    c = random_configuration(rng, small=small, boundaries=("fixed-free",), loads=MECHANISM_LOADS, curved=False)
    return c, rng.uniform(-180.0, 180.0)


def _turn(phi: float, v) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def mechanism_case(c: Configuration, phi_deg: float) -> Case:
    """The configuration's straight fixed-free segment as a one-beam mechanism turned by phi."""
    segment_case = build_case(c, ("fem",), levels=1 if c.magnitude < 1e-3 else 4)
    seg = segment_case.require_segment()
    phi = math.radians(phi_deg)
    tip = _turn(phi, (seg.length, 0.0))
    loads = []
    for ld in segment_case.loads:
        entry = dict(kind=ld.kind, point="tip", values=ld.levels(), follower=ld.follower)
        if ld.direction is not None:
            entry["direction"] = [float(v) for v in _turn(phi, ld.direction)]
        loads.append(entry)
    data = dict(
        case=dict(
            id="contract_mechanism",
            title="turned one-beam mechanism",
            group="contract",
            units=c.units,
            description=f"{c.label()}, phi={phi_deg:.4g}",
        ),
        mechanism=dict(
            nodes=[dict(name="root", x=0.0, y=0.0), dict(name="tip", x=float(tip[0]), y=float(tip[1]))],
            beams=[dict(name="b", start="root", end="tip", E=seg.E, section=seg.section.model_dump(exclude_none=True))],
            supports=[dict(node="root", kind="fixed")],
        ),
        loads=loads,
        outputs=[dict(quantity=q, point="tip") for q in ("x", "y", "rotation")]
        + [dict(quantity=q, point="root") for q in ("reaction_x", "reaction_y", "reaction_moment")],
        methods={"fem": {"elements": 8, "error_estimate": True, "levels": 2}},
    )
    return Case.model_validate(data)


def mechanism_check(c: Configuration, phi_deg: float) -> list[ContractResult]:
    """FEM on the turned mechanism against the segment's reference (linear theory, or the elastica at a
    large load), turned by phi: the global frame and the counter-clockwise signs of a mechanism.

    Each quantity is allowed 3x the FEM's own estimate of that quantity (positions in length, the
    rotation in degrees), plus the axial stretch the inextensible elastica leaves out; one whose estimate
    the FEM marks unreliable is not judged. At a large load
    the elastica is solved first: where it gives no reference (a limit point under load control, where
    the FEM too reports no convergence), nothing is judged."""
    case = mechanism_case(c, phi_deg)
    last = case.n_levels() - 1
    small = c.magnitude < 1e-3
    segment = build_case(c, ("fem", "elastica"), levels=case.n_levels())
    L = segment.require_segment().length
    ref_reac: NDArray[np.float64] | tuple[float, float, float]  # the root reaction (R_x, R_y, M_root)
    if small:
        tip = linear_reference(c, segment)
        (ux, uy, th), xt = tip.motion, tip.tip
        ref_xy, ref_rot, ref_reac = (xt[0] + ux, xt[1] + uy), math.degrees(th), tip.reaction
        scale = max(abs(ux), abs(uy), abs(th) * L)
        base = 1e-4 * scale + 1e-12 * L
    else:
        exact = run_method(segment, "elastica")
        if not exact.converged:
            return [ContractResult("elastica", False, 0, [], f"elastica gave no reference: {exact.message}")]
        get = {(r.quantity, r.point): v for r, v in exact.values.items() if r.level == last}
        ref_xy, ref_rot = (get[("x", "tip")], get[("y", "tip")]), get[("rotation", "tip")]
        ref_reac = (get[("reaction_x", "root")], get[("reaction_y", "root")], get[("reaction_moment", "root")])
        scale = L
        _, EA = c.stiffness()
        base = 2 * max(abs(ref_reac[0]), abs(ref_reac[1])) * L / EA + 1e-9 * L
    run = run_method(case, "fem")
    if not run.converged:
        return [ContractResult("fem", True, 0, [f"fem (mechanism) did not converge: {run.message}"])]
    est = {r.quantity: v for r, v in run.error_estimate.items() if r.level == last and r.point == "tip"}
    position_estimate = max(est.get("x", 0.0), est.get("y", 0.0))
    phi = math.radians(phi_deg)
    want = {"x": _turn(phi, ref_xy)[0], "y": _turn(phi, ref_xy)[1], "rotation": ref_rot}
    reac = _turn(phi, ref_reac[:2])
    want_root = {"reaction_x": reac[0], "reaction_y": reac[1], "reaction_moment": ref_reac[2]}
    load_scale = max(abs(ref_reac[0]), abs(ref_reac[1]), abs(ref_reac[2]) / scale, 1e-300)
    failures = []
    doubtful = {r.quantity for r in run.unreliable_estimate if r.level == last and r.point == "tip"}
    for q, w in want.items():
        if doubtful & ({"x", "y"} if q != "rotation" else {"rotation"}):
            continue  # its estimate is unreliable (the FEM says so): no bound to hold it to
        v = run.values[Request(q, "tip", last)]
        allowed = (
            3 * position_estimate + base if q != "rotation" else 3 * est.get("rotation", 0.0) + math.degrees(base / L)
        )
        if abs(v - w) > allowed:
            failures.append(
                f"fem (mechanism, phi = {phi_deg:.4g}) {q} = {v:.6g}, expected {w:.6g} (allowed {allowed:.3g})"
            )
    for q, w in want_root.items():
        v = run.values[Request(q, "root", last)]
        allowed = (0.02 if not small else 1e-4) * load_scale * (scale if q == "reaction_moment" else 1.0)
        if abs(v - w) > allowed:
            failures.append(
                f"fem (mechanism, phi = {phi_deg:.4g}) {q} = {v:.6g}, expected {w:.6g} (allowed {allowed:.3g})"
            )
    return [ContractResult("fem", True, 6, failures)]


def check(category: str, c: Configuration, phi: float = 0.0) -> list[ContractResult]:
    if category == "contract linear":
        return linear_limit_check(c)
    if category == "contract large":
        return large_deflection_check(c)
    return mechanism_check(c, phi)


def contract_chunk(context: dict, chunk: list[dict]) -> list[dict]:
    """Worker task: rows {category, seed, passed, compared, detail} of a chunk of (category, seed)."""
    rows = []
    for item in chunk:
        c, phi = configuration_for(item["category"], item["seed"])
        try:
            results = check(item["category"], c, phi)
            failures = [f for r in results for f in r.failures]
            compared = sum(r.compared for r in results)
            detail = "; ".join(failures) or "; ".join(r.detail for r in results if r.detail)
        except Exception as exc:  # a crash is a failure with its reason, not a lost task
            failures, compared, detail = [f"{type(exc).__name__}: {exc}"], 0, f"{type(exc).__name__}: {exc}"
        rows.append(
            dict(
                category=item["category"],
                seed=item["seed"],
                passed=not failures,
                compared=compared,
                name=c.label() + (f", phi={phi:.4g}" if phi else ""),
                detail=detail[:2000],
            )
        )
    return rows


SIMPLER = {"units": "dimensionless", "length": 1.0, "E": 1.0, "slenderness": 100.0, "kappa_L": 0.0}


def shrink(category: str, c: Configuration, phi: float) -> tuple[Configuration, float]:
    """A simpler configuration that still fails: each field moved to a plain value, or its load
    rounded, one at a time, kept when the check still fails."""

    def fails(candidate: Configuration, turn: float) -> bool:
        try:
            return any(r.failures for r in check(category, candidate, turn))
        except Exception:
            return True

    for name, simple in list(SIMPLER.items()) + [
        ("angle_deg", round(c.angle_deg, -1)),
        ("moment_ratio", round(c.moment_ratio, 1)),
    ]:
        if getattr(c, name) != simple:
            trial = Configuration(**(asdict(c) | {name: simple}))
            if trial.units == "dimensionless":
                trial = replace(trial, length=1.0, E=1.0)
            if fails(trial, phi):
                c = trial
    if phi and fails(c, round(phi, -1)):
        phi = round(phi, -1)
    return c, phi


REGRESSION_MARK = "stress-contract regression: "


def write_regression(category: str, c: Configuration, phi: float, folder: Path, failures: list[str]) -> Path:
    """Keep a shrunk failure as a case file, every method side by side: the failure it showed in
    ``case.findings``, and the configuration in the description after ``REGRESSION_MARK`` as JSON
    ({category, phi, configuration, status}), so ``tests/validation/test_contract_regressions.py`` can re-run the
    contract check on it (status 'open': it must still fail; 'fixed': it must pass)."""
    methods = tuple(m for m in ("fem", "elastica", "prbm", "bcm") if applicable(m, c))
    case = (
        mechanism_case(c, phi)
        if category == "contract mechanism"
        else build_case(c, methods, levels=1 if category == "contract linear" else 4)
    )
    data = case.model_dump(mode="json", exclude_none=True)
    tag = hashlib.sha256(json.dumps([category, asdict(c), phi], sort_keys=True).encode()).hexdigest()[:8]
    record = {"category": category, "phi": phi, "configuration": asdict(c), "status": "open"}
    reason = (
        "a shrunk stress-contract failure: what it showed is in case.findings; the contract check itself is "
        "re-run on this configuration by tests/validation/test_contract_regressions.py"
    )
    data["case"] |= {
        "id": f"contract_regression_{tag}",
        "title": f"shrunk {category} failure",
        "group": "stress regressions",
        "description": f"Found by prbm-validate stress --long. {REGRESSION_MARK}{json.dumps(record)}",
        "findings": [f"{category}: {f}" for f in failures] or [f"{category}: the check raised"],
        "unchecked": {m: reason for m in data["methods"]},
    }
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"contract_regression_{tag}.toml"
    path.write_text(tomli_w.dumps(data))
    return path


def regression_record(description: str) -> dict:
    """The {category, phi, configuration, status} a regression case file carries (see write_regression)."""
    return json.loads(description.split(REGRESSION_MARK, 1)[1])


def failures_of(category: str, c: Configuration, phi: float) -> list[str]:
    """The contract failures of one configuration (a crash is a failure with its reason)."""
    try:
        return [f for r in check(category, c, phi) for f in r.failures]
    except Exception as exc:  # noqa: BLE001 - the reason is the result
        return [f"{type(exc).__name__}: {exc}"]


def run_contract_stress(
    out: Path,
    *,
    seed: int,
    count: int = 10_000,
    executor: str = "process",
    workers: int | None = None,
    scheduler: str | None = None,
    shares=(0.6, 0.25, 0.15),
) -> tuple[list[dict], dict]:
    """Run ``count`` generated configurations (linear, large, mechanism in ``shares``) on the sweep
    executors; shrink each failure into ``out/regressions``. Returns the rows and a run summary."""
    started = time.perf_counter()
    rng = random.Random(seed)
    counts = [int(round(count * s)) for s in shares]
    counts[0] += count - sum(counts)
    items = [dict(category=cat, seed=rng.getrandbits(48)) for cat, n in zip(CATEGORIES, counts) for _ in range(n)]
    rng.shuffle(items)
    workers = workers or 2
    size = _chunk_size(len(items), workers, 0)
    chunks = [items[i : i + size] for i in range(0, len(items), size)]
    rows: list[dict] = []
    for chunk, result in completed(executor, {}, chunks, workers=workers, scheduler=scheduler, task=contract_chunk):
        if isinstance(result, BaseException):
            rows.extend(
                dict(
                    category=i["category"],
                    seed=i["seed"],
                    passed=False,
                    compared=0,
                    name=str(i["seed"]),
                    detail=f"task failed: {type(result).__name__}: {result}",
                )
                for i in chunk
            )
        else:
            rows.extend(result)
    for row in rows:
        if not row["passed"]:
            c, phi = configuration_for(row["category"], row["seed"])
            small, turn = shrink(row["category"], c, phi)
            path = write_regression(
                row["category"], small, turn, out / "regressions", failures_of(row["category"], small, turn)
            )
            row["detail"] += f"; shrunk to {small.label()}, kept as {path.name}"
    summary = {
        "configurations": len(rows),
        "executor": scheduler or executor,
        "workers": workers,
        "chunk": size,
        "wall_time_s": time.perf_counter() - started,
        "compared_values": int(sum(r["compared"] for r in rows)),
    }
    return rows, summary
