"""The synthesized compliant mechanism as a case file of the project (``validation/case/schema.py``).

The mesh is built in the energy-free configuration (Theta20, Theta30, Theta40), O2 at the origin,
following the conventions of ``cases/chapter6/*.toml``: a node shared by a beam end and a rigid link
is a rigid connection; a revolute joint without a spring is a ``[[joints]]`` entry; a segment is
placed as [bapat2015] places it --

* SLFP (eq. 186): a flexure of length l centred on its PRB pivot, along its link;
* fixed-guided (eq. 188): one beam of length l = R / gamma centred on the PRB link, clamped to the
  ground and to the coupler (its pivots sit (1 - gamma) l / 2 from each end);
* fixed-pinned (eq. 187): a beam of length l = R / gamma from the pin, clamped at its far end, the
  characteristic pivot at gamma l from the pin.

Load levels are the precision positions P1, P2, ...; the drive is chosen by the specification
(``[verification].drive``).
"""

from __future__ import annotations

import math
from pathlib import Path

from prbm.synthesis import compliance as cp
from prbm.synthesis.segments import SegmentDesign
from prbm.synthesis.dyads import FourBarDesign, SynthesisError, arg_deg, polar


def _fmt(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int,)) and not isinstance(value, bool):
        return str(value)
    if hasattr(value, "item") and not isinstance(value, (list, tuple, dict, str)):
        value = value.item()  # numpy scalar
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(round(value, 10)) if math.isfinite(value) else "nan"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {_fmt(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def toml_text(data: dict, header: str = "") -> str:
    """A small TOML writer for case files: top-level scalars, tables, arrays of tables; anything
    nested deeper is written inline."""
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    scalars = {k: v for k, v in data.items() if not isinstance(v, dict) and not _is_table_array(v)}
    for k, v in scalars.items():
        lines.append(f"{k} = {_fmt(v)}")
    for k, v in data.items():
        if isinstance(v, dict):
            _table(lines, k, v)
    for k, v in data.items():
        if _is_table_array(v):
            for item in v:
                lines.append("")
                lines.append(f"[[{k}]]")
                lines += [f"{kk} = {_fmt(vv)}" for kk, vv in item.items()]
    return "\n".join(lines) + "\n"


def _is_table_array(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(lines, name, table):
    lines.append("")
    lines.append(f"[{name}]")
    subtables = {}
    for k, v in table.items():
        if isinstance(v, dict) and name == "methods":
            subtables[k] = v
        elif _is_table_array(v):
            lines.append(f"{k} = [")
            lines += [f"  {_fmt(item)}," for item in v]
            lines.append("]")
        else:
            lines.append(f"{k} = {_fmt(v)}")
    for k, v in subtables.items():
        _table(lines, f"{name}.{k}", v)


class _Builder:
    def __init__(self) -> None:
        self.nodes: dict[str, complex] = {}
        self.beams: list[dict] = []
        self.links: list[dict] = []
        self.joints: list[dict] = []
        self.supports: list[dict] = []

    def node(self, name: str, z: complex) -> str:
        self.nodes[name] = z
        return name

    def beam(self, name, start, end, seg):
        self.beams.append(
            {
                "name": name,
                "start": start,
                "end": end,
                "section": {"kind": "rectangle", "width": seg.width, "thickness": seg.thickness},
                "segment_type": seg.kind,
            }
        )


def _ground_link(
    b: _Builder, name: str, G: complex, M: complex, theta: float, segs: dict[str, SegmentDesign], coupler: list[str]
):
    """One ground-pivoted link G->M (deg direction theta in the mesh state) with its segments."""
    u = polar(1.0, theta)
    R = abs(M - G)
    tag = name[-1]
    whole = [s for s in segs.values() if s.kind in ("fixed-guided", "fixed-pinned")]
    if whole:
        seg = whole[0]
        if seg.kind == "fixed-guided":
            e = (seg.length - R) / 2.0
            g, m = b.node(f"G{tag}", G - e * u), b.node(f"C{tag}", M + e * u)
            b.beam(f"seg{tag}", g, m, seg)
            b.supports.append({"node": g, "kind": "fixed"})
            coupler.append(m)
        elif segs.get("moving") is seg:  # pinned at the ground pivot, clamped beyond M to the coupler
            g, f = b.node(f"O{tag}", G), b.node(f"F{tag}", G + seg.length * u)
            b.beam(f"seg{tag}", g, f, seg)
            b.supports.append({"node": g, "kind": "pinned", "member": f"seg{tag}"})
            coupler.append(f)
        else:  # clamped to ground behind the pin at M
            g, m = b.node(f"G{tag}", M - seg.length * u), b.node(f"M{tag}", M)
            b.beam(f"seg{tag}", g, m, seg)
            b.supports.append({"node": g, "kind": "fixed"})
            b.joints.append({"node": m, "members": [f"seg{tag}", "coupler"]})
            coupler.append(m)
        return None
    ground, moving = segs.get("ground"), segs.get("moving")
    if ground is not None:
        g0, g1 = b.node(f"G{tag}", G - ground.length / 2 * u), b.node(f"S{tag}g", G + ground.length / 2 * u)
        b.beam(f"slfp{tag}g", g0, g1, ground)
        b.supports.append({"node": g0, "kind": "fixed"})
        start = g1
    else:
        start = b.node(f"O{tag}", G)
        b.supports.append({"node": start, "kind": "pinned", "member": f"link{tag}"})
    if moving is not None:
        m0, m1 = b.node(f"S{tag}m", M - moving.length / 2 * u), b.node(f"C{tag}", M + moving.length / 2 * u)
        b.beam(f"slfp{tag}m", m0, m1, moving)
        end = m0
        coupler.append(m1)
    else:
        end = b.node(f"J{tag}", M)
        b.joints.append({"node": end, "members": [f"link{tag}", "coupler"]})
        coupler.append(end)
    b.links.append({"name": f"link{tag}", "nodes": [start, end]})
    return f"link{tag}"


def _drive(b: "_Builder", drive: str, positions, free_angles, rigid, P: complex, P_j: list[complex]):
    """The loads that drive the mechanism through the precision positions, and the outputs wanted."""
    t20, t30, t40 = free_angles
    rigid2, rigid4 = rigid
    loads, outputs = [], []
    if drive == "input-rotation":
        if rigid2 is None:
            raise SynthesisError("drive 'input-rotation' needs a rigid input link 2 (SLFPs or pins on Z2)")
        start = next(l for l in b.links if l["name"] == rigid2)["nodes"][0]
        loads.append(
            {
                "kind": "rotation",
                "point": start,
                "body": rigid2,
                "values": [a[0] - t20 for a in positions],
                "label": "input rotation Theta2j - Theta20 (deg)",
            }
        )
        outputs += [
            {"quantity": "input_torque"},
            {"quantity": "strain_energy"},
            {"quantity": "dx", "point": "P"},
            {"quantity": "dy", "point": "P"},
        ]
    elif drive == "output-rotation":
        if rigid4 is None:
            raise SynthesisError("drive 'output-rotation' needs a rigid link 4")
        start = next(l for l in b.links if l["name"] == rigid4)["nodes"][0]
        loads.append(
            {
                "kind": "rotation",
                "point": start,
                "body": rigid4,
                "values": [a[2] - t40 for a in positions],
                "label": "output rotation Theta4j - Theta40 (deg)",
            }
        )
        outputs += [{"quantity": "strain_energy"}, {"quantity": "dx", "point": "P"}, {"quantity": "dy", "point": "P"}]
    else:
        loads.append(
            {
                "kind": "displacement",
                "point": "P",
                "direction": [1.0, 0.0],
                "values": [(p - P).real for p in P_j],
                "label": "prescribed coupler-point X",
            }
        )
        loads.append(
            {
                "kind": "rotation",
                "point": "P",
                "body": "coupler",
                "values": [a[1] - t30 for a in positions],
                "label": "prescribed coupler rotation (deg)",
            }
        )
        outputs += [{"quantity": "strain_energy"}, {"quantity": "dy", "point": "P"}]
    return loads, outputs


def _references(d, name: str, outputs: list[dict], P: complex, P_j: list[complex], levels: list[int]) -> list[dict]:
    """The synthesized PRBM's values (and any printed ANSYS values) as the case's references."""
    spec, m = d.spec, d.mechanism
    c = spec.compliance
    references = []
    quantity = {"energy": "strain_energy", "torque": "input_torque"}[c.kind]
    if any(o["quantity"] == quantity for o in outputs):
        for j, v in enumerate(c.values):
            references.append(
                {
                    "quantity": quantity,
                    "level": j,
                    "value": float(d.springs.achieved[j]),
                    "label": "PRBM",
                    "source": {"file": name, "section": "synthesis", "note": f"specified {v:g}"},
                }
            )
    if c.kind == "torque" and any(o["quantity"] == "strain_energy" for o in outputs):
        U = cp.design_rows(m, d.free_state, d.positions, "energy") @ d.springs.k
        for j, u in enumerate(U):
            references.append(
                {
                    "quantity": "strain_energy",
                    "level": j,
                    "value": float(u),
                    "label": "PRBM",
                    "source": {"file": name, "section": "synthesis", "note": "eq. 181 with the springs"},
                }
            )
    wanted = {o["quantity"] for o in outputs}
    for j, p in enumerate(P_j):
        for q, v in (("dx", (p - P).real), ("dy", (p - P).imag)):
            if q in wanted:
                references.append(
                    {
                        "quantity": q,
                        "point": "P",
                        "level": j,
                        "value": v,
                        "label": "PRBM",
                        "source": {"file": name, "section": "synthesis", "note": "precision position"},
                    }
                )
    for pr in spec.printed:
        if pr.name.startswith("fem.") and pr.label == "ANSYS":
            _, q, lab = pr.name.split(".")
            level = int(lab.lstrip("P")) - 1
            if q in {o["quantity"] for o in outputs} and level in levels:
                references.append(
                    {
                        "quantity": q,
                        "level": level,
                        "value": float(pr.value),
                        "label": "ANSYS",
                        "source": pr.source.model_dump(exclude_none=True),
                    }
                )
    return references


def build_case(d, spec_path: Path | str) -> dict:
    """The case as a dict in the schema's structure (``toml_text`` writes it)."""
    spec, m = d.spec, d.mechanism
    if not isinstance(m, FourBarDesign):
        raise SynthesisError("case generation is implemented for four-bar designs only")
    if not d.segments:
        raise SynthesisError("no [[segments]] in the specification: nothing compliant to build")
    t20, t30, t40 = d.free_state.angles
    O2, O4 = 0j, m.Z1
    A, B = polar(abs(m.Z2), t20), O4 + polar(abs(m.Z4), t40)
    P = A + polar(abs(m.Z5), arg_deg(m.Z5) + t30 - arg_deg(m.Z3))
    b = _Builder()
    b.node("P", P)
    coupler: list[str] = ["P"]
    by_link: dict[str, dict[str, SegmentDesign]] = {"Z2": {}, "Z4": {}}
    for seg in d.segments:
        if seg.link not in by_link:
            raise SynthesisError(f"a segment on the coupler {seg.link} is not supported by the case generator")
        for s in seg.springs:
            by_link[seg.link]["ground" if s in (1, 4) else "moving"] = seg
    rigid2 = _ground_link(b, "Z2", O2, A, t20, by_link["Z2"], coupler)
    rigid4 = _ground_link(b, "Z4", O4, B, t40, by_link["Z4"], coupler)
    b.links.append({"name": "coupler", "nodes": coupler})

    levels = list(range(len(d.positions)))
    drive = spec.verification.drive
    positions = [c.angles for c in d.positions]
    P_j = [polar(abs(m.Z2), a[0]) + polar(abs(m.Z5), arg_deg(m.Z5) + a[1] - arg_deg(m.Z3)) for a in positions]
    loads, outputs = _drive(b, drive, positions, (t20, t30, t40), (rigid2, rigid4), P, P_j)
    name = Path(spec_path).name
    references = _references(d, name, outputs, P, P_j, levels)
    info = {
        "id": f"synth_{spec.design.id}",
        "title": f"Synthesized: {spec.design.title}",
        "group": "synthesis",
        "units": spec.design.units,
        "description": f"Generated by 'prbm-validate synthesize {name}': the PRBM design built as a compliant "
        f"mechanism in its energy-free state, driven to the precision positions ({drive}).",
        "source": {"file": name, "section": "synthesis"},
        "assumptions": [
            f"segments placed as in seed 000 eqs 186-188 (see validation/synthesis/casefile.py); "
            f"E = {spec.material.E:g}"
        ],
    }
    mech = {
        "E": spec.material.E,
        "nodes": [{"name": k, "x": round(z.real, 10), "y": round(z.imag, 10)} for k, z in b.nodes.items()],
        "beams": b.beams,
        "links": b.links,
        "supports": b.supports,
    }
    if b.joints:
        mech["joints"] = b.joints
    return {
        "level_labels": [c.label.split(" ")[0] for c in d.positions],
        "case": info,
        "mechanism": mech,
        "loads": loads,
        "outputs": outputs,
        "methods": {"fem": {"elements": spec.verification.elements}},
        "references": references,
    }


def write_case(d, spec_path, out_dir: Path) -> Path:
    data = build_case(d, spec_path)
    path = Path(out_dir) / f"{data['case']['id']}.toml"
    header = (
        f"Generated by prbm-validate synthesize from {Path(spec_path).name}; do not edit by hand.\n"
        "Mesh in the energy-free configuration; load levels are the precision positions."
    )
    path.write_text(toml_text(data, header), encoding="utf-8")
    return path
