"""The loads of a case's load path, by name, value and unit per level (no pandas: the CLI's ``solve``
uses it at start-up; ``validation/run/tables.py`` builds its tables from it)."""

from __future__ import annotations

from validation.case.schema import Case, LoadSpec

LOAD_UNITS = {"force": "force", "moment": "moment", "displacement": "length"}


def load_name(load: LoadSpec, index: int, case: Case) -> str:
    """A load's name: its label, else 'kind at point' (with its index when that repeats)."""
    if load.label:
        return load.label
    name = f"{load.kind} at {load.point}"
    same = [
        i
        for i, other in enumerate(case.loads)
        if not other.label and (other.kind, other.point) == (load.kind, load.point)
    ]
    return name if len(same) == 1 else f"{name} #{index}"


def load_unit(load: LoadSpec, case: Case) -> str:
    """Unit of a load's values in the case's unit system (degrees for a prescribed rotation)."""
    if load.kind == "rotation":
        return "deg"
    if load.kind == "distributed":  # per unit length of the beam
        return f"{case.unit('force')}/{case.unit('length')}"
    if load.kind == "self_weight":  # a multiple of full gravity
        return "x gravity"
    dimension = LOAD_UNITS.get(load.kind)
    return case.unit(dimension) if dimension else ""


def driving_load(case: Case) -> int | None:
    """Index of the load plotted against: the first whose value changes along the path, else the first."""
    for i, load in enumerate(case.loads):
        levels = load.levels()
        if max(levels) != min(levels):
            return i
    return 0 if case.loads else None


def level_labels(case: Case) -> list[str]:
    """The case's name for each level, else its index."""
    return case.level_labels or [str(i) for i in range(case.n_levels())]
