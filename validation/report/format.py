"""How the report writes numbers and run states: at most four significant digits, percentages, a
colour scale on the PRBM error, and one status badge per method run or case.

``run_badge`` is the one place that turns a ``MethodRun`` into a badge.  It reads the run's
``status`` enum where the run has one and otherwise infers the state from the adapter's message
(a refusal starts ``not applicable:``, a crash ``error:``).
"""
from __future__ import annotations

import enum
import html
import math

import numpy as np
import pandas as pd

# PRBM error colour scale, in % of the characteristic length: green at or below LOW, red at HIGH and
# above, logarithmic in between (0.5 % is the target for the PRBM's end-point error, [bapat2015, §2.3]).
ERROR_SCALE_LOW, ERROR_SCALE_HIGH = 0.5, 10.0


class Badge(enum.Enum):
    """The state of a method run or a case, as the report shows it."""
    AGREES = "agrees"
    FINDING = "finding"
    REFUSED = "refused"
    EXPECTED = "expected failure"
    FAILED = "failed"

    @property
    def colour(self) -> str:
        return {"agrees": "#2e7d32", "finding": "#b26a00", "refused": "#5f6b7a", "expected failure": "#4a6fa5",
                "failed": "#c62828"}[self.value]

    def html(self, reason: str = "") -> str:
        title = f" title='{html.escape(reason, quote=True)}'" if reason else ""
        return (f"<span class='badge' style='background:{self.colour}'{title}>{self.value}</span>")


def run_badge(run, expected: str | None = None) -> tuple[Badge, str]:
    """(badge, reason) of one method run: refused (the method cannot model the case), failed
    (crashed or did not converge), or agrees; a refusal or failure the case records as its expected
    outcome (``case.expected_failure``, passed as ``expected``) is an expected failure, with the reason."""
    badge, reason = _run_badge(run)
    if expected and badge in (Badge.REFUSED, Badge.FAILED):
        return Badge.EXPECTED, f"expected: {expected} ({reason})" if reason else f"expected: {expected}"
    return badge, reason


def _run_badge(run) -> tuple[Badge, str]:
    status = getattr(run, "status", None)
    name = str(getattr(status, "name", status or "")).lower()
    if name:
        if "refus" in name or "applicable" in name:
            return Badge.REFUSED, run.message.removeprefix("not applicable: ")
        if name not in ("ok", "converged", "agrees", "success"):
            return Badge.FAILED, run.message
        return Badge.AGREES, ""
    if run.extras.get("not_applicable") or run.message.startswith("not applicable"):
        return Badge.REFUSED, run.message.removeprefix("not applicable: ")
    if run.message.startswith("error:") or not run.converged:
        return Badge.FAILED, run.message
    return Badge.AGREES, ""


def sig(value, digits: int = 4) -> str:
    """A number with at most ``digits`` significant digits ('' for a missing value)."""
    if value is None or isinstance(value, str):
        return value or ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(int(value)) if abs(int(value)) < 10 ** digits else f"{float(value):.{digits}g}"
    value = float(value)
    if math.isnan(value):
        return ""
    return f"{value:.{digits}g}"


def percent(fraction, digits: int = 3) -> str:
    """A fraction as a percentage, e.g. 0.01777 -> '1.78 %'."""
    if fraction is None or (isinstance(fraction, float) and math.isnan(fraction)):
        return ""
    return f"{100 * float(fraction):.{digits}g} %"


def seconds(value) -> str:
    """A wall time in s or ms."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    return f"{1000 * value:.3g} ms" if value < 1 else f"{value:.3g} s"


def error_colour(percent_of_length: float) -> str:
    """Background colour of a PRBM error (in % of L) on the green-to-red scale."""
    if percent_of_length is None or math.isnan(percent_of_length):
        return ""
    low, high = math.log10(ERROR_SCALE_LOW), math.log10(ERROR_SCALE_HIGH)
    t = (math.log10(max(percent_of_length, 1e-12)) - low) / (high - low)
    t = min(max(t, 0.0), 1.0)
    # green (120 deg) through yellow to red (0 deg), light enough to read black text on
    return f"hsl({120 * (1 - t):.0f},70%,80%)"


def by_case(table: pd.DataFrame) -> dict[str, pd.DataFrame]:
    """Each case's rows of the whole table (its row order and index kept, as ``table[table["case"] ==
    id]`` gives them) in one pass, not one scan of the whole table per case."""
    return {str(case): part for case, part in table.groupby("case", sort=False)}


def rows_of(parts: dict[str, pd.DataFrame], table: pd.DataFrame, case: str) -> pd.DataFrame:
    """The rows of ``case`` from ``by_case`` (none: the table's empty slice)."""
    return parts[case] if case in parts else table.iloc[0:0]
