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


def _rows(case, points, measured, finding_level=None):
    rows = []
    for level, ((x, y), (mx, my)) in enumerate(zip(points, measured)):
        for q, v, m in (("x", x, mx), ("y", y, my)):
            rows.append(dict(case=case, method="fem", quantity=q, point="tip", level=level, value=v,
                             reference_label="measured", reference_value=m,
                             finding="mis-copied" if level == finding_level else None))
    return rows


def test_rms_distance_per_reading_and_the_closest():
    measured = [(10.0, 0.0), (9.0, 3.0), (8.0, 4.0), (7.0, 5.0)]
    base = [(10.0, 0.0), (9.0, 3.3), (8.4, 4.3), (7.0, 5.0)]          # distances 0.3, 0.5, 0
    other = [(10.0, 0.0), (9.1, 3.0), (8.0, 4.1), (9.9, 9.9)]         # 0.1, 0.1, last row flagged
    table = pd.DataFrame(_rows("base", base, measured) + _rows("other", other, measured, finding_level=3))
    groups = readings_groups([_result("base"), _result("other", "base")], table)
    assert len(groups) == 1 and groups[0].experiment == "base"
    t = groups[0].table.set_index("case")
    assert t.loc["base", "rms"] == pytest.approx(math.sqrt((0.09 + 0.25 + 0.0) / 3))
    assert t.loc["other", "rms"] == pytest.approx(0.1) and t.loc["other", "levels"] == 2
    assert t.loc["base", "max"] == pytest.approx(0.5)
    assert groups[0].closest() == "other"
