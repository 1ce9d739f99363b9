"""Readings of one experiment side by side: how far each case's computed points land from the measured ones.

An experiment whose loading the source leaves open is written as one case per plausible reading; each
reading names the base case in ``[case] readings_of``. For every case of the group and every method,
the distance |r_computed - r_measured| at a point is taken per load level over the position pairs
the references give (x with y, dx with dy; label ``measured``), levels whose reference carries a
finding (a mis-copied row) and the first level when every reading matches it exactly (the unloaded
state) left out; the group's table lists the rms and the largest distance, and marks, for each method,
the reading closest to the measurements (smallest rms among that method's rows): the question a reading
answers is "which loading makes this model match the experiment", so a PRBM row never takes the mark
from the FEM's closest reading nor the other way round.

Beside the rms (in the case's length unit) the table gives it in % of the characteristic length L
(``rms_pct_L``) and, where the method estimates its own error (the FEM's Richardson estimate e per
coordinate), how far the computed rms can be from the exact one (``rms_estimate``): a computed point
within e_l = sqrt(e_a^2 + e_b^2) of the exact one moves its distance by at most e_l (triangle
inequality), so the rms moves by at most sqrt(mean_l e_l^2) (Minkowski); empty where a value has no
estimate or its estimate is marked unreliable (no bound).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

PAIRS = (("x", "y"), ("dx", "dy"))


@dataclass
class ReadingsGroup:
    experiment: str  # the base case id
    table: pd.DataFrame  # case, title, method, levels, unit, rms, rms_pct_L, rms_estimate, max,
    # closest (per method)

    def closest(self, method: str) -> str | None:
        """The reading whose ``method`` rows lie closest to the measurements (None: no such rows)."""
        best = self.table[self.table["closest"] & (self.table["method"] == method)]
        return None if best.empty else str(best["case"].iloc[0])


def _estimates(rows: pd.DataFrame) -> pd.Series:
    """Each row's error estimate, NaN where there is none or it is marked unreliable (no bound)."""
    if "error_estimate" not in rows:
        return pd.Series(np.nan, index=rows.index)
    estimate = rows["error_estimate"].astype(float)
    if "error_estimate_reliable" in rows:
        estimate = estimate.where(rows["error_estimate_reliable"].map(lambda r: r is not False))
    return estimate


def _distances(rows: pd.DataFrame) -> pd.DataFrame:
    """Per (case, method, point, level): the distance over the position pair the rows hold, its error
    bound from the method's estimate (NaN: none) and the case's length scale L and unit."""
    measured = rows[
        (rows["reference_label"] == "measured")
        & rows["finding"].isna()
        & rows["value"].notna()
        & rows["reference_value"].notna()
    ]
    columns = ["case", "method", "point", "level", "distance", "estimate", "L", "unit"]
    frames = []
    for a, b in PAIRS:
        pair = measured[measured["quantity"].isin((a, b))]
        if pair.empty:
            continue
        pair = pair.assign(
            sq=(pair["value"] - pair["reference_value"]) ** 2,
            esq=_estimates(pair) ** 2,
            L=pair["scale"] if "scale" in pair else np.nan,
            unit=pair["unit"] if "unit" in pair else "",
        )
        grouped = pair.groupby(["case", "method", "point", "level"])
        both = grouped["quantity"].nunique() == 2
        estimated = grouped["esq"].count() == 2
        frame = pd.DataFrame(
            {
                "distance": np.sqrt(grouped["sq"].sum()),
                "estimate": np.sqrt(grouped["esq"].sum()).where(estimated),
                "L": grouped["L"].first(),
                "unit": grouped["unit"].first(),
            }
        )
        frames.append(frame[both].reset_index())
    return pd.concat(frames) if frames else pd.DataFrame(columns=columns)


def readings_groups(results, table: pd.DataFrame) -> list[ReadingsGroup]:
    """One group per base case that other cases name in ``readings_of``."""
    members: dict[str, list] = {}
    cases = {r.loaded.id: r.loaded.case for r in results}
    for case_id, case in cases.items():
        base = case.case.readings_of
        if base is not None and base in cases:
            members.setdefault(base, [base]).append(case_id)
    groups = []
    for base, ids in sorted(members.items()):
        dist = _distances(table[table["case"].isin(ids)])
        if dist.empty:
            continue
        first = dist["level"].min()  # the unloaded state, when every
        if dist.loc[dist["level"] == first, "distance"].max() <= 1e-9:  # reading matches it exactly
            dist = dist[dist["level"] != first]
        by_run = dist.groupby(["case", "method"])
        summary = (
            by_run["distance"]
            .agg(levels="count", rms=lambda d: float(np.sqrt(np.mean(np.square(d)))), max="max")
            .reset_index()
        )
        summary.insert(1, "title", [cases[c].case.title for c in summary["case"]])
        summary.insert(4, "unit", by_run["unit"].first().to_numpy())
        summary.insert(6, "rms_pct_L", 100 * summary["rms"] / by_run["L"].first().astype(float).to_numpy())
        summary.insert(
            7,
            "rms_estimate",
            by_run["estimate"]
            .agg(  # NaN if any level has no bound
                lambda e: float(np.sqrt(np.mean(np.square(e)))) if e.notna().all() else np.nan
            )
            .to_numpy(),
        )
        summary["closest"] = summary["rms"] == summary.groupby("method")["rms"].transform("min")
        groups.append(ReadingsGroup(base, summary.sort_values("rms").reset_index(drop=True)))
    return groups
