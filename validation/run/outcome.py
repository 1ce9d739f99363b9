"""Many cases run, as tables: the wide comparison table of a case (``tabulate``), the outcome of a run
over many case files (``run_cases`` -> ``RunOutcome``: its table, failed comparisons, problems and
exit status), and the one-row-per-case summary with the largest PRBM-to-FEM error.

``run_cases`` returns one tidy pandas table (a row per method x output x load level x reference)
with the value, its unit, the published value and its source, the absolute and relative error,
whether the claimed tolerance is met, the wall time, and whether the method converged.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from validation.case.capabilities import QUANTITIES
from validation.methods.base import RunStatus
from validation.run.compare import agreement_checks, fem_elastica_checks, reference_check
from validation.run.exit_status import combine, decide, of_run_status
from validation.run.parallel import PathRun, run_paths
from validation.run.runner import CaseResult, characteristic_length, requests_for
from validation.run.timeline import Timed


COLUMNS = ["case", "group", "method", "quantity", "point", "level", "level_label", "value", "unit", "scale",
           "error_estimate", "reference_label", "reference_value", "source", "compare", "tolerance_rel",
           "tolerance_abs", "abs_error", "rel_error", "norm_error", "within_tolerance", "finding",
           "wall_time", "converged", "message", "applicability", "cached", "check"]


def tabulate(result: CaseResult) -> pd.DataFrame:
    """The tidy comparison table of one case."""
    case = result.loaded.case
    labels = case.level_labels or [str(i) for i in range(case.n_levels())]
    refs: dict[tuple, list] = {}
    for index, ref in enumerate(case.references):
        point = ref.point if QUANTITIES[ref.quantity].at_point else ""
        refs.setdefault((ref.quantity, point, ref.level), []).append((index, ref))
    scale = characteristic_length(case)
    automatic = fem_elastica_checks(case, result.runs, scale)
    agreed: dict[str, list] = {}
    for agreement in case.agreements:
        for req, check in agreement_checks(case, agreement, result.runs).items():
            agreed.setdefault(agreement.method, []).append((req, check))
    rows = []
    for method, run in result.runs.items():
        requests = requests_for(case, method)
        if not requests:
            rows.append(dict(case=case.case.id, group=case.case.group, method=method, quantity=None,
                             point=None, level=None, level_label=None, value=math.nan, unit=None,
                             wall_time=run.wall_time, converged=run.converged, message=run.message,
                             cached=result.cached.get(method, False)))
            continue
        bases = {}
        for req in requests:
            value = run.values.get(req, math.nan)
            dimension = QUANTITIES[req.quantity].dimension
            base = dict(case=case.case.id, group=case.case.group, method=method, quantity=req.quantity,
                        point=req.point, level=req.level, level_label=labels[req.level], value=value,
                        unit=case.unit(dimension), scale=scale,
                        error_estimate=run.error_estimate.get(req, math.nan),
                        wall_time=run.wall_time,
                        converged=run.level_converged.get(req.level, run.converged),
                        message=run.level_messages.get(req.level, run.message),
                        applicability="; ".join(f.value for f in getattr(run, "applicability", {}).get(req.level, ())),
                        cached=result.cached.get(method, False))
            bases[req] = base
            matching = refs.get(req, [])
            if not matching:
                rows.append(base)
            for index, ref in matching:
                if ref.compare == method and ref.tolerance is not None:
                    check = reference_check(ref, value, result.reproduced.get(index))
                    rows.append(base | _check_row(check, dimension, scale))
                    continue
                abs_error = abs(value - ref.value)
                rows.append(base | dict(
                    reference_label=ref.label, reference_value=ref.value, source=ref.source.label(),
                    compare=False, abs_error=abs_error,
                    rel_error=abs_error / abs(ref.value) if ref.value != 0 else math.nan,
                    norm_error=abs_error / scale if dimension == "length" else math.nan,
                    within_tolerance=None, finding=ref.finding.text if ref.finding else ref.note))
            if method == "fem" and req in automatic:
                rows.append(base | _check_row(automatic[req], dimension, scale))
        for req, check in agreed.get(method, []):
            if req in bases:
                rows.append(bases[req] | _check_row(check, QUANTITIES[req.quantity].dimension, scale))
    frame = pd.DataFrame(rows)
    return frame.reindex(columns=COLUMNS)


def _check_row(check, dimension: str, scale: float) -> dict:
    """The comparison columns of one enforced check."""
    row = dict(reference_label=check.reference_label, reference_value=check.reference_value,
               source=check.source, compare=True,
               tolerance_rel=check.tolerance.rel if check.tolerance else None,
               tolerance_abs=check.tolerance.abs if check.tolerance else None,
               abs_error=check.abs_error, rel_error=check.rel_error,
               norm_error=check.abs_error / scale if dimension == "length" else math.nan,
               within_tolerance=check.within, finding=check.finding, check=check.kind)
    if check.detail:
        row["message"] = check.detail
    return row


@dataclass
class RunOutcome:
    table: pd.DataFrame
    errors: list[str]
    results: list[CaseResult] = field(default_factory=list)
    after: dict[str, object] = field(default_factory=dict)  # case id -> what run_cases' ``after`` returned
    timeline: list[Timed] = field(default_factory=list)     # every primer, case, method, page, extra task

    @property
    def failed_comparisons(self) -> pd.DataFrame:
        t = self.table
        if t.empty:
            return t
        claimed = t[t["within_tolerance"].notna()]
        return claimed[claimed["within_tolerance"] == False]  # noqa: E712

    @property
    def method_problems(self) -> list[str]:
        """'<case> <method>: <status>: <message>' for every method run that did not end ok."""
        return [f"{r.loaded.id} {method}: {run.summary()}"
                for r in self.results for method, run in r.runs.items() if not run.ok]

    @property
    def unexpected_problems(self) -> list[str]:
        """``method_problems`` less the runs whose case records that outcome as expected
        (``case.expected_failure``, with its reason; the suite checks that they do fail)."""
        return [f"{case_id} {method}: {run.summary()}"
                for case_id, method, run in self._runs_not_expected_to_fail() if not run.ok]

    def _runs_not_expected_to_fail(self):
        """(case id, method, run) for every run whose case does not record it in expected_failure."""
        return [(r.loaded.id, method, run) for r in self.results for method, run in r.runs.items()
                if method not in r.loaded.case.case.expected_failure]

    @property
    def exit_status(self) -> int:
        """The rule of validation/run/exit_status.py: bad input 2; a failed comparison or a method that
        failed, refused or did not converge where its case does not expect it 1; else 0."""
        statuses = [decide(bad_input=bool(self.errors), failed=len(self.failed_comparisons) > 0)]
        statuses += [of_run_status(run.status) for _, _, run in self._runs_not_expected_to_fail()]
        return int(combine(statuses))


def run_cases(paths: list[Path], methods: list[str] | None = None, use_cache: bool = True,
              jobs: int = 1, progress: bool = False, after=None, extra=(),
              costs: dict[str, float] | None = None) -> RunOutcome:
    """Run every case file; bad files are reported as errors and the others still run. ``jobs`` worker
    processes, scheduled by ``validation.run.parallel`` (compiled methods compiled once, ``extra`` tasks
    beside the cases, ``after(result)`` in the worker after each case, longest first by ``costs``)."""
    bar = tqdm(total=len(paths), unit="case", disable=not progress, leave=False)

    def advance(run: PathRun) -> None:
        bar.set_postfix_str(run.path.stem)
        bar.update()

    timeline: list[Timed] = []
    runs = run_paths(paths, methods, use_cache, jobs, after=after, extra=list(extra), progress=advance,
                     timeline=timeline, costs=costs)
    bar.close()
    results = sorted((r.result for r in runs if r.result is not None), key=lambda r: str(r.loaded.path))
    errors = [r.error for r in runs if r.error is not None]
    tables = [tabulate(r) for r in results]
    table = pd.concat(tables, ignore_index=True) if tables else pd.DataFrame(columns=COLUMNS)
    if len(table):
        table = table.sort_values(["group", "case", "method", "quantity", "point", "level"],
                                  kind="stable", ignore_index=True)
    return RunOutcome(table=table, errors=sorted(errors), results=results,
                      after={r.result.loaded.id: r.after for r in runs if r.result is not None and r.after is not None},
                      timeline=timeline)


def prbm_fem_errors(part: pd.DataFrame) -> tuple[float, float]:
    """Largest PRBM-to-FEM error of one case: (relative, length error over the characteristic length).

    The relative error divides by max(|FEM|, 1 % of the largest |FEM| of the same quantity), so that a
    quantity passing through zero (a displacement at the unloaded level, x of a closed circle) does not
    report a meaningless huge ratio; the length-normalised error covers those."""
    values = part.drop_duplicates(["method", "quantity", "point", "level"])
    pivot = values.pivot_table(index=["quantity", "point", "level"], columns="method", values="value",
                               aggfunc="first")
    if not {"prbm", "fem"} <= set(pivot.columns):
        return math.nan, math.nan
    both = pivot[["prbm", "fem"]].dropna()
    if both.empty:
        return math.nan, math.nan
    diff = (both["prbm"] - both["fem"]).abs()
    scale = both["fem"].abs().groupby(level="quantity").transform("max")
    rel = diff / np.maximum(both["fem"].abs(), 0.01 * scale).where(scale > 0)
    lengths = [q for q in both.index.get_level_values("quantity").unique() if QUANTITIES[q].dimension == "length"]
    char = float(part["scale"].dropna().iloc[0]) if part["scale"].notna().any() else math.nan
    norm = diff[diff.index.get_level_values("quantity").isin(lengths)] / char
    return (float(rel.max()) if rel.notna().any() else math.nan,
            float(norm.max()) if len(norm) and norm.notna().any() else math.nan)


def fem_error_relative(part: pd.DataFrame) -> float:
    """The FEM's own largest error estimate in one case, made dimensionless: lengths over the
    characteristic length, other quantities over max(|value|, 1 % of the largest |value| of the same
    quantity)."""
    fem = part[(part["method"] == "fem") & part["error_estimate"].notna()].drop_duplicates(
        ["quantity", "point", "level"])
    if fem.empty:
        return math.nan
    biggest = fem["value"].abs().groupby(fem["quantity"]).transform("max")
    lengths = fem["quantity"].map(lambda q: QUANTITIES[q].dimension == "length")
    denom = np.where(lengths, fem["scale"], np.maximum(fem["value"].abs(), 0.01 * biggest))
    ratio = fem["error_estimate"] / np.where(denom > 0, denom, np.nan)
    return float(ratio.max()) if ratio.notna().any() else math.nan


FEM_VALIDATION = "FEM-validation benchmark"
METHOD_WORDS = {"prbm": "PRBM", "fem": "FEM"}


def no_prbm_fem_reason(result: CaseResult) -> str:
    """The one-line reason a case has no PRBM-vs-FEM number (asked only when it has none): a
    FEM-validation benchmark (``case.purpose``), the case's own reason (``case.no_prbm_fem``), a
    loading reading whose base case carries the number (``case.readings_of``), else what the runs say:
    a method missing from the case, a method that refused or failed (its message), or no shared output."""
    info = result.loaded.case.case
    if info.purpose == "fem-validation":
        return FEM_VALIDATION + (f": {info.no_prbm_fem}" if info.no_prbm_fem else " (runs no PRBM)")
    if info.no_prbm_fem:
        return info.no_prbm_fem
    if info.readings_of:
        return (f"a loading reading of {info.readings_of} (FEM only): the PRBM-vs-FEM number is in the row of "
                f"{info.readings_of}")
    missing = [METHOD_WORDS[m] for m in ("prbm", "fem") if m not in result.runs]
    if missing:
        return f"no {' or '.join(missing)} in this case (the case states no reason)"
    for method in ("prbm", "fem"):
        run = result.runs[method]
        if not run.ok:
            verb = "refuses" if run.status is RunStatus.NOT_APPLICABLE else "gave no answer"
            return f"{METHOD_WORDS[method]} {verb}: {' '.join(run.message.split())}"
    return "the PRBM and the FEM share no output"


def summary(table: pd.DataFrame, results: list[CaseResult] | None = None) -> pd.DataFrame:
    """One row per case: methods run, largest PRBM-to-FEM error, comparisons passed, wall times, and
    (given the case ``results``) ``no_prbm_fem_reason``: the one-line reason a case without a
    PRBM-vs-FEM number has none, missing (NaN, as an empty CSV cell reads back) where the number exists."""
    by_id = {r.loaded.id: r for r in results or []}
    rows = []
    for (group, case_id), part in table.groupby(["group", "case"], sort=True):
        values = part.drop_duplicates(["method", "quantity", "point", "level"])
        prbm_fem, prbm_fem_norm = prbm_fem_errors(part)
        absent = math.isnan(prbm_fem) and math.isnan(prbm_fem_norm)
        reason = no_prbm_fem_reason(by_id[case_id]) if absent and case_id in by_id else math.nan  # NaN: none
        claimed = part[part["within_tolerance"].notna()]
        times = values.groupby("method")["wall_time"].first()
        status = values.groupby("method")["converged"].first()
        rows.append(dict(group=group, case=case_id,
                         methods=" ".join(f"{m}{'' if status[m] else '(!)'}" for m in times.index),
                         max_prbm_fem_rel=prbm_fem, max_prbm_fem_per_length=prbm_fem_norm,
                         no_prbm_fem_reason=reason,
                         fem_error_est_rel=fem_error_relative(part),
                         checks=len(claimed),
                         failed=int((claimed["within_tolerance"] == False).sum()),  # noqa: E712
                         findings=int(part["finding"].notna().sum()),
                         **{f"t_{m}_s": float(t) for m, t in times.items()}))
    return pd.DataFrame(rows)
