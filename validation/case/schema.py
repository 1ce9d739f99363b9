"""Case-file schema: what a TOML file under ``cases/`` may say, validated with pydantic v2.

A case is one published test, example or benchmark. It describes *either* a single compliant
``segment`` *or* a planar ``mechanism``, the ``loads`` applied along a load path, the
``outputs`` wanted at named load levels, the ``methods`` to run with their options, and the
published ``references`` with their source and the tolerance the project claims.

Conventions (every case file uses them, whatever its unit system):
- x runs along the undeformed segment from its fixed end, y is transverse, angles are
  counter-clockwise positive, moments counter-clockwise positive.
- Lengths, forces, moduli and moments are in the file's ``units`` system (see ``UNIT_SYSTEMS``);
  angles in outputs and references are in degrees.
- Load level ``i`` is the i-th entry of every load's path; all loads of a case have the same
  number of levels.

Every number is finite and representable (``validation.case.strict``); ranges that depend on the case's
own scale (non-dimensional loads, slenderness, tolerances against the characteristic length, the work
a case asks for against its ``[limits]``) are ``validation.case.scale``'s, and an option its method
would not read is refused by ``validation.case.option_use``. Ids are file-name-safe (``ID_PATTERN``):
they name the report's pages and folders.
"""

from __future__ import annotations

import math
import re
from typing import Any, Literal

import numpy as np
from pydantic import Field, ValidationError, field_validator, model_validator
from pydantic_core import PydanticCustomError

from references import key_of_seed_file

from validation.case import scale
from validation.case.capabilities import METHODS, QUANTITIES, method_quantities
from validation.case.method_options import OPTIONS
from validation.case.names import nearest
from validation.case.option_use import unused_options
from validation.case.overrides import PathError, apply as apply_field
from validation.case.strict import TINY, Finite, Fraction, NonNegative, Positive, Strict, field_path

UNIT_SYSTEMS: dict[str, dict[str, str]] = {
    "in-lb": {
        "length": "in",
        "force": "lbf",
        "modulus": "psi",
        "moment": "lbf*in",
        "energy": "lbf*in",
        "stiffness": "lbf*in/rad",
    },
    "SI": {"length": "m", "force": "N", "modulus": "Pa", "moment": "N*m", "energy": "J", "stiffness": "N*m/rad"},
    "mm-N": {"length": "mm", "force": "N", "modulus": "MPa", "moment": "N*mm", "energy": "mJ", "stiffness": "N*mm/rad"},
    "dimensionless": {
        "length": "L",
        "force": "EI/L^2",
        "modulus": "E",
        "moment": "EI/L",
        "energy": "EI/L",
        "stiffness": "EI/L",
    },
}


class Source(Strict):
    """Where a number was printed: seed file, section, table, row, column (any may be omitted)."""

    file: str
    section: str | None = None
    table: str | None = None
    row: str | None = None
    column: str | None = None
    page: str | None = None
    note: str | None = None

    def label(self) -> str:
        """Where the number is printed: the document by its key (``[bapat2015]``) when the file is one of
        the seed documents (``references``), else the file as written; then section, table, row, column."""
        try:
            parts = [f"[{key_of_seed_file(self.file)}]"]
        except ValueError:
            parts = [self.file]
        for key in ("section", "table", "row", "column"):
            value = getattr(self, key)
            if value:
                parts.append(f"{key} {value}")
        return ", ".join(parts)


class Layer(Strict):
    """One sliding layer of a composite section."""

    E: Positive
    width: Positive
    thickness: Positive
    name: str | None = None
    weight_density: Positive | None = Field(
        default=None, description="weight per unit volume (force/length^3), for self-weight"
    )


class SectionSpec(Strict):
    """A cross-section: a rectangle, I and A given directly, or a stack of sliding layers."""

    kind: Literal["rectangle", "inertia", "layers"]
    width: Positive | None = None
    thickness: Positive | None = None
    I: Positive | None = None
    A: Positive | None = None
    c: Positive | None = Field(default=None, description="extreme-fibre distance, for stresses")
    layers: list[Layer] | None = None
    bonded: bool = Field(
        default=False,
        description="layers bonded (one section bending about the E-weighted "
        "neutral axis) instead of sliding on each other",
    )
    weight_density: Positive | None = Field(
        default=None, description="weight per unit volume (force/length^3), for self-weight"
    )

    @model_validator(mode="after")
    def _complete(self) -> "SectionSpec":
        need = {"rectangle": ("width", "thickness"), "inertia": ("I",), "layers": ("layers",)}[self.kind]
        for name in need:
            if getattr(self, name) is None:
                raise ValueError(f"section kind '{self.kind}' needs field '{name}'")
        if self.kind == "layers" and not self.layers:
            raise ValueError("section kind 'layers' needs at least one layer")
        if self.bonded and self.kind != "layers":
            raise ValueError("'bonded' applies to a section of kind 'layers'")
        return self

    def _stack(self) -> list[Layer]:
        """The layers of a 'layers' section (``_complete`` has checked they are given)."""
        if self.layers is None:
            raise ValueError(f"section kind '{self.kind}' has no layers")
        return self.layers

    def _rectangle(self) -> tuple[float, float]:
        """(width, thickness) of a 'rectangle' section (``_complete`` has checked they are given)."""
        if self.width is None or self.thickness is None:
            raise ValueError(f"section kind '{self.kind}' has no width and thickness")
        return self.width, self.thickness

    def _given_inertia(self) -> float:
        """I of an 'inertia' section (``_complete`` has checked it is given)."""
        if self.I is None:
            raise ValueError(f"section kind '{self.kind}' has no I")
        return self.I

    def weight_per_length(self) -> float | None:
        """Weight per unit length (sum of weight density x area), None when a density is missing."""
        if self.kind != "layers":
            return None if self.weight_density is None else self.weight_density * self.area()
        total = 0.0
        for layer in self._stack():
            if layer.weight_density is None:
                return None
            total += layer.weight_density * layer.width * layer.thickness
        return total

    def inertia(self) -> float:
        """Second moment of area I (for 'layers', the E-weighted stack is in ``bending_stiffness``)."""
        if self.kind == "rectangle":
            width, thickness = self._rectangle()
            return width * thickness**3 / 12.0
        if self.kind == "inertia":
            return self._given_inertia()
        return sum(layer.width * layer.thickness**3 / 12.0 for layer in self._stack())

    def stiffness(self, E: float | None) -> tuple[float, float]:
        """(EA, EI) of the section with modulus E; sliding layers carry their own moduli (E unused)
        and bend each about its own centroid."""
        if self.kind == "layers" and self.bonded:  # stacked bottom to top, transformed section
            layers = self._stack()
            EA = sum(l.E * l.width * l.thickness for l in layers)
            tops = np.cumsum([l.thickness for l in layers])
            mids = tops - np.array([l.thickness for l in layers]) / 2
            axis = sum(l.E * l.width * l.thickness * z for l, z in zip(layers, mids)) / EA
            return EA, sum(
                l.E * l.width * (l.thickness**3 / 12.0 + l.thickness * (z - axis) ** 2) for l, z in zip(layers, mids)
            )
        if self.kind == "layers":
            layers = self._stack()
            return (
                sum(l.E * l.width * l.thickness for l in layers),
                sum(l.E * l.width * l.thickness**3 / 12.0 for l in layers),
            )
        if E is None:
            raise ValueError(f"a section of kind '{self.kind}' needs the modulus E")
        return E * self.area(), E * self.inertia()

    def area(self) -> float:
        if self.kind == "rectangle":
            width, thickness = self._rectangle()
            return width * thickness
        if self.kind == "inertia":
            return self.A if self.A is not None else math.nan
        return sum(layer.width * layer.thickness for layer in self._stack())


class SegmentSpec(Strict):
    """A single compliant segment, fixed at x = 0 and lying along +x when unloaded (if straight)."""

    boundary: Literal["fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed", "pinned-pinned"]
    length: Positive
    E: Positive | None = Field(default=None, description="modulus; omit only for a 'layers' section")
    section: SectionSpec
    curvature: Finite = Field(default=0.0, description="initial curvature 1/R (1/length), 0 = straight")
    radius: Positive | None = Field(default=None, description="initial radius; alternative to curvature")
    model: str | None = Field(default=None, description="named PRBM model variant, e.g. 'inflection' or 'slfp'")

    @model_validator(mode="after")
    def _consistent(self) -> "SegmentSpec":
        if self.section.kind != "layers" and self.E is None:
            raise ValueError("field 'E' is required unless the section is a stack of layers")
        if self.radius is not None and self.curvature != 0.0:
            raise ValueError("give either 'curvature' or 'radius', not both")
        return self

    def initial_curvature(self) -> float:
        return 1.0 / self.radius if self.radius is not None else self.curvature

    def bending_stiffness(self) -> float:
        """EI; for sliding layers the sum of each layer's E*I about its own centroid."""
        return self.section.stiffness(self.E)[1]

    def axial_stiffness(self) -> float:
        return self.section.stiffness(self.E)[0]


class NodeSpec(Strict):
    name: str
    x: Finite
    y: Finite


class BeamSpec(Strict):
    """A flexible member between two named nodes (straight, or an arc of given curvature)."""

    name: str
    start: str
    end: str
    E: Positive | None = None
    section: SectionSpec
    curvature: Finite = 0.0
    segment_type: str | None = Field(default=None, description="PRBM segment model, e.g. 'fixed-pinned', 'slfp'")


class LinkSpec(Strict):
    """A rigid body through two or more named nodes."""

    name: str
    nodes: list[str] = Field(min_length=2)


class JointSpec(Strict):
    """A revolute joint at a node between the named members (beams or links), optional torsional spring."""

    node: str
    members: list[str] = Field(min_length=1)
    spring: NonNegative = 0.0


class SupportSpec(Strict):
    node: str
    kind: Literal["fixed", "pinned", "slider", "guided"]
    direction: tuple[Finite, Finite] | None = Field(default=None, description="free direction of slider/guided")
    member: str | None = Field(default=None, description="the member a pinned or guided support holds")

    @field_validator("direction")
    @classmethod
    def _nonzero(cls, value: tuple[float, float] | None) -> tuple[float, float] | None:
        if value is not None and math.hypot(*value) < TINY:
            raise ValueError("the free direction must not be the zero vector (its length is below 1e-100)")
        return value


class MechanismSpec(Strict):
    nodes: list[NodeSpec] = Field(min_length=2)
    beams: list[BeamSpec] = Field(default_factory=list)
    links: list[LinkSpec] = Field(default_factory=list)
    joints: list[JointSpec] = Field(default_factory=list)
    supports: list[SupportSpec] = Field(min_length=1)
    E: Positive | None = Field(default=None, description="default modulus of the beams")

    @model_validator(mode="after")
    def _references_exist(self) -> "MechanismSpec":
        names = [n.name for n in self.nodes]
        if len(set(names)) != len(names):
            raise ValueError("node names must be unique")
        known = set(names)
        members = {b.name for b in self.beams} | {l.name for l in self.links}
        for beam in self.beams:
            for end in (beam.start, beam.end):
                if end not in known:
                    raise ValueError(f"beam '{beam.name}' names unknown node '{end}'")
            if beam.start == beam.end:
                raise ValueError(f"beam '{beam.name}' has zero length (start = end)")
            if beam.E is None and self.E is None and beam.section.kind != "layers":
                raise ValueError(f"beam '{beam.name}' has no E and the mechanism gives no default E")
        for link in self.links:
            for node in link.nodes:
                if node not in known:
                    raise ValueError(f"link '{link.name}' names unknown node '{node}'")
        for joint in self.joints:
            if joint.node not in known:
                raise ValueError(f"joint names unknown node '{joint.node}'")
            for member in joint.members:
                if member not in members:
                    raise ValueError(f"joint at '{joint.node}' names unknown member '{member}'")
        for support in self.supports:
            if support.node not in known:
                raise ValueError(f"support names unknown node '{support.node}'")
        coords = {(round(n.x, 12), round(n.y, 12)) for n in self.nodes}
        if len(coords) != len(self.nodes):
            raise ValueError("two nodes share the same coordinates (coincident nodes)")
        return self


class Ramp(Strict):
    """``count`` evenly spaced levels from ``start`` to ``stop``; the count is held to ``limits.levels``
    by ``Case`` before the levels are built."""

    start: Finite
    stop: Finite
    count: int = Field(ge=1)


class LoadSpec(Strict):
    """One load along the load path.

    ``direction`` is normalised here, once, to the unit vector d / |d| (so [1, 1] is 45 degrees and
    ``values[i]`` is the load's magnitude); every method reads the unit vector. A zero vector (length
    below 1e-100) is refused.

    kind 'force': the force at level i is ``values[i] * direction``, of magnitude ``|values[i]|`` (a
    transverse P with axial nP is direction = [-n, 1] and values = P sqrt(1 + n^2)); 'follower'
    rotates it with the point.
    kind 'moment': a couple (or input torque) ``values[i]`` at the point, on ``body`` if given.
    kind 'displacement' / 'rotation': prescribed position change of length ``values[i]`` along
    ``direction`` / prescribed rotation in degrees.

    Loads attached to bodies: a follower force with ``body`` (a beam or link ending at the point)
    turns with that body's rotation there, so it keeps its angle to the body. A force with
    ``toward = [x, y]`` pulls with magnitude ``values[i]`` from the point toward that fixed point
    (a rope over a pulley), turned by ``angle`` degrees (counter-clockwise) from that line: angle
    90 keeps it perpendicular to the line joining a fixed pivot (no ``direction``).

    kind 'distributed': a uniform load per unit length ``values[i] * direction`` along the whole
    segment, or along the beam ``member``; ``follower = true`` turns it with the beam (a pressure
    stays normal to it; ``direction`` is then given in the unloaded beam's frame).
    kind 'self_weight': the weight of the beams (``section.weight_density`` or every layer's, force
    per unit volume, times the area) along the gravity ``direction``, scaled by ``values[i]`` (1 =
    full gravity at that level; use the same value at every level for a load present throughout).
    """

    kind: Literal["force", "moment", "displacement", "rotation", "distributed", "self_weight"]
    point: str = "tip"
    direction: tuple[Finite, Finite] | None = None
    follower: bool = False
    body: str | None = None
    member: str | None = Field(default=None, description="distributed/self-weight: the beam carrying it (default: all)")
    toward: tuple[Finite, Finite] | None = Field(default=None, description="force: the fixed point it pulls toward")
    angle: Finite = Field(default=0.0, description="force toward a point: angle (deg, CCW) from the line to it")
    values: list[Finite] | None = Field(default=None, min_length=1)
    ramp: Ramp | None = None
    label: str | None = None

    @field_validator("direction")
    @classmethod
    def _unit_direction(cls, value: tuple[float, float] | None) -> tuple[float, float] | None:
        if value is None:
            return None
        length = math.hypot(*value)
        if length < TINY:
            raise ValueError("must not be the zero vector (its length is below 1e-100)")
        return (value[0] / length, value[1] / length)

    @model_validator(mode="after")
    def _path(self) -> "LoadSpec":
        if (self.values is None) == (self.ramp is None):
            raise ValueError("give exactly one of 'values' (a list of levels) or 'ramp'")
        if self.toward is not None:
            if self.kind != "force" or self.follower or self.direction is not None:
                raise ValueError(
                    "'toward' makes a force pull toward a fixed point: a 'force' load without 'direction' or 'follower'"
                )
        elif self.angle != 0.0:
            raise ValueError("'angle' is the angle from the line to the point 'toward', which is missing")
        needs_direction = ("force", "displacement", "distributed", "self_weight")
        if self.kind in needs_direction and self.direction is None and self.toward is None:
            raise ValueError(f"a '{self.kind}' load needs a 'direction' [dx, dy]")
        if self.follower and self.kind not in ("force", "distributed"):
            raise ValueError("only a force or a distributed load can be a follower")
        if self.member is not None and self.kind not in ("distributed", "self_weight"):
            raise ValueError("'member' names the beam of a distributed or self-weight load")
        if self.body is not None and self.kind == "force" and not self.follower:
            raise ValueError("a force on a 'body' must be a follower (it turns with that body)")
        if self.kind == "self_weight" and self.follower:
            raise ValueError("self-weight is a dead load (gravity keeps its direction)")
        return self

    def require_direction(self) -> tuple[float, float]:
        """The unit direction of a load that needs one (``_path`` has checked it is given)."""
        if self.direction is None:
            raise ValueError(f"a '{self.kind}' load has no 'direction'")
        return self.direction

    def levels(self) -> list[float]:
        if self.values is not None:
            return list(self.values)
        r = self.ramp
        if r is None:
            raise ValueError("a load gives neither 'values' nor 'ramp'")
        if r.count == 1:
            return [r.stop]
        return [r.start + (r.stop - r.start) * i / (r.count - 1) for i in range(r.count)]


class OutputSpec(Strict):
    """One quantity wanted, at a point, at some load levels, from some (default: all) methods."""

    quantity: str
    point: str = "tip"
    levels: list[int] | Literal["all"] = "all"
    methods: list[str] | None = None

    @field_validator("quantity")
    @classmethod
    def _known(cls, value: str) -> str:
        if value not in QUANTITIES:
            raise ValueError(f"unknown quantity '{value}'{nearest(value, QUANTITIES)}")
        return value


class Tolerance(Strict):
    """How closely a value must meet another: ``rel`` a fraction (0 < rel < 1: a relative tolerance of 100 %
    accepts zero), ``abs`` in the quantity's unit (finite and positive; against the characteristic length
    and 180 degrees in ``validation.case.scale``)."""

    rel: Fraction | None = None
    abs: Positive | None = None


class Finding(Strict):
    """A known disagreement between a printed number and the method that should reproduce it, with
    the evidence that explains it, both halves checked by the suite.

    The printed value must still disagree with the method (outside the reference's tolerance: a
    finding on a comparison that passes is stale), and the explanation must reproduce:
    ``computed``: the method's value equals this number (the corrected entry, e.g. printed 5.41,
    computed 9.41; or an independent computation named in ``text``) within ``tolerance``;
    ``reproduce_with``: the method re-run with these case fields set (dotted paths as in sweeps,
    e.g. ``segment.section.I``) meets the printed value within ``tolerance``.
    ``tolerance`` defaults to the reference's."""

    text: str = Field(min_length=1)
    computed: Finite | None = None
    reproduce_with: dict[str, Any] | None = None
    tolerance: Tolerance | None = None

    @model_validator(mode="after")
    def _explains(self) -> "Finding":
        if (self.computed is None) == (self.reproduce_with is None):
            raise ValueError(
                "a finding states exactly one of 'computed' (the value the method gives "
                "instead) or 'reproduce_with' (the inputs that reproduce the printed value); "
                "a remark that is not a disagreement is a 'note'"
            )
        if self.reproduce_with is not None and not self.reproduce_with:
            raise ValueError("'reproduce_with' is empty")
        return self


class ReferenceSpec(Strict):
    """A published number, where it was printed, and which method should reproduce it how closely.

    ``finding``: a disagreement the suite asserts (see ``Finding``); ``note``: a remark (convergence,
    provenance) that leaves the comparison enforced."""

    quantity: str
    point: str = "tip"
    level: int = Field(ge=0)
    value: Finite
    label: Literal["PRBM", "ANSYS", "elliptic", "measured", "exact", "BCM", "chain", "published"]
    source: Source
    compare: str | None = Field(default=None, description="method expected to reproduce it; None = record only")
    tolerance: Tolerance | None = None
    finding: Finding | None = Field(default=None, description="a known misprint or disagreement, with its evidence")
    note: str | None = Field(default=None, description="a remark that is not a disagreement; the check stays enforced")

    @field_validator("quantity")
    @classmethod
    def _known(cls, value: str) -> str:
        if value not in QUANTITIES:
            raise ValueError(f"unknown quantity '{value}'{nearest(value, QUANTITIES)}")
        return value

    @model_validator(mode="after")
    def _tolerance_needs_method(self) -> "ReferenceSpec":
        if self.tolerance is not None and self.compare is None:
            raise ValueError("a tolerance needs 'compare' (the method that should meet it)")
        if self.finding is not None and self.tolerance is None:
            raise ValueError("a finding needs 'compare' and 'tolerance' (the check it explains the failure of)")
        return self


class Agreement(Strict):
    """An acceptance limit between two methods, or a method and a printed column, checked like a
    reference: ``method`` against ``against`` (another method of the case, or the references with
    that label, e.g. 'measured') on each quantity at each level where both have a value.

    Error measures are the report's: ``abs`` in the quantity's unit; ``rel`` relative to
    max(|against|, 1 % of the largest |against| of the quantity over the compared levels), so a
    quantity passing through zero is judged on its scale. Either limit met passes. ``basis`` says
    where the limit comes from (a source, or a derivation)."""

    method: str
    against: str
    quantities: list[str] = Field(min_length=1)
    point: str = "tip"
    levels: list[int] | Literal["all"] = "all"
    tolerance: Tolerance
    basis: str = Field(min_length=1)

    @field_validator("quantities")
    @classmethod
    def _known(cls, value: list[str]) -> list[str]:
        for q in value:
            if q not in QUANTITIES:
                raise ValueError(f"unknown quantity '{q}'")
        return value

    @model_validator(mode="after")
    def _has_limit(self) -> "Agreement":
        if self.tolerance.rel is None and self.tolerance.abs is None:
            raise ValueError("the tolerance needs 'rel' and/or 'abs'")
        return self


ID_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,99}$"


def safe_id(value: str | None) -> str | None:
    """An id that can name a file and a folder of the report: a letter or digit, then at most 99 letters,
    digits, '_', '.', '-', and no '..' (a path out of the folder)."""
    if value is not None and (not re.fullmatch(ID_PATTERN, value) or ".." in value):
        shown = value if len(value) <= 40 else f"{value[:40]}... ({len(value)} characters)"
        raise ValueError(
            f"'{shown}' is not a valid id: 1 to 100 letters, digits, '_', '.', '-', starting with a "
            "letter or digit, without '..'"
        )
    return value


class CaseInfo(Strict):
    id: str = Field(description="unique; names the report's page and folders of the case (``safe_id``)")
    title: str
    group: str = Field(description="report grouping, e.g. 'chapter 3', 'chapter 9', 'benchmarks'")
    units: str
    description: str = ""
    source: Source | None = None
    assumptions: list[str] = Field(default_factory=list)
    findings: list[str] = Field(
        default_factory=list,
        description="case-level misprints and disagreements, with their evidence, that no single reference carries",
    )
    unchecked: dict[str, str] = Field(
        default_factory=dict,
        description="method -> the one-line reason none of its values at a loaded level can be checked",
    )
    expected_failure: dict[str, str] = Field(
        default_factory=dict, description="method -> why it is expected not to converge or not to apply on this case"
    )
    readings_of: str | None = Field(
        default=None,
        description="id of the base case of an experiment this case is "
        "one loading reading of (the report sets them side by side)",
    )
    no_prbm_fem: str | None = Field(
        default=None,
        description="why this case has no PRBM-vs-FEM number, in one line: "
        "no seed PRBM for this configuration, geometry not in the seed, or an "
        "FEM-only benchmark validating the FEM itself",
    )
    purpose: Literal["prbm-comparison", "fem-validation"] = Field(
        default="prbm-comparison",
        description="'fem-validation': a benchmark that validates the FEM itself (against "
        "published or exact results) and runs no PRBM, so it has no PRBM-vs-FEM number by design; the summary "
        "labels it so",
    )

    @field_validator("id", "readings_of")
    @classmethod
    def _safe(cls, value: str | None) -> str | None:
        return safe_id(value)

    @field_validator("no_prbm_fem")
    @classmethod
    def _one_line(cls, value: str | None) -> str | None:
        if value is not None and (not value.strip() or "\n" in value):
            raise ValueError("give the reason in one non-empty line")
        return value

    @field_validator("units")
    @classmethod
    def _units(cls, value: str) -> str:
        if value not in UNIT_SYSTEMS:
            raise ValueError(f"unknown unit system '{value}'; use one of {', '.join(UNIT_SYSTEMS)}")
        return value


class Limits(Strict):
    """``[limits]``: the work a case may ask for, checked before any solve (``levels``, ``elements``) or while
    it runs (``seconds``: a case over it stops with status 'timed out', the other cases go on). The
    defaults are far above every shipped case (at most 20 levels and 5120 elements in the finest mesh, each
    case well under a minute) and far below what exhausts a workstation; raise them here for a case that
    needs more."""

    levels: int = Field(default=1000, ge=1, le=1_000_000, description="load levels of each load (ramp.count, values)")
    elements: int = Field(
        default=100_000, ge=1, le=10_000_000, description="elements of the finest mesh a method solves"
    )
    seconds: float = Field(
        default=600.0, gt=0, le=86_400.0, allow_inf_nan=False, description="wall time of the case's methods together"
    )


class Case(Strict):
    case: CaseInfo
    limits: Limits = Field(default_factory=Limits)
    segment: SegmentSpec | None = None
    mechanism: MechanismSpec | None = None
    loads: list[LoadSpec] = Field(default_factory=list)
    level_labels: list[str] | None = None
    outputs: list[OutputSpec] = Field(min_length=1)
    methods: dict[str, dict[str, Any]] = Field(min_length=1)
    references: list[ReferenceSpec] = Field(default_factory=list)
    agreements: list[Agreement] = Field(default_factory=list)

    @field_validator("methods")
    @classmethod
    def _options(cls, methods: dict[str, dict[str, Any]]) -> dict[str, dict[str, Any]]:
        """Each method's options against its typed model (validation/case/method_options.py); the error's
        ``ctx['field']`` carries the option's path below ``methods`` for the one-line message."""
        for name, options in methods.items():
            model = OPTIONS.get(name)
            if model is None:
                continue  # an unknown method is reported by _coherent
            try:
                model.model_validate(options or {})
            except ValidationError as exc:
                # a misspelled name first: it is why a required field then looks missing
                err = min(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
                message = err["msg"]
                if err["type"] == "extra_forbidden" and len(err["loc"]) == 1:
                    message = f"unknown option of method '{name}'{nearest(str(err['loc'][0]), model.model_fields)}"
                elif err["type"] == "extra_forbidden":
                    known = _fields_at(model, err["loc"][:-1])
                    message = f"unknown field '{err['loc'][-1]}'{nearest(str(err['loc'][-1]), known)}"
                raise PydanticCustomError(
                    "method_option",
                    "{message}",
                    {
                        "message": message.removeprefix("Value error, "),
                        "field": ".".join(p for p in (name, field_path(err["loc"])) if p),
                    },
                ) from None
        return methods

    @model_validator(mode="after")
    def _coherent(self) -> "Case":
        if (self.segment is None) == (self.mechanism is None):
            raise ValueError("a case describes exactly one of [segment] or [mechanism]")
        too_many = scale.work_problems(self)  # before anything builds the levels
        if too_many:
            raise ValueError("\n".join(too_many))
        problems: list[str] = []  # every problem, one line each ("field: what is wrong")
        n = self.n_levels()
        for i, load in enumerate(self.loads):
            if len(load.levels()) != n:
                problems.append(f"loads.{i}: has {len(load.levels())} levels, loads.0 has {n}")
        if self.level_labels is not None and len(self.level_labels) != n:
            problems.append(f"level_labels has {len(self.level_labels)} entries for {n} load levels")
        points = self.point_names()
        for i, load in enumerate(self.loads):
            if load.point not in points:
                problems.append(f"loads.{i}.point: unknown point '{load.point}'{nearest(load.point, points)}")
            try:
                self._check_body_load(i, load)
            except ValueError as exc:  # listed with the others
                problems.append(str(exc))
        for name in self.methods:
            try:
                method_quantities(name)
            except ValueError as exc:
                problems.append(f"methods.{name}: {exc}")
        for i, out in enumerate(self.outputs):
            chosen = out.methods if out.methods is not None else list(self.methods)
            for method in chosen:
                if method not in self.methods:
                    problems.append(
                        f"outputs.{i}.methods: method '{method}' is not in [methods]{nearest(method, self.methods)}"
                    )
                    continue
                if method in METHODS and out.quantity not in method_quantities(method):
                    problems.append(f"outputs.{i}: method '{method}' cannot give '{out.quantity}'")
            if out.levels != "all" and any(not 0 <= lv < max(n, 1) for lv in out.levels):
                problems.append(f"outputs.{i}.levels: level outside 0..{max(n, 1) - 1}")
            if out.point not in points and QUANTITIES[out.quantity].at_point:
                problems.append(f"outputs.{i}.point: unknown point '{out.point}'{nearest(out.point, points)}")
        for i, ref in enumerate(self.references):
            if ref.level >= max(n, 1):
                problems.append(f"references.{i}.level: {ref.level} but the case has {n} load levels")
            if ref.compare is not None and ref.compare not in self.methods:
                problems.append(f"references.{i}.compare: method '{ref.compare}' is not in [methods]")
        labels = {ref.label for ref in self.references}
        for i, agr in enumerate(self.agreements):
            if agr.method not in self.methods:
                problems.append(f"agreements.{i}.method: method '{agr.method}' is not in [methods]")
            if agr.against not in self.methods and agr.against not in labels:
                problems.append(
                    f"agreements.{i}.against: '{agr.against}' is neither a method in [methods] "
                    f"nor a reference label of this case"
                )
            if agr.against == agr.method:
                problems.append(f"agreements.{i}: a method against itself checks nothing")
            if agr.levels != "all" and any(not 0 <= lv < max(n, 1) for lv in agr.levels):
                problems.append(f"agreements.{i}.levels: level outside 0..{max(n, 1) - 1}")
        if self.case.purpose == "fem-validation" and "prbm" in self.methods:
            problems.append(
                "case.purpose: a 'fem-validation' benchmark runs no PRBM (remove [methods.prbm] or the purpose)"
            )
        for field_name in ("unchecked", "expected_failure"):
            for method in getattr(self.case, field_name):
                if method not in self.methods:
                    problems.append(f"case.{field_name}: method '{method}' is not in [methods]")
        problems += self._range_problems()
        if problems:
            raise ValueError("\n".join(problems))
        return self

    def _range_problems(self) -> list[str]:
        """Ranges on the case's own scale, bounded work, options its methods would not read, and the case
        each finding's ``reproduce_with`` makes (``validation.case.scale``, ``validation.case.option_use``)."""
        problems = scale.stiffness_problems(self)
        if problems:  # the load ranges divide by these stiffnesses
            return problems
        problems = (
            scale.load_problems(self)
            + scale.tolerance_problems(self)
            + scale.mesh_problems(self)
            + scale.option_problems(self)
            + unused_options(self)
        )
        for i, ref in enumerate(self.references):
            if ref.finding is not None and ref.finding.reproduce_with:
                where = f"references.{i}.finding.reproduce_with"
                problems += self._reproduced_problems(where, ref.finding.reproduce_with)
        return problems

    def _reproduced_problems(self, where: str, fields: dict[str, Any]) -> list[str]:
        """The case a finding re-runs with ``fields`` set must itself be a valid case."""
        data = without_checks(self.model_dump(exclude_unset=True), list(self.methods))
        try:
            for path, value in fields.items():
                apply_field(data, path, "set", value)
            Case.model_validate(data)
        except PathError as exc:
            return [f"{where}: {exc}"]
        except ValidationError as exc:
            err = exc.errors()[0]
            inner = field_path(err["loc"]) or "(the case)"
            message = err["msg"].removeprefix("Value error, ").split("\n")[0]
            return [f"{where}: the case it re-runs is invalid: {inner}: {message}"]
        return []

    def _check_body_load(self, i: int, load: LoadSpec) -> None:
        """The beam of a distributed load, the body of a follower force and the weight densities exist."""
        beams = {} if self.mechanism is None else {b.name: b for b in self.mechanism.beams}
        if load.member is not None:
            if self.segment is not None:
                raise ValueError(f"loads.{i}.member: a segment case has one beam; omit 'member'")
            if load.member not in beams:
                raise ValueError(f"loads.{i}.member: unknown beam '{load.member}'")
        if load.kind == "force" and load.body is not None:
            if self.segment is not None:
                raise ValueError(f"loads.{i}.body: a segment case has one body; omit 'body'")
            mechanism = self.require_mechanism()
            bodies: dict[str, tuple[str, ...]] = {b.name: (b.start, b.end) for b in mechanism.beams}
            bodies.update({l.name: tuple(l.nodes) for l in mechanism.links})
            if load.body not in bodies:
                raise ValueError(f"loads.{i}.body: unknown beam or link '{load.body}'")
            if load.point not in bodies[load.body]:
                raise ValueError(f"loads.{i}.body: '{load.body}' does not reach point '{load.point}'")
        if load.kind == "self_weight":
            sections = (
                [("segment.section", self.segment.section)]
                if self.segment is not None
                else [
                    (f"beam '{b.name}'", b.section)
                    for b in self.require_mechanism().beams
                    if load.member in (None, b.name)
                ]
            )
            for where, section in sections:
                if section.weight_per_length() is None:
                    raise ValueError(
                        f"loads.{i}: self_weight needs the weight_density of {where} (or of each of its layers)"
                    )

    def n_levels(self) -> int:
        return len(self.loads[0].levels()) if self.loads else 1

    def require_segment(self) -> SegmentSpec:
        """The case's ``[segment]``; a ValueError for a mechanism case."""
        if self.segment is None:
            raise ValueError(f"case '{self.case.id}' describes a mechanism, not a segment")
        return self.segment

    def require_mechanism(self) -> MechanismSpec:
        """The case's ``[mechanism]``; a ValueError for a segment case."""
        if self.mechanism is None:
            raise ValueError(f"case '{self.case.id}' describes a segment, not a mechanism")
        return self.mechanism

    def point_names(self) -> set[str]:
        if self.segment is not None:
            return {"tip", "root"}
        return {n.name for n in self.require_mechanism().nodes} | {"input"}

    def unit(self, dimension: str) -> str:
        if dimension in ("deg", "1", "count"):
            return dimension
        return UNIT_SYSTEMS[self.case.units][dimension]


def _fields_at(model: type[Strict], location: tuple) -> list[str]:
    """The field names of the option model that ``location`` (a pydantic error location below a method's
    options) leads to, for the nearest names of an unknown one; [] where it leads to no model."""
    for part in location:
        field = model.model_fields.get(str(part)) if isinstance(model, type) else None
        if field is None:
            return []
        found = [
            a
            for a in (field.annotation, *getattr(field.annotation, "__args__", ()))
            if isinstance(a, type) and issubclass(a, Strict)
        ]
        if not found:
            return []
        model = found[0]
    return list(model.model_fields) if isinstance(model, type) else []


def without_checks(data: dict, methods: list[str]) -> dict:
    """Case data (as read from TOML) restricted to ``methods`` for a derived run (a sweep point, a stress
    variant): references and agreements dropped, ``case.unchecked`` / ``case.expected_failure`` kept only
    for the methods that remain. Modifies and returns ``data``."""
    data["references"] = []
    data["agreements"] = []
    info = data.get("case") or {}
    for key in ("unchecked", "expected_failure"):
        if key in info:
            info[key] = {m: why for m, why in info[key].items() if m in methods}
    return data
