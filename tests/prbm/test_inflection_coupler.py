"""Chapter-5 coupler PRBM (prbm/inflection_coupler.py): fixed-guided inflection segments on one rigid
coupler, coupler X and rotation prescribed, Y free (seed 000 section 5.5, eqs 131-152).

Expected values are derivations, not our output:
* one segment alone: the coupler needs no Y force, so the segment's end force is horizontal,
  Im((-nP + iP) e^{i theta1}) = 0, i.e. n = cot(theta1) (0.0875 at 85 deg, -0.364 at 110 deg);
* the mirror image of a configuration about the Y axis (x -> -x, gamma -> -gamma) has the same Y;
* the case-2 problem (b, theta0, n -> a) at the equilibrium's n gives back the coupler's end a.
"""

import functools
import math

import pytest

from prbm.inflection import InflectionBeam, solve_displacements
from prbm.inflection_coupler import CouplerDrive, GuidedSegment, solve_coupler

E = 450000.0


def _EI(t):
    return E * 1.5 * t**3 / 12


# seed 000 section 5.5 Example 3, segment A (theta1 = 85 deg) and B (110 deg); Example 2 segments (90 deg)
EX3_A = GuidedSegment("segA", complex(-2.7273, -8.0178), complex(-2.0811, -0.6320), _EI(0.11478))
EX3_B = GuidedSegment("segB", complex(4.5442, -5.6287), complex(2.5201, -0.0676), _EI(0.08896))
EX2 = [
    GuidedSegment("segA", complex(0.6653, -8.1814), complex(0.6653, -0.7114), _EI(0.175)),
    GuidedSegment("segB", complex(2.9957, -12.2001), complex(2.9957, -3.8701), _EI(0.175)),
]


@functools.lru_cache(maxsize=None)
def _ex2_segment_a_alone():
    """Example 2's segment A alone, coupler X -3, rotation +10 deg: solved once per worker for the two tests
    that use it (they share an xdist group)."""
    return solve_coupler(EX2[:1], CouplerDrive(0j, 1 + 0j, -3.0, math.radians(10.0)))


@pytest.mark.parametrize("seg", [EX3_A, EX3_B], ids=["85deg", "110deg"])
def test_one_segment_alone_carries_a_horizontal_end_force(seg):
    res = solve_coupler([seg], CouplerDrive(0j, 1 + 0j, -1.5, math.radians(-10.0)))
    assert res.converged, res.message
    state = res.extras["states"][0]
    assert state.n == pytest.approx(1.0 / math.tan(seg.theta1), abs=1e-6)
    assert abs(state.force.imag) < 1e-6 * abs(state.force)
    # the case-2 problem at that n returns the end the coupler puts there
    drive = CouplerDrive(0j, 1 + 0j, -1.5, math.radians(-10.0))
    a, b, theta0 = drive.segment_end(seg, float(res.outputs["t"]))
    back = solve_displacements(InflectionBeam(seg.length, seg.EI), b=b, theta0=theta0, n=state.n)
    assert float(back.outputs["a"]) == pytest.approx(a, abs=1e-8 * seg.length)


@pytest.mark.xdist_group("ex2_segment_a_alone")
def test_the_mirror_image_has_the_same_free_motion():
    seg = EX2[0]
    mirrored = GuidedSegment("m", complex(-seg.root.real, seg.root.imag), complex(-seg.end.real, seg.end.imag), seg.EI)
    right = _ex2_segment_a_alone()
    left = solve_coupler([mirrored], CouplerDrive(0j, 1 + 0j, 3.0, math.radians(-10.0)))
    assert right.converged and left.converged
    assert float(left.outputs["t"]) == pytest.approx(float(right.outputs["t"]), abs=1e-9)
    assert float(left.outputs["strain_energy"]) == pytest.approx(float(right.outputs["strain_energy"]), rel=1e-9)
    assert float(left.outputs["force_along"]) == pytest.approx(-float(right.outputs["force_along"]), rel=1e-9)


@pytest.mark.xdist_group("ex2_segment_a_alone")
def test_two_segments_with_disjoint_windows_have_no_state_and_say_why():
    res = solve_coupler(EX2, CouplerDrive(0j, 1 + 0j, -3.0, math.radians(10.0)))
    assert not res.converged and "disjoint" in res.message and not res.outputs
    low_a, high_a = res.extras["windows"][0].low, res.extras["windows"][0].high
    alone = _ex2_segment_a_alone()
    assert low_a <= float(alone.outputs["t"]) <= high_a


def test_two_equal_segments_side_by_side_balance_at_the_single_answer():
    """Two copies of one segment, 1 apart, the coupler translated without turning: both ends move alike, so
    each carries half of nothing along Y: the balance is the single segment's, exactly."""
    seg = EX3_A
    twin = GuidedSegment("twin", seg.root + 1.0, seg.end + 1.0, seg.EI)
    drive = CouplerDrive(seg.end + 0.5, 1 + 0j, -1.0, 0.0)
    both = solve_coupler([seg, twin], drive)
    assert both.converged, both.message
    one = solve_coupler([seg], drive)
    assert float(both.outputs["t"]) == pytest.approx(float(one.outputs["t"]), abs=1e-9)
    assert float(both.outputs["strain_energy"]) == pytest.approx(2 * float(one.outputs["strain_energy"]), rel=1e-6)


@pytest.mark.parametrize("family", ["pauly-midha", "howell"])
def test_the_root_finders_float_kernel_is_the_numpy_state(family):
    """The plain-float state the root finders iterate on (``prbm.inflection._point_state``, F from eq 95 by
    ``_point_force``) is eqs (95)-(104) as ``inflection_state`` evaluates them: every output at points across
    and outside the fits' range, phi1 = pi/2 (n = 0), phi1 = pi (sin = 0: n infinite), theta10 = 0."""
    import numpy as np
    from prbm.inflection import _force_from_95, _point_ends, _point_force, _point_loads, _point_state, inflection_state

    beam = InflectionBeam(7.4, 85.0, family)
    rng = np.random.default_rng(5)
    points = [
        (rng.uniform(0.05, 3.1), rng.uniform(-1.4, 1.4), rng.uniform(0.3, 7.1), rng.uniform(-1, 1.5))
        for _ in range(200)
    ] + [
        (math.pi / 2, 0.1, 3.0, 0.5),
        (math.pi, 0.2, 3.0, 0.4),
        (1.0, 0.0, 3.0, 0.0),
        (1.0, 0.2, 3.0, math.inf),
    ]  # math raises: the numpy fallback
    for phi1, theta0, l1, theta10 in points:
        with np.errstate(all="ignore"):
            F = float(_force_from_95(beam, phi1, l1, theta10))
            want = {k: float(v) for k, v in inflection_state(beam, F, phi1, theta0, l1, theta10).items()}
        assert _point_force(beam, phi1, l1, theta10) == pytest.approx(F, rel=1e-12, nan_ok=True)
        got = _point_state(beam, F, phi1, theta0, l1, theta10)
        assert got.keys() == want.keys()
        for key, value in want.items():
            assert got[key] == pytest.approx(value, rel=1e-12, abs=1e-300, nan_ok=True), (key, phi1, theta0)
        # the residuals' lean kernels: r96, a and b, or r95, r96 and M of the whole state, the same floats
        for lean, keys in ((_point_ends, {"r96", "a", "b"}), (_point_loads, {"r95", "r96", "M"})):
            part = lean(beam, F, phi1, theta0, l1, theta10)
            assert part.keys() == keys
            assert all(part[k] == got[k] or (math.isnan(part[k]) and math.isnan(got[k])) for k in part), (
                lean.__name__,
                phi1,
                theta0,
            )
