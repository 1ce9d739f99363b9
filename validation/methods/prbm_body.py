"""The PRBM adapter for one beam carrying a rigid body, and for the curved pinned-pinned beam.

One beam fixed at one end whose other end E carries rigid links (chapter 5 Example 1; no ``links``
option): the loads of each level (dead forces and couples at nodes of those links) are given to
``prbm.solve_segment_with_body`` in the beam frame (x from the fixed end O along O->E), which transfers
them to E with the current offsets (M + r x F) and solves the segment model forward. Segment model:
``segment_type = 'fixed-guided-inflection'`` (or option ``segment_model = 'inflection'``) -> the
chapter-3/5 inflection PRBM (eqs 83-104 = 131-152); 'fixed-pinned', 'fixed-free' or none ->
fixed_pinned_tip / pure_moment_tip / fixed_guided_monotonic_tip as for a single segment; 'slfp' ->
the beam is the flexure and the body the rigid segment (eqs 71-76). Outputs at any body node (or E):
x, y, dx, dy, rotation (of the body, deg), strain_energy (PRBM springs). Shapes: the PRB chain of
the beam, then the body through its nodes.

One initially curved beam pinned at one end and on a slider along its chord at the other, a force
along the chord at the slider: ``prbm.curved_pinned_pinned`` (two curved fixed-pinned halves fixed at
mid-span, [bapat2015, §2.3.5]).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

import prbm
from validation.case.method_options import PrbmOptions
from validation.case.schema import BeamSpec, LinkSpec
from validation.methods.base import MethodRun, NotApplicable
from validation.methods.prbm_atlas import flag_atlas_levels
from validation.methods.prbm_common import plain, polyline, prefer


def one_beam_carrying_a_body(mech) -> bool:
    """One beam, fixed at one end by the only support, its other end not released by a joint
    (chapter 5 Example 1): the segment-with-body path and its chapter-3/5 models apply."""
    if len(mech.beams) != 1 or len(mech.supports) != 1 or mech.supports[0].kind != "fixed":
        return False
    beam = mech.beams[0]
    root = mech.supports[0].node
    if root not in (beam.start, beam.end):
        return False
    end = beam.end if root == beam.start else beam.start
    return not any(j.node == end for j in mech.joints)


@dataclass
class CarriedBody:
    """The beam O -> E (fixed at O) and the rigid body at E: its nodes (complex, case frame), the
    links through E, and the beam frame (x from O along O -> E): ``to_local`` = e^{-i angle(E - O)}."""

    beam: BeamSpec
    root: str
    end: str
    nodes: dict[str, complex]
    body: set[str]
    links: list[LinkSpec]
    length: float
    EI: float
    to_local: complex

    @property
    def O(self) -> complex:
        return self.nodes[self.root]

    @property
    def E(self) -> complex:
        return self.nodes[self.end]


def _carried_body(mech) -> CarriedBody:
    beam = mech.beams[0]
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    fixed = {s.node for s in mech.supports if s.kind == "fixed"}
    if len(mech.supports) != 1 or not fixed & {beam.start, beam.end}:
        raise NotApplicable(
            "one beam with one fixed end and nothing else supported is the only "
            "non-four-bar mechanism the PRBM adapter models"
        )
    root, end = (beam.start, beam.end) if beam.start in fixed else (beam.end, beam.start)
    if any(j.node == end for j in mech.joints):
        raise NotApplicable(f"a joint at the beam end '{end}': the body is not rigidly attached")
    if beam.curvature != 0.0:
        raise NotApplicable("an initially curved beam carrying a rigid body")
    links = [lk for lk in mech.links if end in lk.nodes]
    O, E = nodes[root], nodes[end]
    return CarriedBody(
        beam,
        root,
        end,
        nodes,
        {end} | {nd for lk in links for nd in lk.nodes},
        links,
        abs(E - O),
        beam.section.stiffness(beam.E or mech.E)[1],
        cmath.exp(-1j * cmath.phase(E - O)),
    )


def _segment_model(cb: CarriedBody, options: PrbmOptions):
    """(the beam's segment model: an InflectionBeam or a tip(F, M) function, its kind)."""
    L, EI = cb.length, cb.EI
    kind = cb.beam.segment_type or (
        "fixed-guided-inflection" if options.segment_model == "inflection" else "fixed-pinned"
    )
    family = options.family
    if kind in ("fixed-guided-inflection", "inflection"):
        return prbm.InflectionBeam(L, EI, family), kind
    if kind in ("fixed-pinned", "fixed-free"):
        return _tip_model(L, EI, family, options.extrapolate), kind
    if kind == "slfp":  # the beam is the flexure; the body is the rigid segment (eqs 71-76)

        def model(F: complex, M: float):
            return prbm.slfp_end_tip(F, M, flexure_length=L, EI=EI)

        return model, kind
    raise NotApplicable(f"segment type '{kind}' carrying a rigid body: not modelled")


def _body_loads(case, cb: CarriedBody) -> list[list]:
    """Per level, the loads on the body as ``prbm.BodyLoad`` in the beam frame (offsets from E)."""
    per_level: list[list] = [[] for _ in range(case.n_levels())]
    for i, load in enumerate(case.loads):
        if load.point not in cb.body:
            raise NotApplicable(f"loads.{i} acts on '{load.point}', not on the body carried by '{cb.beam.name}'")
        if load.kind not in ("force", "moment") or load.follower:
            raise NotApplicable(f"loads.{i}: only dead forces and couples on the body are modelled")
        r0 = (cb.nodes[load.point] - cb.E) * cb.to_local
        for lv, v in enumerate(load.levels()):
            if load.kind == "force":
                per_level[lv].append(prbm.BodyLoad(r0, force=complex(*load.direction) * v * cb.to_local))
            else:
                per_level[lv].append(prbm.BodyLoad(r0, moment=v))
    return per_level


def _body_values(cb: CarriedBody, results: dict, requests) -> dict:
    values = {}
    to_global = 1.0 / cb.to_local
    for req in requests:
        res = results[req.level]
        if req.point not in cb.body:
            raise NotApplicable(f"point '{req.point}' is not on the body carried by '{cb.beam.name}'")
        z = cb.O + res.extras["points"][req.point] * to_global
        z0 = cb.nodes[req.point]
        table = {
            "x": z.real,
            "y": z.imag,
            "dx": (z - z0).real,
            "dy": (z - z0).imag,
            "rotation": math.degrees(float(res.outputs["rotation"])),
            "strain_energy": float(res.outputs.get("U", res.outputs.get("strain_energy", np.nan))),
        }
        if req.quantity not in table:
            raise NotApplicable(f"the PRBM of a segment with a rigid body gives no '{req.quantity}'")
        values[req] = float(table[req.quantity]) if res.converged else math.nan
    return values


def _body_shapes(cb: CarriedBody, results: dict, model, kind: str, n: int) -> list:
    """Per level: the PRB chain of the beam, then each body link through its nodes (case frame)."""
    shapes: list[list[np.ndarray]] = []
    to_global = 1.0 / cb.to_local
    L = cb.length
    for lv in range(n):
        res = results[lv]
        if not res.converged:
            shapes.append([])
            continue
        seg = res.extras["segment"]
        if seg is None:
            chain = np.array([0.0, L])
        elif isinstance(model, prbm.InflectionBeam):
            chain = prbm.inflection_pivots(seg.outputs) @ np.array([1.0, 1j])
        else:
            g = float(np.asarray(seg.constants.get("gamma", 0.5 if kind == "slfp" else np.nan)).ravel()[0])
            chain = np.array([0.0, (1 - g) * L, complex(float(res.outputs["a"]), float(res.outputs["b"]))])
        lines = [polyline(cb.O + chain * to_global)]
        for link in cb.links:
            lines.append(polyline([cb.O + res.extras["points"][nm] * to_global for nm in link.nodes]))
        shapes.append(lines)
    return shapes


def run_segment_with_body(case, requests, options: PrbmOptions, info: MethodRun) -> dict:
    """A [mechanism] of one beam, fixed at one end, whose other end carries the rigid links through it
    (see the module docstring)."""
    cb = _carried_body(case.mechanism)
    model, kind = _segment_model(cb, options)
    n = case.n_levels()
    per_level = _body_loads(case, cb)
    offsets = {name: (cb.nodes[name] - cb.E) * cb.to_local for name in cb.body}
    needed = sorted({r.level for r in requests} | set(range(n)))
    results = {
        lv: prbm.solve_segment_with_body(
            model, per_level[lv], offsets, rest=(cb.length, 0.0, 0.0), prefer=prefer(options)
        )
        for lv in needed
    }
    values = _body_values(cb, results, requests)
    info.converged = all(results[lv].converged for lv in needed)
    info.level_converged = {lv: bool(results[lv].converged) for lv in needed}
    info.level_messages = {lv: results[lv].message for lv in needed}
    info.message = (
        f"PRBM {kind} segment '{cb.beam.name}' carrying a rigid body (M + r x F at the current pose); "
        + "; ".join(f"level {lv}: {results[lv].message}" for lv in needed)
    )
    info.extras.update(
        {
            "shapes": _body_shapes(cb, results, model, kind, n),
            "model": results[needed[-1]].model,
            "end_loads": {lv: {k: float(results[lv].outputs[k]) for k in ("Fx", "Fy", "M")} for lv in needed},
        }
    )
    return values


def run_pinned_pinned(case, requests, info: MethodRun) -> dict:
    """One initially curved beam pinned at one end and on a slider along its chord at the other, a
    force along the chord at the slider: ``prbm.curved_pinned_pinned`` (two curved fixed-pinned halves
    fixed at mid-span, [bapat2015, §2.3.5]). Outputs at the slider node: x, y, dx, dy (the chord's
    change along the chord), force_x, force_y (the applied force)."""
    mech = case.mechanism
    beam = mech.beams[0]
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    slider = next(s for s in mech.supports if s.kind == "slider")
    if slider.node not in (beam.start, beam.end):
        raise NotApplicable("the slider does not hold the beam's end")
    pin = beam.start if slider.node == beam.end else beam.end
    chord_vector = nodes[slider.node] - nodes[pin]
    chord0 = abs(chord_vector)
    along = chord_vector / chord0
    if (
        slider.direction is None
        or abs(abs(complex(*slider.direction) / abs(complex(*slider.direction)) * along.conjugate()) - 1.0) > 1e-9
        or abs((complex(*slider.direction) * along.conjugate()).imag) > 1e-9 * abs(complex(*slider.direction))
    ):
        raise NotApplicable("the slider's free direction is not along the chord")
    if beam.curvature == 0.0:
        raise NotApplicable("a straight pinned-pinned beam under a chord force does not bend (no PRBM)")
    n = case.n_levels()
    force = np.zeros(n, complex)
    for i, load in enumerate(case.loads):
        if load.point != slider.node or load.kind != "force" or load.follower:
            raise NotApplicable(f"loads.{i}: only a dead force at the slider '{slider.node}' is modelled")
        force += np.asarray(load.levels(), float) * complex(*load.direction)
    if np.any(np.abs((force * along.conjugate()).imag) > 1e-12 * np.maximum(np.abs(force), 1e-300)):
        raise NotApplicable("the force at the slider is not along the chord")
    F_axial = (force * along.conjugate()).real  # + pulls the pins apart
    EI = beam.section.stiffness(beam.E or mech.E)[1]
    kappa = beam.curvature
    length = 2.0 / abs(kappa) * math.asin(min(1.0, abs(kappa) * chord0 / 2.0))  # arc over the chord
    res = prbm.curved_pinned_pinned(F_axial, length=length, EI=EI, curvature=abs(kappa))
    chord = np.broadcast_to(res.outputs["chord"], (n,))
    tip = nodes[pin] + chord * along
    table = {
        "x": tip.real,
        "y": tip.imag,
        "dx": (tip - nodes[slider.node]).real,
        "dy": (tip - nodes[slider.node]).imag,
        "force_x": force.real,
        "force_y": force.imag,
    }
    values = {}
    for req in requests:
        if req.point != slider.node or req.quantity not in table:
            raise NotApplicable(f"the curved pinned-pinned PRBM gives no '{req.quantity}' at '{req.point}'")
        values[req] = float(table[req.quantity][req.level])
    info.converged = bool(res.converged)
    converged = res.level_converged if res.level_converged is not None else np.asarray(res.converged)
    info.level_converged = {lv: bool(ok) for lv, ok in enumerate(np.broadcast_to(converged, (n,)))}
    info.message = f"{res.model}; constant gamma = {res.constants['gamma']}, K_Theta = {res.constants['K_theta']}"
    info.extras.update({"model": res.model, "constants": plain(res.constants)})
    flag_atlas_levels(
        info,
        {
            lv: (
                "pinned_pinned",
                {
                    "kappa0": abs(kappa) * length,
                    "sense": 1.0 if f >= 0 else -1.0,
                    "load": abs(f) * length * length / EI,
                },
                1.0,
            )
            for lv, f in enumerate(F_axial.tolist())
        },
    )
    return values


def _tip_model(L: float, EI: float, family: str, extrapolate: str):
    """tip(F, M) of a straight fixed-free segment (segment frame, M CCW), as the single-segment branch."""

    def tip(F: complex, M: float):
        if F.imag == 0 and F.real != 0:
            raise NotApplicable("a purely axial end force: outside every PRBM n-fit (n infinite)")
        if F == 0:
            return prbm.pure_moment_tip(M, length=L, EI=EI)
        n_ratio = -F.real / F.imag
        if M == 0:
            return prbm.fixed_pinned_tip(F.imag, n_ratio, length=L, EI=EI, family=family, extrapolate=extrapolate)
        return prbm.fixed_guided_monotonic_tip(
            F.imag, n_ratio, M, length=L, EI=EI, family=family, extrapolate=extrapolate
        )

    return tip
