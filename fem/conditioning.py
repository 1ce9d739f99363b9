"""Whether double precision can resolve the Newton corrections of a model at all.

A correction dq = -K^-1 r computed by a backward-stable LU factorisation in floating point (unit
roundoff u = 2^-53) has a relative error of up to about kappa(K) u (Higham 2002, ch. 7 and 9). The
corrector then converges only linearly, at a rate that grows with kappa u; near kappa u = 1 a correction
has no correct digit. (The residual test cannot stand in: its rounding floor, the element forces of a
position error eps |x|, grows with the element stiffness too, so the corrector's test is then the size of
the correction, `newton`.)

The measure is the tangent of the unloaded state K0 (material stiffness only; symmetric positive
definite for every model that passed `free_motion`), Jacobi-scaled,

    S = D K0 D,   D = diag(|K0_ii|^(-1/2)),

so that neither the units of translations and rotations nor the stiffness scale of each DOF counts
(van der Sluis 1969: within a factor n of the best diagonal scaling). rcond_1(S) = 1/(||S||_1 ||S^-1||_1)
is estimated from S's LU factors with a few solves (Hager's method as refined by Higham, the
iteration of LAPACK's ``dlacn2``: `linear_solver.inverse_norm1`, O(n) for a band). As ||S^-1||_1 is
never overestimated, rcond is never underestimated: no refusal comes from the estimate's error. The
model is stopped (`solver._beyond_precision`: at a run's first failed Newton attempt or its 16th
step) when rcond < u: S is singular to working precision, the test
of LAPACK's expert drivers (xGESVX, xPOSVX: INFO = N + 1).

A fine mesh reaches it: the translations of an element carry its bending stiffness 12 EI/L0^3, while
the softest bending mode of a member of length L is of order EI/L^3, so the scaled condition number of a
beam grows as (L/L0)^4 (a cantilever of n equal elements: kappa_1(S) about 10 n^4, the limit 1/u
near n = 5500). The refusal says how many times coarser the mesh must be: (u / rcond)^(1/4).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np

from typing import TYPE_CHECKING

from .linear_solver import SingularMatrix

from .types import FloatArray

if TYPE_CHECKING:
    from .assembly import System

__all__ = ["UNIT_ROUNDOFF", "scaled_rcond", "beyond_precision"]

UNIT_ROUNDOFF = 0.5 * float(np.finfo(float).eps)  # u = 2^-53, LAPACK's DLAMCH('Epsilon')


def scaled_rcond(system: System) -> float:
    """rcond_1 of the Jacobi-scaled unloaded tangent S = D K0 D (estimated from its LU factors); NaN
    when S has an exactly zero pivot (a free motion, `free_motion`'s to name)."""
    F_fixed, F0, presc = system.loads_at(-1, 0, 0.0)
    K0: FloatArray = system.evaluate(
        np.zeros(system.n), system.disc.beta0.copy(), 0.0, F_fixed, F0, presc, need_K=True
    )["K"]
    layout = system.layout
    diag = np.abs(layout.diagonal(K0))
    D = np.ones(system.n)
    np.divide(1.0, np.sqrt(diag), out=D, where=diag > 0.0)
    S = layout.scaled(K0, D)
    try:
        return layout.factor(S).rcond(layout.norm1(S))
    except SingularMatrix:
        return float("nan")


def beyond_precision(system: System) -> str | None:
    """Why the model's Newton corrections cannot be resolved in double precision (its Jacobi-scaled
    unloaded tangent is singular to working precision), or None."""
    if system.n == 0:
        return None
    rc = scaled_rcond(system)
    if not rc < UNIT_ROUNDOFF:
        return None
    coarser = (UNIT_ROUNDOFF / rc) ** 0.25 if rc > 0.0 else float("inf")
    return (
        f"stopped: the unloaded tangent (Jacobi-scaled) is singular to working "
        f"precision, its reciprocal condition number {rc:.2e} below the unit roundoff {UNIT_ROUNDOFF:.2e}: "
        "a Newton correction would have no correct digit, and the load steps would converge, if at "
        "all, only linearly and in ever shorter steps. A beam's condition number grows as the fourth "
        f"power of its elements per member: use at least {coarser:.2g} times fewer elements"
    )
