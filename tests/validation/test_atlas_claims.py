"""The atlas's claim checker (validation.atlas.claims) on small synthetic atlases, and the shipped
claims file (cases/atlas/claims.toml) against the atlas's models and columns."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from validation.atlas.claims import Claim, check_claims, domain_study_rows, load_claims
from validation.atlas.lines import solve_line
from validation.atlas.models import MODELS

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "cases" / "atlas" / "claims.toml"


def atlas(errors, x=None, model="m", status="ok") -> pd.DataFrame:
    """One line of a synthetic atlas: the error ``e`` along an input ``x`` (0, 1, 2, ...)."""
    errors = np.asarray(errors, float)
    x = np.arange(errors.size, dtype=float) if x is None else np.asarray(x, float)
    return pd.DataFrame({"model": model, "status": status, "x": x, "flag": True, "e": errors})


def claim(bound=1.0, range_=(("x", 0.0, 100.0),), model="m", along=None) -> Claim:
    return Claim(
        "c",
        (model,) if isinstance(model, str) else tuple(model),
        "src",
        "quote",
        "e",
        bound,
        "note",
        tuple(range_),
        along or (range_[0][0] if range_ else "load"),
    )


def verdict(df, c) -> pd.Series:
    return check_claims(df, [c]).iloc[0]


RAMP = np.linspace(0.05, 0.95, 10)  # within 1.0, worst 0.95


def test_holds():
    r = verdict(atlas(RAMP), claim())
    assert (r.verdict, r.points, r.share_within) == ("holds", 10, 1.0)
    assert r.worst == pytest.approx(0.95)


def test_holds_on_part_names_the_prefix():
    r = verdict(atlas(np.r_[RAMP[:8], 1.5, 0.2]), claim())
    assert r.verdict == "holds on part of its range"
    assert r.holds_where.startswith("x <= 7 ")
    assert r.share_within == pytest.approx(0.9)


def test_does_not_hold_when_most_points_fail():
    r = verdict(atlas([0.1, 0.2, 3, 3, 3, 3, 3, 3, 3, 3]), claim())
    assert r.verdict == "does not hold" and r.share_within == pytest.approx(0.2)


def test_does_not_hold_when_it_fails_at_the_low_end():
    r = verdict(atlas(np.r_[2.0, RAMP[1:]]), claim())  # 90 % within, but not at x = 0
    assert r.verdict == "does not hold" and "x = 0" in r.why


def test_not_testable_says_why():
    r = verdict(atlas(RAMP), claim(model="other"))
    assert r.verdict == "not testable" and "no rows of other" in r.why
    r = verdict(atlas(RAMP), claim(range_=(("x", 50.0, 60.0),)))
    assert r.verdict == "not testable" and "x in [50, 60]" in r.why
    r = verdict(atlas(RAMP, status="exact not converged"), claim())
    assert r.verdict == "not testable" and "status ok" in r.why
    r = verdict(atlas([np.nan] * 3), claim())
    assert r.verdict == "not testable" and "NaN" in r.why


def test_range_and_boolean_range_select_points():
    df = atlas(np.r_[RAMP, 5.0, 5.0])
    df.loc[10:, "flag"] = False
    r = verdict(df, claim(range_=(("x", 0.0, 100.0), ("flag", 1.0, 1.0))))
    assert (r.verdict, r.points) == ("holds", 10)


def test_unmeasured_points_are_left_out():
    r = verdict(atlas(np.r_[RAMP, np.nan]), claim())
    assert (r.verdict, r.points, r.unmeasured) == ("holds", 11, 1)


def test_multi_model_claim_pools_points():
    df = pd.concat([atlas(RAMP, model="a"), atlas(RAMP + 1.0, model="b")])
    assert verdict(df, claim(model=("a",))).verdict == "holds"
    assert verdict(df, claim(model=("a", "b"))).points == 20


@pytest.mark.parametrize(
    "bound, scale, expected",
    [
        (1.0, 1.0, "holds"),
        (0.9, 1.0, "holds on part of its range"),  # the bound 10 % lower
        (1.0, 1.1, "holds on part of its range"),  # the data 10 % higher
    ],
)
def test_a_planted_ten_percent_change_flips_the_verdict(bound, scale, expected):
    assert verdict(atlas(RAMP * scale), claim(bound=bound)).verdict == expected


def test_a_planted_ten_percent_change_flips_does_not_hold():
    errors = np.r_[np.full(5, 0.95), np.full(5, 2.0)]  # exactly half within
    assert verdict(atlas(errors), claim()).verdict == "holds on part of its range"
    assert verdict(atlas(errors * 1.1), claim()).verdict == "does not hold"


GOOD = """
[[claim]]
id = "a_claim"
model = "fixed_pinned_pauly_midha"
source = "s"
quote = "q"
metric = "tip_error"
bound = 0.5
note = "n"
[claim.range]
prb_angle_deg = [0.0, 65.0]
"""


def test_load_claims_reads_a_good_file(tmp_path):
    path = tmp_path / "claims.toml"
    path.write_text(GOOD)
    (c,) = load_claims(path)
    assert (c.id, c.models, c.bound, c.range, c.along) == (
        "a_claim",
        ("fixed_pinned_pauly_midha",),
        0.5,
        (("prb_angle_deg", 0.0, 65.0),),
        "prb_angle_deg",
    )


@pytest.mark.parametrize(
    "old, new, field",
    [
        ("bound = 0.5", 'bound = "half"', "bound"),
        ("bound = 0.5", "bound = -1", "bound"),
        ('metric = "tip_error"\n', "", "metric"),
        ("[0.0, 65.0]", "[65.0, 0.0]", "range.prb_angle_deg"),
        ("[0.0, 65.0]", "[0.0]", "range.prb_angle_deg"),
        ('note = "n"', 'note = "n"\nbonud = 1', "bonud"),
        ('id = "a_claim"', 'id = "A Claim"', "id"),
        ('model = "fixed_pinned_pauly_midha"', "model = []", "model"),
    ],
)
def test_a_bad_field_gives_a_one_line_error_naming_it(tmp_path, old, new, field):
    path = tmp_path / "claims.toml"
    path.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(ValueError) as info:
        load_claims(path)
    message = str(info.value)
    assert "\n" not in message
    assert str(path) in message and f"field {field!r}" in message
    assert "claim 'a_claim'" in message or "claim 'A Claim'" in message


def test_a_bad_file_gives_a_one_line_error(tmp_path):
    path = tmp_path / "claims.toml"
    path.write_text("[[claim]\nid = ")
    with pytest.raises(ValueError, match="not a readable TOML file") as info:
        load_claims(path)
    assert "\n" not in str(info.value)
    path.write_text(GOOD + GOOD)
    with pytest.raises(ValueError, match="claim 'a_claim': field 'id': used by two claims"):
        load_claims(path)


def atlas_columns() -> set[str]:
    """The columns an atlas has: a row of a real line (two levels of the cheapest model), the model
    column and every model's inputs."""
    pure = MODELS["pure_moment"]
    rows = solve_line(pure, {}, np.array([0.1, 0.2]))
    return set(rows[0]) | {"model"} | {name for m in MODELS.values() for name in m.inputs}


def test_shipped_claims_name_known_models_and_columns():
    claims = load_claims(SHIPPED)
    columns = atlas_columns()
    errors = {
        "tip_error",
        "angle_error_deg",
        "path_error",
        "path_error_rel",
        "stiffness_error",
        "locus_error",
        "locus_error_rel",
    }
    assert len(claims) >= 8
    for c in claims:
        assert set(c.models) <= set(MODELS), c.id
        assert c.metric in errors, c.id
        assert c.along in columns, c.id
        for column, lo, hi in c.range:
            assert column in columns, (c.id, column)
            for name in c.models:  # an input range names an input of the model
                inputs = {a.name for a in MODELS[name].shape_axes}
                every_input = {a.name for m in MODELS.values() for a in m.shape_axes}
                assert column not in every_input or column in inputs, (c.id, column, name)


def test_the_domain_study_bounds_become_claim_rows():
    summary = [
        {
            "checks": [
                {
                    "name": "eq (116)",
                    "claim_percent": 1.0,
                    "max_percent": 5.9,
                    "mean_percent": 2.3,
                    "over": "0.4 <= b/l <= 0.85",
                },
                {
                    "name": "gamma-bar_l circle (117)",
                    "claim_percent": 1.0,
                    "max_percent": 0.9,
                    "mean_percent": 0.4,
                    "over": "0.4 <= b/l <= 0.85",
                },
            ]
        },
        {"checks": []},
    ]
    rows = domain_study_rows(summary)
    assert list(rows["verdict"]) == ["does not hold", "holds"]
    assert list(rows["worst"]) == [5.9, 0.9] and (rows["bound"] == 1.0).all()
    assert rows["id"].is_unique
