"""The PRBM error atlas: its exact side against closed forms, the path/stiffness split on a model whose
answer is known, the build's resume, the shipped error maps against a fresh coarse atlas, and the PRBM
adapter's flags on loads no shipped case has."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

import elastica
import prbm
from validation.atlas import dataset, regions
from validation.atlas.expected import VALIDITY_LIMIT, expectation, load_maps
from validation.atlas.lines import solve_line
from validation.atlas.measured import _split, agreement, frame_of
from validation.atlas.models import MODELS, PrbmLine
from validation.case.loader import case_by_id, load_case
from validation.cli.main import main
from validation.methods.base import Applicability
from validation.report import atlas_page
from validation.run.runner import run_method


@pytest.fixture(scope="module")
def coarse(coarse_atlas) -> pd.DataFrame:
    """The coarse atlas of the current code (built once a session, tests/validation/conftest.py), every
    line of every model computed by its one build run."""
    runs = atlas_page.manifest(coarse_atlas, "coarse")["runs"]
    assert [run["lines_run"] for run in runs] == [len(dataset.tasks(list(MODELS), "coarse"))]
    return dataset.load(coarse_atlas, "coarse")


def test_every_model_has_ten_thousand_points_on_the_full_grid():
    for name, m in MODELS.items():
        assert m.points(coarse=False) >= 10_000, name


def test_the_exact_side_is_the_elliptic_solution():
    """Fixed-pinned lines against [bapat2015, eqs 6-7] (elastica.elliptic, an independent closed form)."""
    m = MODELS["fixed_pinned_pauly_midha"]
    loads = m.load.values(coarse=True)
    for angle in (30.0, 90.0, 150.0):
        rows = [r for r in solve_line(m, {"load_angle_deg": angle}, loads) if r["status"] == "ok"]
        assert len(rows) > 10
        n = -1.0 / math.tan(math.radians(angle))
        for r in rows[::4]:
            P = r["load"] * math.sin(math.radians(angle))
            tip = elastica.fixed_pinned_tip(P, n)
            assert r["exact_x"] == pytest.approx(tip.a, abs=1e-7)
            assert r["exact_y"] == pytest.approx(tip.b, abs=1e-7)


def _circle(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact tip of a unit cantilever under an end moment M L/EI: a circular arc."""
    M = np.asarray(M, float)
    return np.sin(M) / M, (1.0 - np.cos(M)) / M, M


@pytest.mark.parametrize("stiffer", [1.1, 0.9])
def test_a_model_on_the_exact_path_with_a_wrong_spring_has_only_stiffness_error(stiffer):
    """A 'PRBM' that lands on the exact arc but needs ``stiffer`` times the moment: path error 0 and
    stiffness error 100 (stiffer - 1) %, while its error at equal load is not 0."""

    def prbm(shape, loads):
        x, y, t = _circle(loads / stiffer)
        return PrbmLine(x, y, t, t, np.ones(loads.size, bool), np.ones(loads.size, bool))

    m = replace(MODELS["pure_moment"], prbm=prbm, dense=8)
    rows = [r for r in solve_line(m, {}, np.geomspace(0.05, 3.0, 200)) if r["status"] == "ok"]
    inside = [r for r in rows if math.isfinite(r["stiffness_error"])]
    assert len(inside) >= 180
    for r in inside:  # the PRBM read between its dense points (steps h <= 0.01 rad): O(h^2) ~ 1e-6 L, and
        assert r["path_error"] < 1e-3  # the polyline's sag (h |dr/dM|)^2 kappa/8 ~ 1e-6 L: well below 1e-5 L
        assert r["locus_error"] < 1e-3
        assert r["stiffness_error"] == pytest.approx(100.0 * (stiffer - 1.0), abs=1e-3)
    assert max(r["tip_error"] for r in rows) > 1.0


def test_the_exact_model_has_no_error():
    def prbm(shape, loads):
        x, y, t = _circle(loads)
        return PrbmLine(x, y, t, t, np.ones(loads.size, bool), np.ones(loads.size, bool))

    m = replace(MODELS["pure_moment"], prbm=prbm)
    rows = solve_line(m, {}, np.geomspace(0.05, 3.0, 25))
    assert max(r["tip_error"] for r in rows) < 1e-7
    assert max(abs(r["stiffness_error"]) for r in rows if math.isfinite(r["stiffness_error"])) < 1e-3


def test_a_build_resumes_and_a_new_line_set_runs_only_what_is_missing(tmp_path: Path):
    first = dataset.build("coarse", models=["pure_moment", "fixed_pinned_constant"], out=tmp_path, executor="serial")
    assert first.lines_run == 1 + 9 and first.points == 200 + 9 * 24
    again = dataset.build("coarse", models=["pure_moment", "fixed_pinned_constant"], out=tmp_path, executor="serial")
    assert again.lines_run == 0 and again.lines_skipped == 10
    for part in (dataset.folder(tmp_path, "coarse") / "parts").glob("*.parquet"):
        part.unlink()
    third = dataset.build("coarse", models=["pure_moment"], out=tmp_path, executor="serial")
    assert third.lines_run == 1
    assert dataset.complete(tmp_path, "coarse", ["pure_moment"])
    assert not dataset.complete(tmp_path, "coarse", ["fixed_pinned_constant"])


def test_the_shipped_maps_predict_a_fresh_coarse_atlas(coarse):
    """The coarse grid's nodes are not the full grid's: the maps interpolate.  Stated tolerance: at 95 % of
    a model's points the prediction is within 0.5 % of L or a quarter of the measured error, and the
    5 % region (in or out) agrees at 97 % of them."""
    maps = load_maps()
    assert set(maps) == set(MODELS)
    for name in MODELS:
        rows = coarse[(coarse["model"] == name) & (coarse["status"] == "ok")]
        predicted = np.array([maps[name].expected({k: r[k] for k in maps[name].axes}) for _, r in rows.iterrows()])
        measured = rows["tip_error"].to_numpy()
        mapped = np.isfinite(predicted)
        assert mapped.mean() >= 0.9, name
        p, m = predicted[mapped], measured[mapped]
        close = np.abs(p - m) <= np.maximum(0.5, 0.25 * m)
        assert close.mean() >= 0.95, (name, close.mean())
        assert ((p > VALIDITY_LIMIT) == (m > VALIDITY_LIMIT)).mean() >= 0.97, name


def _segment_case(
    tmp_path: Path,
    *,
    curvature: float = 0.0,
    direction=(0.0, 1.0),
    values=(1.0,),
    follower: bool = False,
    boundary: str = "fixed-free",
) -> Path:
    path = tmp_path / "user.toml"
    path.write_text(f"""
[case]
id = "user_segment"
title = "a user's segment"
group = "user"
units = "dimensionless"
description = "a load no shipped case has"

[segment]
boundary = "{boundary}"
length = 1.0
E = 1.0
curvature = {curvature}
section = {{ kind = "inertia", I = 1.0, A = 1.0e8 }}

[[loads]]
kind = "force"
direction = [{direction[0]}, {direction[1]}]
follower = {str(follower).lower()}
values = [{", ".join(str(v) for v in values)}]

[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"

[methods.prbm]
""")
    return path


def _prbm(path: Path):
    return run_method(load_case(path).case, "prbm")


def test_a_strongly_curved_segment_is_flagged_where_the_atlas_says(tmp_path):
    run = _prbm(_segment_case(tmp_path, curvature=2.5, values=(0.5, 5.0)))
    assert Applicability.OUTSIDE_VALIDITY not in run.applicability.get(0, [])
    assert Applicability.OUTSIDE_VALIDITY in run.applicability[1]
    assert run.expected_error[1] > VALIDITY_LIMIT > run.expected_error[0]
    assert "atlas expects" in run.level_messages[1]


def test_a_follower_force_is_flagged_from_moderate_loads_on(tmp_path):
    run = _prbm(_segment_case(tmp_path, follower=True, values=(1.0, 10.0, 15.0, 20.0)))
    assert not run.applicability.get(0)
    for level in (1, 2, 3):
        assert Applicability.OUTSIDE_VALIDITY in run.applicability[level]


def test_a_mirrored_load_has_the_mirrored_expectation(tmp_path):
    up = _prbm(_segment_case(tmp_path, direction=(-0.6, 0.8), values=(3.0,)))
    down = _prbm(_segment_case(tmp_path, direction=(-0.6, -0.8), values=(3.0,)))
    assert up.expected_error[0] == pytest.approx(down.expected_error[0], rel=1e-12)
    assert 0.0 < up.expected_error[0] < VALIDITY_LIMIT


def test_the_expected_error_scales_with_the_segment():
    """The atlas is dimensionless: a 10x longer, 1000x stiffer segment under the same F L^2/EI has the same
    expectation."""
    small = expectation("fixed_pinned_pauly_midha", {"load_angle_deg": 90.0, "load": 4.0})
    assert small is not None and math.isfinite(small.expected_error)
    assert small.expected_error > 0.0
    beyond = expectation("fixed_pinned_pauly_midha", {"load_angle_deg": 90.0, "load": 1e4})
    assert beyond.outside and not math.isfinite(beyond.expected_error)


def _line(errors, statuses=None) -> pd.DataFrame:
    n = len(errors)
    return pd.DataFrame(
        {
            "model": "pure_moment",
            "load": np.arange(1.0, n + 1),
            "tip_error": errors,
            "status": statuses or ["ok"] * n,
            "exact_rotation_deg": 10.0 * np.arange(1.0, n + 1),
            "deflection": np.arange(1.0, n + 1),
        }
    )


def test_a_region_ends_at_the_first_level_past_its_threshold():
    frame = _line([0.1, 0.3, 0.6, 0.2, 2.0, 6.0])
    limits = {t: regions.line_limits(frame, "pure_moment", t).iloc[0] for t in (0.5, 1.0, 3.0, 5.0)}
    assert limits[0.5]["load_limit"] == 2.0  # 0.6 at load 3 ends it, though load 4 is back to 0.2
    assert limits[1.0]["load_limit"] == 4.0 and limits[1.0]["deflection"] == 40.0
    assert limits[3.0]["load_limit"] == 5.0 and not limits[3.0]["whole_line"]
    assert limits[5.0]["load_limit"] == 5.0


def test_a_region_starts_where_the_model_starts_answering():
    frame = _line([np.nan, np.nan, 0.2, 0.4, 0.8], ["prbm gives no answer"] * 2 + ["ok"] * 3)
    row = regions.line_limits(frame, "pure_moment", 0.5).iloc[0]
    assert row["first_load"] == 3.0 and row["load_limit"] == 4.0
    silent = _line([np.nan] * 3, ["prbm gives no answer"] * 3)
    assert regions.line_limits(silent, "pure_moment", 0.5).empty


@pytest.mark.parametrize("mirror", [1.0, -1.0])
def test_a_measured_error_is_split_like_the_atlas(mirror):
    """A 'FEM' tip that is the PRBM's own tip at 1.1 times the load: all of the error is stiffness
    (+10 %), none is path, at either side of the axis."""
    F, angle = 3.0, 70.0
    n = -1.0 / math.tan(math.radians(angle))
    P = 1.1 * F * math.sin(math.radians(angle))
    tip = prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0).outputs
    x, y, rotation = float(tip["a"]), mirror * float(tip["b"]), mirror * math.degrees(float(tip["theta0"]))
    path, stiffness, locus, why = _split(
        "fixed_pinned_pauly_midha", {"load_angle_deg": angle, "load": F}, mirror, x, y, rotation
    )
    assert why == ""
    assert path < 1e-3 and locus < 1e-3
    assert stiffness == pytest.approx(10.0, abs=0.01)


def test_the_atlas_command_builds_summarises_and_refuses_a_bad_model(tmp_path, capsys):
    assert main(["atlas", "nonsense", "--out", str(tmp_path)]) == 2
    assert "unknown atlas model" in capsys.readouterr().err
    assert main(["atlas", "pure_moment", "--coarse", "--serial", "--quiet", "--out", str(tmp_path)]) == 0
    folder = dataset.folder(tmp_path, "coarse")
    assert (folder / "maps" / "pure_moment.png").stat().st_size > 1000
    table = pd.read_csv(folder / "regions.csv")
    assert list(table["threshold"]) == [0.5, 1.0, 3.0, 5.0]
    assert (table["worst_load"].diff().dropna() >= 0).all()  # a looser threshold reaches at least as far
    claims = pd.read_csv(folder / "claims.csv")
    assert set(claims["model"]) == {"pure_moment"}
    assert main(["atlas", "pure_moment", "--coarse", "--serial", "--quiet", "--out", str(tmp_path)]) == 0
    assert "0 line(s) run, 1 already done" in capsys.readouterr().out


def test_a_transverse_force_is_n_zero_on_the_atlas_grid():
    """cos(90 deg) is 6e-17: read as n < 0 it put the 90 deg line outside eq 51's printed 0 <= n range and
    left every n = 0 level of the Theta-dependent model unmapped."""
    rows = solve_line(MODELS["theta_dependent_51"], {"load_angle_deg": 90.0}, np.array([0.5, 1.0, 2.0]))
    assert all(r["status"] == "ok" for r in rows)


def test_the_alternative_models_get_expected_errors():
    for case_id, model in (
        ("bapat2015_theta_dependent_k_eq51", "theta_dependent_51"),
        ("cantilever_uniform_load", "chain"),
    ):
        run = run_method(case_by_id(case_id).case, "prbm")
        assert run.extras["atlas_model"] == model
        assert len(run.expected_error) == len(run.level_converged)
        assert all(math.isfinite(e) and e < VALIDITY_LIMIT for e in run.expected_error.values())


def test_a_build_runs_on_a_local_dask_cluster(tmp_path):
    pytest.importorskip("distributed")
    record = dataset.build("coarse", models=["pure_moment"], out=tmp_path, executor="dask", workers=1)
    assert record.lines_run == 1 and record.points == 200
    assert dataset.complete(tmp_path, "coarse", ["pure_moment"])


def test_no_measured_levels_is_an_agreement_of_nothing():
    assert agreement(frame_of([])) == {"levels": 0}


def test_a_finished_build_is_one_parquet_file_with_its_spec(tmp_path):
    dataset.build("coarse", models=["pure_moment"], out=tmp_path, executor="serial")
    whole = pq.read_table(dataset.folder(tmp_path, "coarse") / "atlas.parquet")
    meta = whole.schema.metadata
    assert meta[b"code_version"].decode() == dataset.code_version()
    spec = json.loads(meta[b"atlas_spec"])
    assert spec["grid"] == "coarse" and spec["models"]["pure_moment"]["points"] == whole.num_rows == 200


def test_the_maps_return_their_nodes_and_interpolate_linearly_between():
    """At a node a map gives its stored error; half way between two neighbouring nodes of one axis (load in
    its logarithm) the mean of the two: multilinear interpolation, checked on every shipped map."""
    for name, m in load_maps().items():
        idx = tuple(max(0, v.size // 2 - 1) for v in m.values)
        at = {a: float(v[i]) for a, v, i in zip(m.axes, m.values, idx)}
        here = float(m.error[idx])
        if not math.isfinite(here):
            continue
        assert m.expected(at) == pytest.approx(here, rel=1e-12, abs=1e-15), name
        k = len(m.axes) - 1  # the load axis, interpolated in log(load)
        nxt = idx[:k] + (idx[k] + 1,)
        there = float(m.error[nxt])
        if math.isfinite(there):
            lo, hi = m.values[k][idx[k]], m.values[k][idx[k] + 1]
            mid = {**at, "load": math.sqrt(lo * hi)}
            assert m.expected(mid) == pytest.approx(0.5 * (here + there), rel=1e-9), name


def _limits_line_by_line(frame: pd.DataFrame, model: str, threshold: float) -> pd.DataFrame:
    """``regions.line_limits`` written the plain way, a pandas group per line: the reference."""
    m = MODELS[model]
    rows = frame[frame["model"] == model].sort_values("load")
    names = [a.name for a in m.shape_axes]
    out = []
    for key, line in rows.groupby(names, sort=True) if names else [((), rows)]:
        answered = (line["status"] == "ok").to_numpy()
        if not answered.any():
            continue
        line = line.iloc[int(np.argmax(answered)) :]
        inside = (line["status"] == "ok").to_numpy() & (line["tip_error"].to_numpy() <= threshold)
        first_out = int(np.argmin(inside)) if not inside.all() else len(inside)
        last = line.iloc[first_out - 1] if first_out > 0 else None
        reached = 0.0
        if last is not None:
            reached = abs(last["exact_rotation_deg"]) if m.coordinate == "tip angle" else last["deflection"]
        out.append(
            {
                **dict(zip(names, key if isinstance(key, tuple) else (key,))),
                "first_load": float(line["load"].iloc[0]),
                "load_limit": float(last["load"]) if last is not None else 0.0,
                "deflection": float(reached),
                "whole_line": first_out == len(inside),
            }
        )
    return pd.DataFrame(out)


def test_the_lines_of_a_map_are_read_once_as_each_alone_would_read(coarse):
    """``line_limits`` reads a model's lines once for every threshold (``answered_lines``): the same
    table, to the bit, as a pandas group per line, on every model of the coarse atlas at the report's
    two thresholds (1 % and 5 %) and on two interleaved lines given out of load order."""
    for name in MODELS:
        for threshold in (1.0, 5.0):
            got = regions.line_limits(coarse, name, threshold)
            pd.testing.assert_frame_equal(got, _limits_line_by_line(coarse, name, threshold), check_exact=True)
    two = pd.concat([_line([0.1, 0.7, 0.2]).assign(load_angle_deg=a) for a in (90.0, 30.0)], ignore_index=True)
    two = two.assign(model="fixed_pinned_pauly_midha").iloc[[5, 0, 3, 1, 4, 2]]
    got = regions.line_limits(two, "fixed_pinned_pauly_midha", 0.5)
    assert got["load_angle_deg"].tolist() == [30.0, 90.0] and got["load_limit"].tolist() == [1.0, 1.0]
    pd.testing.assert_frame_equal(got, _limits_line_by_line(two, "fixed_pinned_pauly_midha", 0.5))
