"""The contract between the runner and each method adapter.

An adapter module ``validation/methods/<name>.py`` defines

    def run(case: Case, requests: list[Request], options: <Method>Options) -> MethodRun

``options`` is the method's validated model (``validation.case.method_options``: ``FemOptions``, ...), every
option the case does not give at the model's default; the adapter reads its fields. It translates the case into its library's own model, computes *only* the requested outputs,
and returns their values in the case's units (angles in degrees). If the method cannot model
the case it raises ``NotApplicable`` with the reason, which the results table records; if an
option of ``[methods.<name>]`` is wrong (unknown name, wrong type) it raises ``Misconfigured`` naming
the option. Every run carries a ``RunStatus``, so callers never parse the message text.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, NamedTuple


class Request(NamedTuple):
    quantity: str
    point: str
    level: int


class NotApplicable(Exception):
    """The method cannot model this case; the message says why."""


class Misconfigured(Exception):
    """An option of the method is wrong (unknown, wrongly typed, out of range); the message names it."""


class RunStatus(str, Enum):
    """How a method run ended: the one field callers read instead of parsing ``message``."""

    OK = "ok"  # every requested output computed, converged
    NOT_CONVERGED = "not converged"  # the solver ran but did not converge (at some level)
    NOT_APPLICABLE = "not applicable"  # the method refused the case (NotApplicable), with the reason
    FAILED = "failed"  # the method raised an unexpected exception (a bug or a crash)
    MISCONFIGURED = "misconfigured"  # a method option of the case is wrong: bad input
    TIMED_OUT = "timed out"  # stopped at the case's wall-time limit ([limits] seconds)


class Applicability(str, Enum):
    """Why a method's value at a level lies outside what its model was made for (a structured flag the
    results table carries in its ``applicability`` column, beside the human message)."""

    INFLECTION = "inflection expected"  # the load bends the segment through an inflection point
    LOAD_RATIO = "load ratio outside the fit"  # n outside the published fit's range (extrapolated)
    DEFLECTION = "PRB angle beyond the fit"  # the pseudo-rigid-body angle past the fit's printed range
    OUTSIDE_VALIDITY = "outside validity"  # outside the model's 5 % region of the error atlas, or unmapped


@dataclass
class MethodRun:
    values: dict[Request, float]
    converged: bool = True
    message: str = ""
    wall_time: float = 0.0
    error_estimate: dict[Request, float] = field(default_factory=dict)
    # the values whose error estimate is no bound (the FEM's meshes not in the asymptotic range), with why:
    # the estimate stays in ``error_estimate`` but no check and no summary reads it
    unreliable_estimate: dict[Request, str] = field(default_factory=dict)
    level_converged: dict[int, bool] = field(default_factory=dict)
    level_messages: dict[int, str] = field(default_factory=dict)
    # extras["shapes"]: per level, the deformed shape as a list of (n, 2) polylines (the report draws them);
    # extras["iterations"]: Newton iterations (the benchmark reads it); extras["path"]: a continuation path;
    # extras["elements"], extras["refine"]: the FEM's elements per member and its finest mesh over them.
    extras: dict[str, Any] = field(default_factory=dict)
    # per level, the model-applicability flags (empty: the model was made for this load)
    applicability: dict[int, list[Applicability]] = field(default_factory=dict)
    # per level, the tip error (% of L) the PRBM error atlas expects for this model and load (validation/atlas)
    expected_error: dict[int, float] = field(default_factory=dict)
    # None: derived from ``converged`` (OK or NOT_CONVERGED)
    status: RunStatus | None = None

    def __post_init__(self) -> None:
        if self.status is None:
            self.status = RunStatus.OK if self.converged else RunStatus.NOT_CONVERGED
        elif self.status is not RunStatus.OK:
            self.converged = False

    def flag(self, level: int, flag: Applicability) -> None:
        """Mark a level as outside what the model was made for (once per flag)."""
        flags = self.applicability.setdefault(level, [])
        if flag not in flags:
            flags.append(flag)

    def estimate_reliable(self, req: Request) -> bool | None:
        """Whether the error estimate of a value is a bound: None without an estimate, False where it is
        marked unreliable."""
        if req not in self.error_estimate:
            return None
        return req not in self.unreliable_estimate

    @property
    def ok(self) -> bool:
        return self.status is RunStatus.OK

    def summary(self) -> str:
        """'<status>: <message>' in words, without saying the status twice."""
        if self.status is None:  # ``__post_init__`` sets it: None only when reset afterwards
            raise ValueError("the run's status is not set")
        return f"{self.status.value}: {self.message.removeprefix(self.status.value + ': ')}"


class DeferredList(Sequence):
    """A list built by ``build`` when first read (len, index, iteration, truth): what only the report
    reads (a run's shapes) costs a plain run or a benchmark nothing. Pickles (the cache, a worker's
    answer) as the plain list."""

    def __init__(self, build: Callable[[], list]):
        self._items: list | Callable[[], list] = build  # the builder until first read, then the list

    def _built(self) -> list:
        if not isinstance(self._items, list):
            self._items = list(self._items())
        return self._items

    def __getitem__(self, index):
        return self._built()[index]

    def __len__(self) -> int:
        return len(self._built())

    def __reduce__(self):
        return list, (self._built(),)


def reject_loads_along_beams(case, method: str, turning: bool = False, why: str = "") -> None:
    """Raise NotApplicable for the loads a point-load method cannot take: distributed and self-weight
    loads (``why``: the reason, appended), and (unless ``turning``: the method takes them) forces toward a
    fixed point and forces turning with a named body."""
    for i, load in enumerate(case.loads):
        if load.kind in ("distributed", "self_weight"):
            raise NotApplicable(
                f"loads.{i}: {why}"
                if why
                else f"loads.{i}: {method} takes no {load.kind.replace('_', '-')} load (a load along the beam)"
            )
        if turning:
            continue
        if load.toward is not None:
            raise NotApplicable(f"loads.{i}: {method} takes no force toward a fixed point")
        if load.kind == "force" and load.body is not None:
            raise NotApplicable(f"loads.{i}: {method} takes no force turning with body '{load.body}'")
