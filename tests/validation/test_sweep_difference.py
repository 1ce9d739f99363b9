"""The 'difference' sweep plot's numbers: the largest |a - b| / |b| of the first method against the
second, per case, quantity and swept value (planted values, so a wrong denominator, a missing
absolute value or a maximum taken over the wrong axis fails)."""

from __future__ import annotations

import pandas as pd
import pytest

from validation.sweep.plot import difference


def _rows():
    rows = []
    for length, fem, prbm in ((0.25, [10.0, -20.0], [10.5, -21.0]), (1.0, [10.0, -20.0], [9.0, -20.2])):
        for level in range(2):
            for method, value in (("fem", fem[level]), ("prbm", prbm[level])):
                rows.append(
                    dict(
                        case="c",
                        quantity="input_torque",
                        point="",
                        level=level,
                        method=method,
                        value=value,
                        status="ok",
                        l=length,
                    )
                )
    rows.append(
        dict(case="c", quantity="input_torque", point="", level=0, method="prbm", value=1e9, status="failed", l=0.25)
    )
    return pd.DataFrame(rows)


def test_difference_is_the_largest_relative_gap_per_swept_value():
    table = difference(_rows(), "l", ["prbm", "fem"]).set_index("l")["relative_difference"]
    assert table[0.25] == pytest.approx(0.05)  # max(0.5/10, 1/20)
    assert table[1.0] == pytest.approx(0.1)  # max(1/10, 0.2/20)


def test_difference_needs_both_methods():
    assert difference(_rows(), "l", ["prbm"]).empty
