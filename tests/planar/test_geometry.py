"""``planar.welded_bodies``: which rigid links move as one, from the joints and supports alone.

Each expected answer is read off the drawing of the geometry: links sharing a node are welded unless a
joint there names one of them; a link welded at a fixed support is the ground."""

import pytest

import planar
from planar import GROUND, Geometry, Joint, Node, RigidLink, Support


def _nodes(*names):
    return tuple(Node(n, float(i), 0.0) for i, n in enumerate(names))


def test_links_sharing_a_node_without_a_joint_are_one_body():
    geo = Geometry(_nodes("A", "B", "C"), links=(RigidLink("ab", ("A", "B")), RigidLink("bc", ("B", "C"))))
    bodies = planar.welded_bodies(geo)
    assert bodies.body_of_link == {"ab": "ab", "bc": "ab"}
    assert bodies.nodes_of == {"ab": ["A", "B", "C"]}
    assert bodies.owner == {"A": "ab", "B": "ab", "C": "ab"}


def test_a_joint_keeps_two_bodies_and_its_node_on_both():
    geo = Geometry(
        _nodes("A", "B", "C"),
        links=(RigidLink("ab", ("A", "B")), RigidLink("bc", ("B", "C"))),
        joints=(Joint("B", ("bc",)),),
    )
    bodies = planar.welded_bodies(geo)
    assert bodies.body_of_link == {"ab": "ab", "bc": "bc"}
    assert bodies.nodes_of == {"ab": ["A", "B"], "bc": ["B", "C"]}  # B: the pin's place on both
    assert bodies.owner["B"] == "ab"  # welded only to ab


def test_a_fixed_support_grounds_what_is_welded_to_it_and_a_pinned_one_does_not():
    geo = Geometry(
        _nodes("A", "B", "C", "D"),
        links=(RigidLink("ab", ("A", "B")), RigidLink("bc", ("B", "C")), RigidLink("cd", ("C", "D"))),
        joints=(Joint("C", ("cd",)),),
        supports=(Support("A", "fixed"), Support("D", "pinned")),
    )
    bodies = planar.welded_bodies(geo)
    assert bodies.body_of_link == {"ab": GROUND, "bc": GROUND, "cd": "cd"}
    assert bodies.nodes_of == {"cd": ["C", "D"]}
    assert bodies.links_of(GROUND) == ["ab", "bc"]
    assert bodies.owner["A"] == GROUND and bodies.owner["D"] == "cd"


def test_a_support_of_an_unknown_kind_is_refused_by_name():
    with pytest.raises(ValueError, match="support at 'A': kind 'clamped'"):
        Support("A", "clamped")
