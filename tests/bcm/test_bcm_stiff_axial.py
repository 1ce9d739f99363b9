"""A rigid body on axially stiff BCM beams finds its equilibrium inside the BCM's range.

Seed 004's parallel-guided mechanism with EA/EI = 1e6 (k_a = 1e6): MINPACK's hybrid solver stalled
from F L^2/EI = 0.5 on ("not making good progress"), although the coupler moves only 0.02-0.04 L,
inside the BCM's stated range of 0.1 L (seed 003 section 2). Expected values: the linear limit of
two guided beams sharing the load, dx = F L^3/(24 EI) (each beam F/2 with the guided-beam
stiffness 12 EI/L^3), which the BCM meets to second order in the deflection (its nonlinear terms
are O((u/L)^2): under 0.5 % up to u = 0.083 L, where a planted 10 % error or a stall would fail),
and equilibrium itself (the beams' generalised force equals the load's).
"""

import numpy as np
import pytest

from bcm.mechanisms import BCMBeam, RigidBodyOnBeams

KA = 1.0e6
MIDDLE = (0.25, 1.0)


def _guide() -> RigidBodyOnBeams:
    return RigidBodyOnBeams([BCMBeam((x, 0.0), (x, 1.0), 1.0, KA) for x in (0.0, 0.5)], MIDDLE)


@pytest.mark.parametrize("load", [0.5, 1.0, 2.0])
def test_stiff_axial_parallel_guide_solves_from_rest(load):
    guide = _guide()
    forces = [(MIDDLE, (load, 0.0))]
    q, _ = guide.solve(forces=forces)
    assert q[0] == pytest.approx(load / 24.0, rel=5e-3, abs=0.0)
    unbalance = guide.internal_force(q) - guide.external_force(q, forces, 0.0)
    assert np.max(np.abs(unbalance)) <= 1e-10 * load


def test_no_equilibrium_far_outside_the_range_is_reported_not_returned():
    """From rest at F L^2/EI = 10 (linear dx 0.42 L, four times the BCM's range) the walk towards the
    root may fail; if it does, it says so; if it returns, the state is an equilibrium."""
    guide = _guide()
    forces = [(MIDDLE, (10.0, 0.0))]
    try:
        q, _ = guide.solve(forces=forces)
    except RuntimeError as exc:
        assert "BCM equilibrium not found" in str(exc)
    else:
        assert np.max(np.abs(guide.internal_force(q) - guide.external_force(q, forces, 0.0))) <= 1e-9
