"""The plain description of a planar compliant mechanism, in one vocabulary for every library.

A leaf package, like ``argcheck``: it imports nothing of the project, and ``prbm``, ``fem``,
``elastica`` and ``bcm`` may all import it while never importing each other. It holds data and one
geometric rule (the direction of a pull toward a fixed point, ``pull_direction``), no solver.

The words, each meaning one thing everywhere:

- **node**: a named point of the unloaded geometry (x, y).
- **beam**: a flexible member between two nodes (bending stiffness EI, axial EA, initial curvature).
- **rigid link**: a rigid member through two or more nodes (``RigidLink``).
- **joint**: a revolute hinge at a node between the members it names (``Joint``), with an optional
  torsion spring; a member not named is welded there.
- **support**: how a node is held by the ground: fixed, pinned, slider or guided (``Support``).
- **body**: what moves as one: rigid links welded together (``welded_bodies``), or the ground.
- **pin**: a revolute pair between two bodies at a point (``Pin``), what a joint becomes once the
  bodies are known.
- **point**: where a load acts, named by a node (or a point a library adds, such as a pivot).
- **force**, **pointed force** (toward a fixed point), **distributed load** (along a beam), **couple**,
  **prescribed displacement**, **prescribed rotation**: the loads (``Force``, ``PointedForce``,
  ``DistributedLoad``, ``Couple``, ``PrescribedDisplacement``, ``PrescribedRotation``), one value per level.
"""

from planar.geometry import (
    GROUND,
    Beam,
    Geometry,
    Joint,
    Node,
    RigidLink,
    Support,
    SupportKind,
    WeldedBodies,
    welded_bodies,
)
from planar.loads import (
    Couple,
    DistributedLoad,
    Force,
    Load,
    Pin,
    PointedForce,
    PrescribedDisplacement,
    PrescribedRotation,
    pull_direction,
)

__all__ = [
    "GROUND",
    "Node",
    "Beam",
    "RigidLink",
    "Joint",
    "Support",
    "SupportKind",
    "Geometry",
    "WeldedBodies",
    "welded_bodies",
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
