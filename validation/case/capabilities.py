"""What each method can compute, known without importing any solver.

The schema uses this to reject a case that asks a method for an output it cannot give,
before anything runs. Quantities carry their physical dimension, which the unit system of
the case turns into a unit string.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Quantity:
    dimension: str  # 'length', 'deg', 'force', 'moment', 'energy', '1', 'count'
    at_point: bool  # True when the quantity belongs to a named point
    description: str
    per_level: bool = True  # False: one number of the whole case (a count of the model, a limit load),
    #                         not a value that follows the load levels (the report draws no curve of it)


QUANTITIES: dict[str, Quantity] = {
    "x": Quantity("length", True, "x coordinate of the point (the seeds' 'a' for a segment tip)"),
    "y": Quantity("length", True, "y coordinate of the point (the seeds' 'b' for a segment tip)"),
    "dx": Quantity("length", True, "x displacement of the point from the unloaded state"),
    "dy": Quantity("length", True, "y displacement of the point from the unloaded state"),
    "rotation": Quantity("deg", True, "rotation of the point (the seeds' theta_0 at a tip), degrees"),
    "force_x": Quantity("force", True, "x force applied at the point (solved for when positions are prescribed)"),
    "force_y": Quantity("force", True, "y force applied at the point"),
    "moment": Quantity("moment", True, "moment applied at the point"),
    "reaction_x": Quantity("force", True, "x reaction at a support"),
    "reaction_y": Quantity("force", True, "y reaction at a support"),
    "reaction_moment": Quantity("moment", True, "moment reaction at a support"),
    "input_angle": Quantity("deg", False, "input link angle of a mechanism"),
    "input_torque": Quantity("moment", False, "input torque of a mechanism"),
    "strain_energy": Quantity("energy", False, "total strain energy"),
    "mechanical_advantage": Quantity("1", False, "output force over input force"),
    "dof": Quantity("count", False, "maximum degrees of freedom", per_level=False),
    "prb_angle": Quantity("deg", False, "pseudo-rigid-body angle Theta"),
    "limit_load": Quantity("force", False, "load at the first limit point", per_level=False),
    "max_stress": Quantity("modulus", False, "largest bending stress |E (N/EA +- M c/EI)| over every beam"),
    "inflection_points": Quantity("count", False, "number of curvature sign changes along the beams"),
}

_POSITIONS = {"x", "y", "dx", "dy", "rotation"}
_LOADS = {"force_x", "force_y", "moment"}
_REACTIONS = {"reaction_x", "reaction_y", "reaction_moment"}

METHODS: dict[str, frozenset[str]] = {
    "fem": frozenset(
        _POSITIONS
        | _LOADS
        | _REACTIONS
        | {
            "strain_energy",
            "input_angle",
            "input_torque",
            "limit_load",
            "max_stress",
            "inflection_points",
            "mechanical_advantage",
            "dof",
        }
    ),
    "prbm": frozenset(
        _POSITIONS
        | _LOADS
        | _REACTIONS
        | {"strain_energy", "input_angle", "input_torque", "mechanical_advantage", "dof", "prb_angle"}
    ),
    "elastica": frozenset(_POSITIONS | _LOADS | _REACTIONS | {"strain_energy"}),
    "bcm": frozenset(_POSITIONS | _LOADS | {"strain_energy"}),
    # peer, for benchmarks and cross-checks (the 'peer' extra)
    "opensees": frozenset(_POSITIONS | {"limit_load"}),
}


def method_quantities(method: str) -> frozenset[str]:
    """Quantities a method can give; a ValueError names the method if it is unknown."""
    try:
        return METHODS[method]
    except KeyError:
        raise ValueError(f"unknown method '{method}'; known: {', '.join(METHODS)}") from None
