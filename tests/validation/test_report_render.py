"""The off-screen ParaView picture of a case page: its legend names each series in the colour of its
line (the FEM line is coloured by its bending moment on viridis: its entry takes viridis's middle
colour, not the light blue pyvista gives a scalar-coloured mesh), and one canvas serves many pictures."""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib import colormaps
from matplotlib.colors import to_rgb
from PIL import Image

from validation.case.loader import case_by_id
from validation.report import paraview
from validation.run.case_run import run_case


def _legend(canvas) -> dict[str, tuple[float, float, float]]:
    actor = canvas.shown[-1]
    return {actor.GetEntryString(i): tuple(actor.GetEntryColor(i)) for i in range(actor.GetNumberOfEntries())}


def test_the_legend_gives_each_series_its_line_colour(tmp_path: Path):
    pytest.importorskip("pyvista")
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=True)
    series = paraview.case_series(result.loaded.case, result.runs)
    png = paraview.render_series(series, tmp_path / "a.png", "first")
    if png is None:
        pytest.skip("pyvista cannot render here")
    canvas = paraview._CANVASES[paraview.CANVAS]
    legend = _legend(canvas)
    viridis_middle = colormaps[paraview.FEM_COLOURMAP](0.5)[:3]
    assert legend["FEM (colour: bending moment)"] == pytest.approx(viridis_middle, abs=0.01)
    assert legend["PRBM"] == pytest.approx(to_rgb(paraview.RENDER_COLOURS["prbm"]))
    assert legend["undeformed"] == pytest.approx(to_rgb(paraview.UNDEFORMED_COLOUR))
    # a second picture of fewer series: its own legend and title, nothing left of the first
    only_fem = [p for p in series if p.method == "fem"]
    paraview.render_series(only_fem, tmp_path / "b.png", "second")
    assert set(_legend(canvas)) == {"FEM (colour: bending moment)", "undeformed"}
    assert canvas.title.GetText(2) == "second"
    meshes = [a for a in canvas.plotter.renderer.actors.values() if a in canvas.shown]
    assert len(meshes) == 3  # the FEM mesh, the undeformed mesh and the legend


def test_each_picture_shows_its_own_series(tmp_path: Path):
    """The canvas renders once a picture, just before its screenshot (the calls that add meshes, the
    scalar bar and the legend are told not to render): a picture taken without that render would show
    the previous picture. Pictures A, B, A on one canvas: the two A's equal pixel for pixel, B differs."""
    pytest.importorskip("pyvista")
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=True)
    series = paraview.case_series(result.loaded.case, result.runs)
    only_prbm = [p for p in series if p.method == "prbm"]
    pictures = [
        paraview.render_series(parts, tmp_path / f"{i}.png", title)
        for i, (parts, title) in enumerate([(series, "all"), (only_prbm, "prbm"), (series, "all")])
    ]
    if None in pictures:
        pytest.skip("pyvista cannot render here")
    first, second, third = (np.asarray(Image.open(png)) for png in pictures)
    assert (first == third).all()
    assert (first != second).any(axis=-1).mean() > 0.01  # another picture, not the last one again


def test_without_plotly_the_report_says_so_in_one_line(tmp_path, monkeypatch, capsys):
    """The charts need the plotly.js bundle of the plotly package: without it, one line naming it."""
    from validation.report import build, charts

    no_plotly = SimpleNamespace(util=SimpleNamespace(find_spec=lambda name: None))  # find_spec finds no plotly
    monkeypatch.setattr(charts, "importlib", no_plotly)
    status = build.build_report(tmp_path, use_cache=True, jobs=1, cases=["cantilever_tip_load"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 1 and len(err) == 1
    assert "plotly" in err[0] and "pip install plotly" in err[0]
