"""Plots of a finished (or partly finished) sweep, written next to its Parquet parts.

``plot_sweep(out)`` reads ``out/sweep.json`` (the spec's ``[plot]`` table) and the results, and
draws one of:

* ``domain``: the characteristic deflection domain. Each method's tip positions (``plot.x``,
  ``plot.y`` at ``plot.point``) over every load direction and magnitude as a point cloud, and its
  boundary at the largest load level (points joined in the order of the swept angle).
* ``scatter``: Monte Carlo spread of a point (the coupler point of a mechanism) at each load level,
  per method: the samples, their mean, standard deviations and the 95 % covariance ellipse
  (Mahalanobis radius sqrt(chi2_2(0.95)) = 2.448); the numbers go to ``spread.csv``.
* ``convergence``: discretisation error against the swept parameter ``plot.by`` (FEM elements):
  |value - reference| for each case, quantity and point, the largest over load levels, where the
  reference is the exact elastica of the same case if the sweep ran it, else the finest mesh
  (then the finest point is left out). Log-log, with the observed order between the two finest
  meshes; the numbers go to ``convergence.csv``.
* ``difference``: the model error of the first method of the sweep against the second (e.g. the
  PRBM against the FEM) over the swept parameter ``plot.by``: |a - b| / |b| for each case and
  quantity, the largest over points and load levels (|b| > 0); the numbers go to ``difference.csv``.

Whatever the kind, every output that does not depend on the swept parameters for some method is
found (``validation/sweep/sensitivity.py``), written to ``invariance.csv`` and said in the plots'
legends and the summary, instead of being drawn as a zero spread; quantities other than the plot's
axes (an input torque, an energy) get their own spread plot per level, ``quantities.png``.

Only rows with status 'ok' are plotted; failed points stay in the dataset.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from validation.sweep.run import load_results
from validation.sweep.sensitivity import invariance, summary_lines
import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

CHI2_2DOF_95 = 5.991464547107979  # chi-square quantile, 2 degrees of freedom, 0.95


NOISE = 1e-9  # a spread below NOISE x the study's largest magnitude is rounding: no spread


def _save(fig, path: Path) -> Path:
    """Lay out, write and close a figure, its legends (below the axes) inside the picture; the path written."""
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def _legend(ax) -> None:
    """The axes' legend under them, clear of the data (and of the x label)."""
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.16), borderaxespad=0.0, frameon=False)


def _at_value(set_limits, values, scale: float) -> None:
    """Values whose spread is below rounding (``NOISE`` x ``scale``, the study's largest magnitude of the
    quantity) drawn at their value: limits of +- 5 % of ``scale`` around it (+- 1 when the study is all
    zero) instead of an axis 1e-16 wide; a real spread keeps matplotlib's limits."""
    values = np.asarray(values, float)
    values = values[np.isfinite(values)]
    if not len(values) or values.max() - values.min() > NOISE * scale:
        return
    centre = float(values.mean()) if abs(values.mean()) > NOISE * scale else 0.0
    half = 0.05 * scale or 1.0
    set_limits(centre - half, centre + half)


def _figure(rows: int = 1, cols: int = 1, size=(6.4, 4.8)):
    fig, axes = plt.subplots(rows, cols, figsize=(size[0] * cols, size[1] * rows), squeeze=False)
    return plt, fig, axes.ravel()


def axes_of(frame: pd.DataFrame, spec: dict) -> tuple[str, str, str | None]:
    """The plot's quantities and point: as the spec says, else (x, y) or (dx, dy) at the first point."""
    ok = frame[frame["status"] == "ok"]
    have = set(ok["quantity"].dropna())
    x = spec.get("x") or ("x" if "x" in have else "dx")
    y = spec.get("y") or ("y" if "y" in have else "dy")
    point = spec.get("point")
    if point is None:
        both = ok[ok["quantity"].isin([x, y])].groupby("point")["quantity"].nunique()
        point = next((p for p in both.index if both[p] == 2), None)
    return x, y, point


def _positions(frame: pd.DataFrame, x: str, y: str, point: str | None) -> pd.DataFrame:
    """One row per (point id, method, level) with columns x and y (none without a point)."""
    ok = frame[(frame["status"] == "ok") & (frame["point"] == point) & frame["quantity"].isin([x, y])]
    index = [
        c
        for c in ok.columns
        if c
        not in (
            "quantity",
            "value",
            "unit",
            "error_estimate",
            "converged",
            "status",
            "message",
            "wall_time",
            "point_time",
            "run",
        )
    ]
    wide = ok.pivot_table(index=index, columns="quantity", values="value", aggfunc="first").reset_index()
    return wide.dropna(subset=[c for c in (x, y) if c in wide.columns])


def plot_domain(frame: pd.DataFrame, manifest: dict, out: Path) -> list[Path]:
    x, y, point = axes_of(frame, manifest["plot"])
    wide = _positions(frame, x, y, point)
    if wide.empty or x not in wide or y not in wide:
        return []
    angles = [p.get("name") or p["path"] for p in manifest["parameters"] if p.get("mode") == "angle"]
    cases = sorted(wide["case"].unique())
    plt, fig, axes = _figure(1, len(cases))
    for ax, case in zip(axes, cases):
        part = wide[wide["case"] == case]
        for k, (method, rows) in enumerate(part.groupby("method")):
            color = f"C{k}"
            ax.scatter(rows[x], rows[y], s=4, color=color, alpha=0.35, label=f"{method} ({len(rows)} pts)")
            top = rows[rows["level"] == rows["level"].max()]
            if angles and len(top) > 1:
                top = top.sort_values(angles[0])
                ax.plot(top[x], top[y], color=color, lw=1.5, label=f"{method}, largest load")
        ax.set_xlabel(f"{x} at {point}")
        ax.set_ylabel(f"{y} at {point}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{case}: deflection domain")
        ax.grid(alpha=0.3)
        _legend(ax)
    return [_save(fig, out / "domain.png")]


def ellipse(mean: np.ndarray, cov: np.ndarray, scale2: float = CHI2_2DOF_95, n: int = 100) -> np.ndarray:
    """Points of the ellipse (p - mean)^T cov^-1 (p - mean) = scale2, as an (n, 2) array."""
    values, vectors = np.linalg.eigh(cov)
    t = np.linspace(0, 2 * math.pi, n)
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)
    return mean + (circle * np.sqrt(np.clip(values, 0, None) * scale2)) @ vectors.T


def spread(frame: pd.DataFrame, x: str, y: str, point: str | None) -> pd.DataFrame:
    """Mean, standard deviation and correlation of (x, y) per case, method and level."""
    wide = _positions(frame, x, y, point)
    rows = []
    for (case, method, level), part in wide.groupby(["case", "method", "level"]):
        xy = part[[x, y]].to_numpy(float)
        cov = np.cov(xy.T) if len(xy) > 1 else np.zeros((2, 2))
        sx, sy = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
        rows.append(
            dict(
                case=case,
                method=method,
                level=int(level),
                n=len(xy),
                **{
                    f"mean_{x}": xy[:, 0].mean(),
                    f"mean_{y}": xy[:, 1].mean(),
                    f"std_{x}": sx,
                    f"std_{y}": sy,
                    "correlation": cov[0, 1] / (sx * sy) if sx * sy > 0 else math.nan,
                },
            )
        )
    return pd.DataFrame(rows)


def parameter_columns(manifest: dict) -> list[str]:
    return [p.get("name") or p["path"] for p in manifest["parameters"]]


def _constant(frame: pd.DataFrame, manifest: dict) -> set[tuple]:
    """(case, method, quantity, point) of every output that no swept parameter changes."""
    table = invariance(frame, parameter_columns(manifest))
    return {
        tuple(r)
        for r in table[~table["varies"].astype(bool)][["case", "method", "quantity", "point"]].itertuples(index=False)
    }


def plot_scatter(frame: pd.DataFrame, manifest: dict, out: Path) -> list[Path]:
    x, y, point = axes_of(frame, manifest["plot"])
    constant = _constant(frame, manifest)
    wide = _positions(frame, x, y, point)
    if wide.empty or x not in wide or y not in wide:
        return []
    levels = manifest["plot"].get("levels") or sorted(int(v) for v in wide["level"].unique())
    table = spread(frame, x, y, point)
    table.to_csv(out / "spread.csv", index=False)
    plt, fig, axes = _figure(1, len(levels), size=(5.0, 4.6))
    for ax, level in zip(axes, levels):
        part = wide[wide["level"] == level]
        for k, (method, rows) in enumerate(part.groupby("method")):
            color = f"C{k}"
            xy = rows[[x, y]].to_numpy(float)
            mean = xy.mean(axis=0)
            ax.scatter(xy[:, 0], xy[:, 1], s=5, color=color, alpha=0.4)
            label = f"{method}: n={len(xy)}"
            case = rows["case"].iloc[0]
            if {(case, method, x, point), (case, method, y, point)} <= constant:
                label += ": does not depend on the swept parameters (zero spread by construction)"
            elif len(xy) > 2:
                sd = xy.std(axis=0, ddof=1)
                label += f", std=({sd[0]:.3g}, {sd[1]:.3g})"
                ring = ellipse(mean, np.cov(xy.T))
                ax.plot(ring[:, 0], ring[:, 1], color=color, lw=1.5)
            ax.plot(*mean, marker="+", ms=12, color=color, label=label)
        ax.set_title(f"level {level}: {point} ({x}, {y}), 95 % ellipse")
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        ax.ticklabel_format(useOffset=False)
        _at_value(ax.set_xlim, part[x], float(wide[x].abs().max()))
        _at_value(ax.set_ylim, part[y], float(wide[y].abs().max()))
        ax.grid(alpha=0.3)
        _legend(ax)
    return [_save(fig, out / "scatter.png")]


def convergence(frame: pd.DataFrame, by: str) -> pd.DataFrame:
    """Largest error over levels per case, method, quantity, point and value of ``by``."""
    ok = frame[(frame["status"] == "ok") & frame["quantity"].notna()]
    keys = ["case", "quantity", "point", "level"]
    exact = ok[ok["method"] == "elastica"].groupby(keys)["value"].first()
    studied = ok[ok["method"] != "elastica"]
    rows = []
    for (case, method), part in studied.groupby(["case", "method"]):
        finest = part[by].max()
        for key, group in part.groupby(["quantity", "point", "level"]):
            full = (case, *key)
            if full in exact.index:
                reference, against = exact[full], "elastica"
            else:
                fine = group[group[by] == finest]["value"]
                if fine.empty:
                    continue
                reference, against = fine.iloc[0], f"{by} = {finest:g}"
            for _, row in group.iterrows():
                if against != "elastica" and row[by] == finest:
                    continue
                rows.append(
                    dict(
                        case=case,
                        method=method,
                        quantity=key[0],
                        point=key[1],
                        level=key[2],
                        by=row[by],
                        error=abs(row["value"] - reference),
                        reference=against,
                    )
                )
    table = pd.DataFrame(rows)
    if table.empty:
        return table
    return (
        table.groupby(["case", "method", "quantity", "point", "by", "reference"], as_index=False)["error"]
        .max()
        .rename(columns={"by": by})
    )


def plot_convergence(frame: pd.DataFrame, manifest: dict, out: Path) -> list[Path]:
    by = manifest["plot"].get("by")
    if not by or by not in frame.columns:
        by = next((p.get("name") or p["path"] for p in manifest["parameters"]), None)
    table = convergence(frame, by)
    if table.empty:
        return []
    table.to_csv(out / "convergence.csv", index=False)
    cases = sorted(table["case"].unique())
    plt, fig, axes = _figure(1, len(cases), size=(5.2, 4.4))
    for ax, case in zip(axes, cases):
        part = table[table["case"] == case]
        for (method, quantity, point, reference), line in part.groupby(["method", "quantity", "point", "reference"]):
            line = line.sort_values(by)
            n, e = line[by].to_numpy(float), line["error"].to_numpy(float)
            label = f"{method} {quantity}@{point}" if point else f"{method} {quantity}"
            if len(n) >= 2 and e[-1] > 0 and e[-2] > 0:
                label += f" (order {math.log(e[-2] / e[-1]) / math.log(n[-1] / n[-2]):.2f})"
            ax.loglog(n, np.where(e > 0, e, np.nan), marker="o", label=label)
        ax.set_xlabel(by)
        ax.set_ylabel(f"|error| (largest over levels; vs {part['reference'].iloc[0]})")
        ax.set_title(case)
        ax.grid(alpha=0.3, which="both")
        _legend(ax)
    return [_save(fig, out / "convergence.png")]


def plot_quantities(frame: pd.DataFrame, manifest: dict, out: Path, skip: set[str]) -> list[Path]:
    """Spread of every quantity not on the main plot's axes, per level and method: the samples, their
    mean and standard deviation, or the words 'constant' where no parameter changes it."""
    ok = frame[(frame["status"] == "ok") & frame["quantity"].notna() & ~frame["quantity"].isin(skip)]
    if ok.empty:
        return []
    constant = _constant(frame, manifest)
    groups = list(ok.groupby(["case", "quantity", "point"], dropna=False))
    plt, fig, axes = _figure(1, len(groups), size=(5.0, 4.2))
    for ax, ((case, quantity, point), part) in zip(axes, groups):
        for k, (method, rows) in enumerate(part.groupby("method")):
            levels = rows.groupby("level")["value"]
            mean, sd = levels.mean(), levels.std(ddof=1).fillna(0.0)
            ax.scatter(rows["level"] + 0.08 * k, rows["value"], s=5, color=f"C{k}", alpha=0.35)
            label = f"{method}: mean, +-2 std"
            if (case, method, quantity, point) in constant:
                label = f"{method}: constant, does not depend on the swept parameters"
            ax.errorbar(mean.index + 0.08 * k, mean, yerr=2 * sd, color=f"C{k}", capsize=3, label=label)
        where = f" at {point}" if isinstance(point, str) and point else ""
        unit = part["unit"].dropna().iloc[0] if part["unit"].notna().any() else ""
        ax.set_title(f"{case}: {quantity}{where}")
        ax.set_xlabel("load level")
        ax.set_ylabel(f"{quantity} [{unit}]")
        ax.ticklabel_format(useOffset=False)
        _at_value(ax.set_ylim, part["value"], float(part["value"].abs().max()))
        ax.grid(alpha=0.3)
        _legend(ax)
    return [_save(fig, out / "quantities.png")]


def difference(frame: pd.DataFrame, by: str, methods: list[str]) -> pd.DataFrame:
    """Largest |a - b| / |b| over levels and points per case, quantity and value of ``by``."""
    ok = frame[(frame["status"] == "ok") & frame["quantity"].notna() & frame["method"].isin(methods[:2])]
    wide = ok.pivot_table(
        index=["case", "quantity", "point", "level", by], columns="method", values="value", aggfunc="first"
    ).dropna()
    if len(methods) < 2 or not set(methods[:2]) <= set(wide.columns):
        return pd.DataFrame()
    a, b = wide[methods[0]], wide[methods[1]]
    rel = ((a - b).abs() / b.abs()).where(b.abs() > 0).rename("relative_difference").dropna()
    return rel.groupby(level=["case", "quantity", by]).max().reset_index()


def plot_difference(frame: pd.DataFrame, manifest: dict, out: Path) -> list[Path]:
    by = manifest["plot"].get("by") or next((p.get("name") or p["path"] for p in manifest["parameters"]), None)
    if by is None:  # a sweep has at least one parameter (``SweepSpec``)
        return []
    methods = list(manifest.get("methods") or [])
    table = difference(frame, by, methods)
    if table.empty:
        return []
    table.to_csv(out / "difference.csv", index=False)
    plt, fig, axes = _figure(1, 1, size=(6.0, 4.4))
    ax = axes[0]
    for (case, quantity), line in table.groupby(["case", "quantity"]):
        line = line.sort_values(by)
        ax.plot(line[by], 100 * line["relative_difference"], marker="o", label=f"{case} {quantity}")
    ax.set_xlabel(by)
    ax.set_ylabel(f"|{methods[0]} - {methods[1]}| / |{methods[1]}| [%] (largest over levels)")
    ax.grid(alpha=0.3)
    _legend(ax)
    return [_save(fig, out / "difference.png")]


PLOTS = {"domain": plot_domain, "scatter": plot_scatter, "convergence": plot_convergence, "difference": plot_difference}


def sensitivity_summary(out: Path | str) -> list[str]:
    """Write ``invariance.csv``; one line per case and method whose outputs no parameter changes."""
    out = Path(out)
    manifest = json.loads((out / "sweep.json").read_text())
    frame = load_results(out)
    if frame.empty:
        return []
    table = invariance(frame, parameter_columns(manifest))
    table.to_csv(out / "invariance.csv", index=False)
    return summary_lines(table, parameter_columns(manifest))


def plot_sweep(out: Path | str) -> list[Path]:
    """Draw the plot the spec asks for next to the results; the files written (none if no data)."""
    out = Path(out)
    manifest_path = out / "sweep.json"
    if not manifest_path.is_file():
        return []
    manifest = json.loads(manifest_path.read_text())
    draw = PLOTS.get(manifest["plot"]["kind"])
    frame = load_results(out)
    if draw is None or frame.empty:
        return []
    written = draw(frame, manifest, out)
    if manifest["plot"]["kind"] == "scatter":
        x, y, _ = axes_of(frame, manifest["plot"])
        written += plot_quantities(frame, manifest, out, skip={x, y})
    return written
