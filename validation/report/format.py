"""How the report writes numbers, verdicts and sources: at most four significant digits, percentages,
a colour scale on the PRBM error, a verdict (``validation.run.verdict``) on its colour, and a source
document cited by its key (``references``), not by the number of the file it is kept in.
"""

from __future__ import annotations

import html
import math
import re

import numpy as np
import pandas as pd

from references import REFERENCES, citation
from validation.run.verdict import Verdict

# PRBM error colour scale, in % of the characteristic length: green at or below LOW, red at HIGH and
# above, logarithmic in between (0.5 % is the target for the PRBM's end-point error, [bapat2015, §2.3]).
ERROR_SCALE_LOW, ERROR_SCALE_HIGH = 0.5, 10.0


VERDICT_COLOURS = {
    Verdict.WITHIN: "#2e7d32",
    Verdict.FINDING: "#b26a00",
    Verdict.NO_LIMIT: "#6d6d6d",
    Verdict.OUTSIDE_VALIDITY: "#8d6e00",
    Verdict.EXPECTED: "#4a6fa5",
    Verdict.OUTSIDE_LIMIT: "#c62828",
    Verdict.REFUSED: "#5f6b7a",
    Verdict.NOT_CONVERGED: "#c62828",
    Verdict.FAILED: "#c62828",
}


def verdict_html(verdict: Verdict, reason: str = "") -> str:
    """A verdict as the report shows it: its words on its colour, the reason (else its meaning) on hover."""
    title = html.escape(reason or verdict.meaning, quote=True)
    return (
        f"<span class='badge' style='background:{VERDICT_COLOURS[verdict]}' title='{title}'>"
        f"{html.escape(verdict.value)}</span>"
    )


def sig(value, digits: int = 4) -> str:
    """A number with at most ``digits`` significant digits ('' for a missing value)."""
    if value is None or isinstance(value, str):
        return value or ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(int(value)) if abs(int(value)) < 10**digits else f"{float(value):.{digits}g}"
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


# a source document named by its seed file as the case files' texts name it: 'seed', a space and the
# file's three digits, with or without the rest of the file name ('_0cc4...txt'), 'Seed' at a sentence's
# start; a case id has no space after 'seed' and is left alone
SEED_NAME = re.compile(r"\b[Ss]eed (\d{3})(?:_[0-9a-f]{16}(?:\.txt)?)?\b")
SEED_KEYS = {ref.seed_file.split("_")[0]: ref.key for ref in REFERENCES.values()}


def cite_keys(text: str) -> str:
    """``text`` with each source document named by its key instead of its seed file ('seed', a space
    and the seed file's three digits): an equation place after it, 'eqs 131-152', then reads '[bapat2015]
    eqs 131-152' (the place is the document's own numbering)."""
    return SEED_NAME.sub(lambda m: f"[{SEED_KEYS[m.group(1)]}]" if m.group(1) in SEED_KEYS else m.group(0), text)


def document_title(key: str) -> str:
    """The title of the document cited as ``key`` (the quoted part of its citation), e.g. 'Pseudo
    rigid-body (PRB) modeling' for ``ananthasuresh_l18``; the whole citation when it quotes none."""
    text = citation(key)
    quoted = re.search(r'"([^"]+)"', text)
    return quoted.group(1) if quoted else text
