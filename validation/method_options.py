"""The options each method accepts in ``[methods.<name>]``, checked before any solve.

A misspelled option name or a wrongly typed value is bad input (exit status 2), reported with the
nearest valid names, instead of a crash inside the solver or an option silently ignored. Methods
whose options are not described here (the PRBM's, which depend on the problem it solves) are
checked by their adapter, which raises ``Misconfigured``.
"""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from validation.names import nearest

PositiveFloat = Annotated[float, Field(gt=0, allow_inf_nan=False)]
PositiveInt = Annotated[int, Field(ge=1)]
PerLevel = Annotated[float, Field(allow_inf_nan=False)] | list[Annotated[float, Field(allow_inf_nan=False)]]


class Options(BaseModel):
    """Base: unknown options are errors; values are not coerced (``"16"`` is not an integer)."""

    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class FemOptions(Options):
    elements: PositiveInt = 16
    error_estimate: bool = True
    richardson: bool = False
    tol: PositiveFloat | None = None
    rtol: PositiveFloat = 1e-10
    levels: PositiveInt = 2
    limit_control: Literal["arclength", "displacement"] = "arclength"
    control_step: PositiveFloat | None = None
    max_steps: PositiveInt | None = None
    arc_length: PositiveFloat | None = None
    inextensible_ratio: PositiveFloat = 1e6
    rigid_ratio: PositiveFloat = 1e6


class ElasticaOptions(Options):
    I: PositiveFloat | None = None
    EI: PositiveFloat | None = None
    rtol: PositiveFloat | None = None
    tol: PositiveFloat | None = None
    samples: PositiveInt = 41
    problem: Literal["inflection"] | None = None
    b: PerLevel | None = None
    theta0: PerLevel | None = None
    l1: PerLevel | None = None


class BcmOptions(Options):
    I: PositiveFloat | None = None
    EI: PositiveFloat | None = None


class OpenSeesOptions(Options):
    elements: PositiveInt = 16
    control_step: PositiveFloat | None = None
    max_steps: PositiveInt = 2000
    steps_per_level: PositiveInt = 10


MODELS: dict[str, type[Options]] = {"fem": FemOptions, "elastica": ElasticaOptions, "bcm": BcmOptions,
                                    "opensees": OpenSeesOptions}


def check(methods: dict[str, dict | None]) -> list[tuple[str, str]]:
    """(field, problem) of every wrong option in a case's ``[methods]`` table, e.g.
    ``("methods.fem.elemnts", "unknown option; nearest: elements")``."""
    problems = []
    for method, options in methods.items():
        model = MODELS.get(method)
        if model is None:
            continue
        try:
            model.model_validate(options or {})
        except ValidationError as exc:
            for err in exc.errors():
                name = ".".join(str(p) for p in err["loc"][:1])
                field = f"methods.{method}.{name}"
                if err["type"] == "extra_forbidden":
                    problems.append((field, f"unknown option of method '{method}'"
                                            f"{nearest(name, model.model_fields)}"))
                else:
                    problems.append((field, f"{err['msg']} (got {err['input']!r})"))
    return problems
