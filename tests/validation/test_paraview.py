"""ParaView files: the FEM's point data obey statics, the series read back with meshio and pyvista
hold the arrays, lengths and time values the case implies, and the PRBM links are written."""

import math
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

import fem
from validation.report import paraview
from validation.case.loader import case_by_id
from validation.run.case_run import run_case


@pytest.fixture(scope="module")
def tip_loaded_cantilever():
    """A rectangular cantilever (E = 1e4, 1 x 0.05, L = 1) with an upward tip force P = 0.5, 1."""
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.rectangle(1e4, 1.0, 0.05), n_elements=32)
    model.add_support("root", "fixed")
    model.add_force("tip", 0.0, np.array([0.5, 1.0]))
    return fem.solve(model), 1.0


def test_fem_nodal_fields_obey_statics(tip_loaded_cantilever):
    result, P = tip_loaded_cantilever
    fields = result.nodal_fields(1)
    xy = result.mesh_positions[1]
    x_tip, y_tip = result.position("tip", 1)
    # a vertical tip force P: the bending moment at any section is P times the horizontal lever arm
    np.testing.assert_allclose(fields.bending_moment, P * (x_tip - xy[:, 0]), atol=1e-9 * P)
    EI = 1e4 * 0.05**3 / 12
    np.testing.assert_allclose(fields.curvature, fields.bending_moment / EI, rtol=1e-9, atol=1e-12)
    # the axial force of an element is the force's component along its chord, P sin(beta) (tension
    # positive); a node takes the mean of the elements meeting there
    conn = result.connectivity
    chord = xy[conn[:, 1]] - xy[conn[:, 0]]
    along = P * chord[:, 1] / np.hypot(*chord.T)
    count = np.bincount(conn.ravel(), minlength=len(xy))
    expected = (np.bincount(conn[:, 0], along, len(xy)) + np.bincount(conn[:, 1], along, len(xy))) / count
    np.testing.assert_allclose(fields.axial_force, expected, atol=1e-6 * P)
    # displacement is position minus the undeformed mesh; the tip's is (x_tip - 1, y_tip)
    tip = np.argmin(np.hypot(*(xy - [x_tip, y_tip]).T))
    np.testing.assert_allclose(fields.displacement[tip], [x_tip - 1.0, y_tip], atol=1e-12)
    # the largest bending stress at the root: M c / I + N / A of the first element
    root = np.argmin(np.hypot(*xy.T))
    c, I, A = 0.025, 0.05**3 / 12, 0.05
    expected = fields.bending_moment[root] * c / I + abs(fields.axial_force[root]) / A
    assert fields.bending_stress[root] == pytest.approx(expected, rel=1e-9)  # one element meets the root


@pytest.fixture(scope="module")
def cantilever_files(tmp_path_factory):
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=False)
    folder = tmp_path_factory.mktemp("vtu")
    return result, paraview.write_case_series(result.loaded.case, result.runs, folder)


def _times(pvd):
    return [float(d.get("timestep")) for d in ET.parse(pvd).getroot().iter("DataSet")]


def test_cantilever_series_read_back(cantilever_files):
    result, files = cantilever_files
    assert sorted(p.name for p in files) == ["elastica.pvd", "fem.pvd", "prbm.pvd"]
    case = result.loaded.case
    loads = list(case.loads[0].levels())
    fem_pvd = next(p for p in files if p.stem == "fem")
    assert _times(fem_pvd) == pytest.approx(loads)  # one time per load level, the load's value
    folder = fem_pvd.parent
    for k in range(case.n_levels()):
        mesh = meshio.read(folder / f"fem_{k:04d}.vtu")
        arrays = set(mesh.point_data)
        assert {"displacement", "rotation", "bending_moment", "axial_force", "curvature"} <= arrays
        assert all(len(v) == len(mesh.points) for v in mesh.point_data.values())
    last = meshio.read(folder / f"fem_{case.n_levels() - 1:04d}.vtu")
    tip = np.argmax(last.points[:, 0] - last.point_data["displacement"][:, 0])  # undeformed x = L
    run = result.runs["fem"]
    y_tip = next(v for r, v in run.values.items() if r.quantity == "y" and r.level == case.n_levels() - 1)
    rotation = next(v for r, v in run.values.items() if r.quantity == "rotation" and r.level == case.n_levels() - 1)
    assert last.point_data["displacement"][tip, 1] == pytest.approx(y_tip, rel=1e-3)
    assert last.point_data["rotation"][tip] == pytest.approx(rotation, rel=1e-3)  # degrees, as the outputs
    undeformed = meshio.read(folder / "fem_undeformed.vtu")
    assert np.allclose(undeformed.points[:, 1], 0.0) and undeformed.points[:, 0].max() == pytest.approx(1.0)
    prbm = meshio.read(folder / "prbm_0009.vtu")
    assert len(prbm.cells_dict["line"]) == 2 and len(prbm.cells_dict["vertex"]) == 3  # two links, pivots
    elastica = meshio.read(folder / "elastica_0009.vtu")
    length = np.hypot(*np.diff(elastica.points[:, :2], axis=0).T).sum()
    assert length == pytest.approx(1.0, rel=1e-3)  # the inextensible centreline keeps its length


def test_pyvista_opens_the_series_and_renders(cantilever_files, tmp_path):
    pv = pytest.importorskip("pyvista")
    result, files = cantilever_files
    fem_pvd = next(p for p in files if p.stem == "fem")
    reader = pv.get_reader(str(fem_pvd))
    assert len(reader.time_values) == result.loaded.case.n_levels()
    reader.set_active_time_point(len(reader.time_values) - 1)
    block = reader.read()
    assert len(block[0].point_data.keys()) >= 4
    png = paraview.render_series(
        paraview.case_series(result.loaded.case, result.runs), tmp_path / "render.png", "cantilever"
    )
    if png is None:
        pytest.skip("pyvista cannot render here")
    picture = pv.read(str(png))
    pixels = np.asarray(picture.point_data[picture.point_data.keys()[0]])
    assert pixels.std() > 0  # not a blank picture


def test_test2_file_holds_the_prbm_links(tmp_path):
    result = run_case(case_by_id("bapat2015_test2"), methods=["prbm"], use_cache=False)
    files = paraview.write_case_series(result.loaded.case, result.runs, tmp_path)
    assert [p.stem for p in files] == ["prbm"]
    mesh = meshio.read(tmp_path / "prbm_0000.vtu")
    # the four-bar O2-A-B-O4 (3 links) and the coupler triangle A-P-B (2 segments)
    assert len(mesh.cells_dict["line"]) == 5
    assert not math.isnan(mesh.points.sum())


def test_test2_fem_files_and_shapes_draw_the_rigid_coupler(tmp_path):
    """Test 2's coupler is a rigid body (seed 000 fig. 9.21: the segment tip A carries B and the coupler
    point P), in the FEM two rigid links A-B and A-P with no element of their own. The FEM's files, its
    picture and its shapes chart draw them: two line cells after the elements, both from the master A,
    each as long at every level as unloaded (rigid); the bending moment at P, which no element reaches,
    is NaN (no value made up)."""
    result = run_case(case_by_id("bapat2015_test2"), methods=["fem"], use_cache=False)
    run = result.runs["fem"]
    fields = run.extras["fields"]
    n_elements = len(fields.connectivity)
    series = paraview.case_series(result.loaded.case, result.runs)
    paraview.write_case_series(result.loaded.case, result.runs, tmp_path, series)
    undeformed = meshio.read(tmp_path / "fem_undeformed.vtu")
    for k in range(result.loaded.case.n_levels()):
        mesh = meshio.read(tmp_path / f"fem_{k:04d}.vtu")
        lines = mesh.cells_dict["line"]
        assert len(lines) == n_elements + 2
        links = lines[n_elements:]
        assert links[0, 0] == links[1, 0] and links[0, 1] != links[1, 1]  # a star from the master A
        length = np.linalg.norm(np.diff(mesh.points[links], axis=1), axis=2).ravel()
        unloaded = np.linalg.norm(np.diff(undeformed.points[links], axis=1), axis=2).ravel()
        np.testing.assert_allclose(length, unloaded, rtol=1e-9)
        assert np.isnan(mesh.point_data["bending_moment"][links[:, 1]]).sum() == 1  # P: no element there
        drawn = run.extras["shapes"][k][-2:]  # the chart's polylines: the element chains, then the links
        np.testing.assert_array_equal(np.array(drawn), mesh.points[links][:, :, :2])
    pv = pytest.importorskip("pyvista")  # the picture: the elements by their moment, the links plain
    frame = series[0].frames[-1]
    elements = paraview._polydata(pv, frame, ("bending_moment",), cells="lines")
    rigid = paraview._polydata(pv, frame, cells="rigid")  # as `render_series` draws them
    on_disk = pv.read(str(tmp_path / f"fem_{len(series[0].frames) - 1:04d}.vtu"))
    two = [tuple(c.point_ids) for c in on_disk.cell if c.n_points == 2]
    assert [tuple(c.point_ids) for mesh in (elements, rigid) for c in mesh.cell if c.n_points == 2] == two
    assert rigid.n_cells == 2 and "bending_moment" not in rigid.point_data


def test_test2_elastica_draws_its_rigid_bodies():
    """The exact elastica of Test 2 draws its rigid bodies beside the beam, as the FEM does: the coupler
    A-B-P as lines from A to B and to P, the rigid link O4-B; each as long at every level as in the case
    file's geometry (rigid), the coupler's lines starting where the beam's centreline ends (A)."""
    case = case_by_id("bapat2015_test2").case
    run = run_case(case_by_id("bapat2015_test2"), methods=["elastica"], use_cache=False).runs["elastica"]
    nodes = {n.name: np.array([n.x, n.y]) for n in case.mechanism.nodes}
    for k, shape in enumerate(run.extras["shapes"]):
        beam, *bodies = shape
        assert len(bodies) == 3
        for line, (a, b) in zip(bodies, (("A", "B"), ("A", "P"), ("O4", "B"))):
            assert np.linalg.norm(line[1] - line[0]) == pytest.approx(np.linalg.norm(nodes[b] - nodes[a]), rel=1e-9)
        np.testing.assert_allclose(bodies[0][0], beam[-1, :2], atol=1e-9)  # A: the beam's end
        np.testing.assert_allclose(bodies[2][0], nodes["O4"], atol=1e-12)  # O4: the ground pivot, fixed
    frames = paraview.elastica_series(case, run.extras["shapes"]).frames  # its ParaView files, picture
    for frame, shape in zip(frames, run.extras["shapes"]):
        assert len(frame.lines) == len(shape[0]) - 1 and len(frame.rigid) == 3
        np.testing.assert_array_equal(frame.points[frame.rigid], np.array(shape[1:]))
        assert np.isnan(frame.point_data["curvature"][frame.rigid]).all()  # no centreline field there


def test_all_methods_collection_has_one_part_per_method(cantilever_files):
    result, files = cantilever_files
    root = ET.parse(files[0].parent / "all_methods.pvd").getroot()
    parts = {}
    for entry in root.iter("DataSet"):
        parts.setdefault(entry.get("part"), []).append(entry.get("file"))
    assert sorted(len(v) for v in parts.values()) == [10, 10, 10]
    assert {f.split("_")[0] for files_ in parts.values() for f in files_} == {"fem", "prbm", "elastica"}
    assert all((files[0].parent / f).exists() for files_ in parts.values() for f in files_)


def test_a_method_that_drew_some_levels_keeps_their_load_as_time(cantilever_files):
    result, _ = cantilever_files
    shapes = result.runs["elastica"].extras["shapes"]
    some = {9: shapes[9], 2: shapes[2]}
    series = paraview.elastica_series(result.loaded.case, some)
    assert series.times == [3.0, 10.0]  # levels 2 and 9 of P L^2/EI = 1..10


def test_fem_library_export_writes_the_series(tip_loaded_cantilever, tmp_path):
    result, _ = tip_loaded_cantilever
    paths = result.to_vtu(str(tmp_path / "beam"))
    assert _times(tmp_path / "beam.pvd") == pytest.approx(list(result.load_factor))
    last = meshio.read(paths[-1])
    assert set(last.point_data) == {
        "displacement",
        "rotation",
        "curvature",
        "bending_moment",
        "axial_force",
        "bending_stress",
    }  # a rectangle knows E and c: stress too
    np.testing.assert_allclose(last.point_data["bending_moment"], result.nodal_fields(1).bending_moment)
    assert len(meshio.read(tmp_path / "beam_undeformed.vtu").points) == len(last.points)


def test_a_mechanism_elastica_centreline_has_its_tangent_angle():
    """Beam centrelines given as (x, y) points: a quarter circle of radius 2 has tangent angle 0..90 deg
    and curvature 1/2 (the exact circle, sampled)."""
    phi = np.linspace(0.0, np.pi / 2, 201)
    arc = np.column_stack([2 * np.sin(phi), 2 * (1 - np.cos(phi))])
    case = case_by_id("bapat2015_test2").case
    series = paraview.elastica_series(case, [[arc]] * case.n_levels())
    frame = series.frames[0]
    assert len(frame.lines) == 200
    np.testing.assert_allclose(frame.point_data["rotation"][[0, 100, 200]], [0.0, 45.0, 90.0], atol=0.01)
    np.testing.assert_allclose(frame.point_data["curvature"][1:-1], 0.5, rtol=1e-3)


def test_the_picture_draws_the_meshes_the_files_hold(tmp_path):
    """`render_series` draws each series' last level (and the FEM's undeformed mesh) from memory
    (`_polydata`), not by reading the files back: those meshes equal what `write_case_series` wrote, as
    pyvista (ParaView's VTK) reads them: the same points, line cells, vertex cells and bending moment."""
    pv = pytest.importorskip("pyvista")
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=True)
    series = paraview.case_series(result.loaded.case, result.runs)
    files = paraview.write_case_series(result.loaded.case, result.runs, tmp_path, series)
    assert [p.stem for p in files] == [s.method for s in series] and len(series) >= 2

    def cells(mesh, size):
        return [tuple(c.point_ids) for c in mesh.cell if c.n_points == size]

    for part in series:
        last = len(part.frames) - 1
        on_disk = pv.read(str(tmp_path / f"{part.method}_{last:04d}.vtu"))
        drawn = paraview._polydata(pv, part.frames[-1], ("bending_moment",))
        np.testing.assert_array_equal(drawn.points, on_disk.points)
        assert cells(drawn, 2) == cells(on_disk, 2) and cells(drawn, 1) == cells(on_disk, 1)
        if part.method == "fem":
            np.testing.assert_array_equal(drawn.point_data["bending_moment"], on_disk.point_data["bending_moment"])
            undeformed = pv.read(str(tmp_path / "fem_undeformed.vtu"))
            np.testing.assert_array_equal(paraview._polydata(pv, part.undeformed).points, undeformed.points)
