"""Error maps from an atlas dataset, thinned for shipping (``validation/atlas/error_maps.json``).

``write_maps(frame, version)`` takes the full atlas (``validation.atlas.dataset``), puts each model's tip
error (% of L, equal load) on its regular grid (shape inputs x load levels; NaN where the line went
beyond the atlas or a method gave no answer), thins the grid (every k-th node of the longest axis,
until a model has at most ``MAX_NODES`` nodes) and writes the maps the PRBM adapter reads
(``validation.atlas.expected``), with the code version of the atlas they came from.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from validation.atlas.expected import MAPS_FILE, VALIDITY_LIMIT, ErrorMap, load_maps
from validation.atlas.models import MODELS

MAX_NODES = 6000  # per model, in the shipped maps


def from_atlas(frame: pd.DataFrame, model: str, stride: dict[str, int] | None = None, version: str = "") -> ErrorMap:
    """The error map of ``model`` from an atlas frame (its rows on a regular grid), thinned by ``stride``."""
    m = MODELS[model]
    rows = frame[frame["model"] == model]
    axes = tuple(a.name for a in m.shape_axes) + ("load",)
    values = tuple(np.sort(rows[name].unique()) for name in axes)
    error = np.full([v.size for v in values], np.nan)
    index = tuple(np.searchsorted(v, rows[name].to_numpy()) for name, v in zip(axes, values))
    ok = (rows["status"] == "ok").to_numpy()
    error[index] = np.where(ok, rows["tip_error"].to_numpy(), np.nan)
    stride = stride or {}
    picks = []
    for name, v in zip(axes, values):
        step = stride.get(name, 1)
        keep = np.arange(0, v.size, step)
        if keep[-1] != v.size - 1:
            keep = np.append(keep, v.size - 1)
        picks.append(keep)
    error = error[np.ix_(*picks)]
    values = tuple(v[p] for v, p in zip(values, picks))
    return ErrorMap(model, axes, values, error, version)


def _strides(frame: pd.DataFrame, model: str) -> dict[str, int]:
    """Thin the load axis, then the shape axes, until the map has at most ``MAX_NODES`` nodes."""
    m = MODELS[model]
    sizes = {a.name: frame.loc[frame["model"] == model, a.name].nunique() for a in m.shape_axes}
    sizes["load"] = frame.loc[frame["model"] == model, "load"].nunique()
    stride = {name: 1 for name in sizes}
    while np.prod([math.ceil(sizes[k] / stride[k]) for k in sizes]) > MAX_NODES:
        biggest = max(sizes, key=lambda k: math.ceil(sizes[k] / stride[k]))
        stride[biggest] += 1
    return stride


def write_maps(frame: pd.DataFrame, version: str, path: Path = MAPS_FILE) -> Path:
    """Write the maps of every model in ``frame`` (the full atlas) for the PRBM adapter."""
    models = {
        model: from_atlas(frame, model, _strides(frame, model), version).to_json()
        for model in sorted(frame["model"].unique())
    }
    data = {"version": version, "validity_limit": VALIDITY_LIMIT, "models": models}
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, separators=(",", ":")))
    tmp.replace(path)
    load_maps.cache_clear()
    return path
