"""Beam constraint model [chen2021]: strain and complementary energies, both energy theorems, examples.

Loads and deflections are normalised (forces by EI/L^2, moments by EI/L, lengths by L); angles in
radians.

>>> import bcm
>>> ux, uy, theta = bcm.deflections_from_loads(0.0, 1e-6, 0.0, 1e7)
>>> round(float(uy / 1e-6), 6), round(float(theta / 1e-6), 6)   # linear cantilever: f/3 and f/2
(0.333333, 0.5)
"""

from bcm.beam import (
    C0,
    C1,
    C2,
    C3,
    K0,
    K1,
    K2,
    axial_stiffness_parameter,
    bcm_residual,
    complementary_energy,
    deflections_from_complementary,
    deflections_from_loads,
    exact_compliance,
    loads_from_deflections,
    quadratic_forms,
    solve_mixed,
    strain_energy,
)
from bcm.mechanisms import (
    BCMBeam,
    RigidBodyOnBeams,
    circular_guided_torque,
    circular_guided_torque_eq20,
    eq32_corrected,
    eq32_printed,
    slant_parallelogram,
)

__all__ = [
    "C0",
    "C1",
    "C2",
    "C3",
    "K0",
    "K1",
    "K2",
    "axial_stiffness_parameter",
    "bcm_residual",
    "complementary_energy",
    "deflections_from_complementary",
    "deflections_from_loads",
    "exact_compliance",
    "loads_from_deflections",
    "quadratic_forms",
    "solve_mixed",
    "strain_energy",
    "BCMBeam",
    "RigidBodyOnBeams",
    "circular_guided_torque",
    "circular_guided_torque_eq20",
    "eq32_corrected",
    "eq32_printed",
    "slant_parallelogram",
]
