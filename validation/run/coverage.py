"""What each method can do: the coverage matrix, generated from the adapters themselves.

For every load kind (``LOAD_KINDS``) on every boundary (``BOUNDARIES``: the segment boundaries of
``SegmentSpec``, an initially curved fixed-free segment, and a mechanism) the matrix builds one minimal
valid case for each method (``minimal_case``) and runs that method on it through the harness's own
single-method runner (``validation.run.runner.run_method``); the cell records how the run ended
(``Cell``): it answers (status ok), refuses (not applicable, with the method's reason), fails (not
converged, failed, misconfigured) or the case format itself cannot say the combination (the schema
or the mobility check rejects it: a gap of the format, not of a method).

The minimal cases (dimensionless: L = 1, EI = 1, EA = 1e4 EI/L^2):

- a load of unit size: P L^2/EI = 1 (force, follower force, force toward a point), M L/EI = 1 (moment),
  w L^3/EI = 1 (distributed load; self-weight of weight per length 1 along -y); a prescribed
  displacement of 0.1 L, a prescribed rotation of 10 degrees;
- on a segment at the tip: forces, displacements and distributed loads transverse (+y), except on a
  pinned-pinned segment, whose tip may turn about the root pin across the chord (a mechanism under a
  transverse tip load): there the tip loads pull along the chord (+x) and the displacement stretches
  it by 1e-3 L; a force toward a point pulls toward (1, 2), one length above the straight tip ((2, 0)
  for pinned-pinned); the curved segment has kappa L = 1/2;
- two mechanisms of ``cases/``, scaled to a first beam of unit length with every beam's EI = 1
  (``MECHANISMS``): the parallel-guided mechanism (two clamped beams, a rigid coupler), loaded at the
  coupler midpoint along +x, and the circular-guided mechanism of [chen2021] (a clamped beam whose end
  rides on a crank pinned to the ground), loaded at the beam's end across it and driven by the crank's
  rotation; the follower force turns with the rigid link, distributed loads and weight act on every
  beam;
- one output: the loaded point's ``x``; for a prescribed displacement the force along it, for a
  prescribed rotation the moment (the load the motion needs);
- each method at its default options, the FEM on a small mesh (``FEM_OPTIONS``).

Nothing is cached: each cell is a run of a few milliseconds to a second.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from typing import Any, Literal

from pydantic import ValidationError

from validation.case.loader import CASES_DIR, check_case, describe_all
from validation.case.schema import Case
from validation.methods.base import RunStatus
from validation.run.runner import run_method

LOAD_KINDS = (
    "force",
    "follower force",
    "force toward a point",
    "moment",
    "distributed load",
    "self-weight",
    "prescribed displacement",
    "prescribed rotation",
)
SEGMENTS = ("fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed", "pinned-pinned", "curved fixed-free")
METHODS = ("prbm", "fem", "elastica", "bcm")
FEM_OPTIONS = {"elements": 4, "error_estimate": False}
CURVATURE = 0.5  # kappa L of the curved segment
AREA = 1e4  # EA L^2/EI of every beam
SECTION: dict[str, Any] = {"kind": "inertia", "I": 1.0, "A": AREA}
WEIGHT_DENSITY = 1.0 / AREA  # weight per volume: a weight of 1 EI/L^3 per length


@dataclass(frozen=True)
class MechanismRow:
    """A mechanism of ``cases/`` and where the row's loads act on it."""

    file: str  # below cases/
    point: str  # the loaded node
    body: str  # the rigid link a follower force turns with
    direction: tuple[float, float]
    toward: tuple[float, float]  # the fixed point a rope pulls toward
    driven: tuple[str, str | None]  # (node, body) of the prescribed rotation


MECHANISMS = {
    "parallel-guided mechanism": MechanismRow(
        "segments/parallel_guided_mechanism.toml", "M", "coupler", (1.0, 0.0), (1.25, 1.0), ("M", None)
    ),
    "circular-guided mechanism": MechanismRow(
        "seed003/circular_guided.toml", "A", "crank", (0.0, 1.0), (1.0, 1.0), ("B", "crank")
    ),
}
BOUNDARIES = SEGMENTS + tuple(MECHANISMS)

Status = Literal["answers", "refuses", "fails", "invalid case"]


@dataclass(frozen=True)
class Cell:
    """How one method ended on one (load kind, boundary): ``status`` and, unless it answers, why."""

    load: str
    boundary: str
    method: str
    status: Status
    reason: str = ""

    def label(self) -> str:
        """'answers', 'refuses: <reason>', 'fails: <message>' or 'invalid case: <why>'."""
        return self.status if self.status == "answers" else f"{self.status}: {self.reason}"

    def short(self) -> str:
        """The matrix's cell: 'yes', or 'no: <reason>' ('no (fails): ...', 'no (invalid case): ...')."""
        if self.status == "answers":
            return "yes"
        kind = "" if self.status == "refuses" else f" ({self.status})"
        return f"no{kind}: {self.reason}"


def mechanism(row: MechanismRow, weight: bool) -> dict[str, Any]:
    """The ``[mechanism]`` of the row's case file, scaled so that its first beam has unit length, E = 1 and
    every beam the section ``SECTION`` (with ``weight``, its weight density)."""
    data = tomllib.loads((CASES_DIR / row.file).read_text(encoding="utf-8"))["mechanism"]
    at = {node["name"]: (node["x"], node["y"]) for node in data["nodes"]}
    first = data["beams"][0]
    scale = math.dist(at[first["start"]], at[first["end"]])
    section = dict(SECTION, **({"weight_density": WEIGHT_DENSITY} if weight else {}))
    data["E"] = 1.0
    data["nodes"] = [dict(node, x=node["x"] / scale, y=node["y"] / scale) for node in data["nodes"]]
    data["beams"] = [{k: v for k, v in dict(beam, section=section).items() if k != "E"} for beam in data["beams"]]
    return data


def _load(kind: str, boundary: str) -> dict[str, Any]:
    """The one load of the row, at its point, of unit size (see the module's docstring)."""
    row = MECHANISMS.get(boundary)
    if row is not None:
        point, direction, toward = row.point, list(row.direction), list(row.toward)
    elif boundary == "pinned-pinned":
        point, direction, toward = "tip", [1.0, 0.0], [2.0, 0.0]
    else:
        point, direction, toward = "tip", [0.0, 1.0], [1.0, 2.0]
    displacement = 1e-3 if boundary == "pinned-pinned" else 0.1
    follower_body = {"body": row.body} if row is not None else {}
    rotated, body = row.driven if row is not None else (point, None)
    loads: dict[str, dict[str, Any]] = {
        "force": dict(kind="force", point=point, direction=direction, values=[1.0]),
        "follower force": dict(
            kind="force", point=point, direction=direction, values=[1.0], follower=True, **follower_body
        ),
        "force toward a point": dict(kind="force", point=point, toward=toward, values=[1.0]),
        "moment": dict(kind="moment", point=point, values=[1.0]),
        "distributed load": dict(kind="distributed", point=point, direction=direction, values=[1.0]),
        "self-weight": dict(kind="self_weight", point=point, direction=[0.0, -1.0], values=[1.0]),
        "prescribed displacement": dict(kind="displacement", point=point, direction=direction, values=[displacement]),
        "prescribed rotation": dict(kind="rotation", point=rotated, values=[10.0], **({"body": body} if body else {})),
    }
    return loads[kind]


def _output(load: dict[str, Any]) -> dict[str, Any]:
    """The x of the loaded point; the load a prescribed motion needs there."""
    quantity = "x"
    if load["kind"] == "displacement":
        quantity = "force_x" if load["direction"][0] else "force_y"
    elif load["kind"] == "rotation":
        quantity = "moment"
    return {"quantity": quantity, "point": load["point"]}


def minimal_case(load: str, boundary: str, method: str) -> dict[str, Any]:
    """The case data (as read from TOML) of one cell: ``load`` (one of ``LOAD_KINDS``) on ``boundary``
    (one of ``BOUNDARIES``), asking ``method`` for one output."""
    spec = _load(load, boundary)
    weight = spec["kind"] == "self_weight"
    data: dict[str, Any] = {
        "case": {"id": "coverage", "title": f"{load} on {boundary}", "group": "coverage", "units": "dimensionless"},
        "loads": [spec],
        "outputs": [_output(spec)],
        "methods": {method: dict(FEM_OPTIONS) if method == "fem" else {}},
    }
    if boundary in MECHANISMS:
        data["mechanism"] = mechanism(MECHANISMS[boundary], weight)
    else:
        section = dict(SECTION, **({"weight_density": WEIGHT_DENSITY} if weight else {}))
        data["segment"] = {
            "boundary": boundary.removeprefix("curved "),
            "length": 1.0,
            "E": 1.0,
            "section": section,
            "curvature": CURVATURE if boundary.startswith("curved ") else 0.0,
        }
    return data


def shorten(message: str, width: int = 72) -> str:
    """A run's message in one short phrase: without the status, the exception's class, the load's field
    and the model's prefix, its first clause (of a failure: the first failed level's), at most ``width``
    characters (cut at a word, '...')."""
    clauses = message.split("\n")[0].split("; ")
    failed = [c for c in clauses if re.match(r"^(elastica mechanism: )?level \d+: ", c)]
    text = (failed or clauses)[0]
    text = re.sub(r"^(not applicable|not converged|error|misconfigured): ", "", text)
    text = re.sub(r"^[A-Z][a-z]+[A-Z]\w*: ", "", text)  # an exception's class name
    text = re.sub(r"^(elastica mechanism|BCM adapter): ", "", text)
    text = re.sub(r"^(loads\.\d+|(load )?level \d+): ", "", text)
    text = re.sub(r" \(at [\w.]+:\d+\)$", "", text).strip().rstrip(".")
    if len(text) <= width:
        return text
    return text[: width - 3].rsplit(" ", 1)[0].rstrip(",;:") + "..."


def cell(load: str, boundary: str, method: str) -> Cell:
    """Build the cell's minimal case, validate it as the loader does, and run the method on it."""
    try:
        case = Case.model_validate(minimal_case(load, boundary, method))
    except ValidationError as exc:
        field, problem = describe_all(exc, Case)[0]
        return Cell(load, boundary, method, "invalid case", shorten(f"{field}: {problem}"))
    problems = check_case(case)
    if problems:
        field, problem = problems[0]
        return Cell(load, boundary, method, "invalid case", shorten(f"{field}: {problem}"))
    run = run_method(case, method)
    if run.status is RunStatus.OK:
        return Cell(load, boundary, method, "answers")
    if run.status is RunStatus.NOT_APPLICABLE:
        return Cell(load, boundary, method, "refuses", shorten(run.message))
    return Cell(load, boundary, method, "fails", shorten(run.message))


def matrix(methods: tuple[str, ...] = METHODS) -> list[Cell]:
    """Every cell, row by row (load kind, then boundary), each row's methods in ``methods`` order."""
    return [cell(load, boundary, method) for load in LOAD_KINDS for boundary in BOUNDARIES for method in methods]


def _rows(cells: list[Cell]) -> tuple[list[str], list[tuple[str, str, list[str]]]]:
    methods = list(dict.fromkeys(c.method for c in cells))
    by_row: dict[tuple[str, str], dict[str, str]] = {}
    for c in cells:
        by_row.setdefault((c.load, c.boundary), {})[c.method] = c.short()
    return methods, [(load, boundary, [row[m] for m in methods]) for (load, boundary), row in by_row.items()]


def markdown(cells: list[Cell]) -> str:
    """The matrix as a Markdown table: a row per (load kind, boundary), a column per method."""
    methods, rows = _rows(cells)
    lines = ["| load | boundary | " + " | ".join(methods) + " |", "|---|---|" + "---|" * len(methods)]
    lines += [
        "| " + " | ".join([load, boundary, *(t.replace("|", "\\|") for t in texts)]) + " |"
        for load, boundary, texts in rows
    ]
    return "\n".join(lines)


def text(cells: list[Cell]) -> str:
    """The matrix as a fixed-width text table, for the terminal."""
    methods, rows = _rows(cells)
    table = [["load", "boundary", *methods]] + [[load, boundary, *texts] for load, boundary, texts in rows]
    widths = [max(len(r[i]) for r in table) for i in range(len(table[0]))]
    return "\n".join("  ".join(v.ljust(w) for v, w in zip(r, widths)).rstrip() for r in table)


def refusals(cells: list[Cell]) -> list[Cell]:
    """The cells whose method refused (not applicable)."""
    return [c for c in cells if c.status == "refuses"]
