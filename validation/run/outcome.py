"""Many cases run, as tables: the wide comparison table of a case (``tabulate``), the outcome of a run
over many case files (``run_cases`` -> ``RunOutcome``: its table, failed comparisons, problems and
exit status), and the one-row-per-case summary with the largest PRBM-to-FEM error.

``run_cases`` returns one tidy pandas table (a row per method x output x load level x reference)
with the value, its unit, the published value and its source, the absolute and relative error,
whether the claimed tolerance is met, the wall time, and whether the method converged. Each case's rows
are tabulated in the worker that ran the case (``Tabulate``), beside the other cases, and put together
here once the last is back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np
import pandas as pd

from validation.case.capabilities import QUANTITIES
from validation.case.scale import characteristic_length
from validation.methods.base import RunStatus
from validation.run.compare import agreement_checks, fem_elastica_checks, reference_check
from validation.run.exit_status import combine, decide, misconfigured_line, of_run_status
from validation.run.parallel import run_paths
from validation.run.progress import CaseProgress
from validation.run.runner import CaseResult, requests_for
from validation.run.timeline import Timed
from validation.run.verdict import Verdict, prbm_fem_verdict, row_verdict, run_verdict, table_verdict


COLUMNS = [
    "case",
    "group",
    "method",
    "quantity",
    "point",
    "level",
    "level_label",
    "value",
    "unit",
    "scale",
    "error_estimate",
    "error_estimate_reliable",
    "reference_label",
    "reference_value",
    "source",
    "compare",
    "tolerance_rel",
    "tolerance_abs",
    "abs_error",
    "rel_error",
    "norm_error",
    "within_tolerance",
    "finding",
    "wall_time",
    "converged",
    "message",
    "applicability",
    "expected_error",
    "cached",
    "check",
    "verdict",
]


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
    rows: list[dict[str, Any]] = []
    for method, run in result.runs.items():
        requests = requests_for(case, method)
        if not requests:
            rows.append(
                dict(
                    case=case.case.id,
                    group=case.case.group,
                    method=method,
                    quantity=None,
                    point=None,
                    level=None,
                    level_label=None,
                    value=math.nan,
                    unit=None,
                    wall_time=run.wall_time,
                    converged=run.converged,
                    message=run.message,
                    cached=result.cached.get(method, False),
                )
            )
            continue
        bases = {}
        for req in requests:
            value = run.values.get(req, math.nan)
            dimension = QUANTITIES[req.quantity].dimension
            base = dict(
                case=case.case.id,
                group=case.case.group,
                method=method,
                quantity=req.quantity,
                point=req.point,
                level=req.level,
                level_label=labels[req.level],
                value=value,
                unit=case.unit(dimension),
                scale=scale,
                error_estimate=run.error_estimate.get(req, math.nan),
                error_estimate_reliable=run.estimate_reliable(req),
                wall_time=run.wall_time,
                converged=run.level_converged.get(req.level, run.converged),
                message=run.level_messages.get(req.level, run.message),
                applicability="; ".join(f.value for f in getattr(run, "applicability", {}).get(req.level, ())),
                expected_error=getattr(run, "expected_error", {}).get(req.level, math.nan),
                cached=result.cached.get(method, False),
            )
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
                rows.append(
                    base
                    | dict(
                        reference_label=ref.label,
                        reference_value=ref.value,
                        source=ref.source.label(),
                        compare=False,
                        abs_error=abs_error,
                        rel_error=abs_error / abs(ref.value) if ref.value != 0 else math.nan,
                        norm_error=abs_error / scale if dimension == "length" else math.nan,
                        within_tolerance=None,
                        finding=ref.finding.text if ref.finding else ref.note,
                    )
                )
            if method == "fem" and req in automatic:
                rows.append(base | _check_row(automatic[req], dimension, scale))
        for req, check in agreed.get(method, []):
            if req in bases:
                rows.append(bases[req] | _check_row(check, QUANTITIES[req.quantity].dimension, scale))
    expected = case.case.expected_failure
    for row in rows:
        run = result.runs[row["method"]]
        level = row.get("level")
        state, _ = run_verdict(run, expected.get(row["method"]), None if level is None else int(level))
        verdict = row_verdict(
            row.get("value", math.nan),
            row.get("within_tolerance"),
            compared=row.get("reference_label") is not None,
            applicability=row.get("applicability") or "",
            run_state=state,
            kind=row.get("check"),
        )
        row["verdict"] = None if verdict is None else verdict.value
    frame = pd.DataFrame(rows)
    return frame.reindex(columns=COLUMNS)


ORDER = ["group", "case", "method", "quantity", "point", "level"]  # the order of the table's rows
# A case's rows hold their text in Python strings (pandas' "python" string storage) where the case ran:
# on tables of tens of rows, filtered and sorted hundreds of times by a report's page, they are cheaper
# than pandas 3's pyarrow-backed default; the whole table takes the default once, when the cases' rows
# are put together (``with_strings``), so that what it holds and writes is the same either way.
CASE_STRINGS = "python"


def sorted_rows(table: pd.DataFrame) -> pd.DataFrame:
    """The rows in the table's order (``ORDER``; a stable sort: rows with equal keys keep theirs)."""
    return table.sort_values(ORDER, kind="stable", ignore_index=True) if len(table) else table


def with_strings(table: pd.DataFrame, storage: str | None = None) -> pd.DataFrame:
    """``table`` with its text columns and its column labels in pandas' ``storage`` of strings (None: the
    default); the values are the same."""
    dtype = pd.StringDtype(storage, na_value=np.nan)
    out = table.astype({c: dtype for c, t in table.dtypes.items() if isinstance(t, pd.StringDtype)})
    out.columns = out.columns.astype(dtype)
    return out


@dataclass(frozen=True)
class CaseRows:
    """What the worker that ran a case sends back (``Tabulate``): the case's rows of the table
    (``tabulate`` in the table's order, text in ``CASE_STRINGS``) and what the caller's ``after`` made
    of them."""

    rows: pd.DataFrame
    after: Any = None


@dataclass(frozen=True)
class Tabulate:
    """``run_cases``' ``after`` of ``run_paths``: the case's rows tabulated in the worker that ran it,
    beside the other cases rather than all of them in this process after the last, then ``then(result,
    rows)`` (e.g. the report's page of the case, drawn from them)."""

    then: Callable[[CaseResult, pd.DataFrame], Any] | None = None

    def __call__(self, result: CaseResult) -> CaseRows:
        with pd.option_context("mode.string_storage", CASE_STRINGS):
            rows = sorted_rows(tabulate(result))
            return CaseRows(rows, None if self.then is None else self.then(result, rows))


def _check_row(check, dimension: str, scale: float) -> dict:
    """The comparison columns of one enforced check."""
    row = dict(
        reference_label=check.reference_label,
        reference_value=check.reference_value,
        source=check.source,
        compare=True,
        tolerance_rel=check.tolerance.rel if check.tolerance else None,
        tolerance_abs=check.tolerance.abs if check.tolerance else None,
        abs_error=check.abs_error,
        rel_error=check.rel_error,
        norm_error=check.abs_error / scale if dimension == "length" else math.nan,
        within_tolerance=check.within,
        finding=check.finding,
        check=check.kind,
    )
    if check.detail:
        row["message"] = check.detail
    return row


@dataclass
class RunOutcome:
    table: pd.DataFrame
    errors: list[str]
    results: list[CaseResult] = field(default_factory=list)
    after: dict[str, object] = field(default_factory=dict)  # case id -> what run_cases' ``after`` returned
    timeline: list[Timed] = field(default_factory=list)  # every primer, case, method, page, extra task

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
        return [
            f"{r.loaded.id} {method}: {run.summary()}"
            for r in self.results
            for method, run in r.runs.items()
            if not run.ok
        ]

    @property
    def outside_limit(self) -> pd.DataFrame:
        """``failed_comparisons`` that have a value to be outside with: the rows of a method that gave
        no value there (refused, failed, did not converge) are its run's verdict, said once in
        ``unexpected_verdicts``, not rows of NaN."""
        failed = self.failed_comparisons
        return failed[failed["value"].notna()] if len(failed) else failed

    @property
    def unexpected_verdicts(self) -> list[str]:
        """'<case> <method>: <status>: <reason>' for every run that refused, failed or did not converge
        where its case does not record an expected failure (``unexpected_problems``, a refusal called
        'refused' as in ``validation.run.verdict``), one line each."""
        lines = []
        for case_id, method, run in self._runs_not_expected_to_fail():
            if run.ok:
                continue
            verdict, reason = run_verdict(run)
            said = f"refused: {reason or 'no message'}" if verdict is Verdict.REFUSED else run.summary()
            lines.append(f"{case_id} {method}: {' '.join(said.split())}")
        return lines

    @property
    def unexpected_problems(self) -> list[str]:
        """``method_problems`` less the runs whose case records that outcome as expected
        (``case.expected_failure``, with its reason; the suite checks that they do fail)."""
        return [
            f"{case_id} {method}: {run.summary()}"
            for case_id, method, run in self._runs_not_expected_to_fail()
            if not run.ok
        ]

    @property
    def misconfigured(self) -> list[str]:
        """One 'file: field: problem' line per method run that found its case misconfigured while it
        solved (bad input found late: the run's status is misconfigured, exit status 2)."""
        return [
            misconfigured_line(r.loaded.path, run)
            for r in self.results
            for run in r.runs.values()
            if run.status is RunStatus.MISCONFIGURED
        ]

    def _runs_not_expected_to_fail(self):
        """(case id, method, run) for every run whose case does not record it in expected_failure."""
        return [
            (r.loaded.id, method, run)
            for r in self.results
            for method, run in r.runs.items()
            if method not in r.loaded.case.case.expected_failure
        ]

    @property
    def exit_status(self) -> int:
        """The rule of validation/run/exit_status.py: bad input 2; a row 'outside the claimed limit', or a
        method that 'failed', 'refused' or 'did not converge' where its case does not record an 'expected
        failure', 1; else 0."""
        statuses = [decide(bad_input=bool(self.errors), failed=len(self.failed_comparisons) > 0)]
        statuses += [of_run_status(run.status) for _, _, run in self._runs_not_expected_to_fail()]
        return int(combine(statuses))


def run_cases(
    paths: list[Path],
    methods: list[str] | None = None,
    use_cache: bool = True,
    jobs: int = 1,
    progress: bool = False,
    after: Callable[[CaseResult, pd.DataFrame], Any] | None = None,
    extra=(),
    costs: dict[str, float] | None = None,
) -> RunOutcome:
    """Run every case file; bad files are reported as errors and the others still run. ``jobs`` worker
    processes, scheduled by ``validation.run.parallel`` (compiled methods compiled once, ``extra`` tasks
    beside the cases, longest first by ``costs``); each case tabulated in the worker that ran it
    (``Tabulate``), then ``after(result, rows)`` there, on its rows."""
    bar = CaseProgress(len(paths), enabled=progress, jobs=jobs)
    timeline: list[Timed] = []
    try:
        runs = run_paths(
            paths,
            methods,
            use_cache,
            jobs,
            after=Tabulate(after),
            extra=list(extra),
            progress=bar.advance,
            timeline=timeline,
            costs=costs,
            watch=bar.watch,
        )
    finally:
        bar.close()
    ran = sorted(((r.result, r.after) for r in runs if r.result is not None), key=lambda done: str(done[0].loaded.path))
    results = [result for result, _ in ran]
    cases: list[CaseRows] = [case for _, case in ran]
    errors = [r.error for r in runs if r.error is not None]
    tables = [case.rows for case in cases]
    table = with_strings(sorted_rows(pd.concat(tables, ignore_index=True))) if tables else pd.DataFrame(columns=COLUMNS)
    return RunOutcome(
        table=table,
        errors=sorted(errors),
        results=results,
        after={r.loaded.id: case.after for r, case in zip(results, cases) if case.after is not None},
        timeline=timeline,
    )


def _first_values(
    part: pd.DataFrame, method: str | None = None, where: list[bool] | None = None
) -> dict[tuple, tuple[float, float, float]]:
    """(method, quantity, point, level) -> (value, error_estimate, scale) of the first row with that key
    (as ``drop_duplicates`` keeps it; only the rows of ``method``, and where ``where`` holds, when given),
    in plain Python: a case has tens of rows, where pandas' per-call cost is most of the time."""
    first: dict[tuple, tuple[float, float, float]] = {}
    rows = len(part)
    columns = (
        part["method"].tolist(),
        part["quantity"].tolist(),
        part["point"].tolist(),
        part["level"].tolist(),
        part["value"].tolist(),
        part["error_estimate"].tolist() if "error_estimate" in part else [math.nan] * rows,
        part["scale"].tolist() if "scale" in part else [math.nan] * rows,
        [True] * rows if where is None else where,
    )
    for m, q, p, lv, value, estimate, scale, wanted in zip(*columns):
        if wanted and (method is None or m == method):
            key = (m, q, p if isinstance(p, str) else "", lv)  # no point: "" in memory, NaN read back from CSV
            first.setdefault(key, (float(value), float(estimate), float(scale)))
    return first


def _nanmax(values: list[float]) -> float:
    finite = [v for v in values if not math.isnan(v)]
    return max(finite) if finite else math.nan


def prbm_fem_errors(part: pd.DataFrame) -> tuple[float, float]:
    """Largest PRBM-to-FEM error of one case: (relative, length error over the characteristic length).

    The relative error divides by max(|FEM|, 1 % of the largest |FEM| of the same quantity), so that a
    quantity passing through zero (a displacement at the unloaded level, x of a closed circle) does not
    report a meaningless huge ratio; the length-normalised error covers those."""
    first = _first_values(part)
    pairs = [
        (q, value, first[("fem", q, p, lv)][0])
        for (m, q, p, lv), (value, _, _) in first.items()
        if m == "prbm" and ("fem", q, p, lv) in first
    ]
    pairs = [(q, prbm, fem) for q, prbm, fem in pairs if not (math.isnan(prbm) or math.isnan(fem))]
    if not pairs:
        return math.nan, math.nan
    scale: dict[str, float] = {}
    for q, _, fem in pairs:
        scale[q] = max(scale.get(q, 0.0), abs(fem))
    rel = [abs(prbm - fem) / max(abs(fem), 0.01 * scale[q]) if scale[q] > 0 else math.nan for q, prbm, fem in pairs]
    char = next((float(s) for s in part["scale"].tolist() if not pd.isna(s)), math.nan)
    norm = [abs(prbm - fem) / char for q, prbm, fem in pairs if QUANTITIES[q].dimension == "length"]
    return _nanmax(rel), _nanmax(norm)


def reliable_estimates(part: pd.DataFrame) -> list[bool]:
    """Per row, whether its error estimate is not marked unreliable (``error_estimate_reliable`` not the
    boolean False: the FEM's meshes were not in the asymptotic range, the estimate is no bound)."""
    if "error_estimate_reliable" not in part:
        return [True] * len(part)
    return [_not_false(value) for value in part["error_estimate_reliable"].tolist()]


def _not_false(value) -> bool:
    """True unless ``value`` is the boolean False (missing, None, NaN and pd.NA are not)."""
    return not (isinstance(value, (bool, np.bool_)) and not value)


def _missing_as_none(value: object) -> object:
    """``value``, or None where it is missing (NaN, None, pd.NA): one key for every missing value, as
    ``drop_duplicates`` compares them."""
    return None if pd.isna(value) else value


def fem_estimates_unreliable(part: pd.DataFrame) -> int:
    """How many of the FEM's values in one case have an error estimate marked unreliable."""
    if "error_estimate_reliable" not in part:
        return 0
    columns = (part["method"], part["error_estimate"].notna(), part["quantity"], part["point"], part["level"])
    keys = set()  # the distinct (quantity, point, level) of the FEM's rows with an unreliable estimate
    for (m, estimated, q, p, lv), reliable in zip(zip(*(c.tolist() for c in columns)), reliable_estimates(part)):
        if m == "fem" and estimated and not reliable:
            keys.add((_missing_as_none(q), _missing_as_none(p), _missing_as_none(lv)))
    return len(keys)


def fem_error_relative(part: pd.DataFrame) -> float:
    """The FEM's own largest error estimate in one case, made dimensionless: lengths over the
    characteristic length, other quantities over max(|value|, 1 % of the largest |value| of the same
    quantity). An estimate marked unreliable (``error_estimate_reliable`` False) is no bound and is left
    out."""
    estimated = part["error_estimate"].notna().tolist()
    where = [has and reliable for has, reliable in zip(estimated, reliable_estimates(part))]
    rows = [
        (q, value, estimate, scale)
        for (_, q, _, _), (value, estimate, scale) in _first_values(part, "fem", where).items()
    ]
    if not rows:
        return math.nan
    biggest: dict[str, float] = {}
    for q, value, _, _ in rows:
        if not math.isnan(value):  # as pandas' max, which skips NaN
            biggest[q] = max(biggest.get(q, -math.inf), abs(value))
    ratios = []
    for q, value, estimate, scale in rows:
        denom = scale if QUANTITIES[q].dimension == "length" else max(abs(value), 0.01 * biggest.get(q, math.nan))
        ratios.append(estimate / denom if denom > 0 else math.nan)
    return _nanmax(ratios)


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
        return (
            f"a loading reading of {info.readings_of} (FEM only): the PRBM-vs-FEM number is in the row of "
            f"{info.readings_of}"
        )
    missing = [METHOD_WORDS[m] for m in ("prbm", "fem") if m not in result.runs]
    if missing:
        return f"no {' or '.join(missing)} in this case (the case states no reason)"
    for method in ("prbm", "fem"):
        run = result.runs[method]
        if not run.ok:
            verb = "refuses" if run.status is RunStatus.NOT_APPLICABLE else "gave no answer"
            return f"{METHOD_WORDS[method]} {verb}: {' '.join(run.message.split())}"
    return "the PRBM and the FEM share no output"


def _run_columns(part: pd.DataFrame) -> tuple[dict[str, float], dict]:
    """Each method's wall time and converged flag in one case, methods in sorted order: the first value
    that is not missing over the case's distinct (method, quantity, point, level) rows (what
    ``drop_duplicates`` then ``groupby(method).first()`` give), NaN where every row misses it."""
    seen: set[tuple] = set()
    times: dict[str, float] = {}
    status: dict[str, object] = {}
    columns = ("method", "quantity", "point", "level", "wall_time", "converged")
    for m, q, p, lv, t, ok in zip(*(part[c].tolist() for c in columns)):
        key = (m, q, p if isinstance(p, str) else "", lv)
        if key in seen:
            continue
        seen.add(key)
        if m not in times or (math.isnan(times[m]) and not pd.isna(t)):
            times[m] = math.nan if pd.isna(t) else float(t)
        if m not in status or (pd.isna(status[m]) and not pd.isna(ok)):
            status[m] = math.nan if pd.isna(ok) else ok
    order = sorted(times)
    return {m: times[m] for m in order}, {m: status[m] for m in order}


@dataclass(frozen=True)
class PrbmFemNumbers:
    """A case's largest PRBM-to-FEM error (relative, and over the characteristic length: ``prbm_fem_errors``)
    with that number's verdict (``prbm_fem_verdict``), and the FEM's largest reliable error estimate
    (``fem_error_relative``) and count of unreliable ones: what ``summary`` and the report's index row of a
    case both give, worked out once where both are wanted."""

    relative: float
    length: float
    verdict: Verdict
    fem_estimate: float
    fem_unreliable: int

    @classmethod
    def of(cls, part: pd.DataFrame) -> PrbmFemNumbers:
        """The numbers of one case's rows (a case without rows: NaN, none unreliable, its verdict of
        none)."""
        if not len(part):
            return cls(math.nan, math.nan, prbm_fem_verdict(part), math.nan, 0)
        relative, length = prbm_fem_errors(part)
        return cls(relative, length, prbm_fem_verdict(part), fem_error_relative(part), fem_estimates_unreliable(part))


def summary_row(
    group: str,
    case_id: str,
    part: pd.DataFrame,
    result: CaseResult | None = None,
    numbers: PrbmFemNumbers | None = None,
) -> dict[str, Any]:
    """The case's row of ``summary`` from its rows ``part`` (its ``result``: for ``no_prbm_fem_reason``;
    ``numbers``: its ``PrbmFemNumbers`` when the caller has them)."""
    numbers = numbers or PrbmFemNumbers.of(part)
    absent = math.isnan(numbers.relative) and math.isnan(numbers.length)
    reason = no_prbm_fem_reason(result) if absent and result is not None else math.nan  # NaN: none
    times, status = _run_columns(part)
    verdicts = [v for v in part["within_tolerance"] if not pd.isna(v)]
    return dict(
        group=group,
        case=case_id,
        verdict=table_verdict(part).value,
        methods=" ".join(f"{m}{'' if status[m] else '(!)'}" for m in times),
        max_prbm_fem_rel=numbers.relative,
        max_prbm_fem_per_length=numbers.length,
        prbm_fem_verdict=math.nan if absent else numbers.verdict.value,
        no_prbm_fem_reason=reason,
        fem_error_est_rel=numbers.fem_estimate,
        fem_estimates_unreliable=numbers.fem_unreliable,
        checks=len(verdicts),
        failed=sum(1 for v in verdicts if v == False),  # noqa: E712
        findings=int(part["finding"].notna().sum()),
        **{f"t_{m}_s": t for m, t in times.items()},
    )


def summary(
    table: pd.DataFrame, results: list[CaseResult] | None = None, rows: Mapping[str, dict[str, Any]] | None = None
) -> pd.DataFrame:
    """One row per case (``summary_row``), by group and case: its verdict (the worst of its rows',
    ``validation.run.verdict``), methods run, largest PRBM-to-FEM error and that number's verdict (``no
    limit claimed`` unless an agreement claims one; empty without the number), comparisons passed, wall
    times, and (given the case ``results``) ``no_prbm_fem_reason``: the one-line reason a case without a
    PRBM-vs-FEM number has none, missing (NaN, as an empty CSV cell reads back) where the number exists.
    ``rows``: rows already worked out (by case id, e.g. where the case ran), taken as they are."""
    by_id = {r.loaded.id: r for r in results or []}
    known = rows or {}
    out = []
    for (group, case_id), part in table.groupby(["group", "case"], sort=True):
        row = known.get(case_id)
        if row is None or row.get("group") != group:
            row = summary_row(group, case_id, part, by_id.get(case_id))
        out.append(row)
    return pd.DataFrame(out)
