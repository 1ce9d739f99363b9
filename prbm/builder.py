"""The PRB model of a compliant mechanism built from its geometry by the rules of [bapat2015] and
[ananthasuresh_l18].

Input: plain geometry (nodes, beams with their bending stiffness EI, rigid links, joints,
supports), the same description the FEM reads. Output: a ``prbm.network.Network`` of rigid bodies,
pins and torsion springs, and for every beam the model chosen, its pivots, spring constants and why.

How each end of a beam is held decides its model:
  clamped  - to the ground (a fixed support), to a rigid link, or to other beams welded at the node
  pinned   - a joint at the node releases the beam, or a pinned support holds it
  free     - nothing else at the node
Rules (gamma = 0.85, K_Theta = 2.65 by default; [bapat2015, ch. 2, eqs 41-49], [ananthasuresh_l18]; a
straight one-pivot beam whose end load ratio n is known (``BeamRule.load_ratio``: a free end loaded by dead forces
of one direction) takes gamma(n), K_Theta(n) of the Pauly-Midha fits (eqs 41, 43) instead, stated in its
record):
  clamped-free, clamped-pinned: one pivot (1 - gamma) L from the clamp, characteristic radius gamma L,
      K = gamma K_Theta EI / L (fixed-pinned / fixed-free PRBM). Initially curved: the pivot
      (1 - gamma) L along the clamp tangent, characteristic radius rho L to the end,
      K = rho K_Theta EI / L [bapat2015, eqs 53-58].
  clamped-clamped: two pivots (1 - gamma) L / 2 from each end, a middle link gamma L, each spring
      2 gamma K_Theta EI / L (the fixed-guided PRBM of [ananthasuresh_l18, 07:13-12:05]; for a body that
      also rotates, [ananthasuresh_l18, 28:08] says to keep 0.85 and check against the FEM).
  clamped-clamped and short (L <= slfp_ratio x the shorter of the two bodies it joins): a
      small-length flexural pivot at its middle, K = EI / L [bapat2015, eq 186].
  pinned-pinned (or pinned-free): a rigid link along the chord, no spring.
Every choice can be overridden per beam (``BeamRule``).

Lock ([chen2021, §4.1], notes seed-003-004 sec. 4.1): a beam clamped to the ground whose other end
is clamped to a body pinned to the ground at G makes, with the standard pivots, a zero-mobility
network. The lock is found from the rank of the joints' Jacobian (``Network.mobility``); the
workaround the notes derive puts the beam's single pivot at G (gamma = |G end| / L when G lies on
the beam between the clamp and the end), stated in the beam's record. If no such G exists the
build raises ``LockedNetwork`` naming the beams.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np
from numpy.typing import NDArray

from prbm.fits import PAULY_MIDHA
from planar import GROUND, Beam, Geometry, Joint, Node, RigidLink, Support, WeldedBodies, welded_bodies
from prbm.network import LockedNetwork, Network, Pin, Slider, TorsionSpring

__all__ = [
    "Node",
    "Beam",
    "RigidLink",
    "Joint",
    "Support",
    "Geometry",
    "EndKind",
    "BeamChoice",
    "BeamRule",
    "Rules",
    "BeamModel",
    "PRBModel",
    "build",
]

GAMMA = 0.85  # [ananthasuresh_l18, 02:10] (Howell and Midha's average)
K_THETA = 2.65  # [bapat2015, ch. 2]; [ananthasuresh_l18, 12:05]: "gamma K_Theta ~ 2.25"
SLFP_RATIO = 0.1  # a flexure at most a tenth of the links it joins is "short" [bapat2015, §2.4]


class EndKind(StrEnum):
    """How a beam end is held (the module docstring's rules)."""

    CLAMPED = "clamped"
    PINNED = "pinned"
    FREE = "free"


class BeamChoice(StrEnum):
    """The PRB model the builder gives a beam; the first five may be named in a ``BeamRule``."""

    FIXED_PINNED = "fixed-pinned"
    FIXED_FREE = "fixed-free"
    FIXED_GUIDED = "fixed-guided"
    SLFP = "slfp"
    RIGID = "rigid"
    PIVOT_AT_PIN = "pivot-at-pin"  # the lock workaround (module docstring)
    RIGID_ON_ONE_BODY = "rigid-both-ends-on-one-body"  # both ends clamped to one body


RULE_CHOICES = (
    BeamChoice.FIXED_PINNED,
    BeamChoice.FIXED_FREE,
    BeamChoice.FIXED_GUIDED,
    BeamChoice.SLFP,
    BeamChoice.RIGID,
)


@dataclass(frozen=True)
class BeamRule:
    """Per-beam overrides: model ('fixed-pinned', 'fixed-guided', 'slfp', 'rigid'), gamma, K_theta,
    or the spring constant(s) directly (``stiffness``, moment/rad)."""

    model: str | None = None
    gamma: float | None = None
    K_theta: float | None = None
    stiffness: float | None = None
    clamp: str | None = None  # for a one-pivot model of a clamped-clamped beam: the clamped end's node
    load_ratio: float | None = None  # n of the end force (-nP, P) in the beam frame, where the loads define it


@dataclass(frozen=True)
class Rules:
    gamma: float = GAMMA
    K_theta: float = K_THETA
    slfp_ratio: float = SLFP_RATIO
    beams: dict[str, BeamRule] = field(default_factory=dict)


@dataclass(frozen=True)
class BeamModel:
    """What the builder made of one beam."""

    beam: str
    model: str
    ends: tuple[str, str]  # how the start and end are held
    pivots: tuple[tuple[float, float], ...]
    springs: tuple[float, ...]  # moment/rad, one per pivot
    gamma: float | None
    K_theta: float | None
    reason: str

    def describe(self) -> str:
        piv = ", ".join(f"({x:.4g}, {y:.4g})" for x, y in self.pivots)
        k = ", ".join(f"{s:.4g}" for s in self.springs)
        return (
            f"{self.beam}: {self.model} ({self.ends[0]}-{self.ends[1]}); pivots {piv or 'none'}; "
            f"K {k or 'none'}; {self.reason}"
        )


@dataclass
class PRBModel:
    network: Network
    beams: list[BeamModel]
    node_body: dict[str, str]  # the body each node moves with
    member_body: dict[tuple[str, str], str]  # (member, node) -> the body that member has at that node
    lock: str | None = None  # the lock found and the workaround applied, if any
    ground_nodes: dict[str, str] = field(default_factory=dict)  # joint/spring to the ground -> its support node

    def describe(self) -> str:
        text = "; ".join(b.describe() for b in self.beams)
        return (f"LOCK: {self.lock}. " if self.lock else "") + text


# --- ends --------------------------------------------------------------------------------------------
@dataclass
class _End:
    kind: EndKind
    body: str | None


#: beam name -> (the clamped end's node, the ground pin G its pivot moves to): the lock workaround
_PivotAt = dict[str, tuple[str, tuple[float, float]]]


def _held(end: _End, beam: Beam) -> str:
    """The body holding a beam end that the beam's model joins to a body (a clamped end always has one)."""
    if end.body is None:
        raise ValueError(f"beam '{beam.name}': its model needs a body at a {end.kind} end that has none")
    return end.body


def build(geometry: Geometry, rules: Rules | None = None) -> PRBModel:
    """The PRB network of a mechanism, with the record of every beam's model (``rules``: the default
    ``Rules()`` made at the call, so it reads the fit constants as they are then). Raises ValueError on an
    inconsistent geometry and LockedNetwork when the PRB model cannot move and no workaround applies."""
    rules = Rules() if rules is None else rules
    model = _build(geometry, rules, pivot_at={})
    if model.network.mobility() > 0 or not geometry.beams:
        return model
    # locked: look for beams clamped to the ground whose far body turns about a ground pin on the beam
    pivot_at: _PivotAt = {}
    notes: list[str] = []
    ground_pins = _ground_pins(geometry, model)
    for bm in model.beams:
        beam = next(b for b in geometry.beams if b.name == bm.beam)
        if bm.ends[0] != EndKind.CLAMPED or bm.ends[1] != EndKind.CLAMPED or beam.curvature != 0.0:
            continue
        coords = {nd.name: np.array([nd.x, nd.y]) for nd in geometry.nodes}
        for root, tip in ((beam.start, beam.end), (beam.end, beam.start)):
            if model.member_body.get((beam.name, root)) != GROUND:
                continue
            far = model.member_body.get((beam.name, tip))
            for G in ground_pins.get(far, []) if far is not None else []:
                O, A = coords[root], coords[tip]
                L = float(np.linalg.norm(A - O))
                s = float(np.dot(G - O, A - O)) / L
                u, w = A - O, G - O
                off = abs(float(u[0] * w[1] - u[1] * w[0])) / L
                if off <= 1e-9 * L and 0.0 < s < L:
                    pivot_at[beam.name] = (root, tuple(G))
                    notes.append(
                        f"beam '{beam.name}': pivot moved to the ground pin of its far body at "
                        f"({G[0]:.4g}, {G[1]:.4g}), gamma = |G {tip}|/L = {(L - s) / L:.4f}"
                    )
                    break
            if beam.name in pivot_at:
                break
    net = model.network
    base = (
        f"the PRB model has zero mobility ({net.n} coordinates, rank of the joint Jacobian "
        f"{net.n - net.first_order_mobility()} at the unloaded pose"
        + (
            ", and its first-order motion does not extend to second order (links in line)"
            if net.first_order_mobility()
            else ""
        )
        + "): the standard pivots and the ground pins lock it"
    )
    if not pivot_at:
        raise LockedNetwork(
            base + "; no beam's far body turns about a ground pin on the beam's line, "
            "so the notes' workaround (pivot at that pin) does not apply"
        )
    fixed = _build(geometry, rules, pivot_at=pivot_at)
    if fixed.network.mobility() == 0:
        raise LockedNetwork(base + "; still locked after " + "; ".join(notes))
    fixed.lock = base + "; workaround (notes seed-003-004 sec. 4.1 option (a)): " + "; ".join(notes)
    return fixed


def _ground_pins(geometry: Geometry, model: PRBModel) -> dict[str, list[NDArray[np.float64]]]:
    out: dict[str, list[NDArray[np.float64]]] = {}
    for pin in model.network.pins:
        if pin.b == GROUND:
            out.setdefault(pin.a, []).append(np.asarray(pin.at, float))
    return out


def _build(geometry: Geometry, rules: Rules, pivot_at: _PivotAt) -> PRBModel:
    return _Builder(geometry, rules, pivot_at).model()


class _Builder:
    """One build: the bodies, points, joints and springs of the network as they are made, beam by beam.
    Every joint or spring to the ground is recorded with the support node it belongs to (``ground_nodes``:
    name -> node), so the reactions at a support can be summed from the network's multipliers."""

    def __init__(self, geometry: Geometry, rules: Rules, pivot_at: _PivotAt):
        self.geometry, self.rules, self.pivot_at = geometry, rules, pivot_at
        self.coords = {nd.name: np.array([nd.x, nd.y], float) for nd in geometry.nodes}
        self.welded = welded_bodies(geometry)
        self.links_at = self.welded.links_at
        self.beams_at: dict[str, list[Beam]] = {}
        for beam in geometry.beams:
            for nd in (beam.start, beam.end):
                if nd not in self.coords:
                    raise ValueError(f"beam '{beam.name}' names unknown node '{nd}'")
                self.beams_at.setdefault(nd, []).append(beam)
        self.supports_at: dict[str, list[Support]] = {}
        for sup in geometry.supports:
            self.supports_at.setdefault(sup.node, []).append(sup)
        self.bodies: list[str] = []
        self.points: dict[str, tuple[str, tuple[float, float]]] = {}
        self.pins: list[Pin] = []
        self.sliders: list[Slider] = []
        self.springs: list[TorsionSpring] = []
        self.node_body: dict[str, str] = {}
        self.member_body: dict[tuple[str, str], str] = {}
        self.records: list[BeamModel] = []
        self.pending: list[tuple[str, str, Beam]] = []  # (node, beam body, beam): pinned ends with no owner yet
        self.by_node: dict[str, list[str]] = {}
        self.held_by: dict[str, int] = {}
        self.ground_nodes: dict[str, str] = {}

    # --- recording ---------------------------------------------------------------------------------
    def pin(self, pin: Pin, node: str) -> None:
        self.pins.append(pin)
        if GROUND in (pin.a, pin.b):
            self.ground_nodes[pin.name] = node

    def spring(self, spring: TorsionSpring, node: str) -> None:
        self.springs.append(spring)
        if GROUND in (spring.a, spring.b):
            self.ground_nodes[spring.name] = node

    def body_of_link(self, name: str) -> str:
        root = self.welded.body_of_link[name]
        if root != GROUND and root not in self.bodies:
            self.bodies.append(root)
        return root

    # --- the steps ---------------------------------------------------------------------------------
    def model(self) -> PRBModel:
        self._node_bodies()
        self._released_links()
        for link in self.geometry.links:
            for nd in link.nodes:
                self.member_body[(link.name, nd)] = self.body_of_link(link.name)
        self.held_by = self._holders()
        for beam in self.geometry.beams:
            self._beam(beam)
        self._pending_ends()
        self._owned_supports()
        return self._network()

    def _node_bodies(self) -> None:
        """The body that owns each node (a link, the ground, or a junction of welded beams)."""
        geometry = self.geometry
        for nd in self.coords:
            kept = [l for l in self.links_at.get(nd, []) if not geometry.released(nd, l)]
            sups = self.supports_at.get(nd, [])
            clamped_beams = [b for b in self.beams_at.get(nd, []) if not geometry.released(nd, b.name)]
            if any(s.kind == "fixed" for s in sups):
                self.node_body[nd] = GROUND
            elif kept:
                self.node_body[nd] = self.body_of_link(kept[0])
            elif self.links_at.get(nd):
                self.node_body[nd] = self.body_of_link(self.links_at[nd][0])
            elif len(clamped_beams) >= 2 or (clamped_beams and any(s.kind in ("slider", "guided") for s in sups)):
                self.node_body[nd] = f"junction:{nd}"
                self.bodies.append(self.node_body[nd])
        for nd, body in self.node_body.items():
            self.points[nd] = (body, tuple(self.coords[nd]))

    def _released_links(self) -> None:
        """Links released at a node (a joint naming them) are pinned to the node's owner there."""
        pinned_pairs = set()
        link_names = {l.name for l in self.geometry.links}
        for j in self.geometry.joints:
            owner = self.node_body.get(j.node)
            for nm in [m for m in j.members if m in link_names]:
                b = self.body_of_link(nm)
                if owner is not None and b != owner and (b, owner, j.node) not in pinned_pairs:
                    self.pin(Pin(b, owner, tuple(self.coords[j.node]), name=f"joint {j.node}"), j.node)
                    pinned_pairs.add((b, owner, j.node))
                    if j.spring:
                        self.spring(TorsionSpring(b, owner, j.spring, name=f"joint {j.node}"), j.node)

    def end_of(self, beam: Beam, nd: str) -> _End:
        owner = self.node_body.get(nd)
        sups = self.supports_at.get(nd, [])
        if self.geometry.released(nd, beam.name):
            return _End(EndKind.PINNED, owner)
        if any(s.kind == "pinned" and s.member in (None, beam.name) for s in sups) and owner is None:
            return _End(EndKind.PINNED, GROUND)
        if any(s.kind == "slider" for s in sups) and owner is None:
            return _End(EndKind.PINNED, None)  # resolved later with a slider on the beam's own body
        if owner is not None:
            return _End(EndKind.CLAMPED, owner)
        return _End(EndKind.FREE, None)

    def _holders(self) -> dict[str, int]:
        """How many beam ends, pins and supports hold each body: a body held by nothing but one clamped
        beam end rides on that beam (the beam is fixed-free there)."""
        held_by: dict[str, int] = {}
        for beam in self.geometry.beams:
            for nd in (beam.start, beam.end):
                end = self.end_of(beam, nd)
                if end.body not in (None, GROUND):
                    held_by[end.body] = held_by.get(end.body, 0) + 1
        for pin in self.pins:
            for b in (pin.a, pin.b):
                held_by[b] = held_by.get(b, 0) + 1
        for sup in self.geometry.supports:
            owner = self.node_body.get(sup.node)
            if owner not in (None, GROUND):
                held_by[owner] = held_by.get(owner, 0) + 1
        return held_by

    def carried(self, end: _End) -> bool:
        return end.kind == EndKind.CLAMPED and end.body not in (None, GROUND) and self.held_by.get(end.body, 0) == 1

    def _choose(self, beam: Beam, e0: _End, e1: _End, L: float, rule: BeamRule) -> BeamChoice:
        """The beam's model by how its ends are held (module docstring), unless the rule names one."""
        if beam.name in self.pivot_at:
            return BeamChoice.PIVOT_AT_PIN
        if rule.model is not None:
            if rule.model not in RULE_CHOICES:
                raise ValueError(
                    f"beam '{beam.name}': unknown PRB model '{rule.model}' (use {', '.join(RULE_CHOICES)})"
                )
            return BeamChoice(rule.model)
        kinds = sorted((e0.kind, e1.kind))
        if (
            kinds == [EndKind.CLAMPED, EndKind.CLAMPED]
            and (self.carried(e0) or self.carried(e1))
            and e0.body != e1.body
        ):
            return BeamChoice.FIXED_FREE
        if kinds == [EndKind.CLAMPED, EndKind.CLAMPED]:
            if e0.body == e1.body:
                return BeamChoice.RIGID_ON_ONE_BODY
            short = self.rules.slfp_ratio * min(
                _size(self.coords, e0.body, self.welded), _size(self.coords, e1.body, self.welded)
            )
            return BeamChoice.SLFP if L <= short else BeamChoice.FIXED_GUIDED
        if EndKind.CLAMPED in kinds:
            return BeamChoice.FIXED_PINNED if EndKind.PINNED in kinds else BeamChoice.FIXED_FREE
        return BeamChoice.RIGID

    def _beam(self, beam: Beam) -> None:
        A, B = self.coords[beam.start], self.coords[beam.end]
        L = _arc_length(A, B, beam.curvature)
        rule = self.rules.beams.get(beam.name, BeamRule())
        e0, e1 = self.end_of(beam, beam.start), self.end_of(beam, beam.end)
        ends = (e0.kind, e1.kind)
        chosen = self._choose(beam, e0, e1, L, rule)
        if chosen == BeamChoice.RIGID_ON_ONE_BODY:
            self.records.append(
                BeamModel(
                    beam.name,
                    BeamChoice.RIGID,
                    ends,
                    (),
                    (),
                    None,
                    None,
                    "both ends clamped to the same rigid body: the beam cannot deflect",
                )
            )
        elif chosen in (BeamChoice.FIXED_PINNED, BeamChoice.FIXED_FREE):
            self._one_pivot(beam, chosen, e0, e1, L, rule)
        elif chosen == BeamChoice.PIVOT_AT_PIN:
            self._pivot_at_pin(beam, ends, L, rule)
        elif chosen == BeamChoice.FIXED_GUIDED:
            self._fixed_guided(beam, e0, e1, L, rule)
        elif chosen == BeamChoice.SLFP:
            self._slfp(beam, e0, e1, L, rule)
        else:
            self._rigid(beam, e0, e1)

    def _parameters(self, rule: BeamRule) -> tuple[float, float]:
        gamma = rule.gamma if rule.gamma is not None else self.rules.gamma
        K_theta = rule.K_theta if rule.K_theta is not None else self.rules.K_theta
        return gamma, K_theta

    def _fitted(self, rule: BeamRule) -> tuple[float, float, str]:
        """gamma and K_Theta of a straight one-pivot beam: the rule's, else the Pauly-Midha fits at the
        beam's load ratio where the loads define one inside the fits' range [bapat2015, eqs 41, 43], else
        the defaults; and the sentence that says which."""
        n = rule.load_ratio
        if rule.gamma is None and rule.K_theta is None and n is not None:
            if PAULY_MIDHA.lower < n <= PAULY_MIDHA.upper:
                return (
                    PAULY_MIDHA.gamma(n),
                    PAULY_MIDHA.K_theta(n),
                    f"; gamma(n), K_Theta(n) of seed 000 eqs 41, 43 at the end load's ratio n = {n:.4g}",
                )
            gamma, K_theta = self._parameters(rule)
            return (
                gamma,
                K_theta,
                (
                    f"; the end load's ratio n = {n:.4g} is outside the fits' range "
                    f"({PAULY_MIDHA.lower:g} < n <= {PAULY_MIDHA.upper:g}): the defaults"
                ),
            )
        return (*self._parameters(rule), "")

    def _one_pivot(self, beam: Beam, chosen: str, e0: _End, e1: _End, L: float, rule: BeamRule) -> None:
        """Fixed-pinned / fixed-free: one pivot (1 - gamma) L from the clamp (eqs 41-49, 53-58)."""
        ends = (e0.kind, e1.kind)
        if EndKind.CLAMPED not in ends:
            raise ValueError(f"beam '{beam.name}': model '{chosen}' needs a clamped end ({ends})")
        gamma, K_theta, fitted = self._fitted(rule) if beam.curvature == 0.0 else (*self._parameters(rule), "")
        root, tip, er, et = (
            (beam.start, beam.end, e0, e1)
            if e0.kind == EndKind.CLAMPED and not self.carried(e0)
            else (beam.end, beam.start, e1, e0)
        )
        if rule.clamp is not None and rule.clamp in (beam.start, beam.end) and rule.clamp != root:
            root, tip, er, et = tip, root, et, er
        O, E = self.coords[root], self.coords[tip]
        kappa = beam.curvature if root == beam.start else -beam.curvature
        P = O + (1.0 - gamma) * L * _tangent(O, E, kappa, L)
        rho = float(np.linalg.norm(E - P)) / L
        if kappa == 0.0:
            k = rule.stiffness or gamma * K_theta * beam.EI / L
            why = (
                f"clamped at {root}, {et.kind} at {tip}: one pivot (1-gamma)L from the clamp, "
                f"K = gamma K_Theta EI/L{fitted}"
            )
        else:
            k = rule.stiffness or rho * K_theta * beam.EI / L
            why = (
                f"initially curved, clamped at {root}: pivot (1-gamma)L along the clamp tangent, "
                f"rho = {rho:.4f}, K = rho K_Theta EI/L (seed 000 eqs 53-58)"
            )
        name = f"prb:{beam.name}"
        if self.carried(et) and et.body is not None:  # the body at the tip rides on the PRB link: it is the link
            name = et.body
            why += f"; the body at {tip} is held by this beam only, so it rides on the PRB link"
        else:
            self.bodies.append(name)
            self._attach_far_end(beam, tip, et, name)
        clamp = _held(er, beam)
        self.spring(TorsionSpring(name, clamp, k, name=f"{beam.name} pivot"), root)
        self.pin(Pin(name, clamp, tuple(P), name=f"{beam.name} pivot"), root)
        self.member_body[(beam.name, root)] = clamp
        self.member_body[(beam.name, tip)] = name
        self.records.append(BeamModel(beam.name, chosen, ends, (tuple(P),), (k,), gamma, K_theta, why))

    def _pivot_at_pin(self, beam: Beam, ends: tuple[str, str], L: float, rule: BeamRule) -> None:
        """The lock workaround: the beam's pivot at its far body's ground pin G (module docstring)."""
        _, K_theta = self._parameters(rule)
        root, G = self.pivot_at[beam.name]
        tip = beam.end if root == beam.start else beam.start
        g_eff = float(np.linalg.norm(self.coords[tip] - np.asarray(G))) / L
        k = rule.stiffness or g_eff * K_theta * beam.EI / L
        far = self.node_body[tip]
        self.spring(TorsionSpring(far, GROUND, k, name=f"{beam.name} pivot"), root)
        self.member_body[(beam.name, root)] = GROUND
        self.member_body[(beam.name, tip)] = far
        self.records.append(
            BeamModel(
                beam.name,
                "fixed-pinned (pivot at the far body's ground pin)",
                ends,
                (G,),
                (k,),
                g_eff,
                K_theta,
                f"lock workaround: gamma = {g_eff:.4f}, K = gamma K_Theta EI/L; the pin there is the beam's pivot",
            )
        )

    def _fixed_guided(self, beam: Beam, e0: _End, e1: _End, L: float, rule: BeamRule) -> None:
        """Clamped-clamped: two pivots (1 - gamma) L/2 from the ends, 2 gamma K_Theta EI/L each
        [ananthasuresh_l18, 07:13-12:05]."""
        ends = (e0.kind, e1.kind)
        if ends != (EndKind.CLAMPED, EndKind.CLAMPED):
            raise ValueError(f"beam '{beam.name}': model 'fixed-guided' needs both ends clamped ({ends})")
        if beam.curvature != 0.0:
            raise ValueError(f"beam '{beam.name}': no fixed-guided PRBM for an initially curved beam in the seeds")
        gamma, K_theta, fitted = self._fitted(rule)
        A, B = self.coords[beam.start], self.coords[beam.end]
        u = (B - A) / L
        P1 = A + (1.0 - gamma) * L / 2 * u
        P2 = B - (1.0 - gamma) * L / 2 * u
        k = rule.stiffness or 2.0 * gamma * K_theta * beam.EI / L
        name = f"prb:{beam.name}"
        self.bodies.append(name)
        b0, b1 = _held(e0, beam), _held(e1, beam)
        self.pin(Pin(name, b0, tuple(P1), name=f"{beam.name} pivot 1"), beam.start)
        self.pin(Pin(name, b1, tuple(P2), name=f"{beam.name} pivot 2"), beam.end)
        self.spring(TorsionSpring(name, b0, k, name=f"{beam.name} pivot 1"), beam.start)
        self.spring(TorsionSpring(name, b1, k, name=f"{beam.name} pivot 2"), beam.end)
        self.member_body[(beam.name, beam.start)] = b0
        self.member_body[(beam.name, beam.end)] = b1
        self.records.append(
            BeamModel(
                beam.name,
                BeamChoice.FIXED_GUIDED,
                ends,
                (tuple(P1), tuple(P2)),
                (k, k),
                gamma,
                K_theta,
                "clamped at both ends to different bodies: two pivots "
                "(1-gamma)L/2 from the ends, K = 2 gamma K_Theta EI/L each (seed 004 3.3)" + fitted,
            )
        )

    def _slfp(self, beam: Beam, e0: _End, e1: _End, L: float, rule: BeamRule) -> None:
        """A short flexure: one pivot at its middle, K = EI/L [bapat2015, eq 186]."""
        ends = (e0.kind, e1.kind)
        if ends != (EndKind.CLAMPED, EndKind.CLAMPED):
            raise ValueError(f"beam '{beam.name}': model 'slfp' needs both ends clamped ({ends})")
        P = _midpoint(self.coords[beam.start], self.coords[beam.end], beam.curvature, L)
        k = rule.stiffness or beam.EI / L
        grounded = beam.start if e0.body == GROUND else beam.end
        b0, b1 = _held(e0, beam), _held(e1, beam)
        self.pin(Pin(b0, b1, tuple(P), name=f"{beam.name} SLFP"), grounded)
        self.spring(TorsionSpring(b0, b1, k, name=f"{beam.name} SLFP"), grounded)
        self.member_body[(beam.name, beam.start)] = b0
        self.member_body[(beam.name, beam.end)] = b1
        self.records.append(
            BeamModel(
                beam.name,
                BeamChoice.SLFP,
                ends,
                (tuple(P),),
                (k,),
                None,
                None,
                f"short flexure (L <= {self.rules.slfp_ratio:g} x the bodies it joins): one "
                "pivot at its middle, K = EI/L (seed 000 eq 186)",
            )
        )

    def _rigid(self, beam: Beam, e0: _End, e1: _End) -> None:
        """Pinned-pinned (or pinned-free): a two-force member along its chord, no spring."""
        name = f"prb:{beam.name}"
        self.bodies.append(name)
        for nd, end in ((beam.start, e0), (beam.end, e1)):
            self._attach_far_end(beam, nd, end, name)
            self.member_body[(beam.name, nd)] = name
        if beam.name not in {b.name for _, _, b in self.pending} and not any(
            p.a == name or p.b == name for p in self.pins
        ):
            raise ValueError(f"beam '{beam.name}': a rigid link held by nothing")
        ends = (e0.kind, e1.kind)
        self.records.append(
            BeamModel(
                beam.name,
                "rigid link",
                ends,
                (),
                (),
                None,
                None,
                f"{ends[0]}-{ends[1]}: a two-force member along its chord, no spring",
            )
        )

    def _attach_far_end(self, beam: Beam, nd: str, end: _End, body: str) -> None:
        """The beam's PRB body reaches node nd: free -> the node moves with it; pinned -> a pin to the
        node's owner (or pending, when the node has none yet)."""
        if end.kind == EndKind.FREE:
            self.node_body[nd] = body
            self.points[nd] = (body, tuple(self.coords[nd]))
        elif end.kind == EndKind.PINNED and end.body is not None:
            self.pin(Pin(body, end.body, tuple(self.coords[nd]), name=f"{beam.name} end {nd}"), nd)
            if nd not in self.points:  # a pinned support on a beam end: the node is on the ground
                self.node_body[nd] = end.body
                self.points[nd] = (end.body, tuple(self.coords[nd]))
        elif end.kind == EndKind.PINNED:
            self.pending.append((nd, body, beam))
        else:  # clamped at the far end of a one-pivot model
            raise ValueError(f"beam '{beam.name}': both ends clamped, but a one-pivot model was chosen")

    def _pending_ends(self) -> None:
        """Pinned ends that found no owner: the first beam body at the node owns it, the others pin to it."""
        for nd, body, _ in self.pending:
            self.by_node.setdefault(nd, []).append(body)
        for nd, bodies_here in self.by_node.items():
            owner = self.node_body.get(nd)
            if owner is None:
                owner = bodies_here[0]
                self.node_body[nd] = owner
                self.points[nd] = (owner, tuple(self.coords[nd]))
                rest = bodies_here[1:]
            else:
                rest = bodies_here
            for b in rest:
                if b != owner:
                    self.pin(Pin(b, owner, tuple(self.coords[nd]), name=f"joint {nd}"), nd)
            for s in self.supports_at.get(nd, []):
                if s.kind == "pinned" and owner != GROUND:
                    self.pin(Pin(owner, GROUND, tuple(self.coords[nd]), name=f"support {nd}"), nd)
                elif s.kind in ("slider", "guided"):
                    d = s.direction or (1.0, 0.0)
                    self.sliders.append(
                        Slider(
                            owner, tuple(self.coords[nd]), (d[0], d[1]), guided=s.kind == "guided", name=f"support {nd}"
                        )
                    )
                    self.ground_nodes[f"support {nd}"] = nd

    def _owned_supports(self) -> None:
        """Supports on nodes owned by a link or junction."""
        for sup in self.geometry.supports:
            owner = self.node_body.get(sup.node)
            if owner is None or owner == GROUND or sup.node in self.by_node:
                continue
            xy = tuple(self.coords[sup.node])
            if sup.kind == "pinned":
                target = owner
                if sup.member is not None and (sup.member, sup.node) in self.member_body:
                    target = self.member_body[(sup.member, sup.node)]
                self.pin(Pin(target, GROUND, xy, name=f"support {sup.node}"), sup.node)
            elif sup.kind in ("slider", "guided"):
                d = sup.direction or (1.0, 0.0)
                self.sliders.append(
                    Slider(owner, xy, (d[0], d[1]), guided=sup.kind == "guided", name=f"support {sup.node}")
                )
                self.ground_nodes[f"support {sup.node}"] = sup.node

    def _network(self) -> PRBModel:
        for nd in self.coords:
            if nd not in self.points:
                raise ValueError(f"node '{nd}' belongs to no member")
        pins, sliders, springs = self.pins, self.sliders, self.springs
        used = {p.a for p in pins} | {p.b for p in pins} | {s.a for s in sliders} | {s.a for s in springs}
        bodies = [b for b in dict.fromkeys(self.bodies) if b in used or any(v[0] == b for v in self.points.values())]
        for b in bodies:
            if b not in used:
                raise ValueError(f"body '{b}' is held by no joint or support: the mechanism floats")
        net = Network(bodies, self.points, pins, sliders, springs)
        return PRBModel(net, self.records, self.node_body, self.member_body, ground_nodes=self.ground_nodes)


def _arc_length(A: NDArray[np.float64], B: NDArray[np.float64], kappa: float) -> float:
    chord = float(np.linalg.norm(B - A))
    if kappa == 0.0:
        return chord
    half = chord * abs(kappa) / 2
    if half >= 1.0:
        raise ValueError("an initially curved beam whose chord exceeds its diameter")
    return 2.0 * math.asin(half) / abs(kappa)


def _tangent(O: NDArray[np.float64], E: NDArray[np.float64], kappa: float, L: float) -> NDArray[np.float64]:
    """Unit tangent at O of the arc O -> E of curvature kappa (CCW positive)."""
    u = (E - O) / np.linalg.norm(E - O)
    half_angle = kappa * L / 2
    c, s = math.cos(-half_angle), math.sin(-half_angle)
    return np.array([c * u[0] - s * u[1], s * u[0] + c * u[1]])


def _midpoint(A: NDArray[np.float64], B: NDArray[np.float64], kappa: float, L: float) -> NDArray[np.float64]:
    if kappa == 0.0:
        return (A + B) / 2
    t = _tangent(A, B, kappa, L)
    n = np.array([-t[1], t[0]])
    R = 1.0 / kappa
    C = A + R * n
    ang = kappa * L / 2
    c, s = math.cos(ang), math.sin(ang)
    r = A - C
    M: NDArray[np.float64] = C + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
    return M


def _size(coords: dict[str, NDArray[np.float64]], body: str | None, welded: WeldedBodies) -> float:
    """Largest distance between two nodes of a body (infinite for the ground)."""
    if body is None or body == GROUND:
        return math.inf
    pts = np.array([coords[nd] for nd in welded.nodes_of.get(body, [])])
    if len(pts) < 2:
        return 0.0
    return float(np.max(np.linalg.norm(pts[:, None] - pts[None], axis=-1)))
