"""Planar pseudo-rigid-body linkages: four-bar and slider-crank with torsional springs.

Four-bar [bapat2015, chs. 6, 7, 9, Figs 6.2, 7.1]: complex vectors Z1 (ground O2 -> O4),
Z2 (input O2 -> A), Z3 (coupler A -> B), Z4 (output O4 -> B), Z5 (A -> coupler point P); loop
Z2 + Z3 = Z1 + Z4.  Springs k1..k4 at O2, A, B, O4 on the joint angles of eq (183):
beta1 = Theta2, beta2 = Theta3 - Theta2 (+ const), beta3 = Theta4 - Theta3, beta4 = Theta4, measured
from the energy-free angles Theta20, Theta30, Theta40.

  U = 1/2 sum k_i (beta_i - beta_i0)^2                                              (181)
  T = dU/dTheta2 = sum k_i (beta_i - beta_i0) d beta_i/dTheta2                      (182), (193)
  h3 = dTheta3/dTheta2 = R2 sin(Theta4 - Theta2) / (R3 sin(Theta3 - Theta4))
  h4 = dTheta4/dTheta2 = R2 sin(Theta3 - Theta2) / (R4 sin(Theta3 - Theta4))

Static equilibrium under an input torque T on link 2 is the stationary point of the total potential
U - T (Theta2 - Theta20) (virtual work, eq 191): solve dU/dTheta2 = T for Theta2 (1-D, bracketed).
Position analysis: Theta4 from the closed-form loop solution on the assembly branch of the
reference (position-1) configuration; Theta3 from the loop.  The inverse (the input angle for a given
output angle, ``FourBar.input_for_output``; the crank angle for a slider position,
``SliderCrank.theta2_at``) is the same circle intersection seen from the other side, in closed form.

Mechanical advantage (chapter 7): rigid-body MA_R = (d_i/d_o)(omega2/omega4) = (d_i/d_o)/h4 (eq 190),
equal to the instant-centre form (d_i/d_o)|I14 I24|/|I12 I24| (eq 202) (both are implemented and
tested to agree); compliant MA = MA_R (1 - F_c/F_i) with F_c = T_c/d_i (eq 192), T_c from (193).
The garbled eqs (201) and (204) are not implemented (notes seed-ch5-9 section 3.5).

Slider-crank (chapter 7, Fig 7.2): crank R2 at Theta2 about O2, coupler R3 to the slider pin on the
axis y = offset (axis along x, Theta1 = 0); springs k1 (O2), k2 (A), k3 (slider pin), f_k (slider).
Compliance torque eq (196); MA_R = d_i/|I12 I24| (eq 199).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import cmath
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from prbm.network import GROUND, Couple, LinearSpring, Network, Pin, Slider, TorsionSpring, solve
from prbm.result import Levels, PRBMResult

__all__ = ["FourBar", "SliderCrank", "four_bar_rates", "slider_crank_rate"]


LOOP_TOLERANCE = 0.01  # printed vectors close only to their rounding (Test 2: 0.002 in on 7 in)

_A = TypeVar("_A", float, NDArray[np.float64])  # an angle at one pose (a float) or at many (an array)


@overload
def _wrap(x: float) -> float: ...


@overload
def _wrap(x: NDArray[Any]) -> NDArray[np.float64]: ...


def _wrap(x: float | NDArray[Any]) -> float | NDArray[np.float64]:
    wrapped: float | NDArray[np.float64] = (np.asarray(x) + np.pi) % (2 * np.pi) - np.pi
    return wrapped


def four_bar_rates(R2: float, R3: float, R4: float, theta2: _A, theta3: _A, theta4: _A) -> tuple[_A, _A]:
    """(h3, h4) = (dTheta3/dTheta2, dTheta4/dTheta2) of a four-bar at its link angles (rad; floats or
    arrays): h3 = R2 sin(Theta4 - Theta2) / (R3 sin(Theta3 - Theta4)), h4 = R2 sin(Theta3 - Theta2) /
    (R4 sin(Theta3 - Theta4)); the joint-angle rates of eq (183) follow (1, h3 - 1, h4 - h3, h4)."""
    h3: _A = R2 * np.sin(theta4 - theta2) / (R3 * np.sin(theta3 - theta4))
    h4: _A = R2 * np.sin(theta3 - theta2) / (R4 * np.sin(theta3 - theta4))
    return h3, h4


def slider_crank_rate(R2: float, R3: float, theta2: _A, theta3: _A) -> _A:
    """g3 = dTheta3/dTheta2 = -R2 cos Theta2 / (R3 cos Theta3) of a slider-crank whose axis is along its
    x axis (from R2 sin Theta2 + R3 sin Theta3 = offset); the spring rates of eq (196) are (1, g3 - 1, g3)."""
    g3: _A = -R2 * np.cos(theta2) / (R3 * np.cos(theta3))
    return g3


@dataclass
class FourBar:
    """A four-bar from its position-1 vectors (complex, any consistent length unit), with springs.

    springs: (k1, k2, k3, k4) torsional stiffnesses (moment/rad); theta_free: energy-free
    (Theta20, Theta30, Theta40) in radians (default: position 1).
    """

    Z1: complex
    Z2: complex
    Z3: complex
    Z4: complex
    Z5: complex = 0j
    springs: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    theta_free: tuple[float, float, float] | None = None

    def __setattr__(self, name: str, value: object) -> None:
        if name in ("springs", "theta_free"):  # the network is built from them: rebuild on change
            object.__setattr__(self, "_network", None)
        object.__setattr__(self, name, value)

    def __post_init__(self) -> None:
        self._network: Network | None = None
        self.R1, self.R2, self.R3, self.R4 = (abs(z) for z in (self.Z1, self.Z2, self.Z3, self.Z4))
        self.theta1 = cmath.phase(self.Z1)
        t2, t3, t4 = (cmath.phase(z) for z in (self.Z2, self.Z3, self.Z4))
        self.theta_ref = (t2, t3, t4)
        # assembly branch: the circle intersection that reproduces position 1
        self.branch = 1.0
        err_plus = self._branch_check()
        self.branch = -1.0
        if self._branch_check() > err_plus:
            self.branch = 1.0
        # Z5 rides on the coupler: its angle minus the coupler angle *as recomputed* at position 1,
        # so that printed vectors whose loop closes only to rounding still give P(position 1) = Z2 + Z5
        # and coupler-point displacements Z2 (e^{i phi} - 1) + Z5 (e^{i gamma} - 1) (eqs 179, 180).
        t3_computed = float(self.angles(t2)[0])
        self.coupler_offset = cmath.phase(self.Z5) - t3_computed if self.Z5 != 0 else 0.0
        self.R5 = abs(self.Z5)
        if self.theta_free is None:
            self.theta_free = self.theta_ref
        self.loop_error = abs(self.Z2 + self.Z3 - self.Z1 - self.Z4)
        longest = max(self.R1, self.R2, self.R3, self.R4)
        if self.loop_error > LOOP_TOLERANCE * longest or not math.isfinite(t3_computed):
            raise ValueError(
                f"the four-bar loop Z2 + Z3 = Z1 + Z4 does not close: |Z2 + Z3 - Z1 - Z4| = "
                f"{self.loop_error:.4g}, more than {LOOP_TOLERANCE:.0%} of the longest link "
                f"({longest:.4g}); check the vectors"
            )

    # --- kinematics -------------------------------------------------------------------------
    @overload
    def angles(self, theta2: float) -> tuple[np.float64, np.float64]: ...

    @overload
    def angles(self, theta2: NDArray[Any]) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

    def angles(
        self, theta2: float | NDArray[Any]
    ) -> tuple[np.float64, np.float64] | tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(Theta3, Theta4) for input angle(s) Theta2 (rad), on the position-1 assembly branch.

        Loop Z2 + Z3 = Z1 + Z4: with D = Z1 - Z2 (A to O4), B = A + R3 e^{i Theta3} = O4 + R4 e^{i Theta4}.
        Intersect circles about A (R3) and O4 (R4); NaN where the linkage cannot assemble.
        """
        if isinstance(theta2, float) or np.ndim(theta2) == 0:
            return self._angles_scalar(float(theta2))
        theta2 = np.asarray(theta2, dtype=float)
        A = self.R2 * np.exp(1j * theta2)
        O4 = self.Z1
        d = O4 - A
        dist = np.abs(d)
        cos_alpha = (self.R3**2 + dist**2 - self.R4**2) / (2 * self.R3 * dist)
        with np.errstate(invalid="ignore"):
            alpha = np.arccos(cos_alpha)
        base = np.angle(d)
        # choose the intersection on the same side as position 1
        theta3 = base - self.branch * alpha
        B = A + self.R3 * np.exp(1j * theta3)
        theta4 = np.angle(B - O4)
        return theta3, theta4

    def _angles_scalar(self, theta2: float) -> tuple[np.float64, np.float64]:
        """``angles`` for one input angle in plain floats (the same construction, no numpy overhead)."""
        A = self.R2 * cmath.exp(1j * theta2)
        d = self.Z1 - A
        dist = abs(d)
        cos_alpha = (self.R3**2 + dist**2 - self.R4**2) / (2 * self.R3 * dist)
        if not -1.0 <= cos_alpha <= 1.0:
            return np.float64(math.nan), np.float64(math.nan)
        theta3 = cmath.phase(d) - self.branch * math.acos(cos_alpha)
        B = A + self.R3 * cmath.exp(1j * theta3)
        return np.float64(theta3), np.float64(cmath.phase(B - self.Z1))

    def input_for_output(self, theta4: float, near: float, *, span: float = math.pi / 2) -> float | None:
        """Input angle Theta2 that puts the output link at theta4 (rad), on the position-1 assembly
        branch, nearest to ``near`` within +-span; None if there is none.

        Closed form (the inverse position problem): B = Z1 + R4 e^{i theta4} is known, so A lies on
        the circles |A| = R2 and |B - A| = R3: Theta2 = arg B +- acos((R2^2 + |B|^2 - R3^2) / (2 R2 |B|)).
        Each candidate is kept only if the forward solution ``angles`` (assembly branch) returns
        theta4 there, to 1e-9 rad.
        """
        B = self.Z1 + self.R4 * cmath.exp(1j * theta4)
        dist = abs(B)
        if dist == 0.0:
            return None
        cos_beta = (self.R2**2 + dist**2 - self.R3**2) / (2 * self.R2 * dist)
        if not -1.0 <= cos_beta <= 1.0:
            return None
        base, beta = cmath.phase(B), math.acos(cos_beta)
        best: float | None = None
        for t2 in (base + beta, base - beta):
            t2 = near + math.remainder(t2 - near, 2 * math.pi)  # the representative nearest `near`
            if abs(t2 - near) > span:
                continue
            t4 = float(self._angles_scalar(t2)[1])
            if not abs(math.remainder(t4 - theta4, 2 * math.pi)) < 1e-9:
                continue  # the other assembly branch
            if best is None or abs(t2 - near) < abs(best - near):
                best = t2
        return best

    def _branch_check(self) -> float:
        t3, t4 = self.angles(self.theta_ref[0])
        return abs(_wrap(t3 - self.theta_ref[1])) + abs(_wrap(t4 - self.theta_ref[2]))

    @overload
    def coupler_point(self, theta2: float, angles: tuple[float, float] | None = None) -> complex: ...

    @overload
    def coupler_point(
        self, theta2: NDArray[Any], angles: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
    ) -> NDArray[np.complex128]: ...

    def coupler_point(
        self,
        theta2: float | NDArray[Any],
        angles: tuple[float, float] | tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
    ) -> complex | NDArray[np.complex128]:
        """Coupler point P = A + R5 e^{i(Theta3 + offset)} (complex, O2 at the origin).

        ``angles``: (Theta3, Theta4) of these theta2 when already known (from ``angles``)."""
        theta2 = np.asarray(theta2, dtype=float)
        theta3, _ = self.angles(theta2) if angles is None else angles
        point: complex | NDArray[Any] = self.R2 * np.exp(1j * theta2) + self.R5 * np.exp(
            1j * (theta3 + self.coupler_offset)
        )
        return point

    def kinematic_coefficients(self, theta2: _A, angles: tuple[_A, _A] | None = None) -> tuple[_A, _A]:
        """(h3, h4) = (dTheta3/dTheta2, dTheta4/dTheta2)."""
        t3, t4 = self.angles(theta2) if angles is None else angles
        return four_bar_rates(self.R2, self.R3, self.R4, theta2, t3, t4)

    # --- springs and equilibrium: the general network (prbm.network) -----------------------
    def network(self) -> Network:
        """This four-bar as a general rigid-link network: bodies 'link2' (O2-A), 'coupler' (A-B-P),
        'link4' (O4-B), built in the energy-free pose (input angle Theta20, the loop re-solved there);
        springs k1 (link2-ground), k2 (coupler-link2), k3 (link4-coupler), k4 (link4-ground) on the
        joint angles of eq (183), free at the energy-free angles (Theta20, Theta30, Theta40) as given."""
        if self._network is None:
            assert self.theta_free is not None  # set in __post_init__ (default: position 1)
            t20, t30, t40 = self.theta_free
            t3, t4 = (float(v) for v in self._angles_scalar(t20))
            A = self.R2 * cmath.exp(1j * t20)
            B = A + self.R3 * cmath.exp(1j * t3)
            P = A + self.R5 * cmath.exp(1j * (t3 + self.coupler_offset))

            def xy(z: complex) -> tuple[float, float]:
                return (z.real, z.imag)

            r3, r4 = float(_wrap(t30 - t3)), float(_wrap(t40 - t4))  # printed angles off the loop
            k1, k2, k3, k4 = self.springs
            self._pose = (t20, t3, t4)
            self._network = Network(
                ["link2", "coupler", "link4"],
                {
                    "O2": (GROUND, (0.0, 0.0)),
                    "A": ("link2", xy(A)),
                    "B": ("coupler", xy(B)),
                    "P": ("coupler", xy(P)),
                    "O4": (GROUND, xy(self.Z1)),
                },
                pins=[
                    Pin("link2", GROUND, (0.0, 0.0), "O2"),
                    Pin("coupler", "link2", xy(A), "A"),
                    Pin("link4", "coupler", xy(B), "B"),
                    Pin("link4", GROUND, xy(self.Z1), "O4"),
                ],
                springs=[
                    TorsionSpring("link2", GROUND, k1, 0.0, "k1"),
                    TorsionSpring("coupler", "link2", k2, r3, "k2"),
                    TorsionSpring("link4", "coupler", k3, r4 - r3, "k3"),
                    TorsionSpring("link4", GROUND, k4, r4, "k4"),
                ],
                origins={"link2": (0.0, 0.0), "coupler": xy(A), "link4": xy(self.Z1)},
            )
        return self._network

    def _configuration(self, theta2: float, angles: tuple[float, float] | None = None) -> NDArray[np.float64]:
        """Network coordinates of the pose at input angle theta2 (closed-form loop, assembly branch)."""
        net = self.network()
        t20, t30c, t40c = self._pose
        t3, t4 = self._angles_scalar(theta2) if angles is None else angles
        A = self.R2 * cmath.exp(1j * theta2)
        q = np.zeros(net.n)
        q[2] = theta2 - t20
        dA = A - self.R2 * cmath.exp(1j * t20)
        q[3:6] = dA.real, dA.imag, float(_wrap(t3 - t30c))
        q[8] = float(_wrap(t4 - t40c))
        return q

    @overload
    def strain_energy(self, theta2: float, angles: tuple[float, float] | None = None) -> float: ...

    @overload
    def strain_energy(
        self, theta2: NDArray[Any], angles: tuple[ArrayLike, ArrayLike] | None = None
    ) -> NDArray[np.float64]: ...

    def strain_energy(
        self, theta2: float | NDArray[Any], angles: tuple[ArrayLike, ArrayLike] | None = None
    ) -> float | NDArray[np.float64]:
        """U = 1/2 sum k_i (beta_i - beta_i0)^2 (eq 181), from the network's springs."""
        return self._per_angle(theta2, angles, lambda q: self.network().strain_energy(q))

    @overload
    def input_torque(self, theta2: float, angles: tuple[float, float] | None = None) -> float: ...

    @overload
    def input_torque(
        self, theta2: NDArray[Any], angles: tuple[ArrayLike, ArrayLike] | None = None
    ) -> NDArray[np.float64]: ...

    def input_torque(
        self, theta2: float | NDArray[Any], angles: tuple[ArrayLike, ArrayLike] | None = None
    ) -> float | NDArray[np.float64]:
        """T on link 2 holding the linkage at Theta2 (eqs 182, 193): the network's driving torque
        (virtual work with the joint-compatible velocity of unit input rate)."""
        return self._per_angle(theta2, angles, lambda q: self.network().driving_torque(q, "link2"))

    def _per_angle(
        self, theta2: ArrayLike, angles: tuple[ArrayLike, ArrayLike] | None, f: Callable[[NDArray[np.float64]], float]
    ) -> float | NDArray[np.float64]:
        theta2 = np.asarray(theta2, float)
        if angles is None:
            angles = self.angles(theta2)
        t3, t4 = (np.asarray(a, float) for a in angles)
        flat = [
            f(self._configuration(float(a), (float(b), float(c)))) if math.isfinite(float(b)) else math.nan
            for a, b, c in zip(
                theta2.ravel(), np.broadcast_to(t3, theta2.shape).ravel(), np.broadcast_to(t4, theta2.shape).ravel()
            )
        ]
        out = np.array(flat).reshape(theta2.shape)
        return out if out.ndim else np.float64(out)

    def positions_under_torque(self, torques: ArrayLike) -> PRBMResult:
        """Equilibrium under input torque(s) T on link 2: the general network solver (Newton with load
        stepping from the energy-free pose; ``prbm.network.solve``). Outputs theta2, theta3, theta4
        (rad), coupler point x, y (O2 origin), U, T; ``extras['network']`` the network result."""
        t0 = time.perf_counter()
        torques = np.atleast_1d(np.asarray(torques, dtype=float))
        net = self.network()
        res = solve(net, [Couple("link2", tuple(torques))], len(torques))
        t20, t3c, t4c = self._pose
        q = np.array([s.q for s in res.states])
        theta2, t3, t4 = t20 + q[:, 2], t3c + q[:, 5], t4c + q[:, 8]
        P = np.array([complex(*res.position("P", i)) for i in range(len(torques))])
        ok = np.array([s.converged for s in res.states])
        out: dict[str, Levels] = {
            "theta2": theta2,
            "theta3": t3,
            "theta4": t4,
            "x": P.real,
            "y": P.imag,
            "U": np.array([res.strain_energy(i) for i in range(len(torques))]),
            "T": torques,
        }
        return PRBMResult(
            bool(ok.all()),
            res.message,
            out,
            {
                "springs": self.springs,
                "theta_free": self.theta_free,
                "R": (self.R1, self.R2, self.R3, self.R4, self.R5),
            },
            "PRB four-bar as a rigid-link network, seed 000 eqs (181)-(183), (191)",
            time.perf_counter() - t0,
            nit=res.iterations,
            level_converged=ok,
            extras={"network": res},
        )

    # --- mechanical advantage ---------------------------------------------------------------
    @overload
    def instant_centres(self, theta2: float) -> tuple[complex, complex, complex]: ...

    @overload
    def instant_centres(
        self, theta2: NDArray[Any]
    ) -> tuple[complex, complex, NDArray[np.complexfloating[Any, Any]]]: ...

    def instant_centres(
        self, theta2: float | NDArray[Any]
    ) -> tuple[complex, complex, complex | NDArray[np.complexfloating[Any, Any]]]:
        """I12 (= O2), I14 (= O4), I24 (intersection of line I12-I14 and line I23-I34) as complex."""
        t3, t4 = self.angles(theta2)
        A = self.R2 * np.exp(1j * np.asarray(theta2, float))
        B = self.Z1 + self.R4 * np.exp(1j * t4)
        O4 = self.Z1
        # I24 on the ground line O2-O4 (through 0 and Z1) and on the coupler line A-B
        u = O4 / abs(O4)
        v = B - A
        # solve s u = A + t v
        det = u.real * (-v.imag) - u.imag * (-v.real)
        s = (A.real * (-v.imag) - A.imag * (-v.real)) / det
        return 0j, O4, s * u

    def rigid_ma(
        self, theta2: _A, d_in: float, d_out: float, *, via: str = "coefficients", angles: tuple[_A, _A] | None = None
    ) -> _A:
        """MA_R = F_o/F_i for F_i at d_in on link 2 and F_o at d_out on link 4 (eqs 190, 202)."""
        if via == "coefficients":
            _, h4 = self.kinematic_coefficients(theta2, angles)
            ma: _A = d_in / d_out / np.abs(h4)
            return ma
        I12, I14, I24 = self.instant_centres(theta2)
        ma = d_in / d_out * np.abs(I14 - I24) / np.abs(I12 - I24)
        return ma

    def compliant_ma(
        self,
        theta2: _A,
        F_in: float,
        d_in: float,
        d_out: float,
        angles: tuple[_A, _A] | None = None,
        *,
        torque: _A | None = None,
    ) -> _A:
        """MA = MA_R (1 - F_c/F_i), F_c = T_c/d_i with T_c the compliance torque (eqs 192, 193).

        ``angles``, ``torque``: (Theta3, Theta4) and ``input_torque`` at theta2, when already known."""
        if angles is None:
            angles = self.angles(theta2)
        F_c = (self.input_torque(theta2, angles) if torque is None else torque) / d_in
        return self.rigid_ma(theta2, d_in, d_out, angles=angles) * (1.0 - F_c / F_in)


@dataclass
class SliderCrank:
    """Slider-crank along the x axis (Theta1 = 0): crank R2 about O2 = 0, coupler R3 to the slider pin
    on y = offset.  Position 1 given by the crank angle theta2_ref and the coupler angle theta3_ref
    (which fixes the assembly branch).  Springs (k1, k2, k3) at O2, A, slider pin; f_k on the slider.
    """

    R2: float
    R3: float
    theta2_ref: float
    theta3_ref: float
    offset: float = 0.0
    springs: tuple[float, float, float] = (0.0, 0.0, 0.0)
    f_k: float = 0.0

    @classmethod
    def from_vectors(cls, Z11: complex, Z2: complex, Z3: complex, **kw: Any) -> "SliderCrank":
        return cls(abs(Z2), abs(Z3), cmath.phase(Z2), cmath.phase(Z3), offset=(Z2 + Z3).imag, **kw)

    def __setattr__(self, name: str, value: object) -> None:
        if name in ("springs", "f_k", "theta2_ref", "theta3_ref", "R2", "R3", "offset"):
            object.__setattr__(self, "_network", None)  # the network is built from them
        object.__setattr__(self, name, value)

    def __post_init__(self) -> None:
        self._network: Network | None = None
        self.branch = 1.0 if math.cos(self.theta3_ref) >= 0 else -1.0
        self.x_ref = self.R2 * math.cos(self.theta2_ref) + self.R3 * math.cos(self.theta3_ref)

    def theta3(self, theta2: _A) -> _A:
        """Coupler angle on the assembly branch of position 1, in the turn of theta3_ref (within pi
        of it), so theta3 - theta3_ref is the coupler's rotation from position 1 whatever the
        quadrant the reference was given in."""
        s = (self.offset - self.R2 * np.sin(theta2)) / self.R3
        with np.errstate(invalid="ignore"):  # NaN where the coupler cannot reach (|s| > 1): callers skip it
            t = np.arcsin(s)
        t = t if self.branch > 0 else np.pi - t
        theta3: _A = self.theta3_ref + np.remainder(t - self.theta3_ref + np.pi, 2.0 * np.pi) - np.pi
        return theta3

    def slider_x(self, theta2: _A) -> _A:
        x: _A = self.R2 * np.cos(theta2) + self.R3 * np.cos(self.theta3(theta2))
        return x

    def theta2_at(self, dx: float) -> float:
        """Crank angle that moves the slider by dx from position 1, nearest to theta2_ref (within pi).

        Closed form: the slider pin S = (x_ref + dx, offset) is known, so A lies on the circles
        |A| = R2 and |S - A| = R3: Theta2 = arg S +- acos((R2^2 + |S|^2 - R3^2) / (2 R2 |S|)); a
        candidate is kept only if ``slider_x`` (on the coupler branch of position 1) returns S there.
        Falls back to the bracketed scan (``_theta2_at_scan``) if no candidate is kept."""
        target = self.x_ref + dx
        S = complex(target, self.offset)
        dist = abs(S)
        best = None
        if dist > 0.0:
            cos_beta = (self.R2**2 + dist**2 - self.R3**2) / (2 * self.R2 * dist)
            if -1.0 <= cos_beta <= 1.0:
                base, beta = cmath.phase(S), math.acos(cos_beta)
                scale = self.R2 + self.R3
                for t2 in (base + beta, base - beta):
                    t2 = self.theta2_ref + math.remainder(t2 - self.theta2_ref, 2 * math.pi)
                    if abs(float(self.slider_x(t2)) - target) > 1e-9 * scale:
                        continue  # the other coupler branch
                    if best is None or abs(t2 - self.theta2_ref) < abs(best - self.theta2_ref):
                        best = t2
        return best if best is not None else self._theta2_at_scan(dx)

    def _theta2_at_scan(self, dx: float) -> float:
        """``theta2_at`` by a scan over theta2_ref +- pi and Brent (the reference implementation)."""
        target = self.x_ref + dx
        grid = self.theta2_ref + np.linspace(-math.pi, math.pi, 2001)
        r = self.slider_x(grid) - target
        i0 = np.argmin(np.abs(grid - self.theta2_ref))
        candidates = [
            i
            for i in range(len(grid) - 1)
            if np.isfinite(r[i]) and np.isfinite(r[i + 1]) and np.sign(r[i]) != np.sign(r[i + 1])
        ]
        if not candidates:
            raise ValueError(f"slider cannot reach dx = {dx}")
        i = min(candidates, key=lambda j: abs(j - i0))
        theta2: float = brentq(lambda t: float(self.slider_x(t)) - target, grid[i], grid[i + 1], xtol=1e-14)
        return theta2

    def network(self) -> Network:
        """This slider-crank as a general network in position 1 (its energy-free pose): bodies 'crank'
        (O2-A) and 'coupler' (A-S), the slider pin S on the ground line y = offset; springs k1
        (crank-ground), k2 (coupler-crank), k3 (coupler-ground: the slider block does not turn) and the
        linear spring f_k on the slider's travel."""
        if self._network is None:
            A = self.R2 * cmath.exp(1j * self.theta2_ref)
            S = A + self.R3 * cmath.exp(1j * self.theta3_ref)
            k1, k2, k3 = self.springs
            self._network = Network(
                ["crank", "coupler"],
                {"O2": (GROUND, (0.0, 0.0)), "A": ("crank", (A.real, A.imag)), "S": ("coupler", (S.real, S.imag))},
                pins=[Pin("crank", GROUND, (0.0, 0.0), "O2"), Pin("coupler", "crank", (A.real, A.imag), "A")],
                sliders=[Slider("coupler", (S.real, S.imag), (1.0, 0.0), name="slider")],
                springs=[
                    TorsionSpring("crank", GROUND, k1, name="k1"),
                    TorsionSpring("coupler", "crank", k2, name="k2"),
                    TorsionSpring("coupler", GROUND, k3, name="k3"),
                ],
                origins={"crank": (0.0, 0.0), "coupler": (A.real, A.imag)},
                linear_springs=[LinearSpring("S", (1.0, 0.0), self.f_k, "f_k")] if self.f_k else [],
            )
        return self._network

    @overload
    def compliance_torque(self, theta2: float) -> float: ...

    @overload
    def compliance_torque(self, theta2: NDArray[Any]) -> NDArray[np.float64]: ...

    def compliance_torque(self, theta2: float | NDArray[Any]) -> float | NDArray[np.float64]:
        """T_c on the crank (eq 196, = dU/dTheta2): the network's driving torque at the pose of each
        crank angle (coupler angle on the branch of position 1)."""
        net = self.network()
        theta2 = np.asarray(theta2, float)
        t3 = self.theta3(theta2)
        A0 = self.R2 * cmath.exp(1j * self.theta2_ref)
        out: NDArray[np.float64] = np.empty(theta2.size)
        for j, (a, b) in enumerate(zip(theta2.ravel(), np.broadcast_to(t3, theta2.shape).ravel())):
            q = np.zeros(net.n)
            dA = self.R2 * cmath.exp(1j * a) - A0
            q[2], q[3], q[4], q[5] = a - self.theta2_ref, dA.real, dA.imag, b - self.theta3_ref
            out[j] = net.driving_torque(q, "crank") if math.isfinite(b) else math.nan
        out = out.reshape(theta2.shape)
        return out if out.ndim else np.float64(out)

    @overload
    def rigid_ma(self, theta2: float, d_in: float) -> float: ...

    @overload
    def rigid_ma(self, theta2: NDArray[Any], d_in: float) -> NDArray[np.float64]: ...

    def rigid_ma(self, theta2: float | NDArray[Any], d_in: float) -> float | NDArray[np.float64]:
        """MA_R = d_i/|I12 I24| (eq 199): I24 where the coupler line meets the line through O2
        perpendicular to the slider axis; |I12 I24| = |dx/dTheta2| (slider speed per crank rate)."""
        theta2 = np.asarray(theta2, float)
        t3 = self.theta3(theta2)
        A = self.R2 * np.exp(1j * theta2)
        # coupler line A + t e^{i t3} meets x = 0
        t = -A.real / np.cos(t3)
        I24 = A + t * np.exp(1j * t3)
        ma: float | NDArray[np.float64] = d_in / np.abs(I24)
        return ma

    @overload
    def compliant_ma(self, theta2: float, F_in: float, d_in: float) -> float: ...

    @overload
    def compliant_ma(self, theta2: NDArray[Any], F_in: float, d_in: float) -> NDArray[np.float64]: ...

    def compliant_ma(self, theta2: float | NDArray[Any], F_in: float, d_in: float) -> float | NDArray[np.float64]:
        """MA = MA_R (1 - F_c/F_i), F_c = |T_c|/d_i (compliance opposing the input; eq 192)."""
        F_c = np.abs(self.compliance_torque(theta2)) / d_in
        ma: float | NDArray[np.float64] = self.rigid_ma(theta2, d_in) * (1.0 - F_c / F_in)
        return ma
