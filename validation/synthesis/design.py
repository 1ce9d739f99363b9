"""From a specification to a PRBM design: rigid-body synthesis, springs, segment dimensions.

The generalised procedure of [bapat2015, ch. 6], in the order of section 6.3:
kinematics first (section 6.4, ``prbm.synthesis.dyads``), then the energy/torque equations for the spring
constants (section 6.5, ``prbm.synthesis.compliance``), then the segments realising them (eqs 186-188,
``prbm.synthesis.segments``) with a stress check.  The kinematics and compliance equations are weakly
coupled (section 6.2), so each step takes the previous one's answer as given.

``design(spec)`` returns a ``Design`` whose ``values`` is a flat table of named numbers (Z1..Z6 as
complex, phi2, gamma3, psi2, Theta30, k1..k4, l2, I2, t2, L2, ...), the names used by ``[[printed]]``
entries of a specification.  A specification with no solution raises ``SynthesisError``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from prbm.synthesis import compliance as cp
from prbm.synthesis import fixed_guided as fixed_guided_prbm
from prbm.synthesis import segments as sg
from prbm.synthesis.dyads import (
    DEG,
    FourBarDesign,
    SliderCrankDesign,
    SynthesisError,
    function_generation,
    motion_generation,
    path_generation,
    path_generation_timed,
    polar,
    slider_crank_timed,
)
from prbm.synthesis.framework import solve_framework
from prbm.synthesis.segments import rectangle_thickness
from validation.synthesis.spec import Spec

# joint -> (link it belongs to, which end): 1 O2 and 2 A on Z2, 4 O4 and 3 B on Z4
SPRING_LINK = {1: ("Z2", "ground"), 2: ("Z2", "moving"), 3: ("Z4", "moving"), 4: ("Z4", "ground")}


@dataclass
class Design:
    spec: Spec
    mechanism: FourBarDesign | SliderCrankDesign | None = None
    free_state: cp.Configuration | None = None
    positions: list[cp.Configuration] = field(default_factory=list)
    springs: cp.SpringResult | None = None
    segments: list[sg.SegmentDesign] = field(default_factory=list)
    values: dict[str, float | complex] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)
    success: bool = True
    extra: dict = field(default_factory=dict)

    def linkage(self) -> FourBarDesign | SliderCrankDesign:
        """The synthesized linkage (``design`` sets it before any step that reads it)."""
        if self.mechanism is None:
            raise SynthesisError("no linkage has been synthesized yet")
        return self.mechanism

    def energy_free(self) -> cp.Configuration:
        """The energy-free configuration (``design`` sets it with the linkage)."""
        if self.free_state is None:
            raise SynthesisError("the energy-free configuration has not been found yet")
        return self.free_state

    def spring_constants(self) -> cp.SpringResult:
        """The solved spring constants (``design`` solves them before sizing the segments)."""
        if self.springs is None:
            raise SynthesisError("the spring constants have not been solved yet")
        return self.springs


def rigid_body(spec: Spec) -> FourBarDesign | SliderCrankDesign:
    """Section 6.4 with the specification's free choices."""
    k = spec.kinematics
    if k is None:
        raise SynthesisError("rigid-body synthesis needs [kinematics]")
    f = k.free
    deltas = [complex(*d) for d in k.delta] if k.delta is not None else []

    def link(R, theta, name):
        if (R is None) != (theta is None):
            raise SynthesisError(f"free choice {name}: give both R{name[-1]} and theta{name[-1]}")
        return None if R is None else polar(R, theta)

    def needed(rotations: list[float] | None, name: str) -> list[float]:
        """Rotations the task needs (``Kinematics._complete`` has checked they are given)."""
        if rotations is None:
            raise SynthesisError(f"task '{k.task}' needs '{name}'")
        return rotations

    if k.mechanism == "slider-crank":
        if f.R2 is None or f.theta3 is None:
            raise SynthesisError("slider-crank synthesis needs free choices R2 and theta3")
        return slider_crank_timed(
            deltas[0].real if k.slider_axis == 0 else abs(deltas[0]),
            needed(k.phi, "phi")[0],
            R2=f.R2,
            theta3=f.theta3,
            theta1=k.slider_axis,
            branch=f.branch_left,
        )
    if k.task == "function":
        if f.theta2 is None or f.theta3 is None or f.R4 is None or f.gamma2 is None:
            raise SynthesisError(
                "function generation needs free choices theta2, theta3, R4 and gamma2 (seed 6.7 Example 2)"
            )
        return function_generation(
            needed(k.phi, "phi"),
            needed(k.psi, "psi"),
            theta2=f.theta2,
            theta3=f.theta3,
            R4=f.R4,
            gamma2=f.gamma2,
            branch=f.branch_left,
        )
    Z2, Z4 = link(f.R2, f.theta2, "Z2"), link(f.R4, f.theta4, "Z4")
    if k.task == "motion":
        return motion_generation(
            deltas,
            needed(k.gamma, "gamma"),
            Z2=Z2,
            Z4=Z4,
            phi=k.phi,
            psi=k.psi,
            branch_left=f.branch_left,
            branch_right=f.branch_right,
        )
    if k.task == "path-timing":
        return path_generation_timed(
            deltas,
            needed(k.phi, "phi"),
            Z2=Z2,
            gamma=k.gamma,
            Z4=Z4,
            psi=k.psi,
            branch_left=f.branch_left,
            branch_right=f.branch_right,
        )
    return path_generation(
        deltas,
        phi=needed(k.phi, "phi"),
        gamma=k.gamma,
        Z2=Z2,
        Z4=Z4,
        psi=k.psi,
        branch_left=f.branch_left,
        branch_right=f.branch_right,
    )


def _record_kinematics(d: Design) -> None:
    m, v = d.linkage(), d.values
    for name, z in m.vectors().items():
        v[name] = z
    n = len(m.phi)
    for j in range(1, n):
        v[f"phi{j + 1}"] = m.phi[j]
        v[f"gamma{j + 1}"] = m.gamma[j]
        if isinstance(m, FourBarDesign):
            v[f"psi{j + 1}"] = m.psi[j]
    for j, c in enumerate(d.positions):
        for i, a in enumerate(c.angles):
            v[f"Theta{i + 2}{j + 1}" if j < 9 else f"Theta{i + 2}_{j + 1}"] = a
    if d.free_state is not None:
        for i, a in enumerate(d.free_state.angles):
            v[f"Theta{i + 2}0"] = a


def _segment_for(spec: Spec, d: Design, choice) -> sg.SegmentDesign:
    m, mat = d.linkage(), spec.material
    R = abs(getattr(m, choice.link))
    ks = [d.spring_constants().k[s - 1] for s in choice.springs]
    if max(ks) - min(ks) > 1e-9 * max(1.0, max(ks)):
        raise SynthesisError(
            f"segment on {choice.link} realises springs {choice.springs} with different constants "
            f"{ks}; add them to one 'equal' group"
        )
    k = ks[0]
    if choice.kind == "slfp":
        seg = sg.slfp(
            k, R=R, E=mat.E, width=choice.width, fraction=choice.fraction, link=choice.link, springs=choice.springs
        )
    elif choice.kind == "fixed-pinned":
        seg = sg.fixed_pinned(
            k,
            R=R,
            E=mat.E,
            width=choice.width,
            gamma=choice.gamma,
            K_theta=choice.K_theta,
            link=choice.link,
            springs=choice.springs,
        )
    else:
        seg = sg.fixed_guided(
            k,
            R=R,
            E=mat.E,
            width=choice.width,
            gamma=choice.gamma,
            K_theta=choice.K_theta,
            link=choice.link,
            springs=choice.springs,
        )
    beta0, _ = cp.springs_at(m, d.energy_free())
    rotations = [abs(cp.springs_at(m, c)[0][s - 1] - beta0[s - 1]) for c in d.positions for s in choice.springs]
    seg.max_moment = k * max(rotations)
    seg.max_stress = seg.stress(seg.max_moment)
    return seg


def _stress_constraints(spec: Spec, d: Design, A_configs) -> dict:
    """SLFP stress <= yield as constraints g(k) <= 0 while k is unknown [bapat2015, Example 1, eq 186]."""
    if spec.material.yield_strength is None:
        return {}
    m = d.linkage()
    beta0, _ = cp.springs_at(m, d.energy_free())
    out = {}
    for choice in spec.segments:
        if choice.kind != "slfp":
            continue
        s = choice.springs[0]
        rot = max(abs(cp.springs_at(m, c)[0][s - 1] - beta0[s - 1]) for c in A_configs)
        R = abs(getattr(m, choice.link))

        def g(k, s=s, rot=rot, R=R, choice=choice):
            stress = sg.slfp_stress_from_k(
                max(k[s - 1], 1e-300), rot, R=R, E=spec.material.E, width=choice.width, fraction=choice.fraction
            )
            return stress / spec.material.yield_strength - 1.0

        out[f"stress of the SLFP at joint {s} <= yield"] = g
    return out


def design(spec: Spec) -> Design:
    """The whole synthesis; ``SynthesisError`` when the specification has no solution."""
    if spec.fixed_guided is not None:
        return two_position_design(spec)
    if spec.framework is not None:
        return framework_design(spec)
    d = Design(spec)
    d.mechanism = rigid_body(spec)
    m = d.mechanism
    c = spec.compliance
    if isinstance(m, SliderCrankDesign):
        extra = [e.slider for e in c.extra] if c is not None else []
        d.free_state, d.positions = cp.slider_configurations(m, extra)
    else:
        d.free_state, d.positions = cp.four_bar_configurations(m, c.energy_free_theta2 if c else None)
        if m.loop_error() > 1e-9:
            raise SynthesisError(f"the synthesized linkage does not close (error {m.loop_error():.3g})")
        for name, z in (("Z2", m.Z2), ("Z3", m.Z3), ("Z4", m.Z4), ("Z1", m.Z1)):
            if abs(z) < 1e-9:
                raise SynthesisError(f"the synthesized linkage degenerates: {name} has zero length")
    _record_kinematics(d)
    if c is None:
        return d
    targets = list(c.values) + [e.value for e in c.extra]
    A = cp.design_rows(m, d.free_state, d.positions, c.kind)
    d.springs = cp.solve_springs(
        A,
        targets,
        springs=c.springs,
        groups=_groups(c),
        bounds=c.bounds,
        constraints=_stress_constraints(spec, d, d.positions),
        label=c.kind,
        rtol=c.rtol,
    )
    d.messages.append(d.springs.message)
    d.success = d.springs.success
    for i, k in enumerate(d.springs.k):
        if i + 1 in c.springs:
            d.values[f"k{i + 1}"] = float(k)
    for j, (a, t) in enumerate(zip(d.springs.achieved, targets)):
        label = d.positions[j].label
        d.values[f"{c.kind}.{label}"] = float(a)
    d.segments = [_segment_for(spec, d, ch) for ch in spec.segments]
    for seg in d.segments:
        tag = seg.link[1:] if seg.kind != "slfp" else str(seg.springs[0])
        d.values[f"l{tag}"] = seg.length
        d.values[f"I{tag}"] = seg.I
        d.values[f"t{tag}"] = seg.thickness
        if seg.kind == "slfp":
            d.values[f"L{seg.link[1:]}"] = seg.rigid_length
        d.values[f"stress{tag}"] = seg.max_stress
        ys = spec.material.yield_strength
        if ys is not None and seg.max_stress > ys * (1 + 1e-9):
            d.success = False
            d.messages.append(
                f"segment {seg.kind} on {seg.link}: PRBM stress {seg.max_stress:.4g} exceeds the "
                f"yield strength {ys:.4g}; widen the segment or lower the energy/torque"
            )
    return d


def _groups(c) -> list[list[int]]:
    grouped = [list(g) for g in c.equal]
    seen = {s for g in grouped for s in g}
    return grouped + [[s] for s in c.springs if s not in seen]


def compare_printed(d: Design) -> list[dict]:
    """Every ``[[printed]]`` design number beside the synthesized one (FEM entries are skipped)."""
    rows: list[dict[str, Any]] = []
    for p in d.spec.printed:
        if p.name.startswith("fem."):
            continue
        got = d.values.get(p.name)
        if got is None:
            rows.append(
                {
                    "name": p.name,
                    "printed": p.value,
                    "synthesized": None,
                    "difference": math.nan,
                    "allowed": p.allowed(),
                    "agrees": False,
                    "expect": p.expect,
                    "source": p.source.label(),
                    "finding": p.finding or "not computed by this synthesis",
                }
            )
            continue
        if isinstance(p.value, tuple):
            printed = complex(*p.value)
            diff = max(abs(complex(got).real - printed.real), abs(complex(got).imag - printed.imag))
        else:
            printed = p.value
            diff = abs(float(np.real(got)) - printed)
        rows.append(
            {
                "name": p.name,
                "printed": p.value,
                "synthesized": got,
                "difference": diff,
                "allowed": p.allowed(),
                "agrees": diff <= p.allowed(),
                "expect": p.expect,
                "source": p.source.label(),
                "finding": p.finding,
            }
        )
    return rows


def framework_design(spec: Spec) -> Design:
    """Chapter 5: every beam of ``[framework]`` solved on its own (they share delta_j and gamma_j)."""

    fw, d = spec.framework, Design(spec)
    if fw is None:
        raise SynthesisError("framework synthesis needs [framework]")
    for seg in fw.segments:
        try:
            root = solve_framework(
                theta1=seg.theta1,
                delta=[complex(*p) for p in fw.delta],
                gamma=fw.gamma,
                n1=seg.n1,
                fixed=seg.fixed,
                energy=seg.energy,
                force=fw.force,
            )[0]
        except SynthesisError as exc:
            d.success = False
            d.messages.append(f"beam '{seg.name}': {exc}")
            continue
        for k, v in root.items():
            d.values[f"{seg.name}.{k}"] = v
        if "EI" in root:
            I = root["EI"] / spec.material.E
            d.values[f"{seg.name}.I"] = I
            if seg.width is not None:
                d.values[f"{seg.name}.t"] = rectangle_thickness(I, seg.width)
        d.messages.append(
            f"beam '{seg.name}': R6 = {root['R6']:.4f}, R5 = {root['R5']:.4f}, Theta5 = {root['Theta5']:.3f} deg"
        )
    return d


def two_position_design(spec):
    """``Design`` for a ``[fixed_guided]`` specification [bapat2015, §3.8]."""
    fg = spec.fixed_guided
    alpha = fg.orientation * DEG
    b = fg.dX * math.sin(alpha) + fg.dY * math.cos(alpha)
    delta = fg.dX * math.cos(alpha) - fg.dY * math.sin(alpha)
    roots = fixed_guided_prbm.solve_two_position(
        E=spec.material.E, P=fg.P, n=fg.n, theta0_deg=fg.theta0, b=b, delta=delta, guess=fg.guess
    )
    d = Design(spec)
    distinct = []
    for r in roots:
        if not any(abs(r[0] - q[0]) < 1e-6 * r[0] for q in distinct):
            distinct.append(r)
    l, I, M, l1, theta10, st = distinct[0]
    d.values.update(
        l=float(l),
        I=float(I),
        M=float(M),
        l1=float(l1),
        theta10=math.degrees(theta10),
        t=rectangle_thickness(I, fg.width),
        b=b,
        delta=delta,
        n2=float(st["n2"]),
    )
    d.extra["roots"] = [{"l": r[0], "I": r[1], "M": r[2], "l1": r[3]} for r in distinct]
    d.messages.append(
        f"{len(distinct)} distinct root(s) of the section-3.8 equations; the shortest beam is reported"
        + ("" if len(distinct) == 1 else f" (others: l = {', '.join(f'{r[0]:.4f}' for r in distinct[1:])})")
    )
    ys = spec.material.yield_strength
    if ys is not None:
        # largest moment along the beam: the larger end moment of the two fixed-pinned parts
        stress = (
            max(abs(M), abs(st["F"] * l1 * math.sin(st["phi1"] - st["Theta1"]) * st["gamma1"]))
            * d.values["t"]
            / (2 * I)
        )
        d.values["stress"] = stress
        if stress > ys:
            d.success = False
            d.messages.append(f"PRBM stress estimate {stress:.4g} exceeds the yield strength {ys:.4g}")
    return d
