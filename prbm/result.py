"""The result object every PRBM solve returns (modelled on scipy.optimize.OptimizeResult).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, TypeAlias

import numpy as np
from numpy.typing import NDArray

#: one output over the load levels: an array of the levels' shape, or one number for a single level
#: given as scalars (``np.float64`` or ``float``)
Levels: TypeAlias = NDArray[np.float64] | float


@dataclass
class PRBMResult:
    """Outcome of one PRBM solve over one or more load levels.

    converged: True when every level converged (``level_converged`` has the detail).
    message: why not, or a summary.
    outputs: name -> array over load levels (e.g. 'a', 'b', 'theta0' in radians, 'Theta', 'P', 'M').
    constants: the model constants used (gamma, K_theta, c_theta, k, ...), arrays over levels when
        they depend on the load.
    model: the model's name and the source equations it implements (cited by key, ``references``).
    wall_time: seconds spent in the solve.
    roots: for problems with several valid solutions, a list (one entry per level) of lists of
        dicts, one per root found; the first root is the one reported in ``outputs``.
    """

    converged: bool
    message: str
    outputs: dict[str, Levels]
    constants: dict[str, Any]
    model: str
    wall_time: float = 0.0
    nit: int = 0
    level_converged: NDArray[np.bool_] | None = None
    roots: list[list[dict[str, float | str]]] | None = None
    extras: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, name: str) -> Levels:
        return self.outputs[name]

    # the result protocol every library's solve result shares: converged, status, message,
    # iterations, wall_time
    @property
    def status(self) -> str:
        return "ok" if self.converged else "not converged"

    @property
    def iterations(self) -> int:
        return self.nit
