"""Typed options and state of a solve: what `solver` passes between its steps.

`SolveOptions` holds what every control mode shares (Newton tolerances, step control, stability
watch); `LoadControl`, `DisplacementControl` and `ArcLengthControl` hold what only their mode reads.
`NewtonOutcome` is what one corrector run returns, `StepState` a converged step on its way to being
accepted (possibly replaced by a stable state on another branch, `BranchSwitch`), `CriticalPoint` a
limit point or bifurcation found along the path.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import numpy as np

from typing import TYPE_CHECKING

from .types import Evaluation, FloatArray, Recorded, SignedFactor

if TYPE_CHECKING:
    from .model import NodeRef

__all__ = [
    "SolveOptions",
    "LoadControl",
    "DisplacementControl",
    "ArcLengthControl",
    "NewtonOutcome",
    "StepState",
    "SwitchStatus",
    "BranchSwitch",
    "CriticalPoint",
]


@dataclass(frozen=True)
class SolveOptions:
    """Shared by the three control modes. Tolerance |r| <= rtol max(|f_ext|, |f_int|) + atol."""

    rtol: float = 1e-10
    atol: float = 0.0
    maxiter: int = 20
    initial_step: float = 1.0  # of a level (load control) or of the path to a target
    min_step: float = 1e-7
    max_rotation_increment: float = np.pi  # rad, per accepted step at any node
    max_iteration_rotation: float = 1.0  # rad, per Newton correction (load control)
    detect_critical: bool = True
    check_stability: bool = True
    predictor: str = "secant"
    target_iterations: int = 5  # arc-length: Delta l adapts towards this
    solver: str = "auto"  # 'auto', 'dense', 'banded' or 'sparse'
    refine: int = 1

    @property
    def watch_det(self) -> bool:
        """The sign of det K is needed at every accepted step."""
        return self.detect_critical or self.check_stability


@dataclass(frozen=True)
class LoadControl:
    """Loads and prescribed values follow their per-level histories; ``n_levels`` applies single-valued
    loads in that many equal levels; ``initial_guess``: a converged result with half the elements;
    ``held``: the model is known to have no free motion (a coarser mesh of this same model passed the
    free-motion test, `free_motion`: refining adds only interior beam nodes, each joined by two
    elements), so the test is not made again."""

    n_levels: int | None = None
    initial_guess: Recorded | None = None
    held: bool = False


@dataclass(frozen=True)
class DisplacementControl:
    """``control_dof`` = (node, 'ux' | 'uy' | 'rz') follows ``targets``; the load factor is free."""

    control_dof: tuple[NodeRef, str]
    targets: tuple[float, ...]


@dataclass(frozen=True)
class ArcLengthControl:
    """Cylindrical arc length from the unloaded state until ``until`` = (node, dof, value) is crossed,
    |lambda| >= ``lambda_max``, ``max_limit_points`` limit points were passed, or ``max_steps``."""

    arc_length: float | None = None
    max_arc_length: float | None = None
    max_steps: int = 2000
    until: tuple[NodeRef, str, float] | None = None
    lambda_max: float | None = None
    direction: float = 1.0
    max_limit_points: int | None = None

    @property
    def has_stop(self) -> bool:
        return self.until is not None or self.lambda_max is not None or self.max_limit_points is not None


@dataclass
class NewtonOutcome:
    """A converged corrector: state, load factor, evaluation there, residual history, iterations and
    the last factorisation of the tangent (one iteration before the converged state; None when the
    start already converged)."""

    q: FloatArray
    lam: float
    ev: Evaluation
    history: list[float]
    iterations: int
    factor: SignedFactor | None
    accept: tuple[bool, float] | None = None  # (an element jumped, largest rotation increment): `newton.accept_check`


@dataclass
class StepState:
    """A converged step before it is accepted: the Newton outcome, the chord angles it started from,
    the sign of det K there, and whether it was moved to another branch."""

    q: FloatArray
    lam: float
    ev: Evaluation
    factor: SignedFactor | None
    history: list[float]
    iterations: int
    beta: FloatArray
    sign: int = 0
    switched: bool = False

    @classmethod
    def of(cls, out: NewtonOutcome, beta: FloatArray, sign: int) -> StepState:
        return cls(out.q, out.lam, out.ev, out.factor, out.history, out.iterations, beta, sign)


class SwitchStatus(enum.Enum):
    STABLE = "stable"  # the eigenvalues put the state within rounding of stable after all
    SWITCHED = "switched"  # a stable state on another branch was found
    FAILED = "failed"  # none was found


@dataclass
class BranchSwitch:
    """Outcome of `stability.switch_branch`: with SWITCHED, the stable state (``outcome``, its Newton
    iterations summed over the search) and a note saying how it was chosen; with FAILED, the reason."""

    status: SwitchStatus
    lowest_eigenvalue: float = float("nan")
    outcome: NewtonOutcome | None = None
    note: str = ""
    reason: str = ""


@dataclass(frozen=True)
class CriticalPoint:
    """A limit point (an extremum of the load factor, ``detail`` 'maximum' or 'minimum') or a
    bifurcation (det K changes sign without one; ``branch_switch`` says how the path left it)."""

    kind: str
    detail: str
    step: int
    load_factor: float
    path_parameter: float
    branch_switch: str | None = None
