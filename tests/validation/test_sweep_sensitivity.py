"""A sweep says which outputs do not depend on the swept parameters, instead of a zero spread."""

from __future__ import annotations

import numpy as np
import pandas as pd

from validation.sweep.sensitivity import invariance, summary_lines


def rows(method: str, quantity: str, values) -> list[dict]:
    return [
        dict(point_id=f"p{i}", case="c", method=method, quantity=quantity, point="P", level=1, value=v, status="ok")
        for i, v in enumerate(values)
    ]


def test_constant_outputs_are_named_and_varying_ones_are_not():
    E = np.linspace(0.95, 1.05, 5)
    frame = pd.DataFrame(
        rows("prbm", "dx", [0.4125] * 5)  # crank-driven: fixed by geometry
        + rows("fem", "dx", 0.4125 / E)  # compliant: moves with E
        + rows("fem", "input_torque", [9.75] * 5)  # the applied load
        + rows("prbm", "input_torque", 38.356 * E * 0.25)  # a spring from E: varies
        + rows("fem", "dy", 2.5 + 1e-15 * np.arange(5))
    )  # rounding only: constant
    table = invariance(frame, ["E_factor"]).set_index(["method", "quantity"])
    assert not table.loc[("prbm", "dx"), "varies"] and table.loc[("fem", "dx"), "varies"]
    assert not table.loc[("fem", "input_torque"), "varies"] and table.loc[("prbm", "input_torque"), "varies"]
    assert not table.loc[("fem", "dy"), "varies"]
    lines = summary_lines(invariance(frame, ["E_factor"]), ["E_factor"])
    assert lines == [
        "c fem: dy@P, input_torque@P do not depend on any swept parameter (E_factor): zero "
        "spread by construction, not a result",
        "c prbm: dx@P does not depend on any swept parameter (E_factor): zero spread by construction, not a result",
    ]
