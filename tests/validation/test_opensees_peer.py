"""The OpenSees peer's mechanisms with rigid links and revolute joints (`validation.methods.opensees`).

The element model is checked without OpenSees (which member ends a joint releases, the links'
hubs); with OpenSeesPy installed (the ``peer`` extra), the peer's
positions are checked against our FEM's on the same mesh: two independent corotational codes, one
with exact rigid links and extra rotation DOFs at the hinges, the other with stiff elements and
released element ends, must land on the same equilibrium.
"""

from __future__ import annotations

import math

import pytest

from validation.case.loader import case_by_id
from validation.case.schema import Case
from validation.methods.base import NotApplicable
from validation.methods.opensees import _geometry
from validation.case.scale import characteristic_length
from validation.run.runner import run_method

RELEASED_AT_I, RELEASED_AT_J = 1, 2


def _elements_between(coords, elems, a, b):
    """The release codes of the elements joining the nodes at a and b (either direction)."""
    index = {tuple(round(v, 9) for v in xy): k for k, xy in enumerate(coords)}
    i, j = index[a], index[b]
    return [
        (code if (e0, e1) == (i, j) else {1: 2, 2: 1}.get(code, code))
        for e0, e1, _, _, code in elems
        if {e0, e1} == {i, j}
    ]


def test_test2_hinges_release_the_coupler_at_A_and_link4_at_B():
    """Test 2 (one beam, a rigid coupler A-B-P, a rigid link O4-B, hinges at A and B, a couple on the
    beam's end at A): the couple's body keeps the node's rotation at A, so the coupler is released
    there; at B the first named member (the coupler) keeps it and link 4 is released. The coupler's
    hub is B (where it is not released), link 4's is O4."""
    case = case_by_id("bapat2015_test2").case
    coords, names, elems, supports = _geometry(case, 4)
    xy = {n.name: (round(n.x, 9), round(n.y, 9)) for n in case.mechanism.nodes}
    assert _elements_between(coords, elems, xy["B"], xy["A"]) == [RELEASED_AT_J]
    assert _elements_between(coords, elems, xy["B"], xy["P"]) == [0]
    assert _elements_between(coords, elems, xy["O4"], xy["B"]) == [RELEASED_AT_J]
    beam = [code for i, j, EA, EI, code in elems if EI < 1e3]  # the Delrin segment's elements
    assert beam == [0, 0, 0, 0]
    assert supports == {names["C"]: "fixed", names["O4"]: "pinned"}
    stiff = [EI for *_, EI, code in elems if EI > 1e3]
    assert len(stiff) == 3 and min(stiff) == pytest.approx(1e6 * max(EI for *_, EI, _ in elems if EI < 1e3))


def _mechanism_case(links, joints, loads, supports=None):
    data = {
        "case": {"id": "peer_links", "title": "a made-up linked mechanism", "group": "tests", "units": "dimensionless"},
        "mechanism": {
            "E": 1.0,
            "nodes": [
                {"name": n, "x": x, "y": y}
                for n, x, y in (("G", 0.0, 0.0), ("A", 1.0, 0.0), ("B", 1.5, 0.5), ("C", 2.0, 0.0))
            ],
            "beams": [{"name": "beam", "start": "G", "end": "A", "section": {"kind": "inertia", "I": 1.0, "A": 1e4}}],
            "links": links,
            "joints": joints,
            "supports": supports or [{"node": "G", "kind": "fixed"}, {"node": "C", "kind": "pinned"}],
        },
        "loads": loads,
        "outputs": [{"quantity": "dy", "point": "B"}],
        "methods": {"opensees": {}},
    }
    return Case.model_validate(data)


HELD = [{"node": n, "kind": "fixed"} for n in ("G", "A", "B", "C")]


def test_a_link_released_at_every_node_gets_a_hub_at_their_centroid():
    """A three-node link hinged at all three nodes (at A to the beam, which keeps A's rotation; at B and
    C, whose supports hold the rotation) keeps its shape through an extra hub node at the centroid, its
    three elements released at the link's nodes only."""
    case = _mechanism_case(
        [{"name": "tri", "nodes": ["A", "B", "C"]}],
        [
            {"node": "A", "members": ["beam", "tri"]},
            {"node": "B", "members": ["tri"]},
            {"node": "C", "members": ["tri"]},
        ],
        [{"kind": "force", "point": "A", "direction": [0.0, 1.0], "values": [1e-3]}],
        supports=[HELD[0], HELD[2], HELD[3]],
    )
    coords, names, elems, supports = _geometry(case, 2)
    centre = (1.5, round(0.5 / 3, 9))
    for node in ("A", "B", "C"):
        assert _elements_between(coords, elems, centre, coords[names[node]]) == [RELEASED_AT_J]
    assert len(coords) == 4 + 1 + 1  # the beam's midpoint, the hub


def test_a_joint_keeps_the_couples_body_on_the_node_and_refuses_a_couple_on_a_released_end():
    """Unanchored, a joint releases every named member but the body a couple at the node acts on; a
    node held by a fixed support releases every named member, and a couple on one of them is refused;
    sprung joints, and joints naming a member that does not reach their node, are refused."""
    links = [{"name": "bar", "nodes": ["A", "C"]}]
    joints = [{"node": "A", "members": ["beam", "bar"]}]
    couple = [{"kind": "moment", "point": "A", "body": "bar", "values": [1e-3]}]
    coords, names, elems, _ = _geometry(_mechanism_case(links, joints, couple), 2)
    assert _elements_between(coords, elems, coords[names["A"]], coords[names["C"]]) == [0]  # bar keeps A
    assert [code for i, j, *_, code in elems if names["A"] in (i, j) and names["C"] not in (i, j)] == [RELEASED_AT_J]
    with pytest.raises(NotApplicable, match="released end of 'bar'"):
        _geometry(_mechanism_case(links, joints, couple, supports=[HELD[0], HELD[1], HELD[3]]), 2)
    force = [{"kind": "force", "point": "B", "direction": [0.0, 1.0], "values": [1e-3]}]
    with pytest.raises(NotApplicable, match="names 'bar', which does not reach that node"):
        _geometry(_mechanism_case(links, [{"node": "B", "members": ["bar"]}], force), 2)
    with pytest.raises(NotApplicable, match="sprung joint"):
        _geometry(_mechanism_case(links, [{"node": "A", "members": ["beam", "bar"], "spring": 2.0}], force), 2)


@pytest.mark.parametrize("case_id, limit", [("bapat2015_test2", 1e-7), ("seed004_parallel_guided", 1e-6)])
def test_the_peer_lands_on_the_fem_equilibrium_of_a_linked_mechanism(case_id, limit):
    """Test 2 (hinges, a rigid coupler, a pinned link) and the parallel-guided mechanism (a rigid
    coupler on two beams): OpenSees with stiff links and released element ends against our FEM with
    exact rigid links and hinge DOFs, 8 elements a beam, every position at every level within
    ``limit`` of the characteristic length (the links' compliance, 1e-6 of the beams', is the
    difference); a hinge left unreleased moves the coupler point by a tenth of the length."""
    pytest.importorskip("openseespy.opensees")
    case = case_by_id(case_id).case
    case = case.model_copy(update={"outputs": [o for o in case.outputs if o.quantity in ("x", "y", "dx", "dy")]})
    fem = run_method(case.model_copy(update={"methods": {"fem": {"elements": 8, "error_estimate": False}}}), "fem")
    peer = run_method(case.model_copy(update={"methods": {"opensees": {"elements": 8}}}), "opensees")
    positions = [r for r in fem.values if r.quantity in ("x", "y", "dx", "dy")]
    assert fem.converged and peer.converged and positions
    scale = characteristic_length(case)
    worst = max(abs(fem.values[r] - peer.values[r]) for r in positions) / scale
    assert worst < limit
    assert max(abs(fem.values[r]) for r in positions) / scale > 0.05 and math.isfinite(worst)


def test_curved_beams_are_cut_into_equal_chords_on_their_arc():
    """The arch's two curved beams (curvature 1/R, counter-clockwise from start to end): the peer's nodes
    of each are n equal chords of the arc, 2 R sin(theta / 2n) each with theta = 2 asin(c / 2R) the angle
    the chord c subtends, turning counter-clockwise (the sign of the curvature) from chord to chord."""
    case = case_by_id("arch_215_clamped_hinged").case
    n = 6
    coords, names, elems, _ = _geometry(case, n)
    interior = len(case.mechanism.nodes)  # the nodes the peer adds along the beams are numbered after these
    for beam in case.mechanism.beams:
        chain = [names[beam.start]]
        while len(chain) < n:  # walk the beam's elements through its interior nodes
            chain.append(next(j for i, j, *_ in elems if i == chain[-1] and j >= interior and j not in chain))
        chain.append(names[beam.end])
        points = [coords[k] for k in chain]
        assert len(points) == n + 1
        R = 1.0 / beam.curvature
        c = math.dist(points[0], points[-1])
        theta = 2 * math.asin(c / (2 * abs(R)))
        chords = [math.dist(p, q) for p, q in zip(points, points[1:])]
        assert chords == pytest.approx([2 * abs(R) * math.sin(theta / (2 * n))] * n, rel=1e-12)
        turns = [
            (q[0] - p[0]) * (s[1] - q[1]) - (q[1] - p[1]) * (s[0] - q[0])
            for p, q, s in zip(points, points[1:], points[2:])
        ]
        assert all(math.copysign(1.0, t) == math.copysign(1.0, beam.curvature) for t in turns)
