"""Type aliases of the FEM library, for annotations: float64, int64, int32 and bool arrays of any shape
(the shape and the unit are stated where an array enters); the loads of one state (`Loads`), an
evaluation of the residual and tangent (`Evaluation`, the dict `assembly.System.evaluate` returns) and a
factorisation's det K sign (`SignedFactor`), a converged result as a warm start reads it (`Recorded`).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

__all__ = ["FloatArray", "IntArray", "Int32Array", "BoolArray", "Loads", "Evaluation", "SignedFactor", "Recorded"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Int32Array = NDArray[np.int32]
BoolArray = NDArray[np.bool_]

# (F_fixed (nf,), F0 (n_conf, 2), prescribed values (n_p,)): `assembly.System.loads_at`
Loads = tuple[FloatArray, FloatArray, FloatArray]

# "u", "C", "el", "f_int", "f_ref_full", "R_full", "r", "f_ref", "F_scale" and "K": `assembly.System.evaluate`
Evaluation = dict[str, Any]


class SignedFactor(Protocol):
    """The sign of det K of a factorisation (`linear_solver.Factor`); ``final``: the factorisation is of
    a converged state itself."""

    @property
    def det_sign(self) -> int: ...

    @property
    def final(self) -> bool: ...


class Recorded(Protocol):
    """A converged result as a warm start reads it (`result.FemResult`): its ``extra`` record, with the
    discretisation "disc" and the full displacements "u_full" (levels, full DOFs) of every level."""

    @property
    def extra(self) -> dict[str, Any]: ...
