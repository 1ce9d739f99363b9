"""The report's atlas page (validation/report/atlas_page.py) from the coarse atlas (built once a session):
the page and every model's map exist, every claim is in the claims table, the predicted-against-measured
sentence has its numbers, a second page reuses the atlas-only part, text is escaped, and the report's
hook turns a failure into a line of the index instead of losing the report; the measured levels worked
out beside a case's page and the scatter drawn in another process are the page's own."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import shutil
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from validation.atlas import claims as atlas_claims
from validation.atlas import dataset
from validation.atlas import measured
from validation.atlas.measured import MeasuredLevel
from validation.atlas.models import MODELS
from validation.report import atlas_page, build

pytestmark = pytest.mark.xdist_group("report_atlas")  # one worker draws the page, once

# two made-up case levels on the diagonal and one off it: the sentence's numbers are known
LEVELS = [
    MeasuredLevel("case_a", 1, "fixed_pinned_pauly_midha", 0.50, 0.55, 0.40, -3.0, 0.20, ""),
    MeasuredLevel("case_a", 2, "fixed_pinned_pauly_midha", 2.00, 2.10, 1.50, -6.0, 0.50, ""),
    MeasuredLevel(
        "case_b", 1, "pure_moment", 8.00, 1.00, float("nan"), float("nan"), 0.30, "the FEM gave no tip rotation"
    ),
]


def made_up_levels(results, table, cached, known=None):
    return measured.frame_of(LEVELS), {}


@pytest.fixture(scope="module")
def coarse(coarse_atlas) -> tuple[str, object, Path]:
    """(grid, rows, folder) of the coarse atlas of the current code, which ``find_atlas`` built serially
    where no atlas was published (once a session: tests/validation/conftest.py)."""
    frame = dataset.load(coarse_atlas, "coarse")
    assert frame is not None
    return "coarse", frame, coarse_atlas


def test_a_complete_coarse_atlas_is_read_not_built_again(coarse, tmp_path):
    """The report's worker builds the coarse atlas, then its main process finds it: a second
    ``find_atlas`` reads it, and the manifest keeps the one run that computed its lines (the page says
    how many runs built it)."""
    grid, frame, where = coarse
    again = atlas_page.find_atlas(tmp_path / "no_published_atlas", build_into=where, executor="serial")
    assert again is not None and again[0] == grid and len(again[1]) == len(frame)
    runs = atlas_page.manifest(where, grid)["runs"]
    assert len(runs) == 1 and runs[0]["lines_run"] > 0


@pytest.fixture(scope="module")
def page(coarse, tmp_path_factory) -> tuple[Path, atlas_page.AtlasPage]:
    out = tmp_path_factory.mktemp("report")
    grid, frame, where = coarse
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(atlas_page, "_measured_frame", made_up_levels)
        written = atlas_page.write_page(out, grid, frame, [], None, where)
    return out, written


def test_the_page_and_every_model_map_exist(page, coarse):
    out, written = page
    text = (out / atlas_page.PAGE).read_text()
    assert written.grid == "coarse" and "coarse grid" in text
    assert f"code version {written.version}" in text
    for name, model in MODELS.items():
        assert f"<h2 id='model-{name}'>" in text, name
        src = f"{atlas_page.FIGURES}/map_{name}.png"
        assert f"src='{src}'" in text
        assert (out / src).is_file() and (out / src).stat().st_size > 1000
    for title in (
        "Predicted against measured",
        "The seeds' claims, checked",
        "Beyond the seeds: refit (gamma, K_Theta)",
    ):
        assert title in text
    assert re.search(r"\d+ points solved in [\d.]+ s", text)  # from the dataset's atlas.json


def test_the_claims_table_has_every_claim(page):
    text = (page[0] / atlas_page.PAGE).read_text()
    for claim in atlas_claims.load_claims(atlas_page.CLAIMS):
        assert f"id='claim-{claim.id}'" in text, claim.id
    assert "class='verdict v-" in text


def test_the_predicted_against_measured_sentence_has_numbers(page):
    out, written = page
    a = written.agreement
    assert (a["levels"], a["cases"]) == (3, 2)
    sentence = atlas_page.agreement_words(a)
    assert re.search(
        r"on 3 levels of 2 cases: 67 % within a factor 2 .* 67 % on the same side of the 5 % "
        r"validity limit, Spearman rank correlation -?\d\.\d\d",
        sentence,
    )
    text = (out / atlas_page.PAGE).read_text()
    assert atlas_page._capital(sentence).replace("'", "&#x27;") in text
    assert (out / atlas_page.FIGURES / "scatter.png").is_file()
    assert "the FEM gave no tip rotation" in text and "cases/case_b.html" in text
    assert "3 levels of 2 cases" in written.index_html and "href='atlas.html'" in written.index_html


def test_a_second_page_reuses_the_atlas_part(page, coarse):
    out, _ = page
    maps = out / atlas_page.FIGURES / "map_pure_moment.png"
    before = maps.stat().st_mtime_ns
    grid, frame, where = coarse
    atlas_page.write_page(out, grid, frame, [], None, where)
    assert maps.stat().st_mtime_ns == before
    assert "no case level has both" in (out / atlas_page.PAGE).read_text()


def test_text_is_escaped(coarse, tmp_path, monkeypatch):
    grid, frame, where = coarse
    name = "pure_moment"
    monkeypatch.setitem(MODELS, name, dataclasses.replace(MODELS[name], title="arc <b>bold</b> & 'quoted'"))
    monkeypatch.setattr(atlas_page, "_measured_frame", made_up_levels)
    atlas_page.write_page(tmp_path, grid, frame[frame["model"] == name], [], None, where)
    text = (tmp_path / atlas_page.PAGE).read_text()
    assert "<b>bold</b>" not in text
    assert "arc &lt;b&gt;bold&lt;/b&gt; &amp; &#x27;quoted&#x27;" in text
    assert "alt='error map of arc &lt;b&gt;bold&lt;/b&gt; &amp; &#x27;quoted&#x27;'" in text


def test_no_atlas_and_no_build_is_no_page(tmp_path):
    assert atlas_page.build_page(tmp_path, [], None, tmp_path / "atlas", build=False) is None
    assert not (tmp_path / atlas_page.PAGE).exists()


def test_a_failed_atlas_page_is_a_line_of_the_index(tmp_path, monkeypatch):
    def fail(*args, **kwargs):
        raise RuntimeError("no <atlas> today")

    monkeypatch.setattr(atlas_page, "build_page", fail)
    outcome = type("Outcome", (), {"results": [], "table": None})()
    (line_html, line_md), error = build._atlas_page(outcome, tmp_path, tmp_path, 1, build=True)
    assert error == "atlas page: could not be drawn: RuntimeError: no <atlas> today"
    assert "class='bad'" in line_html and "no &lt;atlas&gt; today" in line_html
    monkeypatch.setattr(atlas_page, "build_page", lambda *a, **k: None)
    (line_html, _), error = build._atlas_page(outcome, tmp_path, tmp_path, 1, build=False)
    assert error is None and "not drawn" in line_html


def test_measured_levels_of_a_case_are_kept_by_what_they_depend_on(monkeypatch):
    from validation.case.loader import find_case_files
    from validation.run.outcome import run_cases

    outcome = run_cases(find_case_files(["cantilever_tip_load"]), use_cache=True, jobs=1)
    first, keep = atlas_page._measured_frame(outcome.results, outcome.table, {})
    assert len(first) and set(first["case"]) == {"cantilever_tip_load"}
    assert (first["predicted"] > 0).all() and (first["measured"] > 0).all()

    def not_again(results, table):
        raise AssertionError("measured again although nothing changed")

    monkeypatch.setattr(measured, "measured_levels", not_again)
    again, _ = atlas_page._measured_frame(outcome.results, outcome.table, json.loads(json.dumps(keep)))
    assert again.equals(first)
    changed = outcome.table.copy()
    changed.loc[changed["method"] == "fem", "value"] *= 1.01
    with pytest.raises(AssertionError, match="measured again"):
        atlas_page._measured_frame(outcome.results, changed, keep)


def test_measured_levels_worked_out_beside_the_case_page_are_used_by_the_atlas_page(tmp_path, monkeypatch):
    """The page writer works out a case's measured levels where it draws the page (off the report's
    serial path); the atlas page takes them as they are and the previous report's entries are reused."""
    from validation.case.loader import find_case_files
    from validation.run.outcome import run_cases

    outcome = run_cases(find_case_files(["cantilever_tip_load"]), use_cache=True, jobs=1)
    (tmp_path / "cases").mkdir()
    link = build.PageWriter(tmp_path, tmp_path / "no_previous.json")(outcome.results[0])
    assert link.measured is not None and link.measured.levels
    expected, keep = atlas_page._measured_frame(outcome.results, outcome.table, {})

    def not_again(results, table):
        raise AssertionError("measured again although the page writer did")

    monkeypatch.setattr(measured, "measured_levels", not_again)
    cached = {case: got.entry() for case, got in {"cantilever_tip_load": link.measured}.items()}
    got, _ = atlas_page._measured_frame(outcome.results, outcome.table, cached)
    assert got.equals(expected)
    previous = tmp_path / "measured.json"
    previous.write_text(json.dumps(keep))
    again = build.PageWriter(tmp_path, previous)(outcome.results[0])
    assert again.measured == link.measured
    assert build.PageWriter(tmp_path)(outcome.results[0]).measured is None  # not asked for


def test_the_scatter_is_drawn_where_the_caller_says(page, coarse, tmp_path, monkeypatch):
    """``write_page``'s ``draw`` gets the scatter (the report hands it to its figure process)."""
    grid, frame, where = coarse
    monkeypatch.setattr(atlas_page, "_measured_frame", made_up_levels)
    shutil.copytree(page[0] / atlas_page.FIGURES, tmp_path / atlas_page.FIGURES)  # the atlas part, drawn
    handed = []
    atlas_page.write_page(tmp_path, grid, frame, [], None, where, draw=lambda f, *args: handed.append((f, args)))
    scatter = tmp_path / atlas_page.FIGURES / "scatter.png"
    assert [f for f, _ in handed] == [measured.draw_scatter] and handed[0][1][1] == scatter
    assert not scatter.exists()
    handed[0][0](*handed[0][1])
    assert scatter.is_file()


def test_a_picture_that_fails_in_the_figure_process_is_the_atlas_page_s_error():
    with ProcessPoolExecutor(max_workers=1) as pool:
        later = build.FigureProcess(pool)
        later.draw(math.sqrt, 4.0)
        assert later.wait() is None
        later.draw(math.sqrt, -1.0)
        failed = later.wait()
    assert isinstance(failed, ValueError)
    (line_html, _), error = build._atlas_failed(failed)
    assert error == "atlas page: could not be drawn: ValueError: math domain error" and "class='bad'" in line_html


def test_spearman_is_pandas_spearman_to_the_bit():
    rng = np.random.default_rng(7)
    for size in (3, 5, 40, 200):
        a = np.round(rng.random(size), 1)  # ties
        b = a + rng.normal(size=size)
        assert measured.spearman(a, b) == float(pd.Series(a).corr(pd.Series(b), method="spearman"))
    assert math.isnan(measured.spearman(np.ones(4), np.arange(4.0)))


def test_a_case_s_tip_readings_are_its_first_rows_at_the_tip():
    rows = pd.DataFrame(
        {
            "method": ["fem", "fem", "fem", "fem", "prbm"],
            "quantity": ["x", "x", "x", "y", "x"],
            "level": [1, 1, 1, 1, 1],
            "point": ["mid", "tip", "", None, "tip"],
            "value": [9.0, 1.0, 2.0, 3.0, 4.0],
        }
    )
    tips = measured._tips(rows)
    assert tips[("fem", "x", 1)] == 1.0 and tips[("fem", "y", 1)] == 3.0 and tips[("prbm", "x", 1)] == 4.0
    assert math.isnan(measured._tip(tips, "fem", "rotation", 1))
