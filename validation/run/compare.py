"""Comparison semantics: what each enforced check of a case is and whether it holds.

Four kinds of check, each a row of the results table with ``check`` naming its kind and
``within_tolerance`` True or False (a row that only records a value has ``within_tolerance`` None):

reference     a printed number with ``compare`` and ``tolerance``: |value - printed| within the
              tolerance (abs, or rel to |printed|; either met passes).
finding       a printed number the method is known not to reproduce (``schema.Finding``): passes when
              the printed value still disagrees *and* the explanation reproduces (the method gives
              ``computed``, or the re-run with ``reproduce_with`` meets the printed value).
agreement     an acceptance limit between two methods or a method and a printed column
              (``schema.Agreement``), rel measured on the scale of the quantity over the levels.
fem-elastica  automatic wherever the FEM and the exact elastica both give a value: |FEM - elastica|
              within ``FEM_ESTIMATE_MULTIPLE`` times the FEM's own discretisation-error estimate (plus a
              round-off floor); a FEM value without an estimate fails the check; a value whose estimate
              the FEM marks unreliable (``MethodRun.unreliable_estimate``: its meshes were not in the
              asymptotic range, the estimate is no bound) is recorded with the reason, not judged
              (``within_tolerance`` empty).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum
from functools import partial

from validation.case.capabilities import QUANTITIES
from validation.case.method_options import FemOptions
from validation.methods.base import MethodRun, Request
from validation.case.schema import Agreement, Case, ReferenceSpec, Tolerance

FEM_ESTIMATE_MULTIPLE = 3.0
# Round-off floor of the FEM-elastica check: the elastica's own accuracy (shooting rtol ~1e-10) and the
# FEM's Newton tolerance, relative to the quantity's scale (the characteristic length for lengths).
ROUND_OFF = 1e-7
# A quantity's relative error is judged on max(|reference|, RELATIVE_FLOOR x its largest |reference|).
RELATIVE_FLOOR = 0.01


class CheckKind(StrEnum):
    """What a check compares a method's value with."""

    REFERENCE = "reference"  # a published number of the case (its tolerance)
    FINDING = "finding"  # a documented disagreement and the explanation that reproduces it
    AGREEMENT = "agreement"  # another method's value (the case's agreements)
    FEM_ELASTICA = "fem-elastica"  # the FEM against the exact elastica, within the FEM's estimate


@dataclass(frozen=True)
class Check:
    """One enforced comparison: what was compared with what, how far apart, and whether it holds."""

    kind: CheckKind
    reference_label: str
    reference_value: float
    source: str
    tolerance: Tolerance | None
    abs_error: float
    rel_error: float
    within: bool | None  # None: recorded, not judged
    finding: str | None = None
    detail: str = ""


def within(tol: Tolerance, abs_error: float, rel_error: float) -> bool:
    """Either limit met passes; a NaN error meets nothing."""
    ok_abs = tol.abs is not None and abs_error <= tol.abs
    ok_rel = tol.rel is not None and not math.isnan(rel_error) and rel_error <= tol.rel
    return bool(ok_abs or ok_rel)


def _errors(value: float, printed: float) -> tuple[float, float]:
    abs_error = abs(value - printed)
    return abs_error, (abs_error / abs(printed) if printed != 0 else math.nan)


def reference_check(ref: ReferenceSpec, value: float, reproduced: float | None) -> Check:
    """The check a compared reference stands for; ``reproduced`` is the method's value re-run with the
    finding's ``reproduce_with`` (None when the finding has none or the re-run failed)."""
    if ref.tolerance is None:
        raise ValueError(f"reference {ref.label} {ref.value:g} has no tolerance: it is recorded, not checked")
    abs_error, rel_error = _errors(value, ref.value)
    met = within(ref.tolerance, abs_error, rel_error)
    check = partial(
        Check,
        reference_label=ref.label,
        reference_value=ref.value,
        source=ref.source.label(),
        tolerance=ref.tolerance,
        abs_error=abs_error,
        rel_error=rel_error,
    )
    if ref.finding is None:
        return check(kind=CheckKind.REFERENCE, within=met)
    finding = ref.finding
    tol = finding.tolerance or ref.tolerance
    problems = []
    if met:
        problems.append(f"stale finding: the method meets the printed {ref.value:g} (|error| {abs_error:.3g})")
    if finding.computed is not None:
        got = _errors(value, finding.computed)
        if not within(tol, *got):
            problems.append(
                f"the explanation does not reproduce: method {value:.6g}, finding says "
                f"{finding.computed:.6g} (|error| {got[0]:.3g})"
            )
    elif reproduced is None or math.isnan(reproduced):
        problems.append(f"the re-run with {finding.reproduce_with} gave no value")
    else:
        got = _errors(reproduced, ref.value)
        if not within(tol, *got):
            problems.append(
                f"the re-run with {finding.reproduce_with} gives {reproduced:.6g}, not the printed "
                f"{ref.value:g} (|error| {got[0]:.3g})"
            )
    return check(kind=CheckKind.FINDING, within=not problems, finding=finding.text, detail="; ".join(problems))


def agreement_checks(case: Case, agreement: Agreement, runs: dict[str, MethodRun]) -> dict[Request, Check]:
    """Every (quantity, level) the agreement covers where both sides have a value, keyed by the
    request of ``agreement.method``."""
    run = runs.get(agreement.method)
    if run is None:
        return {}
    levels = range(case.n_levels()) if agreement.levels == "all" else agreement.levels
    checks: dict[Request, Check] = {}
    for quantity in agreement.quantities:
        point = agreement.point if QUANTITIES[quantity].at_point else ""
        pairs = []
        for level in levels:
            req = Request(quantity, point, level)
            other = _against_value(case, agreement.against, runs, req)
            if other is not None and not math.isnan(other):
                pairs.append((req, run.values.get(req, math.nan), other))
        if not pairs:
            continue
        scale = max(abs(other) for _, _, other in pairs)
        for req, value, other in pairs:
            abs_error = abs(value - other)
            denom = max(abs(other), RELATIVE_FLOOR * scale)
            rel_error = abs_error / denom if denom > 0 else math.nan
            checks[req] = Check(
                kind=CheckKind.AGREEMENT,
                reference_label=agreement.against,
                reference_value=other,
                source=agreement.basis,
                tolerance=agreement.tolerance,
                abs_error=abs_error,
                rel_error=rel_error,
                within=within(agreement.tolerance, abs_error, rel_error),
            )
    return checks


def _against_value(case: Case, against: str, runs: dict[str, MethodRun], req: Request) -> float | None:
    if against in case.methods:
        run = runs.get(against)
        return None if run is None else run.values.get(req)
    printed = [
        ref.value
        for ref in case.references
        if ref.label == against
        and ref.quantity == req.quantity
        and ref.level == req.level
        and (ref.point if QUANTITIES[ref.quantity].at_point else "") == req.point
    ]
    return printed[0] if printed else None


def axial_strain_bound(case: Case, level: int) -> float:
    """An upper bound of the FEM's axial strain at a level, |F|/EA with |F| the largest force applied
    to the segment (the axial force anywhere is at most the resultant of the end forces): the
    inextensible elastica differs from the extensible FEM by at most this strain times the length in a
    position, and times the value, to first order, in an angle or a force. Zero for a mechanism (the
    elastica does not model one) or when the case prescribes no forces."""
    if case.segment is None:
        return 0.0
    forces = [load for load in case.loads if load.kind == "force"]
    fx = sum(load.levels()[level] * load.direction[0] for load in forces if load.direction is not None)
    fy = sum(load.levels()[level] * load.direction[1] for load in forces if load.direction is not None)
    # the forces that turn: followers, and forces toward a fixed point (they have no direction)
    followers = sum(
        abs(load.levels()[level]) * math.hypot(*load.direction)
        for load in forces
        if load.follower and load.direction is not None
    ) + sum(abs(load.levels()[level]) for load in forces if load.toward is not None)
    force = max(math.hypot(fx, fy), followers)
    EA = case.segment.axial_stiffness()
    if math.isnan(EA):  # no area given: the FEM adapter's stand-in EA = ratio EI / L^2
        ratio = FemOptions.model_validate(case.methods.get("fem") or {}).inextensible_ratio
        EA = ratio * case.segment.bending_stiffness() / case.segment.length**2
    return force / EA if EA > 0 and not math.isnan(EA) else 0.0


def fem_elastica_checks(case: Case, runs: dict[str, MethodRun], scale: float) -> dict[Request, Check]:
    """The FEM held to the exact elastica wherever both give a value, within a small multiple of its
    own error estimate; where the FEM marks that estimate unreliable, the row says so and is not judged."""
    fem, exact = runs.get("fem"), runs.get("elastica")
    if fem is None or exact is None:
        return {}
    checks = {}
    for req, value in fem.values.items():
        other = exact.values.get(req)
        if other is None or math.isnan(other) or math.isnan(value):
            continue
        abs_error, rel_error = _errors(value, other)
        if req in fem.unreliable_estimate:
            checks[req] = Check(
                kind=CheckKind.FEM_ELASTICA,
                reference_label="elastica",
                reference_value=other,
                source="exact elastica; not judged: estimate unreliable",
                tolerance=None,
                abs_error=abs_error,
                rel_error=rel_error,
                within=None,
                detail=f"not judged: {fem.unreliable_estimate[req]}",
            )
            continue
        estimate = fem.error_estimate.get(req, math.nan)
        size = scale if QUANTITIES[req.quantity].dimension == "length" else max(abs(other), 1.0)
        stretch = axial_strain_bound(case, req.level) * (
            scale if QUANTITIES[req.quantity].dimension == "length" else abs(other)
        )
        limit = FEM_ESTIMATE_MULTIPLE * estimate + stretch + ROUND_OFF * size
        detail = "" if not math.isnan(estimate) else "the FEM gave no error estimate for this value"
        checks[req] = Check(
            kind=CheckKind.FEM_ELASTICA,
            reference_label="elastica",
            reference_value=other,
            source=f"exact elastica; limit {FEM_ESTIMATE_MULTIPLE:g} x FEM error estimate "
            f"+ axial stretch |F| L/EA (the elastica is inextensible) + {ROUND_OFF:g} x scale",
            tolerance=Tolerance(abs=limit) if limit > 0 else None,
            abs_error=abs_error,
            rel_error=rel_error,
            within=bool(not math.isnan(limit) and abs_error <= limit),
            detail=detail,
        )
    return checks


def loaded_levels(case: Case) -> set[int]:
    """Levels at which some load is non-zero (every level when the case has no loads)."""
    if not case.loads:
        return set(range(case.n_levels()))
    return {i for i in range(case.n_levels()) if any(load.levels()[i] != 0.0 for load in case.loads)}


def verdict_by_method(case: Case, runs: dict[str, MethodRun], table) -> dict[str, list[str]]:
    """Why a case fails, one line each (empty: it passes). A case fails when an enforced check fails;
    when a method it lists does not converge or does not apply, unless ``case.expected_failure`` says so
    (and then it fails if the method does converge); when a method with values has no enforced check at
    a loaded level, unless ``case.unchecked`` gives the reason. Each problem is filed under the method
    it is about (an agreement under the method it holds to the other)."""
    problems: dict[str, list[str]] = {method: [] for method in runs}
    claimed = table["within_tolerance"].notna()
    outside = claimed & (table["within_tolerance"] == False)  # noqa: E712
    for _, row in table[outside].iterrows() if outside.any() else ():
        if row["method"] in case.case.expected_failure and math.isnan(row["value"]):
            continue  # no value where the method is expected to fail: the expectation is checked below
        problems.setdefault(row["method"], []).append(
            f"{row['check']} {row['method']} {row['quantity']} level {row['level']}: "
            f"{row['value']:.6g} against {row['reference_label']} {row['reference_value']:.6g} "
            f"(|error| {row['abs_error']:.3g}, rel {row['rel_error']:.3g}; tolerance abs "
            f"{row['tolerance_abs']}, rel {row['tolerance_rel']}) {row['message'] or ''}".rstrip()
        )
    for i, agreement in enumerate(case.agreements):
        against_ran = agreement.against in runs or agreement.against not in case.methods
        if agreement.method in runs and against_ran and not agreement_checks(case, agreement, runs):
            problems[agreement.method].append(
                f"agreements.{i} ({agreement.method} against {agreement.against}) compares nothing: "
                f"no level where both sides have {', '.join(agreement.quantities)}"
            )
    loaded = loaded_levels(case)
    checked = _checked_levels(table, claimed)
    for method, run in runs.items():
        failed = not run.converged or not run.values
        expected = case.case.expected_failure.get(method)
        if failed and expected is None:
            problems[method].append(f"{method} did not give every value: {run.message or 'no message'}")
        elif expected is not None and not failed:
            problems[method].append(f"{method} was expected to fail ({expected}) but converged")
        if not run.values or method in case.case.unchecked:
            continue
        if not checked.get(method, set()) & loaded:
            problems[method].append(
                f"{method} has values but no enforced check at a loaded level, and case.unchecked gives no reason"
            )
    return problems


def _checked_levels(table, claimed) -> dict[str, set[int]]:
    """Per method, the levels at which an enforced check (a row of ``table`` where ``claimed``) holds it
    to something: its own checks, and the agreements and FEM-elastica checks held against it."""
    levels: dict[str, set[int]] = {}
    enforced = claimed & table["level"].notna()
    columns = (enforced, table["method"], table["reference_label"], table["check"], table["level"])
    for row_enforced, method, against, kind, level in zip(*(column.tolist() for column in columns)):
        if not row_enforced:
            continue
        levels.setdefault(method, set()).add(int(level))
        if kind in ("agreement", "fem-elastica"):
            levels.setdefault(against, set()).add(int(level))
    return levels


def case_verdict(case: Case, runs: dict[str, MethodRun], table) -> list[str]:
    """Why a case fails, one line each (empty: it passes); ``verdict_by_method`` says for which method."""
    return [line for lines in verdict_by_method(case, runs, table).values() for line in lines]
