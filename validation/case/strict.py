"""The base of every input model of the harness (case files, method options, sweep specs, design
specifications): unknown fields are errors, so a typo is never silently ignored; and the number
types they share.

Every number those models read is finite and of magnitude at most ``HUGE`` (1e100); a magnitude
(``Positive``, ``NonNegative``, ``Fraction``: a modulus, a length, a thickness, a stiffness, a tolerance,
an input force) is moreover 0 or at least ``TINY`` (1e-100). A case multiplies up to three of its numbers
together (E w t^3, P L^2 / EI, w L^3) and squares lengths; inside that band such products stay inside
double precision (1e-308 .. 1e308) in every unit system, where 1e300 overflows to infinity in the first
product and a magnitude of 1e-300 underflows to zero and reaches a solver as a division by zero. A signed
value (a coordinate, a load, a direction's component) may be as small as it likes: it only ever scales
something, and a tiny one is a zero. No physical quantity of a compliant mechanism, in SI, mm-N, in-lb
or dimensionless units, comes within 40 decades of either end. Ranges that depend on the problem's own
scale (a non-dimensional load, a slenderness) are checked on the whole case (``validation.case.scale``).

``defer_build`` leaves each model's validator unbuilt until its first use, so ``prbm-validate solve`` of
one case builds only the models that case reaches (the case schema and the options of its own methods),
not every option, sweep and specification model of the harness."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field

TINY, HUGE = 1e-100, 1e100


def representable(value: float) -> float:
    """``value`` when it is 0 or TINY <= |value| <= HUGE (a magnitude: module docstring); ValueError otherwise."""
    if value != 0.0 and not TINY <= abs(value) <= HUGE:
        raise ValueError(
            f"{value:g} is outside the representable range: give 0 or a magnitude between "
            f"{TINY:g} and {HUGE:g} (products of such numbers overflow or underflow)"
        )
    return value


def bounded(value: float) -> float:
    """``value`` when |value| <= HUGE (a signed value: module docstring); ValueError otherwise."""
    if abs(value) > HUGE:
        raise ValueError(
            f"{value:g} is outside the representable range: give a magnitude of at most {HUGE:g} "
            "(products of such numbers overflow)"
        )
    return value


REPRESENTABLE = AfterValidator(representable)
Finite = Annotated[float, Field(allow_inf_nan=False), AfterValidator(bounded)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False), REPRESENTABLE]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False), REPRESENTABLE]
Fraction = Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False), REPRESENTABLE]
# counts of work (elements, steps, modes): whole numbers (16.0 is 16), bounded whatever the limits say
Count = Annotated[int, Field(ge=1, le=1_000_000)]
# level and load indices: integers as written (0.0 is refused: the adapters index arrays with the file's value)
Index = Annotated[int, Field(ge=0, le=1_000_000, strict=True)]


def field_path(location: tuple) -> str:
    """Dotted field path of a pydantic error location, without validator and union-member tags
    (``function-after[...]``, ``list[...]``, ``float``)."""

    def is_tag(part) -> bool:
        return isinstance(part, str) and (
            part.startswith("function-") or "[" in part or part in ("str", "int", "float", "bool")
        )

    return ".".join(str(p) for p in location if not is_tag(p))


class Strict(BaseModel):
    """Base: unknown fields are errors (a typo must not be silently ignored); validators built at first use."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)
