"""Run one method on a case, only on the outputs it asks for (``run_method``); what a case's run holds
(``CaseResult``) and the findings' re-runs.

No table is built here (``validation.run.outcome`` does that) and no cache is read
(``validation.run.case_run`` runs a whole case through it), so ``solve`` and the adapters start
without pandas or the cache's package-metadata lookups.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
import tomllib
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from validation.case.capabilities import QUANTITIES
from validation.case.loader import LoadedCase
from validation.case.method_options import options_of
from validation.methods.base import Misconfigured, MethodRun, NotApplicable, Request, RunStatus
from validation.case.schema import Case
from validation.case.overrides import apply as apply_field


def requests_for(case: Case, method: str) -> list[Request]:
    """Every (quantity, point, level) the case wants from this method, in order, without repeats."""
    wanted: dict[Request, None] = {}
    every: range | None = None  # range(case.n_levels()), built at most once (n_levels builds the load's level list)
    new = tuple.__new__  # Request(q, p, level) without the named tuple's Python-level __new__ (a third of the time)
    for out in case.outputs:
        if out.methods is not None and method not in out.methods:
            continue
        levels: range | list[int]
        if out.levels == "all":
            levels = every = every if every is not None else range(case.n_levels())
        else:
            levels = out.levels
        quantity = out.quantity
        point = out.point if QUANTITIES[quantity].at_point else ""
        for level in levels:
            wanted[new(Request, (quantity, point, level))] = None
    return list(wanted)


def run_method(case: Case, method: str) -> MethodRun:
    """Call the adapter; a method that cannot model the case, is misconfigured or fails returns a
    run that says so in its ``status`` and ``message``."""
    requests = requests_for(case, method)
    start = time.perf_counter()
    try:
        options = options_of(method, case.methods.get(method))
        name = f"validation.methods.{method}"
        adapter = sys.modules.get(name) or importlib.import_module(name)  # the import system only once
        run = adapter.run(case, requests, options)
    except NotApplicable as exc:
        reason = str(exc) if str(exc).startswith("not applicable") else f"not applicable: {exc}"
        return MethodRun(
            values={},
            converged=False,
            message=reason,
            wall_time=time.perf_counter() - start,
            status=RunStatus.NOT_APPLICABLE,
        )
    except Misconfigured as exc:
        return MethodRun(
            values={},
            converged=False,
            message=f"misconfigured: methods.{method}: {exc}",
            wall_time=time.perf_counter() - start,
            status=RunStatus.MISCONFIGURED,
        )
    except Exception as exc:  # a solver bug must not stop the other cases
        last = traceback.extract_tb(exc.__traceback__)[-1]
        where = f"{Path(last.filename).name}:{last.lineno}"
        return MethodRun(
            values={},
            converged=False,
            message=f"error: {type(exc).__name__}: {exc} (at {where})",
            wall_time=time.perf_counter() - start,
            status=RunStatus.FAILED,
        )
    if not run.wall_time:
        run.wall_time = time.perf_counter() - start
    missing = [r for r in requests if r not in run.values]
    if missing and run.converged:
        run.converged = False
        run.message = (
            run.message + "; " if run.message else ""
        ) + f"did not return {len(missing)} requested output(s), e.g. {missing[0]}"
    asked = {r.level for r in requests}
    unconverged = sorted(lv for lv, ok in run.level_converged.items() if not ok and lv in asked)
    if run.status is RunStatus.OK and (not run.converged or unconverged):
        run.status = RunStatus.NOT_CONVERGED
        run.converged = False
        if unconverged and f"level {unconverged[0]}" not in run.message:
            run.message = (run.message + "; " if run.message else "") + f"not converged at level(s) {unconverged}"
    return run


@dataclass
class CaseResult:
    loaded: LoadedCase
    runs: dict[str, MethodRun] = field(default_factory=dict)
    cached: dict[str, bool] = field(default_factory=dict)
    # the method's value re-run with a finding's ``reproduce_with``, keyed by the reference's index
    reproduced: dict[int, float] = field(default_factory=dict)


def _reproduce(loaded: LoadedCase, method: str, fields: dict) -> MethodRun:
    """The method run on the case with the finding's case fields set."""
    data = tomllib.loads(loaded.text)
    for path, value in fields.items():
        apply_field(data, path, "set", value)
    return run_method(Case.model_validate(data), method)


def reproduce_findings(result: "CaseResult") -> None:
    """Re-run each finding's method with the inputs that explain it, once per distinct input set."""
    runs: dict[tuple[str, str], MethodRun] = {}
    for i, ref in enumerate(result.loaded.case.references):
        if ref.finding is None or ref.finding.reproduce_with is None or ref.compare not in result.runs:
            continue
        key = (ref.compare, json.dumps(ref.finding.reproduce_with, sort_keys=True))
        if key not in runs:
            runs[key] = _reproduce(result.loaded, ref.compare, ref.finding.reproduce_with)
        point = ref.point if QUANTITIES[ref.quantity].at_point else ""
        result.reproduced[i] = runs[key].values.get(Request(ref.quantity, point, ref.level), math.nan)
