"""ParaView files of a case: one ``.pvd`` series per method with the load level as time.

For each method that gave deformed shapes, ``write_case_series`` writes under ``vtu/<case>/``:

- ``fem.pvd`` + ``fem_<k>.vtu``: the deformed FEM mesh (line cells) with the point data of
  ``fem.result.NodalFields`` (displacement, rotation in degrees, curvature, bending moment, axial force
  and, where the section knows E and its extreme-fibre distance, the largest bending stress), and
  ``fem_undeformed.vtu``, the reference mesh;
- ``prbm.pvd``: the pseudo-rigid-body links (line cells) and their pivots and link ends (vertex
  cells), point data ``pivot`` (1 at a pivot or link end);
- ``elastica.pvd``: the exact centreline; a segment's with its rotation (degrees), curvature
  d(theta)/ds, bending moment EI (kappa - kappa0) and displacement from the undeformed (straight or
  circular) segment; a mechanism's beams with the tangent angle and curvature of each centreline;
- ``all_methods.pvd``: the same files, one part per method, where more than one method drew a shape.

Time is the case's first load at each level (its unit in the case's unit system), or the level index
when the case has no load; a FEM continuation (limit load) is timed by its load factor, its hundreds
of steps thinned to the frames its case page draws (``frames_shown``: at most ``MAX_FRAMES`` evenly
spaced ones and every limit point).  Units are the
case file's; rotations in degrees as everywhere in the harness.  ``render_series`` draws the last level
of every series off-screen with pyvista, on one canvas per process (plotter, title, legends) emptied
between pictures, its legend giving each series the colour of its line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Final

import meshio
import numpy as np
from PIL import Image

from validation.case.schema import Case

if TYPE_CHECKING:  # pyvista (VTK) is imported at the first picture: a report without pictures never loads it
    import pyvista
    from pyvista.plotting._typing import ScalarBarArgs  # the keywords of add_scalar_bar (not exported)

MAX_FRAMES = 41  # frames of a continuation's series (evenly spaced, with its limit points)


@dataclass
class ShapeFrame:
    """One level of one method: points (n, 2), line cells (m, 2), vertex cells (k,), point arrays, and the
    line cells of rigid links (r, 2): no field of their own (the FEM's master-slave links, the exact
    elastica's rigid bodies), written after the lines and drawn in one colour."""

    points: np.ndarray
    lines: np.ndarray
    vertices: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    point_data: dict[str, np.ndarray] = field(default_factory=dict)
    rigid: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), int))

    def line_cells(self, which: str = "all") -> np.ndarray:
        """The line cells: ``all`` (the lines, then the rigid links: what the files hold), ``lines`` or
        ``rigid``."""
        lines, rigid = np.asarray(self.lines, int).reshape(-1, 2), np.asarray(self.rigid, int).reshape(-1, 2)
        if which == "lines":
            return lines
        if which == "rigid":
            return rigid
        return np.concatenate([lines, rigid]) if len(rigid) else lines


@dataclass
class ShapeSeries:
    """A method's frames, one per load level, with the level's time value."""

    method: str
    times: list[float]
    frames: list[ShapeFrame]
    undeformed: ShapeFrame | None = None


def _mesh(frame: ShapeFrame) -> meshio.Mesh:
    cells = [("line", frame.line_cells())]
    if len(frame.vertices):
        cells.append(("vertex", np.asarray(frame.vertices, int).reshape(-1, 1)))
    xyz = np.column_stack([frame.points, np.zeros(len(frame.points))])
    return meshio.Mesh(xyz, cells, point_data={k: np.asarray(v, float) for k, v in frame.point_data.items()})


def write_pvd(series: ShapeSeries, folder: Path) -> Path:
    """``<method>.pvd`` with ``<method>_<k>.vtu`` per level (and ``<method>_undeformed.vtu``)."""
    folder.mkdir(parents=True, exist_ok=True)
    for k, frame in enumerate(series.frames):
        meshio.write(folder / f"{series.method}_{k:04d}.vtu", _mesh(frame))
    if series.undeformed is not None:
        meshio.write(folder / f"{series.method}_undeformed.vtu", _mesh(series.undeformed))
    return _collection(folder / f"{series.method}.pvd", [series])


def _collection(target: Path, parts: list[ShapeSeries]) -> Path:
    """A ParaView collection: each series is one part, each of its frames one time step."""
    entries = [
        f'    <DataSet timestep="{time:.12g}" part="{part}" file="{series.method}_{k:04d}.vtu"/>'
        for part, series in enumerate(parts)
        for k, time in enumerate(series.times)
    ]
    target.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
        "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n"
    )
    return target


def level_times(case: Case) -> list[float]:
    """The time value of each level: the first load's value, or the level index."""
    if case.loads:
        return [float(v) for v in case.loads[0].levels()]
    return [float(k) for k in range(case.n_levels())]


def _times(case: Case, levels: list[int]) -> list[float]:
    """The time values of the given levels (the level index where the case's levels do not reach)."""
    times = level_times(case)
    return [times[k] if k < len(times) else float(k) for k in levels]


def _levels(shapes) -> list[int]:
    """The load levels of an adapter's shapes: a dict's keys, or every level of a list."""
    return sorted(shapes) if isinstance(shapes, dict) else list(range(len(shapes)))


def frames_shown(load: np.ndarray, most: int = MAX_FRAMES) -> list[int]:
    """The frames of a long series that are written and drawn: all of them up to ``most``, else ``most``
    evenly spaced ones (the first and the last among them) and every turning point of ``load`` (a limit
    point of a continuation: the load stops rising or falling there)."""
    load = np.asarray(load, float)
    n = len(load)
    if n <= most:
        return list(range(n))
    steps = np.flatnonzero(np.diff(load) != 0)  # a repeated load (a plateau) turns nothing
    rise = np.sign(np.diff(load)[steps])
    turning = steps[np.flatnonzero(rise[1:] != rise[:-1])] + 1  # the last frame before the load turns
    return sorted(set(np.linspace(0, n - 1, most).round().astype(int).tolist()) | set(turning.tolist()))


def fem_series(case: Case, fields) -> ShapeSeries | None:
    """From the FEM adapter's ``extras['fields']`` (a ``fem.result.FieldSeries``); a continuation's
    hundreds of steps thinned to the frames the case page draws (``frames_shown``)."""
    if fields is None or not len(fields.nodal):
        return None
    continuation = len(fields.nodal) != case.n_levels()
    kept = frames_shown(
        fields.load_factor if continuation else np.arange(len(fields.nodal)),
        most=MAX_FRAMES if continuation else len(fields.nodal),
    )
    frames = []
    for k in kept:
        data = fields.nodal[k].point_data()
        data["rotation"] = np.degrees(data["rotation"])
        frames.append(ShapeFrame(fields.positions[k], fields.connectivity, point_data=data, rigid=fields.links))
    undeformed = ShapeFrame(fields.reference, fields.connectivity, rigid=fields.links)
    if continuation:  # a continuation (limit load): its own steps, timed by the load factor
        times = [float(fields.load_factor[k]) for k in kept]
    else:
        times = _times(case, kept)
    return ShapeSeries("fem", times, frames, undeformed)


def normalise_shapes(shapes) -> list[list[np.ndarray]]:
    """Shapes as a list (per level) of lists of (n, 2) polylines.

    Adapters may give a dict {level: ...} or a list per level, and per level one array or a list of
    arrays, each (n, 2)/(n, >2) point rows or (2|3, n) coordinate rows (x, y[, theta])."""
    if isinstance(shapes, dict):
        shapes = [shapes[k] for k in sorted(shapes)]
    out = []
    for entry in shapes:
        lines = [entry] if isinstance(entry, np.ndarray) else list(entry)
        fixed = []
        for line in lines:
            line = np.asarray(line, float)
            if line.ndim != 2:
                continue
            if line.shape[0] in (2, 3) and line.shape[1] > 3:
                line = line[:2].T
            fixed.append(line[:, :2])
        out.append(fixed)
    return out


def prbm_series(case: Case, shapes) -> ShapeSeries | None:
    """The PRB links of every level as line cells, every link end and pivot as a vertex."""
    if not shapes:
        return None
    frames = []
    for polylines in normalise_shapes(shapes):
        points: list[list[float]] = []
        lines: list[list[int]] = []
        for line in (line for line in polylines if len(line) >= 2):
            start = len(points)
            points.extend(line.tolist())
            lines.extend([start + j, start + j + 1] for j in range(len(line) - 1))
        if not lines:
            return None  # a level without links: no series rather than an empty frame
        frames.append(
            ShapeFrame(np.asarray(points), np.asarray(lines), np.arange(len(points)), {"pivot": np.ones(len(points))})
        )
    return ShapeSeries("prbm", _times(case, _levels(shapes)), frames)


def _lines_frame(polylines: list[np.ndarray]) -> ShapeFrame | None:
    """Polylines as one frame of line cells, with each point's tangent angle (degrees) and the
    curvature d(angle)/ds along its polyline; a 2-point line (a rigid body's, `ShapeFrame.rigid`) has no
    centreline field (NaN)."""
    points: list[list[float]] = []
    lines: list[list[int]] = []
    angle: list[float] = []
    curvature: list[float] = []
    rigid: list[list[int]] = []
    for line in (line for line in polylines if len(line) == 2):
        rigid.append([len(points), len(points) + 1])
        points.extend(line.tolist())
        angle.extend([np.nan, np.nan])
        curvature.extend([np.nan, np.nan])
    for line in (line for line in polylines if len(line) >= 3):
        start = len(points)
        points.extend(line.tolist())
        lines.extend([start + j, start + j + 1] for j in range(len(line) - 1))
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(line, axis=0).T))])
        theta = np.unwrap(
            np.arctan2(np.gradient(line[:, 1], s, edge_order=2), np.gradient(line[:, 0], s, edge_order=2))
        )
        angle.extend(np.degrees(theta))
        curvature.extend(np.gradient(theta, s, edge_order=2))
    if not lines:
        return None
    return ShapeFrame(
        np.asarray(points),
        np.asarray(lines),
        point_data={"rotation": np.asarray(angle), "curvature": np.asarray(curvature)},
        rigid=np.asarray(rigid, int).reshape(-1, 2),
    )


def elastica_series(case: Case, shapes) -> ShapeSeries | None:
    """The exact centreline with its point data: a segment's (x, y, theta) rows, or a mechanism's beam
    centrelines (x, y) with the tangent angle and curvature read off them."""
    if not shapes:
        return None
    if case.segment is None:
        built = [_lines_frame(polylines) for polylines in normalise_shapes(shapes)]
        lines_frames = [f for f in built if f is not None]
        if not built or len(lines_frames) != len(built):
            return None
        return ShapeSeries("elastica", _times(case, _levels(shapes)), lines_frames)
    per_level = [shapes[k] for k in _levels(shapes)]
    _, EI = case.segment.section.stiffness(case.segment.E)
    kappa0 = case.segment.initial_curvature()
    frames = []
    for shape in per_level:
        shape = np.asarray(shape, float)
        if shape.ndim != 2 or shape.shape[0] != 3:
            return None
        x, y, theta = shape
        s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])  # inextensible: arc length
        if kappa0:
            reference = np.column_stack([np.sin(kappa0 * s) / kappa0, (1 - np.cos(kappa0 * s)) / kappa0])
        else:
            reference = np.column_stack([s, np.zeros_like(s)])
        curvature = np.gradient(theta, s, edge_order=2)
        displacement = np.column_stack([x, y]) - reference
        frames.append(
            ShapeFrame(
                np.column_stack([x, y]),
                np.column_stack([np.arange(len(x) - 1), np.arange(1, len(x))]),
                point_data={
                    "displacement": np.column_stack([displacement, np.zeros(len(x))]),
                    "rotation": np.degrees(theta),
                    "curvature": curvature,
                    "bending_moment": EI * (curvature - kappa0),
                },
            )
        )
    return ShapeSeries("elastica", _times(case, _levels(shapes)), frames)


def case_series(case: Case, runs: dict) -> list[ShapeSeries]:
    """Every method's series of one case (FEM, PRBM, elastica: those that gave shapes)."""
    builders = {
        "fem": lambda run: fem_series(case, run.extras.get("fields")),
        "prbm": lambda run: prbm_series(case, run.extras.get("shapes")),
        "elastica": lambda run: elastica_series(case, run.extras.get("shapes")),
    }
    parts = []
    for method, build in builders.items():
        run = runs.get(method)
        series = build(run) if run is not None else None
        if series is not None and series.frames:
            parts.append(series)
    return parts


def write_case_series(case: Case, runs: dict, folder: Path, series: list[ShapeSeries] | None = None) -> list[Path]:
    """Every method's series of one case under ``folder`` (``series``: `case_series`'s, when the caller
    has them); returns the ``.pvd`` paths."""
    parts = case_series(case, runs) if series is None else series
    for stale in [*folder.glob("*.vtu"), *folder.glob("*.pvd")]:  # a level or method that is gone
        stale.unlink()
    written = [write_pvd(part, folder) for part in parts]
    if len(parts) > 1:  # every method in one file, one part each, to scrub through the load together
        _collection(folder / "all_methods.pvd", parts)
    return written


RENDER_COLOURS = {"fem": "steelblue", "prbm": "darkorange", "elastica": "seagreen"}
RENDER_NAMES = {"fem": "FEM", "prbm": "PRBM", "elastica": "exact elastica"}  # as the case page names them
FEM_COLOURMAP: Final = "viridis"
FEM_LEGEND_COLOUR = "#21918c"  # viridis at the middle of its range: the FEM line's colour at a mean moment
UNDEFORMED_COLOUR = "grey"
RIGID_COLOUR = "black"  # the FEM's rigid links: no bending moment of their own to colour them by
CANVAS = (900, 540)  # pixels of a picture
# where a picture puts what (fractions of its width and height, from its lower left corner): the
# mechanism in DRAWN, clear of the title (top left), the legend and the colour bar (the right strip)
DRAWN = ((0.03, 0.70), (0.05, 0.88))
LEGEND_LEFT, LEGEND_TOP, LEGEND_ROW = 0.72, 0.90, 0.055
BAR: ScalarBarArgs = {
    "position_x": 0.74,
    "position_y": 0.06,
    "width": 0.22,
    "height": 0.42,
    "vertical": True,
    "n_labels": 5,
    "fmt": "%.3g",
    "title_font_size": 14,
    "label_font_size": 13,
    "color": "black",
    "unconstrained_font_size": True,
}
BAR_RATIO, BAR_GAP = 0.2, 14  # the colour bar's share of its box's width (the rest: its tick labels), and the
#                                 pixels between its title and its top
NOISE = 1e-6  # a field's values within NOISE x its largest magnitude are rounding noise: zero on the colour bar


@dataclass
class Canvas:
    """This process's off-screen plotter and what stays on it between pictures: the title (one corner
    text whose words change), one legend per set of entries (pyvista normalises a legend's symbols, entry
    by entry, each time one is built), and the picture's own actors (meshes, the shown legend), removed
    for the next."""

    plotter: pyvista.Plotter
    title: pyvista.CornerAnnotation
    legends: dict[tuple, object] = field(default_factory=dict)
    shown: list = field(default_factory=list)

    def clear(self) -> None:
        # pyvista wraps Renderer's method (functools.wraps): mypy sees it unbound, wanting a plotter first
        self.plotter.remove_actor(self.shown, reset_camera=False, render=False)  # type: ignore[arg-type]
        for title in list(self.plotter.scalar_bars.keys()):  # its actor too (``clear`` forgets, keeps it drawn)
            self.plotter.scalar_bars.remove_scalar_bar(title, render=False)
        self.shown = []

    def legend(self, entries: tuple[tuple[str, str], ...]) -> None:
        """Show the legend of ``entries`` (label, colour), made the first time it is asked for, in the
        picture's right strip (``LEGEND_LEFT``, from ``LEGEND_TOP`` down)."""
        actor = self.legends.get(entries)
        if actor is None:
            height = LEGEND_ROW * len(entries)
            rows = [list(e) for e in entries]
            # as in ``clear``: a method pyvista wraps, which mypy sees unbound
            actor = self.legends[entries] = self.plotter.add_legend(
                rows,  # type: ignore[arg-type]
                bcolor="white",
                face="line",
                size=(0.27, height),
            )
            actor.SetPosition(LEGEND_LEFT, LEGEND_TOP - height)
            actor.SetPosition2(0.27, height)
        else:
            # as in ``clear``: a method pyvista wraps, which mypy sees unbound
            self.plotter.add_actor(actor, reset_camera=False, pickable=False, render=False)  # type: ignore[arg-type]
        self.shown.append(actor)


_CANVASES: dict[tuple[int, int], Canvas] = {}  # window size -> this process's canvas


def _canvas(pv, size: tuple[int, int] = CANVAS) -> Canvas:
    """This process's off-screen canvas, made once and emptied for each picture: a new VTK render
    window per page costs about as much again as the rendering (its OpenGL context and shaders); one
    sample per pixel (pyvista's default 8-sample anti-aliasing doubles the software rendering's time
    for lines that read the same)."""
    canvas = _CANVASES.get(size)
    if canvas is None:
        samples, pv.global_theme.multi_samples = pv.global_theme.multi_samples, 1  # no 8x MSAA: half the time
        plotter = pv.Plotter(off_screen=True, window_size=size)
        pv.global_theme.multi_samples = samples
        plotter.set_background("white")
        title = plotter.add_text(" ", font_size=10, color="black", name="title")
        canvas = _CANVASES[size] = Canvas(plotter, title)
    else:
        canvas.clear()
    return canvas


def _polydata(pv, frame: ShapeFrame, scalars: tuple[str, ...] = (), cells: str = "all"):
    """A frame as pyvista line (and vertex) cells, with the point arrays named in ``scalars``: the mesh
    ``write_pvd`` writes for the frame, built in memory (what a picture draws of it); ``cells``: its line
    cells (`ShapeFrame.line_cells`; the vertices with all but the rigid links)."""
    lines = frame.line_cells(cells)
    mesh = pv.PolyData(
        np.column_stack([frame.points, np.zeros(len(frame.points))]),
        lines=np.column_stack([np.full(len(lines), 2), lines]).ravel(),
    )
    if len(frame.vertices) and cells != "rigid":
        vertices = np.asarray(frame.vertices, int).ravel()
        mesh.verts = np.column_stack([np.ones(len(vertices), int), vertices]).ravel()
    for name in scalars:
        if name in frame.point_data:
            mesh.point_data[name] = np.asarray(frame.point_data[name], float)
    return mesh


def colour_range(values, noise: float = NOISE) -> tuple[float, float]:
    """The range a colour bar spans over ``values``: their least and largest, a value within ``noise`` x the
    largest magnitude counted as zero (a moment of -1e-8 beside 22.9 is rounding: the bar starts at 0);
    a field of one value spans that value +- 1 (+- 1 % of it)."""
    finite = np.asarray(values, float)
    finite = finite[np.isfinite(finite)]
    if not len(finite):
        return 0.0, 1.0
    peak = float(np.abs(finite).max())
    clipped = np.where(np.abs(finite) <= noise * peak, 0.0, finite)
    low, high = float(clipped.min()), float(clipped.max())
    if high - low <= noise * peak:
        pad = 0.01 * abs(high) or 1.0
        return low - pad, high + pad
    return low, high


def fit_camera(camera, bounds, size: tuple[int, int] = CANVAS, region=DRAWN, margin: float = 1.06) -> None:
    """Look down on the x-y plane (parallel projection) so that ``bounds`` (xmin, xmax, ymin, ymax, ...)
    fill ``region`` of the picture (fractions of its width and height), ``margin`` times over: nothing
    drawn is cut by the picture's edge or hidden under its title, legend or colour bar."""
    (x0, x1), (y0, y1) = region
    aspect = size[0] / size[1]
    width, height = bounds[1] - bounds[0], bounds[3] - bounds[2]
    extent = max(width, height, 1e-12)
    half = margin * max(height / (2 * (y1 - y0)), width / (2 * (x1 - x0) * aspect), 0.02 * extent)
    cx = (bounds[0] + bounds[1]) / 2 - ((x0 + x1) / 2 - 0.5) * 2 * half * aspect
    cy = (bounds[2] + bounds[3]) / 2 - ((y0 + y1) / 2 - 0.5) * 2 * half
    camera.parallel_projection = True
    camera.focal_point = (cx, cy, 0.0)
    camera.position = (cx, cy, 10.0 * extent)
    camera.up = (0.0, 1.0, 0.0)
    camera.parallel_scale = half
    camera.clipping_range = (1e-3 * extent, 100.0 * extent)


def _bar_title(moment_unit: str) -> str:
    """The colour bar's title, on two lines over its ticks: the field, then its unit."""
    return "FEM bending\nmoment" + (f" [{moment_unit}]" if moment_unit else "")


def render_series(series: list[ShapeSeries], png: Path, title: str = "", moment_unit: str = "") -> Path | None:
    """The last level of every series (and the FEM's undeformed mesh) in one off-screen picture, from
    the series ``write_case_series`` writes (the same meshes, built in memory: no reading back): the FEM
    coloured by its bending moment (``moment_unit``) over ``colour_range``, the view fitted to what is drawn
    (``fit_camera``); None when pyvista (VTK) cannot render here."""
    try:
        import pyvista as pv
    except ImportError:
        return None
    pv.vtk_verbosity("error")  # no "bad X server connection" warning on a headless machine
    canvas = _canvas(pv)
    plotter = canvas.plotter
    legend = []  # (label, colour): each entry in its line's colour (pyvista's own legend gives a line
    bounds = []  # coloured by scalars the mesh's default colour, a light blue)
    for part in series:
        method = part.method
        last = part.frames[-1]
        bounds.append(last.points)
        if method == "fem" and "bending_moment" in last.point_data:
            # the elements coloured by their bending moment, the rigid links (which have none) in one colour
            mesh = _polydata(pv, last, ("bending_moment",), cells="lines")
            moment = last.point_data["bending_moment"][np.unique(last.line_cells("lines"))]
            bar: ScalarBarArgs = {"title": _bar_title(moment_unit), "render": False, **BAR}
            canvas.shown.append(
                plotter.add_mesh(
                    mesh,
                    scalars="bending_moment",
                    line_width=6,
                    cmap=FEM_COLOURMAP,
                    clim=colour_range(moment),
                    scalar_bar_args=bar,
                    render=False,
                )
            )
            colour_bar = plotter.scalar_bars[bar["title"]]
            colour_bar.SetBarRatio(BAR_RATIO)  # a thin bar in a box wide enough for its title,
            colour_bar.SetVerticalTitleSeparation(BAR_GAP)  # the title clear of the top tick's label
            legend.append(("FEM (colour: bending moment)", FEM_LEGEND_COLOUR))
            if len(last.rigid):
                canvas.shown.append(
                    plotter.add_mesh(_polydata(pv, last, cells="rigid"), color=RIGID_COLOUR, line_width=4, render=False)
                )
                legend.append(("FEM rigid links", RIGID_COLOUR))
            if part.undeformed is not None:
                bounds.append(part.undeformed.points)
                canvas.shown.append(
                    plotter.add_mesh(
                        _polydata(pv, part.undeformed), color=UNDEFORMED_COLOUR, line_width=2, render=False
                    )
                )
                legend.append(("undeformed", UNDEFORMED_COLOUR))
        else:
            mesh = _polydata(pv, last)
            colour = RENDER_COLOURS.get(method, "black")
            canvas.shown.append(
                plotter.add_mesh(
                    mesh, color=colour, line_width=3, point_size=10, render_points_as_spheres=True, render=False
                )
            )
            legend.append((RENDER_NAMES.get(method, method), colour))
    canvas.title.set_text("upper_left", title or " ")
    points = np.concatenate([np.asarray(b, float).reshape(-1, 2) for b in bounds]) if bounds else np.zeros((1, 2))
    (xmin, ymin), (xmax, ymax) = points.min(axis=0), points.max(axis=0)
    fit_camera(plotter.camera, (xmin, xmax, ymin, ymax))
    canvas.legend(tuple(legend))
    plotter.render()  # the one render of the picture (the calls above are told not to render)
    image = plotter.screenshot(None, return_img=True)
    if image is None:
        return None
    # zlib level 1: faster to compress than the default (6), for somewhat larger files
    Image.fromarray(image).save(png, compress_level=1)
    return png
