"""The atlas refit (validation/atlas/refit.py): its free-parameter PRBM is the published one at the
published parameters, the minimax recovers parameters that generated the data, and the held-out half
of the grid is never used to fit."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import prbm
from prbm.fits import PAULY_MIDHA
from validation.atlas import refit
from validation.atlas.lines import solve_line
from validation.atlas.models import MODELS
from validation.atlas.refit import refit_table

LOADS = np.geomspace(0.05, 60.0, 80)


@pytest.mark.parametrize("n", [-3.0, -1.0, 0.0, 0.7, 2.5, 8.0])
def test_free_prbm_is_the_published_fixed_pinned_at_its_parameters(n):
    phi = math.atan2(1.0, -n)
    gamma, c_theta, K = PAULY_MIDHA.parameters(n)
    x, y, theta = refit.prbm_tip(LOADS, phi, gamma, K, c_theta=c_theta)
    o = prbm.fixed_pinned_tip(LOADS * math.sin(phi), n, length=1.0, EI=1.0, family="pauly-midha").outputs
    for mine, theirs in ((x, o["a"]), (y, o["b"]), (theta, o["theta0"])):
        np.testing.assert_allclose(mine, theirs, rtol=0.0, atol=1e-9)


@pytest.mark.parametrize("kappa0", [0.5, 2.0])
def test_free_prbm_is_the_published_curved_at_its_parameters(kappa0):
    n = -0.5
    phi = math.atan2(1.0, -n)
    gamma, c_theta, K = PAULY_MIDHA.parameters(n)
    x, y, theta = refit.prbm_tip(LOADS, phi, gamma, K, kappa0, c_theta)
    o = prbm.curved_fixed_pinned_tip(LOADS * math.sin(phi), n, length=1.0, EI=1.0, curvature=kappa0).outputs
    for mine, theirs in ((x, o["a"]), (y, o["b"]), (theta, o["theta0"])):
        np.testing.assert_allclose(mine, theirs, rtol=0.0, atol=1e-9)


def _synthetic(gamma: float, K: float, kappa0=(0.0,), angles=np.linspace(45.0, 90.0, 10)) -> pd.DataFrame:
    """Atlas rows whose "exact" tip is the PRBM's own with (gamma, K)."""
    rows = []
    for k0 in kappa0:
        for a in angles:
            x, y, theta = refit.prbm_tip(LOADS, math.radians(a), gamma, K, k0, 1.24)
            for F, xi, yi, ti in zip(LOADS, x, y, theta):
                rows.append(
                    {
                        **({"kappa0": k0} if len(kappa0) > 1 else {}),
                        "load_angle_deg": a,
                        "load": F,
                        "status": "ok",
                        "exact_x": xi,
                        "exact_y": yi,
                        "exact_rotation_deg": math.degrees(ti - k0),
                    }
                )
    return pd.DataFrame(rows)


@pytest.mark.parametrize("curved", [False, True])
def test_refit_recovers_the_parameters_that_made_the_data(curved):
    df = _synthetic(0.80, 2.40, (0.5, 1.0, 1.5) if curved else (0.0,))
    region = refit.Region((45.0, 90.0), 90.0, (0.5, 1.5) if curved else None)
    r = refit.refit_region(df, region, refit.CURVED if curved else refit.FIXED_PINNED)
    assert r.fitted.gamma == pytest.approx(0.80, abs=1e-3)
    assert r.fitted.K_theta == pytest.approx(2.40, abs=1e-3)
    assert r.fit_worst < 1e-4 and r.refit_worst < 1e-4  # % of L
    assert r.published_worst > 1.0 and r.gain > 1e3


@pytest.mark.parametrize("split", ["checkerboard", "lines"])
def test_held_out_half_shares_no_point_with_the_fit_half(split):
    df = _synthetic(0.80, 2.40, (0.5, 1.0, 1.5))
    held = refit.holdout(df, split)
    keys = ["kappa0", "load_angle_deg", "load"]
    fit_keys = set(map(tuple, df.loc[~held, keys].to_numpy()))
    test_keys = set(map(tuple, df.loc[held, keys].to_numpy()))
    assert not fit_keys & test_keys
    assert len(fit_keys) + len(test_keys) == len(df) and abs(len(fit_keys) - len(test_keys)) <= LOADS.size
    lines = {(k, a) for k, a, _ in fit_keys}
    if split == "lines":  # a held-out line is held out whole
        assert not lines & {(k, a) for k, a, _ in test_keys}
    else:  # every line and every load level is in both halves
        assert lines == {(k, a) for k, a, _ in test_keys}
        assert set(df.loc[held, "load"]) == set(df.loc[~held, "load"])


def test_fit_reads_only_the_fit_half():
    df = _synthetic(0.80, 2.40)
    region = refit.Region((45.0, 90.0), 90.0)
    base = refit.refit_region(df, region, refit.FIXED_PINNED)
    held = refit.holdout(df)  # the default split
    spoiled = df.copy()
    spoiled.loc[held, "exact_x"] += 0.05  # held-out points: fit unchanged
    r = refit.refit_region(spoiled, region, refit.FIXED_PINNED)
    assert (r.fitted, r.fit_worst, r.fit_points) == (base.fitted, base.fit_worst, base.fit_points)
    assert r.refit_worst > 4.0  # but the test sees the spoiled points
    spoiled = df.copy()
    spoiled.loc[~held, "exact_x"] += 0.05  # fit points: fit changes
    assert refit.refit_region(spoiled, region, refit.FIXED_PINNED).fitted != base.fitted


def test_table_and_finding():
    table = refit.refit_table(
        _synthetic(0.80, 2.40).to_dict("records"),
        regions=[refit.Region((45.0, 90.0), 60.0), refit.Region((95.0, 135.0), 60.0)],
    )
    assert len(table) == 1  # no point in the second region
    row = table.iloc[0]
    assert row.fit_points + row.test_points == int((_synthetic(0.80, 2.40).exact_rotation_deg <= 60.0).sum())
    text = refit.finding_text(table)
    assert "phi 45-90 deg, rotation <= 60 deg" in text and f"{row.published_worst:.2f} %" in text


def test_a_whole_atlas_frame_is_refit_by_model_name():
    """The atlas's own frame (every model, NaN in the columns of other models' inputs) refits by naming
    the model; without a name it refuses rather than mixing models."""
    rows = []
    for name in ("fixed_pinned_pauly_midha", "pure_moment"):
        m = MODELS[name]
        for shape in m.shapes(coarse=True):
            rows += [{"model": name, "line_id": str(shape), **r} for r in solve_line(m, shape, m.load.values(True))]
    frame = pd.DataFrame(rows)
    table = refit_table(frame, "fixed_pinned_pauly_midha")
    assert len(table) == 8 and (table["test_points"] > 0).all()
    with pytest.raises(ValueError, match="one atlas model at a time"):
        refit_table(frame)
