"""The quantity contract: what each output quantity means, the same in every method.

The comparison of two methods is only worth something if ``rotation``, ``moment``, ``force_y`` ...
mean the same thing in each. This module writes each meaning down once (frame, sign, reference
state, unit) and holds the one rule every adapter uses to decide what a segment's boundary holds.
``tests/validation/test_quantity_contract.py`` checks every method against these meanings on generated
configurations (linear beam theory in the small-load limit, the exact elastica at large deflection).

The meanings:

* Frame: the case frame, global. For a segment x runs along the undeformed segment from its fixed
  end (the root at the origin), y transverse; for a mechanism the frame of its node coordinates.
* Positions ``x``, ``y``: coordinates of the point in the deformed state. ``dx``, ``dy``: the
  change from the unloaded state.
* ``rotation``: the change of the tangent angle at the point from the unloaded shape (degrees,
  counter-clockwise positive). For an initially curved segment this is *not* the absolute tip
  angle: the unloaded tangent angle kappa L is subtracted ([bapat2015, eq 53] names it kappa0).
* ``force_x``, ``force_y``, ``moment`` at a point: the total external load the point receives,
  applied load plus the reaction of whatever holds that freedom (a guide, a clamp, a prescribed
  motion). A guided tip reports its guiding moment; a prescribed displacement reports the force
  needed. Components in the case frame; moments counter-clockwise positive.
* ``reaction_x``, ``reaction_y``, ``reaction_moment``: the load a support exerts on the structure.
* ``strain_energy``: the total elastic energy stored (energy unit), zero in the unloaded state.
* Angles in degrees; every other quantity in the case's unit system (``validation.case.schema.UNIT_SYSTEMS``).

A method that cannot give a quantity's true meaning for a configuration raises ``NotApplicable``
with the reason; it never returns a placeholder (0.0, NaN, the input).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class Reference(enum.Enum):
    """The state a quantity is measured from."""

    DEFORMED = "value in the deformed state"
    UNLOADED = "change from the unloaded state"
    TOTAL_LOAD = "total external load at the point: applied plus the reaction of what holds it"
    SUPPORT = "load the support exerts on the structure"
    NONE = "not a point quantity"


@dataclass(frozen=True)
class Meaning:
    """One quantity's definition: its dimension (``case.unit`` turns it into a unit), the state it is
    measured from, its sign convention and its frame."""

    dimension: str
    reference: Reference
    sign: str
    frame: str = "case frame (global)"


CCW = "counter-clockwise positive"
MEANINGS: dict[str, Meaning] = {
    "x": Meaning("length", Reference.DEFORMED, "+x along the undeformed segment from its fixed end"),
    "y": Meaning("length", Reference.DEFORMED, "+y transverse (x rotated 90 deg counter-clockwise)"),
    "dx": Meaning("length", Reference.UNLOADED, "+x"),
    "dy": Meaning("length", Reference.UNLOADED, "+y"),
    "rotation": Meaning("deg", Reference.UNLOADED, CCW + "; change of the tangent angle"),
    "force_x": Meaning("force", Reference.TOTAL_LOAD, "+x"),
    "force_y": Meaning("force", Reference.TOTAL_LOAD, "+y"),
    "moment": Meaning("moment", Reference.TOTAL_LOAD, CCW),
    "reaction_x": Meaning("force", Reference.SUPPORT, "+x"),
    "reaction_y": Meaning("force", Reference.SUPPORT, "+y"),
    "reaction_moment": Meaning("moment", Reference.SUPPORT, CCW),
    "strain_energy": Meaning("energy", Reference.UNLOADED, "non-negative", frame="none"),
    # [bapat2015, eq 189]: MA = F_o / F_i. F_i > 0 is the input force in the sense that drives the working
    # motion (an input torque T at distance d_i counts as |T| / d_i); F_o is the force the output port
    # exerts on the work piece along the working motion (a held output rotation: its moment / d_o), so
    # MA > 0 when the output pushes the work piece the way the input drives it, and MA = MA_R (1 - F_c/F_i)
    # (eq 192) with F_c the compliance force opposing the input. The same in the PRBM and the FEM.
    "mechanical_advantage": Meaning(
        "dimensionless",
        Reference.NONE,
        "F_o / F_i, F_i > 0 in the driving sense, F_o along the working motion",
        frame="none",
    ),
}

# Tip freedoms each segment boundary holds, unless a load acts on or prescribes them
# (the dissertation's load-specified "fixed-guided" beams of Tables 3.2-3.6 give P, nP and M).
TIP_HELD: dict[str, tuple[str, ...]] = {
    "fixed-free": (),
    "fixed-pinned": (),
    "fixed-guided": ("rz",),
    "fixed-fixed": ("ux", "uy", "rz"),
    "pinned-pinned": ("ux", "uy"),
}


def load_dofs(load) -> set[str]:
    """The freedoms ('ux', 'uy', 'rz') of its point that a load acts on or prescribes."""
    if load.kind in ("distributed", "self_weight"):
        return set()  # along the beam, not at the point
    if load.toward is not None or load.follower:
        return {"ux", "uy"}  # the direction turns: both components
    if load.kind in ("moment", "rotation"):
        return {"rz"}
    d = load.direction
    if load.kind == "displacement":
        return {"ux" if abs(d[0]) > abs(d[1]) else "uy"}
    return {name for name, component in zip(("ux", "uy"), d) if component}


def boundary_held_tip(case) -> list[str]:
    """Tip freedoms the segment's boundary type holds because no load acts on or prescribes them."""
    acted = set().union(*(load_dofs(load) for load in case.loads if load.point == "tip"))
    return [dof for dof in TIP_HELD[case.segment.boundary] if dof not in acted]


def unloaded_tip_angle(length: float, curvature: float) -> float:
    """Tangent angle (rad) at the tip of the unloaded segment: kappa L (the arc starts along +x)."""
    return curvature * length
