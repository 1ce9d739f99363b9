"""The base of every input model of the harness (case files, method options, sweep specs, design
specifications): unknown fields are errors, so a typo is never silently ignored; and the number
types they share.

Start-up (issue 15 item 4): ``defer_build`` leaves each model's validator unbuilt until its first use,
so ``prbm-validate solve`` of one case builds only the models that case reaches (the case schema and
the options of its own methods), not every option, sweep and specification model of the harness."""
from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class Strict(BaseModel):
    """Base: unknown fields are errors (a typo must not be silently ignored); validators built at first use."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)
