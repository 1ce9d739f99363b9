"""The loads on a planar mechanism and the pins between its bodies: one value per load level.

Angles are in radians and counter-clockwise; a rotation or displacement is a change from the unloaded
pose. Units are the caller's, consistent (force, length, force x length).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "Pin",
    "Force",
    "PointedForce",
    "DistributedLoad",
    "Couple",
    "PrescribedDisplacement",
    "PrescribedRotation",
    "Load",
    "pull_direction",
]


@dataclass(frozen=True)
class Pin:
    """A revolute pair between bodies ``a`` and ``b`` (``b`` may be the ground) at ``at``, its position in
    the unloaded pose; ``name`` says what it is (the node it sits at, or the pivot it models)."""

    a: str
    b: str
    at: tuple[float, float]
    name: str = ""


@dataclass(frozen=True)
class Force:
    """A force (fx, fy) per level at a named point; ``follower``: it turns with the body (or beam end)
    that carries the point, from its direction in the unloaded pose."""

    point: str
    fx: tuple[float, ...]
    fy: tuple[float, ...]
    follower: bool = False


@dataclass(frozen=True)
class PointedForce:
    """A force of magnitude ``values`` per level at a named point, along the current line from the point
    toward the fixed point ``toward``, turned by ``angle`` (rad, CCW) from that line: a rope over a pulley
    (angle 0), or a force kept at a fixed angle to the line joining a fixed pivot (angle pi/2). Its
    direction follows the point as it moves."""

    point: str
    values: tuple[float, ...]
    toward: tuple[float, float]
    angle: float = 0.0


@dataclass(frozen=True)
class DistributedLoad:
    """A uniform dead load (wx, wy) per unit reference length along a named beam, per level (self-weight:
    the weight per length, along gravity)."""

    beam: str
    wx: tuple[float, ...]
    wy: tuple[float, ...]


def pull_direction(toward: tuple[float, float], angle: float, at: tuple[float, float]) -> tuple[float, float]:
    """The unit direction of a force at ``at`` pulling toward the fixed point ``toward``, turned by ``angle``
    (rad, CCW) from that line: R(angle) (toward - at)/|toward - at|. A ValueError where the two coincide."""
    dx, dy = toward[0] - at[0], toward[1] - at[1]
    length = math.hypot(dx, dy)
    if length == 0.0:
        raise ValueError(f"a force pulls toward {toward}, where its point now is")
    c, s = math.cos(angle), math.sin(angle)
    return (c * dx - s * dy) / length, (s * dx + c * dy) / length


@dataclass(frozen=True)
class Couple:
    """A couple (CCW) per level on a body."""

    body: str
    m: tuple[float, ...]


@dataclass(frozen=True)
class PrescribedDisplacement:
    """The displacement per level of a named point along ``axis`` ('x' or 'y') from the unloaded pose."""

    point: str
    axis: str
    values: tuple[float, ...]


@dataclass(frozen=True)
class PrescribedRotation:
    """The rotation per level (rad, CCW, from the unloaded pose) of a body."""

    body: str
    values: tuple[float, ...]


#: any one of the loads
Load = Force | PointedForce | DistributedLoad | Couple | PrescribedDisplacement | PrescribedRotation
