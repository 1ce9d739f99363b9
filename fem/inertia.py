"""What the stability checks count as a zero eigenvalue of a tangent, and up to which size they use a
dense eigensolver (`stability`; the compiled corrector's inertia test, `assembly.System.inertia_tol`).

An eigenvalue of a symmetric matrix K computed in double precision is known to within a few
n eps ||K|| (n unknowns, eps the machine epsilon): below ``zero_eigenvalue(scale, n)`` = 10 n eps
``scale`` (``scale`` the largest diagonal of K, 1 for the Jacobi-scaled tangent) it cannot be told
from zero.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np

__all__ = ["EPS", "DENSE_LIMIT", "zero_eigenvalue"]

EPS = float(np.finfo(float).eps)  # machine epsilon (np.finfo is slow to ask)
DENSE_LIMIT = 600  # dense eigh below this many unknowns, shift-invert Lanczos above


def zero_eigenvalue(scale: float, n: int) -> float:
    """The size below which an eigenvalue of a tangent with largest diagonal ``scale`` and ``n``
    unknowns cannot be told from zero: rounding of a symmetric eigensolver, 10 n eps ||K||.

    Not a fixed fraction of the largest diagonal (such as 1e-12): a slender beam's axial terms exceed
    its bending terms by (L/h)^2, so at L/h = 7e4 a genuinely negative bending eigenvalue would pass
    as zero."""
    return 10.0 * n * EPS * scale
