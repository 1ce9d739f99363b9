"""``prbm-validate solve``: one case, every requested output at every level with its loads, as JSON.

Each output's unit is under ``output_units`` (``units`` names the case's unit system). Numbers are
rounded to the precision the method has (``ROUNDING``, also written under ``rounding``): a solver's
result to 10 significant digits (no solver here is converged further; the digits after are round-off,
0.6000000000000001), a value with an error estimate (the FEM's) to the estimate's second significant
digit, and the estimate itself to two significant digits.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from validation.case.capabilities import QUANTITIES
from validation.case.loader import CaseError, find_case_files, load_case
from validation.case.loads import level_labels, load_name, load_unit
from validation.methods.base import RunStatus
from validation.run.exit_status import ExitStatus, combine, misconfigured_line, of_run_status, print_error
from validation.run.runner import requests_for, run_method


SIGNIFICANT = 10
ESTIMATE_DIGITS = 2
ROUNDING = (
    f"values to {SIGNIFICANT} significant digits; a value with an error estimate to the estimate's "
    f"second significant digit; error estimates to {ESTIMATE_DIGITS} significant digits"
)


def _clean(v):
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else v


def significant(value, digits: int = SIGNIFICANT):
    """``value`` rounded to ``digits`` significant digits (None, NaN, 0 and infinities as they are)."""
    if not isinstance(value, float) or not math.isfinite(value) or value == 0.0:
        return value
    return round(value, digits - 1 - math.floor(math.log10(abs(value))))


def to_estimate(value, estimate):
    """``value`` rounded to the second significant digit of its error ``estimate`` (a finite, positive
    estimate), and never to more than ``SIGNIFICANT`` significant digits."""
    if (
        not isinstance(value, float)
        or not math.isfinite(value)
        or not isinstance(estimate, float)
        or not math.isfinite(estimate)
        or estimate <= 0.0
    ):
        return significant(value)
    rounded = round(value, ESTIMATE_DIGITS - 1 - math.floor(math.log10(estimate)))
    return significant(float(rounded))


def _load_entry(name: str, value: float, unit: str, direction: tuple[float, float] | None) -> dict:
    """One load at one level: its value (a force's or displacement's magnitude: the case's direction is a
    unit vector, ``LoadSpec``) and, for a load along a direction, that unit vector [dx, dy]."""
    entry = {"name": name, "value": value, "unit": unit}
    if direction is not None:
        entry["direction"] = list(direction)
    return entry


def solve_document(loaded, method: str, run) -> dict:
    """The JSON document of ``solve``: every requested output at every level, with the level's loads."""
    case = loaded.case
    labels = level_labels(case)
    loads = [
        (load_name(load, i, case), load.levels(), load_unit(load, case), load.direction)
        for i, load in enumerate(case.loads)
    ]
    levels, units = [], {}
    for level in range(case.n_levels()):
        outputs = {}
        for req in requests_for(case, method):
            if req.level != level:
                continue
            name = f"{req.quantity}@{req.point}" if req.point else req.quantity
            estimate = _clean(run.error_estimate.get(req))
            outputs[name] = to_estimate(_clean(run.values.get(req)), estimate)
            units[name] = case.unit(QUANTITIES[req.quantity].dimension)
            if req in run.error_estimate:
                outputs[name + ":error_estimate"] = significant(estimate, ESTIMATE_DIGITS)
            if req in run.unreliable_estimate:  # the estimate is no bound: why
                outputs[name + ":error_estimate_unreliable"] = run.unreliable_estimate[req]
        if outputs:
            entry = {
                "level": level,
                "label": labels[level],
                "loads": [_load_entry(n, significant(v[level]), u, d) for n, v, u, d in loads],
                "outputs": outputs,
            }
            flags = run.applicability.get(level, [])
            if flags:
                entry["applicability"] = [f.value for f in flags]
                entry["applicability_reason"] = run.level_messages.get(level, run.message)
            if level in run.expected_error:  # the PRBM error atlas's expected tip error, % of L
                entry["expected_error_percent_of_L"] = _clean(round(run.expected_error[level], 3))
            levels.append(entry)
    return {
        "case": case.case.id,
        "file": str(loaded.path),
        "method": method,
        "units": case.case.units,
        "output_units": units,
        "rounding": ROUNDING,
        "status": run.status.value,
        "converged": run.converged,
        "message": run.message,
        "wall_time_s": round(run.wall_time, 4),
        "levels": levels,
    }


def run(args) -> int:
    try:
        paths = find_case_files([args.case])
        if len(paths) != 1:
            raise CaseError(args.case, "", f"names {len(paths)} case files; solve takes one")
        loaded = load_case(paths[0])
    except CaseError as exc:
        print_error(exc)
        return ExitStatus.BAD_INPUT
    case = loaded.case
    methods = args.method or list(case.methods)
    unknown = [m for m in methods if m not in case.methods]
    if unknown:
        print(
            f"error: {loaded.path}: methods: the case does not ask for method '{unknown[0]}' "
            f"(it has {', '.join(case.methods)})",
            file=sys.stderr,
        )
        return ExitStatus.BAD_INPUT
    documents, statuses = [], []
    for method in methods:
        run = run_method(case, method)
        if run.status is None:  # ``MethodRun`` derives it when made
            raise ValueError(f"the {method} run has no status")
        statuses.append(of_run_status(run.status))
        if run.status is RunStatus.MISCONFIGURED:
            print_error(misconfigured_line(loaded.path, run))
        elif not run.ok:
            print(f"{case.case.id} {method}: {run.summary()}", file=sys.stderr)
        documents.append(solve_document(loaded, method, run))
    document = documents[0] if len(documents) == 1 else {"case": case.case.id, "runs": documents}
    text = json.dumps(document, indent=None if args.compact else 2)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n", encoding="utf-8")
    else:
        print(text)
    return combine(statuses)
