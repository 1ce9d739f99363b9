"""A rigid body on BCM beams keeps its accuracy at small loads.

The beams' end deflections are formed from the body's displacement, not by subtracting point
coordinates, so a load of 1e-14 EI/L^2 is answered as accurately as 1e-2. Expected values: the
linear limit of seed 003 eq (3), f = K0 [u_y, theta] with K0 = [[12, -6], [-6, 4]] (EI = L = 1)
and f_x = k_a u_x, assembled for a parallel guide of two beams along x, ends at (1, 0) and
(1, 0.5), the body referenced at (1, 0.25): beam i sees u_y = v, theta = phi,
u_x = u - phi (y_i - 0.25).
"""

import numpy as np
import pytest

from bcm.mechanisms import BCMBeam, RigidBodyOnBeams

KA = 1.0e4
ENDS_Y = (0.0, 0.5)


def _linear_stiffness() -> np.ndarray:
    K = np.zeros((3, 3))
    for y in ENDS_Y:
        # (u_x, u_y, theta) of beam i from (u, v, phi)
        T = np.array([[1.0, 0.0, -(y - 0.25)], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        k = np.zeros((3, 3))
        k[0, 0] = KA
        k[1:, 1:] = [[12.0, -6.0], [-6.0, 4.0]]
        K += T.T @ k @ T
    return K


def _guide() -> RigidBodyOnBeams:
    return RigidBodyOnBeams([BCMBeam((0.0, y), (1.0, y), 1.0, KA) for y in ENDS_Y], (1.0, 0.25))


@pytest.mark.parametrize("load", [1e-14, 1e-10, 1e-6])
def test_small_transverse_load_meets_the_linear_limit(load):
    q, _ = _guide().solve(forces=[((1.0, 0.25), (0.0, load))])
    expected = np.linalg.solve(_linear_stiffness(), [0.0, load, 0.0])
    assert q[1] == pytest.approx(expected[1], rel=1e-6, abs=0.0)
    assert q[2] == pytest.approx(expected[2], rel=1e-6, abs=0.0)


def test_small_prescribed_rotation_meets_the_linear_limit():
    phi = 1e-12
    q, moment = _guide().solve(rotation=phi)
    K = _linear_stiffness()
    # u, v free and unloaded: K_ff [u, v] = -K_fr phi; moment = K_rf [u, v] + K_rr phi
    uv = np.linalg.solve(K[:2, :2], -K[:2, 2] * phi)
    assert q[1] == pytest.approx(uv[1], rel=1e-6, abs=0.0)
    assert moment == pytest.approx(K[2, :2] @ uv + K[2, 2] * phi, rel=1e-6, abs=0.0)
