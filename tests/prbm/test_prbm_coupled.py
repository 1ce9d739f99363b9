"""Segment carrying a rigid body (prbm.coupled_segment) and the PRB link shapes of the PRBM adapter."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import prbm
from validation.case.loader import load_case
from validation.methods import prbm as adapter
from validation.methods.base import Request
from validation.report.build import normalise_shapes
from validation.case.method_options import options_of

L, EI = 12.895, 450000.0 * 6.735e-4  # chapter 5 Example 1 strip


def test_body_load_is_moved_with_the_current_offset():
    """A dead load at a body point = the same force at E plus M + r x F, r turned with the end."""
    beam = prbm.InflectionBeam(L, EI)
    r0 = complex(1.4581, -1.5537)  # Q - E of Example 1 in the beam frame
    F = complex(-7.071, 7.071)  # (Fx, Fy) = (-7.071, -7.071) global, in the beam frame
    res = prbm.solve_segment_with_body(beam, [prbm.BodyLoad(r0, F, -58.678)], {"Q": r0})
    assert res.converged, res.message
    gamma = float(res.outputs["rotation"])
    r = r0 * cmath.exp(1j * gamma)
    M_end = -58.678 + (r.conjugate() * F).imag
    assert float(res.outputs["M"]) == pytest.approx(M_end, abs=1e-9)
    plain = prbm.solve_loads(beam, F.imag, -F.real, -M_end)  # chapter-3 convention: M opposing
    found = [root["theta0"] for root in plain.roots[0]]  # the coupled state is one of its roots
    assert min(abs(t - float(res.outputs["theta0"])) for t in found) < 1e-7
    assert res.extras["points"]["Q"] == pytest.approx(complex(float(res.outputs["a"]), float(res.outputs["b"])) + r)


def test_tip_callable_branch_matches_fixed_pinned_with_equivalent_moment():
    """Secant branch: a transverse force on a rigid arm; the end sees F and F x r(theta0)."""
    EI1, L1 = 1.0, 1.0

    def tip(F, M):
        return prbm.fixed_guided_monotonic_tip(F.imag, -F.real / F.imag, M, length=L1, EI=EI1)

    r0 = complex(0.3, 0.0)
    res = prbm.solve_segment_with_body(tip, [prbm.BodyLoad(r0, complex(0.0, 0.5))], {"C": r0}, rest=(L1, 0.0, 0.0))
    assert res.converged, res.message
    t0 = float(res.outputs["theta0"])
    again = tip(complex(0.0, 0.5), 0.5 * 0.3 * math.cos(t0))
    assert float(np.ravel(again.outputs["theta0"])[0]) == pytest.approx(t0, abs=1e-8)


def test_chapter5_example1_shapes_follow_the_body():
    loaded = load_case("cases/chapter5/example1.toml")
    case = loaded.case
    reqs = [Request(q, "P", lv) for q in ("x", "y", "dx", "dy", "rotation") for lv in range(case.n_levels())]
    run = adapter.run(case, reqs, options_of("prbm", case.methods["prbm"]))
    assert run.values[Request("dx", "P", 1)] == pytest.approx(-1.0, abs=0.05)
    shapes = normalise_shapes(run.extras["shapes"])
    assert len(shapes) == case.n_levels()
    for lv, (chain, coupler) in enumerate(shapes):
        # O, pivot 1, inflection point, pivot 2, E (unloaded: O, E); then the coupler E-P-Q
        assert chain.shape == ((2, 2) if lv == 0 else (5, 2)) and coupler.shape == (3, 2)
        assert chain[0] == pytest.approx(
            [-3.6315, -13.8811]
        )  # the clamp O as given in the case file (input, not output)
        assert chain[-1] == pytest.approx(coupler[0])  # the body hangs on the segment end
        assert coupler[1] == pytest.approx([run.values[Request("x", "P", lv)], run.values[Request("y", "P", lv)]])
        lengths = np.hypot(*np.diff(chain, axis=0).T)
        assert lengths.sum() <= L + 1e-9  # PRB links are shorter than the beam


def test_fixed_pinned_segment_shape_is_root_pivot_tip():
    case = load_case("cases/benchmarks/cantilever_tip_load.toml").case
    reqs = [Request("x", "tip", lv) for lv in range(case.n_levels())] + [
        Request("y", "tip", lv) for lv in range(case.n_levels())
    ]
    run = adapter.run(case, reqs, options_of("prbm", case.methods.get("prbm", {})))
    shapes = normalise_shapes(run.extras["shapes"])
    for lv, (line,) in enumerate(shapes):
        assert line.shape == (3, 2)
        assert line[0] == pytest.approx([0.0, 0.0]) and line[1][1] == 0.0
        assert line[2] == pytest.approx([run.values[Request("x", "tip", lv)], run.values[Request("y", "tip", lv)]])
        assert np.hypot(*(line[2] - line[1])) == pytest.approx(case.segment.length - line[1][0])


def test_fourbar_shapes_keep_link_lengths():
    case = load_case("cases/chapter9/test2_partially_compliant_fourbar.toml").case
    reqs = [Request("dx", "P", lv) for lv in range(case.n_levels())]
    run = adapter.run(case, reqs, options_of("prbm", case.methods["prbm"]))
    shapes = normalise_shapes(run.extras["shapes"])
    assert len(shapes) == case.n_levels()
    first = None
    for loop, coupler in shapes:
        lengths = np.hypot(*np.diff(loop, axis=0).T)
        first = lengths if first is None else first
        assert lengths == pytest.approx(first, rel=1e-9)  # O2-A, A-B, B-O4 are rigid
        assert coupler[0] == pytest.approx(loop[1]) and coupler[2] == pytest.approx(loop[2])
