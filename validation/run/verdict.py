"""The one verdict vocabulary: what a comparison row, a case x method and a case are, in words.

Every place that judges or shows a result (the ``verdict`` column of the results and comparisons
tables, ``summary.csv``, the CLI summary, the report's case rows and its first sentence, the pytest
plugin's messages, the exit status) uses these words and nothing else.

A comparison row (a value beside something it is compared with) is:

- ``within the claimed limit``: a limit was claimed (a printed number's tolerance, an agreement between
  methods with its basis, the FEM held to the exact elastica within its own error estimate) and it holds;
- ``finding``: a printed number the method is known not to reproduce, and the recorded explanation
  reproduces within its limit;
- ``no limit claimed``: the number is shown beside the other, nothing is asserted, whatever the error;
- ``outside the model's validity``: the method flags the load as outside what its model was made for
  (``MethodRun.applicability``); a limit that fails there is still ``outside the claimed limit``;
- ``outside the claimed limit``: a claimed limit (or a finding's explanation) does not hold;
- ``refused``, ``did not converge``, ``failed``: the method gave no value there (it refused the case,
  its solver did not converge, or it crashed / timed out / was misconfigured), with its message;
- ``expected failure``: the method gave no value where the case records that it should not
  (``case.expected_failure``, with the reason).

A row that only records a value (compared with nothing) has no verdict. A case x method, and a case,
is the worst of its rows in ``ORDER`` (worst first); a case x method the suite rejects for another
reason (an agreement that compares nothing, a method with values but no enforced check at a loaded
level, an expected failure that converged: ``compare.verdict_by_method``) is ``failed``. ``FAILING``
verdicts make the exit status 1.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import pandas as pd

from validation.methods.base import RunStatus


class Verdict(enum.Enum):
    """A verdict's words; ``meaning`` says in one line what it asserts."""

    WITHIN = "within the claimed limit"
    FINDING = "finding"
    NO_LIMIT = "no limit claimed"
    OUTSIDE_VALIDITY = "outside the model's validity"
    EXPECTED = "expected failure"
    OUTSIDE_LIMIT = "outside the claimed limit"
    REFUSED = "refused"
    NOT_CONVERGED = "did not converge"
    FAILED = "failed"

    @property
    def meaning(self) -> str:
        return MEANINGS[self]

    @property
    def failing(self) -> bool:
        """This verdict makes the exit status 1 (and the case's test fail)."""
        return self in FAILING

    @property
    def rank(self) -> int:
        """Position in ``ORDER``: 0 is the worst."""
        return ORDER.index(self)


MEANINGS = {
    Verdict.WITHIN: "a claimed limit (with its basis) holds",
    Verdict.FINDING: "a printed number known not to be reproduced; the recorded explanation reproduces",
    Verdict.NO_LIMIT: "the number is shown beside the other; nothing is asserted",
    Verdict.OUTSIDE_VALIDITY: "the method flags the load as outside what its model was made for",
    Verdict.EXPECTED: "the method gave no value where the case records that it should not, with the reason",
    Verdict.OUTSIDE_LIMIT: "a claimed limit does not hold",
    Verdict.REFUSED: "the method refused the case (it cannot model it), with the reason",
    Verdict.NOT_CONVERGED: "the method's solver did not converge, with where",
    Verdict.FAILED: "the method crashed, timed out or was misconfigured, or the case's checks are incomplete",
}

# worst first: a case x method (and a case) is the first of these any of its rows is
ORDER = (
    Verdict.FAILED,
    Verdict.NOT_CONVERGED,
    Verdict.OUTSIDE_LIMIT,
    Verdict.REFUSED,
    Verdict.EXPECTED,
    Verdict.OUTSIDE_VALIDITY,
    Verdict.NO_LIMIT,
    Verdict.FINDING,
    Verdict.WITHIN,
)
FAILING = frozenset({Verdict.FAILED, Verdict.NOT_CONVERGED, Verdict.OUTSIDE_LIMIT, Verdict.REFUSED})


def worst(verdicts) -> Verdict | None:
    """The worst of ``verdicts`` in ``ORDER`` (None for none)."""
    verdicts = [v for v in verdicts if v is not None]
    return min(verdicts, key=lambda v: v.rank) if verdicts else None


def parse(word) -> Verdict | None:
    """The verdict a table cell holds (None for an empty cell)."""
    if word is None or (isinstance(word, float) and math.isnan(word)) or word is pd.NA or word == "":
        return None
    return Verdict(str(word))


def run_verdict(run, expected: str | None = None, level: int | None = None) -> tuple[Verdict | None, str]:
    """(verdict, reason) of how a method run ended (at ``level``, when given): None when it gave its
    values; else refused, did not converge or failed, with its message; or expected failure, with
    the case's reason, when the case records it (``expected``)."""
    verdict, reason = _run_verdict(run, level)
    if verdict is not None and expected:
        return Verdict.EXPECTED, f"expected: {expected} ({reason})" if reason else f"expected: {expected}"
    return verdict, reason


def _run_verdict(run, level: int | None) -> tuple[Verdict | None, str]:
    status = getattr(run, "status", None)
    message = getattr(run, "message", "") or ""
    if status is RunStatus.NOT_APPLICABLE or (status is None and message.startswith("not applicable")):
        return Verdict.REFUSED, message.removeprefix("not applicable: ")
    if status in (RunStatus.FAILED, RunStatus.MISCONFIGURED, RunStatus.TIMED_OUT) or message.startswith("error:"):
        return Verdict.FAILED, message
    by_level = getattr(run, "level_converged", {})
    converged = run.converged if level is None else by_level.get(level, run.converged)
    if (status is RunStatus.NOT_CONVERGED and level is None) or not converged:
        return Verdict.NOT_CONVERGED, getattr(run, "level_messages", {}).get(level, message) or message
    return None, ""


def row_verdict(
    value: float, within, compared: bool, applicability: str, run_state: Verdict | None, kind: str | None = None
) -> Verdict | None:
    """The verdict of one results row: ``within`` the claimed limit (True, False, or None when no
    limit), ``compared`` (the row has something beside the value), ``applicability`` the row's flags,
    ``run_state`` the run's verdict at the row's level (``run_verdict``), ``kind`` the check's kind."""
    missing = value is None or pd.isna(value)
    within = None if within is None or pd.isna(within) else bool(within)
    if missing and run_state is not None:
        return run_state
    if within is False:
        return Verdict.OUTSIDE_LIMIT
    if applicability:
        return Verdict.OUTSIDE_VALIDITY
    if within is True:
        return Verdict.FINDING if kind == "finding" else Verdict.WITHIN
    return Verdict.NO_LIMIT if compared else None


@dataclass(frozen=True)
class MethodVerdict:
    """A case x method's verdict with its reason (empty for 'within the claimed limit')."""

    method: str
    verdict: Verdict
    reason: str


def rows_reason(verdict: Verdict, table: pd.DataFrame, rows: list[int]) -> str:
    """Why the rows of ``table`` at positions ``rows`` have ``verdict``, in a few words: the limits, their
    basis, how many rows."""

    def column(name: str) -> list:
        values = table[name].tolist()
        return [values[i] for i in rows]

    if verdict is Verdict.WITHIN:
        bases = sorted({str(s) for s in column("source") if not pd.isna(s)})
        return f"{len(rows)} row(s) within their limit; basis: {'; '.join(bases)}" if bases else ""
    if verdict is Verdict.NO_LIMIT:
        against = sorted({str(s) for s in column("reference_label") if not pd.isna(s)})
        return f"{len(rows)} row(s) against {', '.join(against)} shown with no limit claimed"
    if verdict is Verdict.OUTSIDE_VALIDITY:
        flags = sorted({str(s) for s in column("applicability") if not pd.isna(s) and s})
        expected = [e for e in column("expected_error") if not pd.isna(e)] if "expected_error" in table else []
        atlas = f" (the PRBM error atlas expects up to {max(expected):.3g} % of L at these levels)" if expected else ""
        return f"{len(rows)} row(s) flagged: {'; '.join(flags)}{atlas}"
    if verdict is Verdict.OUTSIDE_LIMIT:
        r = table.iloc[rows[0]]
        return (
            f"{len(rows)} row(s) outside the claimed limit, e.g. {r['quantity']} level {r['level']} against "
            f"{r['reference_label']} (rel error {r['rel_error']:.3g})"
        )
    if verdict is Verdict.FINDING:
        return f"{len(rows)} finding row(s)"
    return ""


def method_verdicts(
    case, runs: dict, table: pd.DataFrame, problems: dict[str, list[str]] | None = None
) -> dict[str, MethodVerdict]:
    """Per method of a case: the worst of its rows' verdicts (``table``'s ``verdict`` column) and of how
    its run ended; ``failed`` with the line when ``problems`` (``compare.verdict_by_method``) files one
    under it that its rows do not already explain."""
    out = {}
    expected = case.case.expected_failure
    rows = _rows_by_verdict(table)
    for method, run in runs.items():
        by_row = rows.get(method, {})
        state, why = run_verdict(run, expected.get(method))
        candidates = list(by_row) + ([state] if state else [])
        verdict = worst(candidates)
        reason = (
            why
            if verdict is state and state is not None
            else (rows_reason(verdict, table, by_row[verdict]) if verdict is not None and verdict in by_row else "")
        )
        lines = (problems or {}).get(method, [])
        if lines and (verdict is None or not verdict.failing):
            verdict, reason = Verdict.FAILED, "; ".join(lines)
        if verdict is None:
            verdict, reason = Verdict.NO_LIMIT, "values only: nothing compared"
        out[method] = MethodVerdict(method, verdict, reason)
    return out


def _rows_by_verdict(table: pd.DataFrame) -> dict[str, dict[Verdict, list[int]]]:
    """Per method, the positions of its rows in ``table`` by their verdict (rows without one left out),
    in the table's order."""
    rows: dict[str, dict[Verdict, list[int]]] = {}
    if not len(table):
        return rows
    for position, (method, word) in enumerate(zip(table["method"].tolist(), table["verdict"].tolist())):
        verdict = parse(word)
        if verdict is not None and isinstance(method, str):
            rows.setdefault(method, {}).setdefault(verdict, []).append(position)
    return rows


def case_verdict_of(verdicts) -> Verdict:
    """A case's verdict: the worst of its methods' (``no limit claimed`` for a case without any)."""
    return worst(v.verdict if isinstance(v, MethodVerdict) else v for v in verdicts) or Verdict.NO_LIMIT


def table_verdict(part: pd.DataFrame) -> Verdict:
    """A case's verdict from its rows alone (as ``summary.csv`` is read back), as ``method_verdicts`` and
    ``case_verdict_of`` give it: per method the worst of its rows' verdicts (``no limit claimed`` for a
    method whose rows only record values: nothing of it is compared), then the worst over the methods
    (rows without a method left out)."""
    if "verdict" not in part:
        return Verdict.NO_LIMIT
    if "method" not in part:
        return worst(parse(w) for w in part["verdict"]) or Verdict.NO_LIMIT
    per_method: dict[object, Verdict | None] = {}
    for method, word in zip(part["method"].tolist(), part["verdict"].tolist()):
        if not pd.isna(method):
            per_method[method] = worst([per_method.get(method), parse(word)])
    return worst(v or Verdict.NO_LIMIT for v in per_method.values()) or Verdict.NO_LIMIT


def prbm_fem_verdict(part: pd.DataFrame) -> Verdict:
    """The verdict of a case's PRBM-vs-FEM number: the worst verdict of the PRBM's rows held to the FEM
    (an agreement with a claimed limit, or flagged outside the model's validity); ``no limit claimed``
    where no such row exists, whatever the size of the difference."""
    if "verdict" not in part or not len(part):
        return Verdict.NO_LIMIT
    found = []
    for method, against, word in zip(
        part["method"].tolist(), part["reference_label"].tolist(), part["verdict"].tolist()
    ):
        if method != "prbm":
            continue
        if against == "fem":
            found.append(parse(word))
        if word == Verdict.OUTSIDE_VALIDITY.value:
            found.append(Verdict.OUTSIDE_VALIDITY)
    return worst(found) or Verdict.NO_LIMIT


def counts_sentence(verdicts: list[Verdict]) -> str:
    """'N cases: a within the claimed limit, b no limit claimed, ...' in ``ORDER`` best first; the
    counts add up to N."""
    counts = {v: sum(1 for x in verdicts if x is v) for v in ORDER}
    parts = [f"{counts[v]} {v.value}" for v in reversed(ORDER) if counts[v]]
    return f"{len(verdicts)} case{'s' if len(verdicts) != 1 else ''}: {', '.join(parts) or 'none'}"


def vocabulary_lines() -> list[str]:
    """Each verdict with its one-line meaning, worst first."""
    return [f"{v.value}: {v.meaning}" for v in ORDER]
