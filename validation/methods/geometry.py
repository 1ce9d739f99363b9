"""A case's ``[mechanism]`` as the libraries' plain geometry (``planar.Geometry``), built in one place.

Every beam carries its bending stiffness EI and axial stiffness EA from its section and material (an
'inertia' section without an area A: EA None, inextensible), and its initial curvature.
"""

from __future__ import annotations

import planar


def geometry(mech) -> planar.Geometry:
    """The plain geometry of a schema ``MechanismSpec``."""
    beams = []
    for beam in mech.beams:
        EA, EI = beam.section.stiffness(beam.E or mech.E)
        inextensible = beam.section.kind == "inertia" and beam.section.A is None
        beams.append(planar.Beam(beam.name, beam.start, beam.end, EI, beam.curvature, None if inextensible else EA))
    return planar.Geometry(
        nodes=tuple(planar.Node(n.name, n.x, n.y) for n in mech.nodes),
        beams=tuple(beams),
        links=tuple(planar.RigidLink(link.name, tuple(link.nodes)) for link in mech.links),
        joints=tuple(planar.Joint(j.node, tuple(j.members), j.spring) for j in mech.joints),
        supports=tuple(
            planar.Support(s.node, planar.SupportKind(s.kind), tuple(s.direction) if s.direction else None, s.member)
            for s in mech.supports
        ),
    )
