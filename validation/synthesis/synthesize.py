"""``prbm-validate synthesize SPEC.toml``: design, write, verify with the FEM, report.

``synthesize(spec_path, out_dir)`` returns the exit status: 0 the design was written (and verified
by the FEM unless the specification or the caller turns the check off), 1 the specification has no solution or the design misses its
specification (the message says why), 2 the specification file is invalid (one line naming the
file and the field).  Output in ``out_dir``: ``<id>.json`` and ``<id>.md`` (the PRBM design, the
printed numbers beside the synthesized ones, the FEM check) and the case file ``synth_<id>.toml``.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

from prbm.synthesis.dyads import SynthesisError
from validation.case.loader import CaseError, load_case
from validation.run.exit_status import ExitStatus, print_error
from validation.methods.base import RunStatus
from validation.run.runner import run_method
from validation.synthesis.casefile import write_case
from validation.synthesis.design import Design, compare_printed, design
from validation.synthesis.spec import SpecError, load_spec


def _jsonable(v):
    if isinstance(v, complex):
        return [v.real, v.imag]
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if hasattr(v, "item"):
        return v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def fem_check(case_path: Path, d: Design) -> dict[str, Any]:
    """Run the FEM on the generated case through the validation runner; a clear status if it cannot."""
    try:
        loaded = load_case(case_path)
    except CaseError as exc:
        return {"status": "invalid-case", "message": f"generated case file rejected: {exc}"}
    run = run_method(loaded.case, "fem")
    rows: list[dict[str, Any]] = []
    refs = {
        (r.quantity, r.point if r.quantity in ("dx", "dy") else "", r.level, r.label): r.value
        for r in loaded.case.references
    }
    for req, value in sorted(run.values.items(), key=lambda kv: (kv[0].level, kv[0].quantity)):
        label = (loaded.case.level_labels or [str(i) for i in range(loaded.case.n_levels())])[req.level]
        prbm = refs.get((req.quantity, req.point if req.quantity in ("dx", "dy") else "", req.level, "PRBM"))
        ansys = refs.get((req.quantity, req.point if req.quantity in ("dx", "dy") else "", req.level, "ANSYS"))
        rows.append(
            {
                "quantity": req.quantity,
                "point": req.point,
                "position": label,
                "fem": value,
                "prbm": prbm,
                "printed_ansys": ansys,
                "difference": None if prbm is None else value - prbm,
                "relative": None if not prbm else (value - prbm) / abs(prbm),
            }
        )
    by_level: dict[str, dict] = {}
    for r in rows:
        if r["quantity"] in ("dx", "dy") and r["prbm"] is not None:
            by_level.setdefault(r["position"], {})[r["quantity"]] = (r["fem"], r["prbm"])
    for label, xy in by_level.items():
        if len(xy) == 2:
            miss = math.hypot(xy["dx"][0] - xy["dx"][1], xy["dy"][0] - xy["dy"][1])
            rows.append(
                {
                    "quantity": "position_error",
                    "point": "P",
                    "position": label,
                    "fem": miss,
                    "prbm": 0.0,
                    "printed_ansys": None,
                    "difference": miss,
                    "relative": None,
                }
            )
    status = "ok" if run.converged else ("not-applicable" if run.status is RunStatus.NOT_APPLICABLE else "failed")
    return {
        "status": status,
        "message": run.message,
        "wall_time": run.wall_time,
        "rows": rows,
        "level_converged": {str(k): v for k, v in run.level_converged.items()},
    }


def _markdown(d: Design, printed: list[dict], fem: dict | None, case_path: Path | None) -> str:
    spec = d.spec
    out = [
        f"# {spec.design.title}",
        "",
        f"Design `{spec.design.id}`" + (f", source {spec.design.source.label()}" if spec.design.source else ""),
        "",
    ]
    out += [f"- {m}" for m in d.messages] + [""]
    out += ["## Design", "", "| quantity | value |", "|---|---|"]
    for k, v in d.values.items():
        out.append(f"| {k} | {v.real:.6g} {v.imag:+.6g}i |" if isinstance(v, complex) else f"| {k} | {v:.6g} |")
    if d.segments:
        out += [
            "",
            "## Segments",
            "",
            "| kind | link | springs | k | l | L | width | t | I | max stress |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]
        for s in d.segments:
            out.append(
                f"| {s.kind} | {s.link} | {s.springs} | {s.k:.6g} | {s.length:.5g} | {s.rigid_length:.5g} | "
                f"{s.width:g} | {s.thickness:.5g} | {s.I:.5g} | {s.max_stress:.5g} |"
            )
    if printed:
        out += [
            "",
            "## Printed vs synthesized",
            "",
            "| name | printed | synthesized | difference | allowed | agrees | expected | source |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in printed:
            got = r["synthesized"]
            got_s = (
                "-"
                if got is None
                else (f"{got.real:.5f} {got.imag:+.5f}i" if isinstance(got, complex) else f"{got:.6g}")
            )
            out.append(
                f"| {r['name']} | {r['printed']} | {got_s} | {r['difference']:.3g} | {r['allowed']:.3g} | "
                f"{'yes' if r['agrees'] else 'no'} | {r['expect']} | {r['source']} |"
            )
        findings = [r for r in printed if r["finding"]]
        if findings:
            out += ["", "Findings:", ""] + [f"- {r['name']}: {r['finding']}" for r in findings]
    if fem is not None:
        out += ["", "## FEM check", "", f"Status: {fem['status']}. {fem.get('message', '')}".rstrip()]
        if case_path is not None:
            out.append(f"Case file: `{case_path.name}`")
        if fem.get("rows"):
            out += [
                "",
                "| position | quantity | FEM | PRBM design | difference | printed ANSYS |",
                "|---|---|---|---|---|---|",
            ]
            for r in fem["rows"]:
                fmt = lambda v: "-" if v is None else f"{v:.5g}"
                out.append(
                    f"| {r['position']} | {r['quantity']} {r['point']} | {fmt(r['fem'])} | {fmt(r['prbm'])} | "
                    f"{fmt(r['difference'])} | {fmt(r['printed_ansys'])} |"
                )
    return "\n".join(out) + "\n"


def synthesize(spec_path, out_dir, *, run_fem: bool | None = None, stream=None) -> int:
    """Design from ``spec_path`` into ``out_dir``; the exit status (0 ok, 1 no solution, 2 bad file)."""
    stream = stream or sys.stdout
    err = sys.stderr
    try:
        spec = load_spec(spec_path)
    except SpecError as exc:
        print_error(exc)
        return ExitStatus.BAD_INPUT
    try:
        d = design(spec)
    except SynthesisError as exc:
        print(f"no solution: {Path(spec_path).name}: {exc}", file=err)
        return ExitStatus.FAILED
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    printed = compare_printed(d)
    case_path: Path | None = None
    fem: dict[str, Any] | None = None
    if spec.kinematics is not None and spec.compliance is not None and spec.segments:
        try:
            case_path = write_case(d, spec_path, out)
        except SynthesisError as exc:
            fem = {"status": "no-case", "message": f"no case file: {exc}"}
        do_fem = spec.verification.run_fem if run_fem is None else run_fem
        if case_path is not None and do_fem:
            fem = fem_check(case_path, d)
        elif case_path is not None:
            fem = {"status": "skipped", "message": "FEM check not requested"}
    report = {
        "id": spec.design.id,
        "success": d.success,
        "messages": d.messages,
        "values": d.values,
        "segments": [s.__dict__ for s in d.segments],
        "springs": None
        if d.springs is None
        else {
            "k": list(d.springs.k),
            "fun": d.springs.fun,
            "achieved": list(d.springs.achieved),
            "target": list(d.springs.target),
            "constraints": d.springs.constraints,
        },
        "printed": printed,
        "fem": fem,
        "case_file": None if case_path is None else case_path.name,
        "extra": d.extra,
    }
    (out / f"{spec.design.id}.json").write_text(json.dumps(_jsonable(report), indent=2), encoding="utf-8")
    (out / f"{spec.design.id}.md").write_text(_markdown(d, printed, fem, case_path), encoding="utf-8")
    print(
        f"{spec.design.id}: {'design written' if d.success else 'design written, specification NOT met'} to {out}",
        file=stream,
    )
    for m in d.messages:
        print(f"  {m}", file=stream)
    if fem is not None:
        print(f"  FEM check: {fem['status']}" + (f" ({fem['message']})" if fem.get("message") else ""), file=stream)
        for r in fem.get("rows", []):
            extra = "" if r["printed_ansys"] is None else f", printed ANSYS {r['printed_ansys']:.5g}"
            prbm = "" if r["prbm"] is None else f" (PRBM {r['prbm']:.5g})"
            print(f"    {r['position']}: {r['quantity']} {r['point']} FEM {r['fem']:.5g}{prbm}{extra}", file=stream)
    return ExitStatus.OK if d.success else ExitStatus.FAILED
