"""Each model's regions of validity from the atlas: where its tip error stays below 0.5, 1, 3 and 5 % of L.

Along a line (fixed shape inputs, growing load) the region ends at the first level whose tip error
passes the threshold, or where the line ends (the exact segment beyond the atlas, a method without an
answer): ``load_limit`` is the last load inside.  Over a model's map axis (``AtlasModel.map_axes[0]``:
the load angle, kappa0, the moment ratio, ...) the region is the worst line at each value (the least
load limit over the other shape inputs), so a region read off the table holds for every line it
summarises.  ``region_table`` gives, per threshold, the limits over the map axis; ``region_words`` says
them in a sentence with numbers; ``grid`` lays a column out over the map axis and the load (what
``map_figure`` draws, with the region boundaries and the seeds' claimed ranges over it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from validation.atlas.expected import REGION_LEVELS
from validation.atlas.models import MODELS


@dataclass(frozen=True)
class AnsweredLine:
    """One line of a model on which it answers, from its first answered level on (by load): its shape
    inputs, loads, whether each level is answered ("ok"), tip errors and the deflection each reaches in the
    model's path coordinate (the exact tip rotation in deg, else the ``deflection`` column)."""

    key: tuple
    load: np.ndarray
    ok: np.ndarray
    error: np.ndarray
    deflection: np.ndarray


def answered_lines(frame: pd.DataFrame, model: str) -> list[AnsweredLine]:
    """The model's lines on which it answers (a line on which it never answers has no region), in the
    order of their shape inputs: read once, for every threshold of ``line_limits``."""
    m = MODELS[model]
    rows = frame[frame["model"] == model].sort_values("load")
    shape_names = [a.name for a in m.shape_axes]
    if shape_names:
        group = rows.groupby(shape_names, sort=True).ngroup().to_numpy()
        order = np.argsort(group, kind="stable")  # line by line, each by load (``rows``' order)
        group = group[order]
        keep = group >= 0  # a line with a missing shape input is none (``groupby`` drops it)
        order, group = order[keep], group[keep]
        bounds = np.flatnonzero(np.diff(group)) + 1
        spans = list(zip(np.concatenate([[0], bounds]), np.concatenate([bounds, [group.size]])))
    else:
        order, spans = np.arange(len(rows)), [(0, len(rows))] if len(rows) else []
    shape = rows[shape_names].to_numpy()[order] if shape_names else None
    ok = (rows["status"] == "ok").to_numpy()[order]
    load, error = rows["load"].to_numpy(float)[order], rows["tip_error"].to_numpy()[order]
    column = "exact_rotation_deg" if m.coordinate == "tip angle" else "deflection"
    reached = rows[column].to_numpy()[order]
    reached = np.abs(reached) if m.coordinate == "tip angle" else reached
    out = []
    for lo, hi in spans:
        answered = ok[lo:hi]
        if not answered.any():
            continue
        first = lo + int(np.argmax(answered))
        key = tuple(shape[lo]) if shape is not None else ()
        out.append(AnsweredLine(key, load[first:hi], ok[first:hi], error[first:hi], reached[first:hi]))
    return out


def _limits(lines: list[AnsweredLine], shape_names: list[str], threshold: float) -> pd.DataFrame:
    """``line_limits`` of lines already read (``answered_lines``)."""
    out = []
    for line in lines:
        inside = line.ok & (line.error <= threshold)
        first_out = int(np.argmin(inside)) if not inside.all() else len(inside)
        last = first_out - 1 if first_out > 0 else None
        out.append(
            {
                **dict(zip(shape_names, line.key)),
                "first_load": float(line.load[0]),
                "load_limit": float(line.load[last]) if last is not None else 0.0,
                "deflection": float(line.deflection[last]) if last is not None else 0.0,
                "whole_line": first_out == len(inside),
            }
        )
    return pd.DataFrame(out)


def line_limits(frame: pd.DataFrame, model: str, threshold: float) -> pd.DataFrame:
    """Per line on which the model answers: its shape inputs, the first load it answers at, the last load
    inside the region, the deflection there (the exact tip rotation in deg, or |b| or the chord change in
    % of L for a guided end or an arc: the model's path coordinate) and whether the whole line stayed inside.
    A model that gives no answer at the smallest loads (the Theta-dependent fits' constant term) starts its
    region where it starts answering; a line on which it never answers has no region (not listed)."""
    shape_names = [a.name for a in MODELS[model].shape_axes]
    return _limits(answered_lines(frame, model), shape_names, threshold)


def deflection_unit(model: str) -> str:
    return "deg of tip rotation" if MODELS[model].coordinate == "tip angle" else "% of L of tip deflection"


def region_table(frame: pd.DataFrame, model: str) -> pd.DataFrame:
    """Per threshold and value of the map axis: the worst line's load limit and deflection there, and how
    many lines the model answers on (``lines``)."""
    m = MODELS[model]
    axis = m.map_axes[0] if m.map_axes[0] != "load" else None
    tables = []
    answered = answered_lines(frame, model)
    shape_names = [a.name for a in m.shape_axes]
    for threshold in REGION_LEVELS:
        lines = _limits(answered, shape_names, threshold)
        worst = lines if axis is None else lines.loc[lines.groupby(axis)["load_limit"].idxmin()]
        tables.append(worst.assign(threshold=threshold, lines=len(lines)))
    return pd.concat(tables, ignore_index=True)


@dataclass(frozen=True)
class RegionSummary:
    """One threshold's region of one model, in numbers: the load limit at the map axis's most favourable
    and least favourable values, and the deflection (``deflection_unit``) the limit reaches on the worst
    line and, as a median, over the map axis; ``lines``: the lines on which the model answers."""

    model: str
    threshold: float
    axis: str | None
    best_value: float
    best_load: float
    worst_value: float
    worst_load: float
    worst_deflection: float
    median_deflection: float
    lines: int


def summaries(frame: pd.DataFrame, model: str) -> list[RegionSummary]:
    table = region_table(frame, model)
    m = MODELS[model]
    axis = m.map_axes[0] if m.map_axes[0] != "load" else None
    out = []
    for threshold, rows in table.groupby("threshold", sort=True):
        best = rows.loc[rows["load_limit"].idxmax()]
        worst = rows.loc[rows["load_limit"].idxmin()]
        out.append(
            RegionSummary(
                model,
                float(threshold),
                axis,
                float(best[axis]) if axis else math.nan,
                float(best["load_limit"]),
                float(worst[axis]) if axis else math.nan,
                float(worst["load_limit"]),
                float(worst["deflection"]),
                float(rows["deflection"].median()),
                int(rows["lines"].iloc[0]),
            )
        )
    return out


def region_words(s: RegionSummary) -> str:
    """A region in a sentence: where it reaches furthest and where least far, with the deflection there."""
    load_label = MODELS[s.model].load.label
    unit = deflection_unit(s.model)
    if s.axis is None:
        return f"below {s.threshold:g} % of L up to {load_label} = {s.worst_load:.3g} ({s.worst_deflection:.0f} {unit})"
    if s.best_load == s.worst_load:
        return (
            f"below {s.threshold:g} % of L on every mapped line up to {load_label} = {s.worst_load:.3g} "
            f"(median deflection there {s.median_deflection:.0f} {unit})"
        )
    return (
        f"below {s.threshold:g} % of L up to {load_label} = {s.best_load:.3g} at {s.axis} = {s.best_value:.4g}, "
        f"but only to {s.worst_load:.3g} at {s.axis} = {s.worst_value:.4g} "
        f"({s.worst_deflection:.0f} {unit} there; median over {s.axis}: {s.median_deflection:.0f})"
    )


def grid(frame: pd.DataFrame, model: str, column: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(map-axis values, loads, worst column value over the other shape inputs) on the atlas grid."""
    m = MODELS[model]
    rows = frame[(frame["model"] == model)]
    axis = m.map_axes[0]
    value = rows[column].where(rows["status"] == "ok")
    if axis == "load":
        loads = np.sort(rows["load"].unique())
        table = value.groupby(rows["load"]).max().reindex(loads).to_numpy()
        return np.array([0.0, 1.0]), loads, np.vstack([table, table]).T
    table = value.groupby([rows["load"], rows[axis]]).max().unstack(axis)
    return table.columns.to_numpy(float), table.index.to_numpy(float), table.to_numpy(float)
