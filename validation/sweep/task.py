"""One sweep point, worker side: base case data + parameter values -> validated case -> rows.

A point is the base case's TOML data with each swept parameter written into it at its dotted
path (``segment.E``, ``mechanism.beams.0.section.thickness``, ``loads.0.values``,
``methods.fem.elements``), in one of four modes:

    set     data[path] = v
    scale   data[path] = v * base          (numbers and lists elementwise; a load or a ramp:
                                            its values, or its ramp start and stop)
    offset  data[path] = v + base          (numbers and lists elementwise)
    angle   data[path] = |base| (cos v, sin v), v in degrees   (a direction vector)

The modified data is validated by the case schema again, so a point the schema rejects (a
negative thickness drawn from a wide normal, say) becomes rows with status 'invalid' and the
one-line reason, never an exception. Each method then runs through ``runner.run_method`` (which
already turns a solver exception into a run with a message) and gives one row per requested
output: value, unit, error estimate, converged, status, message, wall time.

This module imports no executor: it is what a process-pool or Dask worker unpickles and runs.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Sequence

from pydantic import ValidationError
from threadpoolctl import threadpool_limits

from validation.case.capabilities import QUANTITIES, method_quantities
from validation.case.overrides import PathError, apply
from validation.case.schema import Case, without_checks
from validation.methods.base import Request, RunStatus
from validation.run.runner import requests_for, run_method

# Columns every result row has, with their Arrow types (the swept parameters come after them).
ROW_COLUMNS: dict[str, str] = {
    "point_id": "string",
    "case": "string",
    "sample": "int64",
    "method": "string",
    "quantity": "string",
    "point": "string",
    "level": "int64",
    "value": "float64",
    "unit": "string",
    "error_estimate": "float64",
    "converged": "bool",
    "status": "string",
    "message": "string",
    "wall_time": "float64",
    "point_time": "float64",
    "run": "string",
}
STATUSES = ("ok", "not_converged", "not_applicable", "error", "invalid")


def prepare(base: dict, methods: list[str], options: dict[str, dict], outputs: list[dict] | None) -> dict:
    """The base case restricted to the sweep's methods and outputs, references and agreements dropped.

    With the case's own outputs (``outputs`` None), each output keeps only the sweep methods that
    can give its quantity; an output no sweep method can give is dropped.
    """
    data = copy.deepcopy(base)
    own = data.get("methods") or {}
    data["methods"] = {m: {**(own.get(m) or {}), **(options.get(m) or {})} for m in methods}
    without_checks(data, methods)
    if outputs is not None:
        data["outputs"] = copy.deepcopy(outputs)
    else:
        kept = []
        for out in data.get("outputs", []):
            asked = out.get("methods") or methods
            able = [m for m in methods if m in asked and out.get("quantity") in method_quantities(m)]
            if able:
                kept.append(out | {"methods": able})
        data["outputs"] = kept
    return data


def _one_line(exc: ValidationError) -> str:
    err = exc.errors()[0]
    loc = ".".join(str(p) for p in err["loc"] if not (isinstance(p, str) and p.startswith("function-")))
    more = f" (and {exc.error_count() - 1} more)" if exc.error_count() > 1 else ""
    return f"{loc or '(top level)'}: {err['msg'].removeprefix('Value error, ')}{more}"


def _row(task: dict, run_id: str, **fields) -> dict:
    row = dict(
        point_id=task["id"],
        case=task["case"],
        sample=task["sample"],
        method=None,
        quantity=None,
        point=None,
        level=None,
        value=math.nan,
        unit=None,
        error_estimate=math.nan,
        converged=False,
        status="invalid",
        message="",
        wall_time=math.nan,
        point_time=math.nan,
        run=run_id,
    )
    row.update(task["columns"])
    row.update(fields)
    return row


def run_point(context: dict, point: dict) -> list[dict]:
    """Rows of one point (see the module docstring). ``context`` is shared by every point."""

    started = time.perf_counter()
    run_id = context["run"]
    data = copy.deepcopy(context["cases"][point["case"]])
    try:
        for param in context["parameters"]:
            apply(data, param["path"], param["mode"], point["values"][param["name"]])
        case = Case.model_validate(data)
    except PathError as exc:
        return [_row(point, run_id, message=str(exc), point_time=time.perf_counter() - started)]
    except ValidationError as exc:
        return [_row(point, run_id, message=_one_line(exc), point_time=time.perf_counter() - started)]
    rows = []
    for method in context["methods"]:
        run = run_method(case, method)
        status = (
            {
                RunStatus.NOT_APPLICABLE: "not_applicable",
                RunStatus.FAILED: "error",
                RunStatus.MISCONFIGURED: "invalid",
            }.get(run.status)
            if run.status is not None
            else None
        )
        requests: Sequence[Request | None] = requests_for(case, method) or [None]
        for req in requests:
            if req is None:
                rows.append(
                    _row(
                        point,
                        run_id,
                        method=method,
                        status=status or "error",
                        message=run.message or "the method was asked for no output",
                        wall_time=run.wall_time,
                    )
                )
                continue
            converged = bool(run.level_converged.get(req.level, run.converged))
            value = run.values.get(req, math.nan)
            row_status = status or ("ok" if converged and not math.isnan(value) else "not_converged")
            rows.append(
                _row(
                    point,
                    run_id,
                    method=method,
                    quantity=req.quantity,
                    point=req.point,
                    level=req.level,
                    value=float(value),
                    unit=case.unit(QUANTITIES[req.quantity].dimension),
                    error_estimate=float(run.error_estimate.get(req, math.nan)),
                    converged=converged,
                    status=row_status,
                    message=run.level_messages.get(req.level, run.message),
                    wall_time=run.wall_time,
                )
            )
    elapsed = time.perf_counter() - started
    for row in rows:
        row["point_time"] = elapsed
    return rows


_PINNED = False


def _one_blas_thread() -> None:
    """One BLAS thread per worker: the workers are the parallelism (no oversubscription)."""
    global _PINNED
    if not _PINNED:
        _PINNED = True
        threadpool_limits(1)


def run_chunk(context: dict, points: list[dict]) -> list[dict]:
    """Rows of several points (one executor task; batching amortises the per-task overhead)."""
    if context.get("pin_blas", True):
        _one_blas_thread()
    rows: list[dict] = []
    for point in points:
        rows.extend(run_point(context, point))
    return rows
