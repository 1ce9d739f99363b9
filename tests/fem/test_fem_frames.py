"""Verification of fem/ on frames with limit points, traced by arc length.

* Lee's frame (Lee, Manuel & Rossow 1968): P_max L^2/EI = 18.557
  (anchors section 2.3: OpenSeesPy, an independent numpy corotational code and a
  Simo-Reissner code agree; the value is the O(h^2) Richardson limit).
* 215 degree clamped-hinged arch (DaDeppo & Schmidt 1975): P_cr R^2/EI = 8.97
  (source, 3 digits); 8.973 by independent extrapolation (anchors section 2.5).

Each limit load is computed on n and 2n elements per member; its Richardson
extrapolation must match the reference within the reference's own rounding
plus the extrapolation remainder, and the two meshes must bracket it the way
an O(h^2) error does.
"""

import numpy as np

import fem


def lee_frame(n):
    E, A, I = 720.0, 6.0, 2.0
    m = fem.Model()
    m.add_node("A", 0.0, 0.0)
    m.add_node("B", 0.0, 120.0)
    m.add_node("P", 24.0, 120.0)
    m.add_node("C", 120.0, 120.0)
    s = fem.Section.from_EI(E * A, E * I)
    m.add_member("A", "B", s, n_elements=n)
    m.add_member("B", "P", s, n_elements=n // 5)
    m.add_member("P", "C", s, n_elements=n - n // 5)
    m.add_support("A", "pinned")
    m.add_support("C", "pinned")
    m.add_force("P", 0.0, -1.0)
    return m


def trace_lee(n):
    return fem.solve(lee_frame(n), control="arclength", arc_length=5.0, max_arc_length=10.0, until=("P", "uy", -100.0))


def test_lee_frame_both_limit_points_continuous_path():
    L2_EI = 120.0**2 / 1440.0
    results = [trace_lee(n) for n in (10, 20)]
    pmax, pmin = [], []
    for r in results:
        assert r.converged, r.message
        limits = [c for c in r.critical_points if c.kind == "limit"]
        kinds = [c.detail for c in limits]
        assert kinds[:2] == ["maximum", "minimum"], kinds
        pmax.append(limits[0].load_factor)
        pmin.append(limits[1].load_factor)
        # the path reached v = -100 without turning back or jumping
        v = r.positions[:, 2, 1] - 120.0
        assert v[-1] <= -100.0
        steps = np.linalg.norm(np.diff(r.positions[:, 2], axis=0), axis=1)
        assert steps.max() < 10.0
        # ... and never turned back: successive increments of the whole mesh
        # (translations) point the same way
        inc = np.diff(r.mesh_positions, axis=0).reshape(len(r.mesh_positions) - 1, -1)
        assert np.all(np.einsum("ij,ij->i", inc[1:], inc[:-1]) > 0)
        # det K changes sign at the limit points (stable -> unstable -> ...)
        assert np.any(np.diff(r.det_sign) != 0)
    extrap = pmax[1] + (pmax[1] - pmax[0]) / 3
    assert pmax[0] > pmax[1] > extrap  # O(h^2) from above
    assert abs(extrap * L2_EI - 18.557) < 2e-3
    # second limit point: about -9.41 (anchors, one method only): loose check
    extrap_min = pmin[1] + (pmin[1] - pmin[0]) / 3
    assert abs(extrap_min * L2_EI + 9.41) < 0.05


def arch(n):
    R, half = 100.0, np.deg2rad(107.5)
    m = fem.Model()
    m.add_node("left", R * np.cos(np.pi / 2 + half), R * np.sin(np.pi / 2 + half))
    m.add_node("crown", 0.0, R)
    m.add_node("right", R * np.cos(np.pi / 2 - half), R * np.sin(np.pi / 2 - half))
    s = fem.Section.from_EI(1e10, 1e6)
    m.add_member("left", "crown", s, n_elements=n, curvature=-1.0 / R)
    m.add_member("crown", "right", s, n_elements=n, curvature=-1.0 / R)
    m.add_support("left", "fixed")
    m.add_support("right", "pinned")
    m.add_force("crown", 0.0, -1.0)
    return m


def test_arch_215_limit_load():
    R, EI = 100.0, 1e6
    p = []
    for n in (20, 40):
        r = fem.solve(arch(n), control="arclength", arc_length=2.0, max_limit_points=1)
        assert r.converged, r.message
        lim = r.critical_points[0]
        assert lim.kind == "limit" and lim.detail == "maximum"
        p.append(lim.load_factor)
        if n == 40:  # crown displacement at the limit point (DaDeppo: u/R = 0.6116, v/R = 1.1372)
            k = lim.step
            d = r.position("crown", k) - [0.0, R]
            assert abs(abs(d[0]) / R - 0.6116) < 0.01 and abs(-d[1] / R - 1.1372) < 0.01
    extrap = p[1] + (p[1] - p[0]) / 3
    assert p[0] > p[1] > extrap
    assert abs(extrap * R**2 / EI - 8.973) < 1.5e-3
    assert round(extrap * R**2 / EI, 2) == 8.97


def test_lee_displacement_control_first_limit():
    """Displacement control passes the first limit point (no snap-back before it)."""
    r = fem.solve(lee_frame(10), control="displacement", control_dof=("P", "uy"), targets=np.linspace(-5.0, -55.0, 11))
    assert r.converged, r.message
    limits = [c for c in r.critical_points if c.kind == "limit"]
    assert limits and limits[0].detail == "maximum"
    # same mesh as the arc-length run: both find the same discrete limit load
    arc = trace_lee(10)
    assert abs(limits[0].load_factor - arc.critical_points[0].load_factor) < 1e-4


def test_load_control_beyond_limit_reports_failure():
    m = lee_frame(10)
    m.loads.clear()
    m.add_force("P", 0.0, [-1.0, -2.5])  # second level beyond P_max = 1.86
    r = fem.solve(m)
    assert not r.converged
    assert "load level 1" in r.message and "iteration" in r.message
    assert r.n_levels == 1  # the first level is still reported
    assert np.isfinite(r.position("P", 0)).all()
