"""Readings of one experiment side by side (validation.case.readings): distances to the measured points."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pandas as pd
import pytest

from validation.case.readings import readings_groups


def _result(case_id, readings_of=None):
    info = SimpleNamespace(title=case_id, readings_of=readings_of)
    return SimpleNamespace(loaded=SimpleNamespace(id=case_id, case=SimpleNamespace(case=info)))


def _rows(case, points, measured, finding_level=None, method="fem"):
    rows = []
    for level, ((x, y), (mx, my)) in enumerate(zip(points, measured)):
        for q, v, m in (("x", x, mx), ("y", y, my)):
            rows.append(
                dict(
                    case=case,
                    method=method,
                    quantity=q,
                    point="tip",
                    level=level,
                    value=v,
                    reference_label="measured",
                    reference_value=m,
                    finding="mis-copied" if level == finding_level else None,
                )
            )
    return rows


def test_rms_distance_per_reading_and_the_closest():
    measured = [(10.0, 0.0), (9.0, 3.0), (8.0, 4.0), (7.0, 5.0)]
    base = [(10.0, 0.0), (9.0, 3.3), (8.4, 4.3), (7.0, 5.0)]  # distances 0.3, 0.5, 0
    other = [(10.0, 0.0), (9.1, 3.0), (8.0, 4.1), (9.9, 9.9)]  # 0.1, 0.1, last row flagged
    table = pd.DataFrame(_rows("base", base, measured) + _rows("other", other, measured, finding_level=3))
    groups = readings_groups([_result("base"), _result("other", "base")], table)
    assert len(groups) == 1 and groups[0].experiment == "base"
    t = groups[0].table.set_index("case")
    assert t.loc["base", "rms"] == pytest.approx(math.sqrt((0.09 + 0.25 + 0.0) / 3))
    assert t.loc["other", "rms"] == pytest.approx(0.1) and t.loc["other", "levels"] == 2
    assert t.loc["base", "max"] == pytest.approx(0.5)
    assert groups[0].closest("fem") == "other"
    assert groups[0].closest("prbm") is None


def test_the_closest_reading_is_marked_per_method():
    """Each method's own closest reading carries the mark: here the PRBM is closest under 'base' (rms 0.2)
    and the FEM under 'other' (rms 0.1); a mark taken over all rows would go to the FEM's 'other' alone
    and leave the PRBM's best reading unmarked (the defect of issue 25's closing note)."""
    measured = [(10.0, 0.0), (9.0, 3.0), (8.0, 4.0)]
    rows = (
        _rows("base", [(10.0, 0.0), (9.0, 3.3), (8.0, 4.3)], measured, method="fem")  # 0.3, 0.3
        + _rows("other", [(10.0, 0.0), (9.1, 3.0), (8.0, 4.1)], measured, method="fem")  # 0.1, 0.1
        + _rows("base", [(10.0, 0.0), (9.2, 3.0), (8.0, 4.2)], measured, method="prbm")  # 0.2, 0.2
        + _rows("other", [(10.0, 0.0), (9.0, 3.5), (8.5, 4.0)], measured, method="prbm")
    )  # 0.5, 0.5
    groups = readings_groups([_result("base"), _result("other", "base")], pd.DataFrame(rows))
    t = groups[0].table.set_index(["case", "method"])
    assert t.loc[("base", "prbm"), "rms"] == pytest.approx(0.2) and t.loc[("other", "fem"), "rms"] == pytest.approx(0.1)
    marked = sorted(groups[0].table.loc[groups[0].table["closest"], ["method", "case"]].itertuples(index=False))
    assert marked == [("fem", "other"), ("prbm", "base")]
    assert groups[0].closest("fem") == "other" and groups[0].closest("prbm") == "base"
