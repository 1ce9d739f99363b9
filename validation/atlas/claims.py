"""The seeds' printed accuracy claims about PRBM segment models, checked against the error atlas.

A claim (``cases/atlas/claims.toml``) reads one printed sentence onto the atlas: on a model (or several),
over the inputs in its ``range`` (atlas column = [lo, hi], ends included; a boolean column is 0/1),
|metric| <= bound, the metric being an atlas error column in that column's unit.  ``load_claims``
reads and checks the file; ``check_claims`` gives every claim a verdict on an atlas DataFrame
(``validation.atlas.lines.solve_line`` rows with a ``model`` column).

The points of a claim are the atlas's ``ok`` rows of its model(s) inside the range.  A point whose metric
is NaN is *unmeasured* and left out of the verdict: the path split is NaN where the PRBM's line does not
reach the exact path coordinate within the line's loads (typically the last level of a line), which
says nothing either way about the claim; ``unmeasured`` counts them.  The verdict, on the measured points:

* ``not testable``: no measured points (``why`` says which model, range entry or metric left none);
* ``holds``: every point is within the bound;
* ``holds on part of its range``: at least half of the points are within, and so is every point up to
  some value of the claim's ``along`` axis (its first range key unless named; ``load`` without a
  range): ``holds_where`` names the largest such prefix, e.g. "prb_angle_deg <= 41";
* ``does not hold``: fewer than half of the points are within, or the claim already fails at the low
  end of its ``along`` axis (where the model is meant to be at its best).

Sources: [bapat2015] section 2.3 (the 0.5 % end-point tolerance) and the equations each claim cites;
[ananthasuresh_l18] (the lecture's fits and the pure-moment model).
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

FIELDS = {"id", "model", "source", "quote", "metric", "bound", "note", "range", "along"}
REQUIRED = ("id", "model", "source", "quote", "metric", "bound", "note")
VERDICTS = ("holds", "holds on part of its range", "does not hold", "not testable")
_SNAKE = re.compile(r"[a-z][a-z0-9_]*")


@dataclass(frozen=True)
class Claim:
    """One printed claim read onto the atlas: |metric| <= bound on ``models`` over ``range``."""

    id: str
    models: tuple[str, ...]
    source: str
    quote: str
    metric: str
    bound: float
    note: str
    range: tuple[tuple[str, float, float], ...] = ()  # (column, lo, hi), in file order
    along: str = "load"  # the axis ``holds_where`` is told along

    @property
    def model(self) -> str:
        return ", ".join(self.models)


def _fail(path, claim_id: str, field: str, problem: str) -> ValueError:
    """The one-line error: file, claim id and field (those known), then the problem."""
    where = [str(path)] + ([f"claim {claim_id!r}"] if claim_id else []) + ([f"field {field!r}"] if field else [])
    return ValueError(": ".join(where + [problem]).replace("\n", " "))


def _text(path, cid: str, raw: dict, field: str) -> str:
    """A required non-empty string field."""
    value = raw[field]
    if not isinstance(value, str) or not value.strip():
        raise _fail(path, cid, field, "must be a non-empty string")
    return value.strip()


def _claim(path, index: int, raw) -> Claim:
    """One [[claim]] table, checked field by field (``index`` names a claim without an id)."""
    if not isinstance(raw, dict):
        raise _fail(path, f"#{index + 1}", "claim", "each [[claim]] must be a table")
    cid = str(raw.get("id", f"#{index + 1}"))
    for field in REQUIRED:
        if field not in raw:
            raise _fail(path, cid, field, "missing")
    unknown = sorted(set(raw) - FIELDS)
    if unknown:
        raise _fail(path, cid, unknown[0], f"unknown field (known: {', '.join(sorted(FIELDS))})")
    if not isinstance(raw["id"], str) or not _SNAKE.fullmatch(raw["id"]):
        raise _fail(path, cid, "id", "must be a snake_case string")
    models = raw["model"] if isinstance(raw["model"], list) else [raw["model"]]
    if not models or not all(isinstance(m, str) and m for m in models):
        raise _fail(path, cid, "model", "must be a model name or a non-empty list of names")
    bound = raw["bound"]
    if isinstance(bound, bool) or not isinstance(bound, (int, float)) or not math.isfinite(bound) or bound <= 0:
        raise _fail(path, cid, "bound", f"must be a positive number, not {bound!r}")
    ranges = raw.get("range", {})
    if not isinstance(ranges, dict):
        raise _fail(path, cid, "range", "must be a table of column = [lo, hi]")
    spans = []
    for column, pair in ranges.items():
        ok = (
            isinstance(pair, list)
            and len(pair) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in pair)
        )
        if not ok or not pair[0] <= pair[1]:
            raise _fail(path, cid, f"range.{column}", f"must be [lo, hi] with lo <= hi, not {pair!r}")
        spans.append((column, float(pair[0]), float(pair[1])))
    along = raw.get("along", spans[0][0] if spans else "load")
    if not isinstance(along, str) or not along:
        raise _fail(path, cid, "along", "must be a column name")
    return Claim(
        raw["id"],
        tuple(models),
        _text(path, cid, raw, "source"),
        _text(path, cid, raw, "quote"),
        _text(path, cid, raw, "metric"),
        float(bound),
        _text(path, cid, raw, "note"),
        tuple(spans),
        along,
    )


def load_claims(path: Path | str) -> list[Claim]:
    """The claims of a TOML file (``[[claim]]`` tables); a bad file or field raises a one-line
    ``ValueError`` naming the file, the claim id and the field."""
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise _fail(path, "", "", f"not a readable TOML file ({exc})") from None
    raws = data.get("claim")
    if not isinstance(raws, list) or not raws:
        raise _fail(path, "", "claim", "the file needs at least one [[claim]] table")
    claims = [_claim(path, i, raw) for i, raw in enumerate(raws)]
    seen = set()
    for c in claims:
        if c.id in seen:
            raise _fail(path, c.id, "id", "used by two claims")
        seen.add(c.id)
    return claims


def _points(atlas: pd.DataFrame, claim: Claim) -> tuple[pd.DataFrame, str]:
    """The ok rows of the claim's models inside its range, and why there are none (if so)."""
    rows = atlas[atlas["model"].isin(claim.models)] if "model" in atlas else atlas.iloc[:0]
    if rows.empty:
        return rows, f"the atlas has no rows of {claim.model}"
    rows = rows[rows["status"] == "ok"]
    if rows.empty:
        return rows, f"no row of {claim.model} has status ok"
    for column in (claim.metric, claim.along):
        if column not in rows:
            return rows.iloc[:0], f"the atlas has no column {column!r}"
    for column, lo, hi in claim.range:
        if column not in rows:
            return rows.iloc[:0], f"the atlas has no column {column!r}"
        values = rows[column].astype(float)
        inside = rows[(values >= lo) & (values <= hi)]
        if inside.empty:
            span = values.agg(["min", "max"])
            return inside, (
                f"no ok point has {column} in [{lo:g}, {hi:g}] "
                f"(the ok points span [{span['min']:.4g}, {span['max']:.4g}])"
            )
        rows = inside
    return rows, ""


def check_claim(atlas: pd.DataFrame, claim: Claim) -> dict:
    """One claim's row of ``check_claims``."""
    row = {
        "id": claim.id,
        "model": claim.model,
        "source": claim.source,
        "metric": claim.metric,
        "bound": claim.bound,
        "points": 0,
        "unmeasured": 0,
        "worst": math.nan,
        "share_within": math.nan,
        "verdict": "not testable",
        "holds_where": "",
        "why": "",
        "quote": claim.quote,
        "note": claim.note,
    }
    rows, why = _points(atlas, claim)
    if rows.empty:
        return {**row, "why": why}
    size = np.abs(rows[claim.metric].to_numpy(float))
    measured = np.isfinite(size)
    row.update(points=int(rows.shape[0]), unmeasured=int((~measured).sum()))
    if not measured.any():
        return {**row, "why": f"{claim.metric} is NaN at all {rows.shape[0]} points"}
    size, along = size[measured], rows[claim.along].to_numpy(float)[measured]
    within = size <= claim.bound
    share = float(within.mean())
    row.update(worst=float(size.max()), share_within=share)
    if within.all():
        return {**row, "verdict": "holds", "holds_where": "everywhere in its range"}
    failing = along[~within & np.isfinite(along)]
    first_fail = float(failing.min()) if failing.size else -math.inf
    prefix = np.isfinite(along) & (along < first_fail)
    why = f"{share:.0%} of {size.size} measured points within; first failure at {claim.along} = {first_fail:.4g}"
    if share < 0.5 or not prefix.any():
        return {**row, "verdict": "does not hold", "why": why}
    where = f"{claim.along} <= {along[prefix].max():.4g} ({int(prefix.sum())} of {size.size} points)"
    return {**row, "verdict": "holds on part of its range", "holds_where": where, "why": why}


def check_claims(atlas: pd.DataFrame, claims: list[Claim]) -> pd.DataFrame:
    """One row per claim: id, model, source, metric, bound, points, unmeasured, worst (max |metric| over
    the measured points), share_within (of the measured points), verdict, holds_where, why, quote, note
    (the verdict rule is in the module docstring)."""
    return pd.DataFrame([check_claim(atlas, c) for c in claims])


DOMAIN_QUOTE = (
    "The value of gamma-bar_l = 0.8945 can estimate the lower bound within an error of 1% for "
    "normalized transverse deflection between 0.4 and 0.85."
)


def domain_study_rows(summary: list[dict]) -> pd.DataFrame:
    """The printed bound claims of [bapat2015, section 4.6] (eq 116 and the gamma-bar_l circle of eq 117,
    Fig. 4.13) as claim rows: they are about the boundary of the fixed-guided deflection domain, which
    the chapter-4 domain study (``validation.sweep.domain_study``, its ``summary.json``) computes from
    the exact elliptic solutions; the atlas has no such boundary.  The verdict: holds when the largest
    deviation over the printed range is within the claim, else does not hold."""
    rows = []
    for result in summary:
        for check in result.get("checks", []):
            holds = check["max_percent"] <= check["claim_percent"]
            rows.append(
                {
                    "id": "domain_lower_bound_" + re.sub(r"[^a-z0-9]+", "_", check["name"].lower()).strip("_"),
                    "model": "fixed_guided (chapter-4 deflection domain)",
                    "source": "bapat2015, section 4.6, eqs 116-117, Fig. 4.13",
                    "metric": "relative deviation from the exact lower boundary (%)",
                    "bound": check["claim_percent"],
                    "points": math.nan,
                    "unmeasured": 0,
                    "worst": check["max_percent"],
                    "share_within": math.nan,
                    "verdict": "holds" if holds else "does not hold",
                    "holds_where": "",
                    "why": f"{check['name']} over {check['over']}: mean deviation {check['mean_percent']:.2f} %",
                    "quote": DOMAIN_QUOTE,
                    "note": "checked by the chapter-4 domain study on the exact deflection domain (not an atlas "
                    "column): the printed curve against the least a/l per bin of b/l",
                }
            )
    return pd.DataFrame(rows)
