"""One picture of the whole validation: the PRBM's distance from the FEM against how far the structure
deflects, for every case and every load level, coloured by the PRBM segment model, with the accuracy
claims printed in the sources ([bapat2015], [ananthasuresh_l18]) drawn on the same axes.

Axes (both over the case's characteristic length L, the segment length or the mechanism's extent):
x = the largest FEM displacement of any element node at the level, |u|max / L;
y = the largest |PRBM - FEM| of the case's length outputs (positions, displacements) at the level, in % of L.

The claims (``CLAIMS``), each with where it is printed:

- [bapat2015, §2.3] (the PRBM of a fixed-free / fixed-pinned segment): the PRBM parameters are chosen so
  that the beam end point lies "within a small error tolerance, of say 0.5%" of the elliptic-integral
  solution; with the Howell-Midha measure (error over tip deflection, notes/anchors.md §2.7) this is the
  line y = 0.5 % of x.  It is a claim about the *path* (where the PRB end lies for a deflection), while
  the dots are errors at equal load (path and stiffness together): the legend says so, and the atlas
  page (``validation.report.atlas_page``) gives the split and where the path claim holds.
- [bapat2015, eqs 51-52]: the K_Theta(n, Theta) fits hold for 0 < Theta <= 65 deg; the PRB tip of a
  link gamma L turned by Theta has moved 2 gamma L sin(Theta/2), so with gamma = 0.8517 (n = 0) the
  end of the fit range is x = 0.9152.
- [bapat2015, ch. 4, Fig. 4.13]: the characteristic radius factor 0.8945 estimates the lower bound of the
  fixed-guided deflection domain within 1 % for normalised transverse deflection 0.4 to 0.85: the
  segment y = 1 % of x over 0.4 <= x <= 0.85.
- [ananthasuresh_l18] (the PRB-modelling lecture) prints no numeric accuracy: it says the n-fits of
  gamma and K_Theta can be used "comfortably and quite accurately" within their n-ranges; nothing to draw.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from validation.report.format import by_case, rows_of  # noqa: E402
from validation.report.summary import prbm_fem_by_level  # noqa: E402
from validation.run.runner import CaseResult  # noqa: E402

GAMMA_N0 = 0.8517  # Howell-Midha characteristic radius factor at n = 0 ([bapat2015, eq 41]: 0.851892)
THETA_FIT_MAX_DEG = 65.0  # [bapat2015, eqs 51-52]
FLOOR_PERCENT = 1e-3  # errors below this are drawn on it (a log axis has no zero)


@dataclass(frozen=True)
class Claim:
    """A printed accuracy claim: y = slope * x (in % of L) over [x_from, x_to], or a vertical line at x."""

    label: str
    slope: float | None = None
    x_from: float = 0.0
    x_to: float = math.inf
    vertical: float | None = None


CLAIMS = (
    Claim(
        "path claim [bapat2015 §2.3]: PRB end within 0.5 % of the deflection of the\n"
        "beam's end path (the dots are at equal load: path + stiffness error)",
        slope=0.5,
    ),
    Claim(
        "domain claim [bapat2015 ch. 4, Fig. 4.13]: the fixed-guided lower bound\n"
        "within 1 % for b/l 0.4-0.85 (a bound of the domain, not a PRBM-vs-FEM error)",
        slope=1.0,
        x_from=0.4,
        x_to=0.85,
    ),
    Claim(
        f"fit range [bapat2015 eqs 51-52]: K_Θ fitted up to Θ = {THETA_FIT_MAX_DEG:.0f}°\n"
        f"(PRB tip moved 2γL sin(Θ/2), γ = {GAMMA_N0})",
        vertical=2 * GAMMA_N0 * math.sin(math.radians(THETA_FIT_MAX_DEG) / 2),
    ),
)


@dataclass
class OverviewPoint:
    case: str
    level: int
    deflection: float  # |u|max / L; NaN: the FEM kept no displacement field to place the level by
    error_percent: float  # max |PRBM - FEM| / L, in %
    model: str


def segment_model(result: CaseResult) -> str:
    """A short name of the PRBM model the case used (from the adapter's ``extras['model']``)."""
    run = result.runs.get("prbm")
    model = str(run.extras.get("model", "")) if run else ""
    if not model:
        case = result.loaded.case
        return case.segment.boundary if case.segment is not None else "mechanism"
    return re.split(r"[,(;]", model)[0].strip()[:48]


def overview_points(results: list[CaseResult], table: pd.DataFrame) -> list[OverviewPoint]:
    """Every (case, level) where the PRBM and the FEM both give a length output (``case_points`` of
    each case, in the order of ``results``)."""
    parts = by_case(table)
    return [p for result in results for p in case_points(result, rows_of(parts, table, result.loaded.id))]


def case_points(result: CaseResult, part: pd.DataFrame) -> list[OverviewPoint]:
    """The case's points from its rows ``part``: a point per level where the PRBM and the FEM both give a
    length output; a case whose FEM keeps no displacement field gets one point of NaN deflection at its
    largest error, so that the picture counts the same cases as the index's headline (the cases that
    compare a position) and names those it cannot place."""
    errors = prbm_fem_by_level(part).dropna()
    if errors.empty:
        return []
    fem = result.runs.get("fem")
    fields = fem.extras.get("fields") if fem else None
    model = segment_model(result)
    if fields is None:
        worst = int(errors.idxmax())
        return [OverviewPoint(result.loaded.id, worst, math.nan, 100 * float(errors[worst]), model)]
    scale = float(part["scale"].dropna().iloc[0])
    points = []
    for level, error in errors.items():
        level = int(level)
        if level >= len(fields.nodal):
            continue
        deflection = float(np.hypot(*fields.nodal[level].displacement.T).max()) / scale
        points.append(OverviewPoint(result.loaded.id, level, deflection, 100 * float(error), model))
    return points


MODEL_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "h")


def model_style(k: int) -> tuple[tuple, str]:
    """(colour, marker) of the k-th PRBM model of the picture: tab10's ten colours, then the same colours
    with the next marker, so that no two models look alike (100 of them; tab10 alone repeated its colours
    from the eleventh model on)."""
    return plt.get_cmap("tab10")(k % 10), MODEL_MARKERS[(k // 10) % len(MODEL_MARKERS)]


def overview_title(drawn: list[OverviewPoint], compared: set[str]) -> str:
    """'PRBM error at equal load against deflection: 329 load levels of 66 of the 67 cases that compare
    a position', and on a second line the cases not placed and why."""
    placed = {p.case for p in drawn}
    head = f"PRBM error at equal load against deflection: {len(drawn)} load levels of "
    if placed == compared:
        return head + f"{len(placed)} cases (every case that compares a position)"
    missing = sorted(compared - placed)
    named = ", ".join(missing[:2]) + (f" and {len(missing) - 2} more" if len(missing) > 2 else "")
    return (
        head + f"{len(placed)} of the {len(compared)} cases that compare a position\n"
        f"not placed: {named} (no FEM displacement field, or no load, to place it by)"
    )


def plot_overview(points: list[OverviewPoint], png: Path, formats: tuple[str, ...] = ("png", "svg")) -> Path:
    """The picture as PNG, and as SVG whose dots link to their case pages (``formats``: which of the two,
    e.g. each drawn by a process of its own); an empty validation still gets axes and the claims. Its
    title counts the cases that compare a position (``points``' cases) and says which of them it cannot
    place (no FEM displacement field, or no load)."""
    compared = {p.case for p in points}
    points = [p for p in points if p.deflection > 1e-9]  # an unloaded level says nothing; NaN: no field
    fig, ax = plt.subplots(figsize=(12.0, 4.4))
    fig.subplots_adjust(left=0.06, right=0.56, bottom=0.12, top=0.89)
    models = sorted({p.model for p in points})
    for k, model in enumerate(models):
        mine = [p for p in points if p.model == model]
        colour, marker = model_style(k)
        dots = ax.scatter(
            [p.deflection for p in mine],
            [max(p.error_percent, FLOOR_PERCENT) for p in mine],
            s=22,
            color=colour,
            marker=marker,
            edgecolor="k",
            linewidth=0.3,
            label=f"{model} ({len({p.case for p in mine})} case(s))",
        )
        dots.set_urls([f"cases/{p.case}.html" for p in mine])  # the SVG's dots open their case page
    x_max = max([p.deflection for p in points] + [1.2]) * 1.05
    for k, claim in enumerate(CLAIMS):
        style: dict[str, Any] = dict(color="0.2", lw=1.2, ls=("--", ":", "-.")[k % 3], label=claim.label)
        if claim.vertical is not None:
            ax.axvline(claim.vertical, **style)
        else:
            if claim.slope is None:
                raise ValueError(f"claim '{claim.label}' gives neither a slope nor a vertical line")
            xs = np.linspace(max(claim.x_from, 1e-3), min(claim.x_to, x_max), 50)
            ax.plot(xs, claim.slope * xs, **style)
    ax.set_yscale("log")
    ax.set_ylim(bottom=max(min([p.error_percent for p in points] + [0.1]) / 2, FLOOR_PERCENT / 2))
    ax.set_xlim(0, x_max)
    ax.set_xlabel("largest FEM displacement / L")
    ax.set_ylabel("PRBM vs FEM, largest position error [% of L]")
    ax.set_title(overview_title(points, compared), fontsize=10, loc="left")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    if "png" in formats:
        fig.savefig(png, dpi=90)
    if "svg" in formats:
        fig.savefig(png.with_suffix(".svg"))
    plt.close(fig)
    return png
