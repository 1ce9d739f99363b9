"""Geometrically nonlinear 2-D corotational beam FEM: the reference yardstick.

Build a `Model` (plain data), call `solve` (or `solve_load`, `solve_displacement`,
`solve_arclength` with their options objects, or `solve_with_error_estimate`) and read the
`FemResult`.  Consistent units throughout.  The mathematics is stated in each module's docstring
(Crisfield 1991; Battini 2002): `corotational` (element) and `kernel` (the element loop and the
load-control corrector, compiled: one module, so numba's cache cannot go stale across files),
`local_matrices` (local stiffness by scikit-fem quadrature), `discretise` (mesh, DOF numbering in
reverse Cuthill-McKee order, constraints), `assembly` (reduced residual and tangent),
`linear_solver`, `free_motion` (a model that can move without deforming is refused before any Newton
correction), `newton` (corrector, rotation continuity), `options` (typed options and state), `solver` (load / displacement /
arc-length control), `stability`, `critical`, `error_estimate` (Richardson, with a test of the asymptotic range), `warm_start`,
`conditioning` (a mesh too fine for double precision is stopped, with why, at its first failed step), `result`, `soft_modes`, `tip_inverse` (the end loads that hold a prescribed tip pose, with a tied
load found by an outer secant solve).

Angles are in radians (degrees only in case files and reports). Example (the exact tip of the
cantilever at P L^2/EI = 10 is (0.445, 0.810609)):

>>> import numpy as np, fem
>>> m = fem.Model()
>>> m.add_node("root", 0.0, 0.0), m.add_node("tip", 1.0, 0.0)
(0, 1)
>>> m.add_member("root", "tip", fem.Section.from_EI(EA=1e9, EI=1.0), n_elements=8)
0
>>> m.add_support("root", "fixed")
>>> m.add_force("tip", 0.0, np.arange(1.0, 11.0))      # P L^2/EI = 1..10, one per level
>>> est = fem.solve_with_error_estimate(m, tol=1e-6)
>>> xy, err = est.position("tip", level=-1)             # extrapolated value, error estimate
>>> round(float(xy[1]), 5), bool(err[1] < 1e-6)
(0.81061, True)
"""

from .error_estimate import AsymptoticCheck, ErrorEstimate, solve_with_error_estimate
from .free_motion import FreeMotion
from .model import Model
from .result import FemResult
from .section import Section
from .options import ArcLengthControl, DisplacementControl, LoadControl, SolveOptions
from .solver import solve, solve_arclength, solve_displacement, solve_load
from .tip_inverse import LoadRatio, Position, TipInverseResult, ZeroMoment, solve_tip_inverse

__all__ = [
    "Model",
    "Section",
    "solve",
    "solve_load",
    "solve_displacement",
    "solve_arclength",
    "SolveOptions",
    "LoadControl",
    "DisplacementControl",
    "ArcLengthControl",
    "FreeMotion",
    "solve_with_error_estimate",
    "FemResult",
    "ErrorEstimate",
    "AsymptoticCheck",
    "solve_tip_inverse",
    "LoadRatio",
    "ZeroMoment",
    "Position",
    "TipInverseResult",
]
