"""Prediction you can check: the atlas's expected PRBM error beside the PRBM-vs-FEM error each case
measured, and the measured error split as the atlas splits it.

For every level of a case whose PRBM run has an atlas model (``MethodRun.extras['atlas_model']``, set
by ``validation.methods.prbm_atlas``) and whose FEM gave the tip position:

* predicted: the PRBM run's ``expected_error`` (% of L), interpolated from the shipped maps;
* measured: |r_PRBM - r_FEM| / L (% of L) at the same load;
* the split of the measured error ([bapat2015, section 2.3]; ``validation.atlas.lines``): the PRBM is
  followed along its own line of growing load (the level's shape inputs, the load from a thousandth
  of the level's to three times it) and read at the FEM's path coordinate (the tip angle from the
  FEM's ``rotation``; b for a guided end): the path error |r_PRBM(c) - r_FEM| / L and the stiffness
  error F_PRBM(c)/F - 1; and the locus error, the distance from the FEM's tip to the PRBM's curve.
  Where the FEM gave no tip angle (a case that does not ask the FEM for ``rotation``) or the PRBM
  never reaches the FEM's coordinate, the split is NaN with the reason.

The FEM is the measurement because it is what the harness compares the PRBM with on a case; the
atlas's own reference is the exact elastica, which the FEM matches to its error estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from validation.atlas.lines import ExactLine, coordinate, locus_distance, split_at_coordinate, unloaded  # noqa: E402
from validation.atlas.minor_ticks import mark_minor_ticks  # noqa: E402
from validation.atlas.models import MODELS  # noqa: E402


@dataclass(frozen=True)
class MeasuredLevel:
    """One case level: the atlas model and inputs, predicted and measured errors (% of L), the split."""

    case: str
    level: int
    model: str
    predicted: float
    measured: float
    path: float
    stiffness: float
    locus: float
    why_no_split: str


TipKey = tuple[str, str, float]  # (method, quantity, level)


def _tips(table: pd.DataFrame) -> dict[TipKey, float]:
    """The value of each (method, quantity, level) at the tip (a point named 'tip', '' or none): its
    first row in the table's order. One pass over a case's rows instead of a filter per reading."""
    out: dict[TipKey, float] = {}
    columns = (table["method"], table["quantity"], table["level"], table["point"], table["value"])
    for method, quantity, level, point, value in zip(*columns):
        if (pd.isna(point) or point in ("tip", "")) and not pd.isna(level):
            out.setdefault((method, quantity, level), value)  # as it is: ``_tip`` reads it as a number
    return out


def _tip(tips: dict[TipKey, float], method: str, quantity: str, level: int) -> float:
    key = (method, quantity, level)
    return float(tips[key]) if key in tips else math.nan


def _split(
    model: str, inputs: dict, mirror: float, x: float, y: float, rotation_deg: float
) -> tuple[float, float, float, str]:
    """(path %, stiffness %, locus %, why NaN) of a FEM tip (unit frame) against the PRBM's line."""
    m = MODELS[model]
    shape = {k: v for k, v in inputs.items() if k != "load"}
    F = float(inputs["load"])
    if F <= 0.0:
        return math.nan, math.nan, math.nan, "no load"
    x0, y0, t0 = unloaded(m, shape)
    y = mirror * y
    theta = t0 + mirror * math.radians(rotation_deg) if math.isfinite(rotation_deg) else math.nan
    # the PRBM's own line: 600 loads, 150 for a model solved level by level (the Chain: ~3 ms a level)
    loads = np.geomspace(F * 1e-3, F * 3.0, 150 if m.dense == 1 else 600)
    prb = m.prbm(shape, loads)
    locus = float(locus_distance(prb.x, prb.y, prb.ok, np.array([x]), np.array([y]))[0])
    if m.coordinate == "tip angle" and not math.isfinite(theta):
        return math.nan, math.nan, 100.0 * locus, "the FEM gave no tip rotation"
    exact = ExactLine(np.array([x]), np.array([y]), np.array([theta]), ["ok"], 0.0)
    split = split_at_coordinate(m, exact, loads, prb, float(coordinate(m, x0, y0, t0)))
    if not math.isfinite(split.load[0]):
        return math.nan, math.nan, 100.0 * locus, "the PRBM does not reach the FEM's deflection"
    path = math.hypot(split.x[0] - x, split.y[0] - y)
    return 100.0 * path, 100.0 * (split.load[0] / F - 1.0), 100.0 * locus, ""


def measured_levels(results, table: pd.DataFrame) -> list[MeasuredLevel]:
    """Every case level with a predicted and a measured PRBM error (module docstring)."""
    out = []
    for result in results:
        prbm, fem = result.runs.get("prbm"), result.runs.get("fem")
        if prbm is None or fem is None or not prbm.extras.get("atlas_model"):
            continue
        if not prbm.extras.get("atlas_equal_load", True):
            continue  # a prescribed motion: the PRBM's tip is where it was put, its error is in the load
        case = result.loaded.case
        cid = case.case.id
        tips = _tips(table[table["case"] == cid])
        L = float(case.segment.length) if getattr(case, "segment", None) is not None else math.nan
        inputs, mirrors = prbm.extras.get("atlas_inputs", {}), prbm.extras.get("atlas_mirror", {})
        for level, predicted in sorted(prbm.expected_error.items()):
            xp, yp = _tip(tips, "prbm", "x", level), _tip(tips, "prbm", "y", level)
            xf, yf = _tip(tips, "fem", "x", level), _tip(tips, "fem", "y", level)
            if not all(math.isfinite(v) for v in (xp, yp, xf, yf, L)):
                continue
            measured = 100.0 * math.hypot(xp - xf, yp - yf) / L
            rotation = _tip(tips, "fem", "rotation", level)
            model = prbm.extras["atlas_model"]
            path, stiffness, locus, why = _split(
                model, inputs[level], mirrors.get(level, 1.0), xf / L, yf / L, rotation
            )
            out.append(MeasuredLevel(cid, int(level), model, float(predicted), measured, path, stiffness, locus, why))
    return out


def frame_of(levels: list[MeasuredLevel]) -> pd.DataFrame:
    return pd.DataFrame([lv.__dict__ for lv in levels], columns=list(MeasuredLevel.__dataclass_fields__))


def agreement(frame: pd.DataFrame) -> dict[str, float]:
    """How near the diagonal: the share within a factor 2 (or 0.25 % of L, the maps' resolution at small
    errors), the share on the same side of the 5 % validity limit, and the rank correlation."""
    p_all = pd.to_numeric(frame["predicted"], errors="coerce").to_numpy(float)
    m_all = pd.to_numeric(frame["measured"], errors="coerce").to_numpy(float)
    ok = frame[np.isfinite(p_all) & np.isfinite(m_all)]
    if ok.empty:
        return {"levels": 0}
    p, m = ok["predicted"].to_numpy(), ok["measured"].to_numpy()
    near = (np.abs(p - m) <= 0.25) | ((p <= 2 * m) & (m <= 2 * p))
    same_side = (p > 5.0) == (m > 5.0)
    rank = spearman(p, m) if len(ok) > 2 else math.nan
    return {
        "levels": int(len(ok)),
        "cases": int(ok["case"].nunique()),
        "within_factor_2": float(near.mean()),
        "same_side_of_5_percent": float(same_side.mean()),
        "spearman": rank,
    }


def spearman(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation as ``scipy.stats.spearmanr`` (and pandas' ``corr``) computes it, to the
    last bit: Pearson's correlation of the average ranks; NaN where either is constant. Written out
    because importing ``scipy.stats`` costs a fifth of a second on the report's serial path."""
    ranks = np.column_stack([pd.Series(a).rank().to_numpy(float), pd.Series(b).rank().to_numpy(float)])
    if (ranks[:, 0] == ranks[0, 0]).all() or (ranks[:, 1] == ranks[0, 1]).all():
        return math.nan
    return float(np.corrcoef(ranks, rowvar=False)[1, 0])


def draw_scatter(frame: pd.DataFrame, path) -> None:
    """Predicted against measured error, log-log, one colour per model, the diagonal and a factor-2 band."""
    ok = frame[np.isfinite(frame["predicted"]) & np.isfinite(frame["measured"])]
    fig, ax = plt.subplots(figsize=(5.6, 4.6), layout="constrained")
    lo, hi = 1e-3, 100.0
    grid = np.geomspace(lo, hi, 50)
    ax.fill_between(grid, grid / 2, grid * 2, color="0.9", label="within a factor 2")
    ax.plot(grid, grid, color="0.4", lw=1.0, label="predicted = measured")
    for i, (model, rows) in enumerate(ok.groupby("model")):
        ax.scatter(
            np.clip(rows["predicted"], lo, hi),
            np.clip(rows["measured"], lo, hi),
            s=18,
            color=plt.get_cmap("tab10")(i % 10),
            label=MODELS[model].title if model in MODELS else model,
        )
    ax.axvline(5.0, color="#ef476f", ls="--", lw=1.0)
    ax.axhline(5.0, color="#ef476f", ls="--", lw=1.0, label="5 % validity limit")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("expected PRBM tip error from the atlas (% of L)")
    ax.set_ylabel("measured PRBM-vs-FEM tip error (% of L)")
    ax.legend(fontsize=7, loc="upper left")
    mark_minor_ticks(fig)
    fig.savefig(path, dpi=110)
    plt.close(fig)
