"""The tidy result tables, their one schema, and how they are written and read back.

A run gives four tables, each one row per observation, with fixed columns and dtypes:

- ``runs``: one row per case and method: how the run ended (``status``), its message, wall time;
- ``values``: one row per case, method, quantity, point and load level: the value the method gave,
  with the level's load (name, value, unit) so a plot against the load needs no case file;
- ``loads``: one row per case, load and level: every load of the path (a case may have several;
  join on ``case, level``);
- ``comparisons``: one row per value checked against something (a printed reference, or another
  method where the runner compares them): the errors, whether the claimed tolerance holds, and the
  row's ``verdict`` (``validation.run.verdict``: 'no limit claimed' where nothing is asserted).

``values`` never repeats a row, so ``values.pivot(index=[...,"level"], columns="method",
values="value")`` works; ``comparisons`` holds the value it checked but is not needed for plots.
The columns below are the schema: the files under ``reports/latest/`` (CSV and Parquet), the
Python API and the README are all checked against them by the tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from validation.case.capabilities import QUANTITIES
from validation.run.runner import CaseResult, requests_for
from validation.case.loads import driving_load, level_labels, load_name, load_unit
from validation.case.schema import Case


@dataclass(frozen=True)
class Column:
    name: str
    dtype: str  # pandas dtype: "string", "Int64", "float64", "boolean"
    description: str


_KEY = [
    Column("case", "string", "case id ([case].id)"),
    Column("method", "string", "prbm, fem, elastica, bcm or opensees"),
]
_AT = [
    Column("quantity", "string", "output quantity (validation/case/capabilities.py)"),
    Column("point", "string", "named point; empty for whole-model quantities"),
    Column("level", "Int64", "load level (index into every load's path)"),
    Column("level_label", "string", "the case's name for the level ([case] level_labels), else the index"),
]
_LOAD = [
    Column("load", "string", "name of the level's driving load (its label, else 'kind at point')"),
    Column("load_value", "float64", "its value at this level, in load_unit"),
    Column("load_unit", "string", "unit of load_value in the case's unit system (deg for rotations)"),
]

SCHEMA: dict[str, list[Column]] = {
    "runs": [
        Column("case", "string", "case id"),
        Column("group", "string", "report group"),
        Column("method", "string", "method name"),
        Column("status", "string", "ok, not converged, not applicable, failed or misconfigured"),
        Column("converged", "boolean", "the method converged at every level asked for"),
        Column("message", "string", "the method's own words (why it refused, where it failed)"),
        Column("wall_time", "float64", "seconds the method took (0 when cached)"),
        Column("cached", "boolean", "taken from the on-disk cache"),
    ],
    "values": _KEY
    + _AT
    + _LOAD
    + [
        Column("value", "float64", "the method's value; angles in degrees"),
        Column("unit", "string", "unit of value in the case's unit system"),
        Column("error_estimate", "float64", "the method's own error estimate (FEM), else empty"),
        Column(
            "error_estimate_reliable",
            "boolean",
            "False: the estimate is unreliable, no bound (the FEM's "
            "meshes were not in the asymptotic range for this value); empty without an estimate",
        ),
        Column("converged", "boolean", "the method converged at this level"),
        Column(
            "applicability",
            "string",
            "the method's flags on this level's load ('outside validity': outside the "
            "PRBM error atlas's 5 % region; outside the fits' range; an inflection), empty when none",
        ),
        Column(
            "expected_error", "float64", "the PRBM error atlas's expected tip error at this level (% of L), else empty"
        ),
    ],
    "loads": [
        Column("case", "string", "case id"),
        *_AT[2:],
        Column("load", "string", "load name (its label, else 'kind at point')"),
        Column("kind", "string", "force, moment, displacement or rotation"),
        Column("point", "string", "where the load acts"),
        Column("value", "float64", "load value at this level (force: along its direction)"),
        Column("unit", "string", "unit of value"),
    ],
    "comparisons": _KEY
    + _AT
    + _LOAD
    + [
        Column("value", "float64", "the method's value"),
        Column("unit", "string", "unit of value and reference_value"),
        Column("reference_label", "string", "what it is compared with: PRBM, ANSYS, exact, ... or a method"),
        Column("reference_value", "float64", "the printed (or other method's) value"),
        Column("source", "string", "where the reference was printed"),
        Column("tolerance_rel", "float64", "claimed relative tolerance, if any"),
        Column("tolerance_abs", "float64", "claimed absolute tolerance, if any"),
        Column("abs_error", "float64", "|value - reference_value|"),
        Column("rel_error", "float64", "abs_error / |reference_value|"),
        Column("norm_error", "float64", "abs_error over the characteristic length (lengths only)"),
        Column("within_tolerance", "boolean", "the claimed tolerance holds; empty when only recorded"),
        Column("finding", "string", "known misprint or disagreement that explains a miss"),
        Column(
            "verdict",
            "string",
            "within the claimed limit, finding, no limit claimed, outside the model's "
            "validity, expected failure, outside the claimed limit, refused, did not converge or failed "
            "(validation/run/verdict.py)",
        ),
    ],
}


def loads_table(case: Case) -> pd.DataFrame:
    labels = level_labels(case)
    rows = [
        dict(
            case=case.case.id,
            level=level,
            level_label=labels[level],
            load=load_name(load, i, case),
            kind=load.kind,
            point=load.point,
            value=value,
            unit=load_unit(load, case),
        )
        for i, load in enumerate(case.loads)
        for level, value in enumerate(load.levels())
    ]
    return typed(pd.DataFrame(rows), "loads")


def _load_columns(case: Case) -> pd.DataFrame:
    """Per level: load, load_value, load_unit of the driving load."""
    i = driving_load(case)
    n = case.n_levels()
    if i is None:
        return pd.DataFrame(dict(level=range(n), load=[None] * n, load_value=[math.nan] * n, load_unit=[None] * n))
    load = case.loads[i]
    return pd.DataFrame(
        dict(level=range(n), load=load_name(load, i, case), load_value=load.levels(), load_unit=load_unit(load, case))
    )


def runs_table(result: CaseResult) -> pd.DataFrame:
    case = result.loaded.case
    rows = [
        dict(
            case=case.case.id,
            group=case.case.group,
            method=method,
            status=run.status.value if run.status else "",
            converged=run.converged,
            message=run.message,
            wall_time=run.wall_time,
            cached=result.cached.get(method, False),
        )
        for method, run in result.runs.items()
    ]
    return typed(pd.DataFrame(rows), "runs")


def values_table(result: CaseResult) -> pd.DataFrame:
    """One row per method, quantity, point and level the case asked for, with the level's load."""
    case = result.loaded.case
    labels = level_labels(case)
    rows = []
    for method, run in result.runs.items():
        for req in requests_for(case, method):
            dimension = QUANTITIES[req.quantity].dimension
            rows.append(
                dict(
                    case=case.case.id,
                    method=method,
                    quantity=req.quantity,
                    point=req.point,
                    level=req.level,
                    level_label=labels[req.level],
                    value=run.values.get(req, math.nan),
                    unit=case.unit(dimension),
                    error_estimate=run.error_estimate.get(req, math.nan),
                    error_estimate_reliable=run.estimate_reliable(req),
                    converged=run.level_converged.get(req.level, run.converged) and req in run.values,
                    applicability="; ".join(f.value for f in run.applicability.get(req.level, ())),
                    expected_error=run.expected_error.get(req.level, math.nan),
                )
            )
    frame = pd.DataFrame(rows)
    if frame.empty:
        return typed(frame, "values")
    return typed(frame.merge(_load_columns(case), on="level", how="left"), "values")


def comparisons_table(results_rows: pd.DataFrame, loads: pd.DataFrame) -> pd.DataFrame:
    """The rows of the runner's results table that compare a value with something, with the load.

    Pass/fail is read from the runner's ``within_tolerance``; columns the runner adds beyond the
    schema are kept after it."""
    if results_rows.empty or "reference_label" not in results_rows:
        return typed(pd.DataFrame(), "comparisons")
    elsewhere = (
        "load",
        "load_value",
        "load_unit",
        "group",
        "scale",
        "error_estimate",
        "error_estimate_reliable",
        "compare",
        "wall_time",
        "converged",
        "message",
        "cached",
        "applicability",
        "expected_error",
    )  # in values and runs
    compared = results_rows["reference_label"].notna()
    if "within_tolerance" in results_rows:  # any row the runner judged is a comparison
        compared |= results_rows["within_tolerance"].notna()
    rows = results_rows[compared].drop(columns=[c for c in elsewhere if c in results_rows])
    rows = rows.merge(loads, on=["case", "level"], how="left") if len(loads) else rows
    return typed(rows, "comparisons", keep_extra=True)


def driving_loads(results: list[CaseResult]) -> pd.DataFrame:
    """(case, level, load, load_value, load_unit) of every case, for joining onto result rows."""
    parts = [_load_columns(r.loaded.case).assign(case=r.loaded.case.case.id) for r in results]
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(columns=["case", "level"])


def typed(frame: pd.DataFrame, table: str, keep_extra: bool = False) -> pd.DataFrame:
    """The frame with exactly the schema's columns, in order, in the schema's dtypes (missing
    columns empty); with ``keep_extra`` other columns follow, dtypes inferred."""
    columns = SCHEMA[table]
    out = pd.DataFrame(index=frame.index)
    for col in columns:
        data = frame[col.name] if col.name in frame else pd.Series(pd.NA, index=frame.index)
        if col.dtype == "boolean":
            data = data.map(
                lambda v: pd.NA if v is None or v is pd.NA or (isinstance(v, float) and math.isnan(v)) else bool(v)
            )
        data = data.astype(col.dtype)
        out[col.name] = data.mask(data == "") if col.dtype == "string" else data
    if keep_extra:
        for name in frame.columns:
            if name not in out:
                out[name] = frame[name].convert_dtypes()
    return out.reset_index(drop=True)


def with_loads(values: pd.DataFrame, loads: pd.DataFrame) -> pd.DataFrame:
    """The values table with one column per named load, ``"<name> [<unit>]"``, holding its value at
    the row's level (for one case, or cases that share their load names)."""
    if loads.empty:
        return values
    named = loads.assign(column=loads["load"] + " [" + loads["unit"].fillna("") + "]")
    wide = named.pivot_table(index=["case", "level"], columns="column", values="value", aggfunc="first")
    return values.merge(wide.reset_index(), on=["case", "level"], how="left")


def write(tables: dict[str, pd.DataFrame], out: Path) -> None:
    """Each table as ``<name>.csv`` and ``<name>.parquet`` under ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    for name, frame in tables.items():
        frame.to_csv(out / f"{name}.csv", index=False)
        frame.to_parquet(out / f"{name}.parquet", index=False)


def read(path: Path | str, table: str) -> pd.DataFrame:
    """A table written by ``write`` (CSV or Parquet), in the schema's dtypes."""
    path = Path(path)
    if path.suffix == ".parquet":
        return typed(pd.read_parquet(path), table, keep_extra=True)
    dtypes = {c.name: ("string" if c.dtype == "boolean" else c.dtype) for c in SCHEMA[table]}
    frame = pd.read_csv(path, dtype=dtypes, keep_default_na=False, na_values=[""])
    for col in SCHEMA[table]:
        if col.dtype == "boolean" and col.name in frame:
            frame[col.name] = frame[col.name].map({"True": True, "False": False}, na_action="ignore")
    return typed(frame, table, keep_extra=True)


def tables_of(results: list[CaseResult], results_rows: pd.DataFrame) -> dict[str, pd.DataFrame]:
    """runs, values, loads and comparisons of a set of case results (``results_rows``: the runner's
    table of the same results, whose comparison rows are kept as they are)."""

    def concat(parts, table):
        parts = [p for p in parts if len(p)]
        return typed(pd.concat(parts, ignore_index=True), table) if parts else typed(pd.DataFrame(), table)

    runs = concat([runs_table(r) for r in results], "runs")
    values = concat([values_table(r) for r in results], "values")
    loads = concat([loads_table(r.loaded.case) for r in results], "loads")
    comparisons = comparisons_table(results_rows, driving_loads(results))
    return dict(runs=runs, values=values, loads=loads, comparisons=comparisons)
