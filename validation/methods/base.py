"""The contract between the runner and each method adapter.

An adapter module ``validation/methods/<name>.py`` defines

    def run(case: Case, requests: list[Request], options: dict) -> MethodRun

It translates the case into its library's own model, computes *only* the requested outputs,
and returns their values in the case's units (angles in degrees). If the method cannot model
the case it raises ``NotApplicable`` with the reason, which the results table records.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple


class Request(NamedTuple):
    quantity: str
    point: str
    level: int


class NotApplicable(Exception):
    """The method cannot model this case; the message says why."""


@dataclass
class MethodRun:
    values: dict[Request, float]
    converged: bool = True
    message: str = ""
    wall_time: float = 0.0
    error_estimate: dict[Request, float] = field(default_factory=dict)
    level_converged: dict[int, bool] = field(default_factory=dict)
    level_messages: dict[int, str] = field(default_factory=dict)
    # extras["shapes"]: per level, the deformed shape as a list of (n, 2) polylines (the report draws them);
    # extras["iterations"]: Newton iterations (the benchmark reads it); extras["path"]: a continuation path.
    extras: dict[str, Any] = field(default_factory=dict)


def reject_loads_along_beams(case, method: str) -> None:
    """Raise NotApplicable for the loads a point-load method cannot take: distributed and self-weight
    loads, forces toward a fixed point, forces turning with a named body."""
    for i, load in enumerate(case.loads):
        if load.kind in ("distributed", "self_weight"):
            raise NotApplicable(f"loads.{i}: {method} takes no {load.kind.replace('_', '-')} load "
                                "(a load along the beam)")
        if load.toward is not None:
            raise NotApplicable(f"loads.{i}: {method} takes no force toward a fixed point")
        if load.kind == "force" and load.body is not None:
            raise NotApplicable(f"loads.{i}: {method} takes no force turning with body '{load.body}'")
