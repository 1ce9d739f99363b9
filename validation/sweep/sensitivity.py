"""Which outputs of a sweep depend on the swept parameters, per method.

A crank-driven PRBM four-bar's positions do not depend on the modulus or the thickness; an applied
load does not depend on anything. A plot of their spread would show zero and look like a result.
``invariance`` finds them: for each case, method, quantity, point and load level with at least two
distinct parameter points, the spread max - min of the value over the points, and whether it is zero
to rounding (``spread <= RTOL * max(|value|)``, or exactly zero). ``summary_lines`` says it in words
for the sweep's summary and plots.
"""

from __future__ import annotations

import pandas as pd

RTOL = 1e-12  # relative spread below which an output is taken as not depending on the parameters


def invariance(frame: pd.DataFrame, parameters: list[str]) -> pd.DataFrame:
    """(case, method, quantity, point, varies, largest spread, points) from a sweep's result rows."""
    ok = frame[(frame["status"] == "ok") & frame["quantity"].notna()]
    columns = ["case", "method", "quantity", "point", "varies", "spread", "points"]
    if ok.empty or not parameters:
        return pd.DataFrame(columns=columns)
    keys = ["case", "method", "quantity", "point", "level"]
    grouped = ok.groupby(keys, dropna=False)
    per_level = pd.DataFrame(
        {
            "spread": grouped["value"].max() - grouped["value"].min(),
            "size": grouped["value"].apply(lambda v: v.abs().max()),
            "points": grouped["point_id"].nunique() if "point_id" in ok else grouped["value"].size(),
        }
    ).reset_index()
    per_level = per_level[per_level["points"] >= 2]
    per_level["varies"] = per_level["spread"] > RTOL * per_level["size"]
    table = (
        per_level.groupby(keys[:-1], dropna=False)
        .agg(varies=("varies", "any"), spread=("spread", "max"), points=("points", "max"))
        .reset_index()
    )
    return table[columns]


def summary_lines(table: pd.DataFrame, parameters: list[str]) -> list[str]:
    """'<case> <method>: dx@P, dy@P do not depend on E_factor, thickness (zero spread by construction)'."""
    lines = []
    constant = table[~table["varies"].astype(bool)]
    for (case, method), part in constant.groupby(["case", "method"]):
        names = ", ".join(
            f"{q}@{p}" if isinstance(p, str) and p else q for q, p in zip(part["quantity"], part["point"])
        )
        verb = "does" if len(part) == 1 else "do"
        lines.append(
            f"{case} {method}: {names} {verb} not depend on any swept parameter "
            f"({', '.join(parameters)}): zero spread by construction, not a result"
        )
    return lines
