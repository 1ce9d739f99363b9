"""Design specification files (TOML) for ``prbm-validate synthesize``, validated with pydantic v2.

A specification states what the mechanism must do (precision positions, energies or torques), the
designer's free choices, the material and the segment types; optionally the numbers a publication
printed for the same design (``[[printed]]``, each with its source), which the tests and the report
compare with the synthesis.  Angles are in degrees, other quantities in the file's unit system.
A bad file gives one line naming the file and the field (``SpecError``).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from validation.case.loader import SpecError, read_toml_model
from validation.case.schema import UNIT_SYSTEMS, Finite, Positive, Source, Strict

Point = tuple[Finite, Finite]


class DesignInfo(Strict):
    id: str = Field(pattern=r"^[A-Za-z0-9_.-]+$")
    title: str
    units: str = "in-lb"
    source: Source | None = None
    notes: list[str] = Field(default_factory=list)

    @model_validator(mode="after")
    def _units(self) -> "DesignInfo":
        if self.units not in UNIT_SYSTEMS:
            raise ValueError(f"unknown unit system '{self.units}'; use one of {', '.join(UNIT_SYSTEMS)}")
        return self


class FreeChoices(Strict):
    """Free choices of the rigid-body synthesis [bapat2015, §6.4]: link lengths R and directions
    theta (deg) of Z2, Z3, Z4 in position 1, and which closure of a dyad triangle to keep."""

    R2: Positive | None = None
    theta2: Finite | None = None
    R4: Positive | None = None
    theta4: Finite | None = None
    theta3: Finite | None = None
    gamma2: Finite | None = None
    branch_left: int | None = Field(default=None, ge=0)
    branch_right: int | None = Field(default=None, ge=0)


class Kinematics(Strict):
    """Rigid-body task.  Lists run over precision positions 2, 3 (position 1 is the reference)."""

    mechanism: Literal["four-bar", "slider-crank"] = "four-bar"
    task: Literal["function", "path", "motion", "path-timing"]
    delta: list[Point] | None = Field(default=None, description="coupler-point displacements P_j - P_1")
    phi: list[Finite] | None = Field(default=None, description="input (link 2) rotations, deg")
    gamma: list[Finite] | None = Field(default=None, description="coupler rotations, deg")
    psi: list[Finite] | None = Field(default=None, description="output (link 4) rotations, deg")
    slider_axis: Finite = Field(default=0.0, description="slider-crank: axis direction Theta1, deg")
    free: FreeChoices = FreeChoices()

    @model_validator(mode="after")
    def _complete(self) -> "Kinematics":
        need = {
            "function": ("phi", "psi"),
            "path": ("delta", "phi"),
            "motion": ("delta", "gamma"),
            "path-timing": ("delta", "phi"),
        }[self.task]
        for name in need:
            if getattr(self, name) is None:
                raise ValueError(f"task '{self.task}' needs '{name}'")
        lengths = {n: len(getattr(self, n)) for n in ("delta", "phi", "gamma", "psi") if getattr(self, n) is not None}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"lists of different lengths {lengths} (one entry per precision position 2, 3, ...)")
        n = next(iter(lengths.values()))
        if n not in (1, 2):
            raise ValueError(f"{n + 1} precision positions: two or three are supported")
        if self.mechanism == "slider-crank" and (self.task != "path-timing" or n != 1):
            raise ValueError(
                "slider-crank synthesis is implemented for two-position path generation with prescribed timing"
            )
        return self

    def n_positions(self) -> int:
        given = self.delta if self.delta is not None else self.phi
        if given is None:  # ``_complete``: every task needs delta or phi
            raise ValueError(f"task '{self.task}' gives neither 'delta' nor 'phi'")
        return 1 + len(given)


class ExtraPoint(Strict):
    """A specification at a configuration other than a precision position (slider displacement)."""

    slider: Finite
    value: Finite


class Compliance(Strict):
    """Energies or input torques at the precision positions [bapat2015, eqs 181, 182, 185]."""

    kind: Literal["energy", "torque"]
    values: list[Finite] = Field(min_length=1, description="at P1, P2, ...")
    springs: list[int] = Field(
        min_length=1, description="joints carrying a spring: 1 O2, 2 A, 3 B (or slider pin), 4 O4"
    )
    equal: list[list[int]] = Field(default_factory=list, description="groups of springs with equal constants")
    energy_free_theta2: Finite | None = Field(
        default=None, description="input angle of the energy-free state; default P1"
    )
    extra: list[ExtraPoint] = Field(default_factory=list)
    bounds: tuple[Finite, Finite] = (0.0, 1e9)
    rtol: Positive = Field(
        default=1e-6, description="accepted relative miss (least-squares designs: fewer springs than values)"
    )

    @model_validator(mode="after")
    def _springs(self) -> "Compliance":
        if any(s not in (1, 2, 3, 4) for s in self.springs) or len(set(self.springs)) != len(self.springs):
            raise ValueError("springs must be distinct joint numbers 1..4")
        for g in self.equal:
            if not set(g) <= set(self.springs):
                raise ValueError(f"equal group {g} names a joint without a spring")
        return self


class Material(Strict):
    E: Positive
    yield_strength: Positive | None = Field(default=None, description="for the stress check")
    name: str | None = None


class SegmentChoice(Strict):
    """A compliant segment realising springs on one PRB link [bapat2015, eqs 186-188]."""

    kind: Literal["slfp", "fixed-pinned", "fixed-guided"]
    link: Literal["Z2", "Z3", "Z4"]
    springs: list[int] = Field(min_length=1, max_length=2)
    width: Positive
    fraction: Positive = Field(default=0.05, description="SLFP: flexure length l = fraction * rigid length L")
    gamma: Positive | None = Field(default=None, description="characteristic radius factor (fixed-pinned/-guided)")
    K_theta: Positive | None = Field(default=None, description="stiffness coefficient (fixed-pinned/-guided)")

    @model_validator(mode="after")
    def _params(self) -> "SegmentChoice":
        if self.kind != "slfp" and (self.gamma is None or self.K_theta is None):
            raise ValueError(f"a {self.kind} segment needs 'gamma' and 'K_theta'")
        if self.kind == "fixed-guided" and len(self.springs) != 2:
            raise ValueError("a fixed-guided segment realises two springs (one at each end)")
        if self.kind != "fixed-guided" and len(self.springs) != 1:
            raise ValueError(f"a {self.kind} segment realises one spring")
        return self


class Verification(Strict):
    """How the generated case drives the FEM: 'input-rotation' (rigid input link turned, torque
    measured), 'output-rotation' (rigid link 4 turned), 'coupler-x-rotation' (coupler-point X and
    coupler rotation prescribed, Y free, as in the dissertation's chapter-5 verifications)."""

    drive: Literal["input-rotation", "output-rotation", "coupler-x-rotation"] = "coupler-x-rotation"
    elements: int = Field(default=16, ge=1)
    run_fem: bool = True


class Printed(Strict):
    """A number printed for this design, for comparison (never used by the solver)."""

    name: str = Field(description="design quantity, e.g. Z1, gamma3, k1, t2, l4, I2, or fem.input_torque.P2")
    value: Finite | Point
    decimals: int | None = Field(
        default=None, ge=0, description="printed decimals; tolerance = half a unit of the last"
    )
    tolerance: Positive | None = None
    label: Literal["PRBM", "ANSYS", "design"] = "design"
    expect: Literal["reproduce", "misprint", "not-reproduced", "record"] = "reproduce"
    source: Source
    finding: str | None = None

    def allowed(self) -> float:
        if self.tolerance is not None:
            return self.tolerance
        if self.decimals is not None:
            return 0.5 * 10.0 ** (-self.decimals) * (1 + 1e-9) + 1e-12
        return 1e-9


class FixedGuidedTwoPosition(Strict):
    """[bapat2015, §3.8]: fixed-guided segment with one inflection point, two positions.  Beam-frame
    load P, load ratio n (n > 0 compressive), end angle theta0; end displacements dX, dY in a frame
    rotated by ``orientation`` from the beam."""

    P: Finite
    n: Finite
    theta0: Finite = 0.0
    dX: Finite
    dY: Finite
    orientation: Finite = 0.0
    width: Positive
    guess: tuple[Positive, Positive] | None = Field(default=None, description="initial (l, I)")


class FrameworkSegment(Strict):
    """One fixed-guided beam of a chapter-5 design: its free choices [bapat2015, §5.3]."""

    name: str = Field(pattern=r"^[A-Za-z0-9_]+$")
    theta1: Finite = Field(description="deg, direction of the undeformed beam")
    n1: list[Finite] = Field(description="load factors n1j at positions 2, 3, ...")
    fixed: dict[str, Finite] = Field(default_factory=dict, description="free choices R2_j, Theta2_j, R3_j, Theta3_j")
    energy: list[Positive] | None = Field(default=None, description="energy stored by this beam at positions 2, 3, ...")
    width: Positive | None = None

    @model_validator(mode="after")
    def _names(self) -> "FrameworkSegment":
        for key in self.fixed:
            if not re.fullmatch(r"(R2|Theta2|R3|Theta3)_[2-9]", key):
                raise ValueError(f"unknown free choice '{key}' (use R2_j, Theta2_j, R3_j or Theta3_j, j >= 2)")
        return self


class Framework(Strict):
    """[bapat2015, ch. 5]: fixed-guided beams with one inflection point carrying a rigid coupler."""

    delta: list[Point] = Field(min_length=1, description="coupler-point displacements P_j - P_1")
    gamma: list[Finite] = Field(description="coupler rotations, deg")
    force: list[Positive] | None = Field(default=None, description="effecting force magnitudes F_j")
    segments: list[FrameworkSegment] = Field(min_length=1)

    @model_validator(mode="after")
    def _lengths(self) -> "Framework":
        n = len(self.delta)
        if len(self.gamma) != n or (self.force is not None and len(self.force) != n):
            raise ValueError(f"delta, gamma (and force) need one entry per precision position 2..{n + 1}")
        for s in self.segments:
            if len(s.n1) != n or (s.energy is not None and len(s.energy) != n):
                raise ValueError(f"segment '{s.name}': n1 (and energy) need {n} entries")
        return self


class Spec(Strict):
    design: DesignInfo
    kinematics: Kinematics | None = None
    compliance: Compliance | None = None
    material: Material
    segments: list[SegmentChoice] = Field(default_factory=list)
    fixed_guided: FixedGuidedTwoPosition | None = None
    framework: Framework | None = None
    verification: Verification = Verification()
    printed: list[Printed] = Field(default_factory=list)

    @model_validator(mode="after")
    def _coherent(self) -> "Spec":
        if sum(x is not None for x in (self.kinematics, self.fixed_guided, self.framework)) != 1:
            raise ValueError(
                "give exactly one of [kinematics] (chapter 6), [fixed_guided] (section 3.8) or [framework] (chapter 5)"
            )
        if self.compliance is not None and self.kinematics is not None:
            n = self.kinematics.n_positions()
            if len(self.compliance.values) != n:
                raise ValueError(
                    f"compliance.values has {len(self.compliance.values)} entries for {n} precision positions"
                )
        covered = [s for seg in self.segments for s in seg.springs]
        if len(set(covered)) != len(covered):
            raise ValueError("a spring is realised by two segments")
        if self.compliance is not None and self.segments and set(covered) != set(self.compliance.springs):
            raise ValueError(
                f"segments realise springs {sorted(covered)} but the PRBM has {sorted(self.compliance.springs)}"
            )
        return self


def load_spec(path: Path | str) -> Spec:
    """Read and validate a specification; ``SpecError`` with a one-line message on any problem."""
    return read_toml_model(path, Spec, SpecError)[1]
