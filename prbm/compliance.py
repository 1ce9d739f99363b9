"""Compliance torque and compliance force of pseudo-rigid-body four-bars and slider mechanisms with
the input on any moving link, and the mechanical advantage types of [bapat2015, ch. 7].

Four-bar [bapat2015, Fig. 7.1]: links R2 (O2-A), R3 (A-B), R4 (O4-B) at angles theta2, theta3,
theta4; torsional springs k1..k4 at O2, A, B, O4 on the joint angles beta1 = theta2, beta2 =
theta3 - theta2, beta3 = theta4 - theta3, beta4 = theta4, each measured from its energy-free value
(subscript 0).  The compliance torque on the input link q is the virtual work of the springs per
unit input rotation, T_c = dU/dtheta_q = sum k_i (beta_i - beta_i0) d beta_i / d theta_q:

* input at link 2 (eq 193): h3 = dtheta3/dtheta2 = R2 sin(theta4 - theta2)/(R3 sin(theta3 - theta4)),
  h4 = dtheta4/dtheta2 = R2 sin(theta3 - theta2)/(R4 sin(theta3 - theta4));
  T_c = k1 D2 + k2 (D3 - D2)(h3 - 1) + k3 (D4 - D3)(h4 - h3) + k4 D4 h4, D_j = theta_j - theta_j0.
* input at the coupler (eq 194): h2 = dtheta2/dtheta3 = R3 sin(theta3 - theta4)/(R2 sin(theta4 - theta2)),
  h4 = dtheta4/dtheta3 = R3 sin(theta3 - theta2)/(R4 sin(theta4 - theta2));
  T_c = k1 D2 h2 + k2 (D3 - D2)(1 - h2) + k3 (D4 - D3)(h4 - 1) + k4 D4 h4.
* input at link 4 (eq 195): h2 = dtheta2/dtheta4 = R4 sin(theta3 - theta4)/(R2 sin(theta3 - theta2)),
  h3 = dtheta3/dtheta4 = R4 sin(theta4 - theta2)/(R3 sin(theta3 - theta2));
  T_c = k1 D2 h2 + k2 (D3 - D2)(h3 - h2) + k3 (D4 - D3)(1 - h3) + k4 D4.
  As printed, eq (195) repeats the multipliers of (193): (h3 - 1), (h4 - h3) and h4 with h4 not
  defined for this input.  The form above is the virtual work (d beta2/d theta4 = h3 - h2,
  d beta3/d theta4 = 1 - h3, d beta4/d theta4 = 1); ``fourbar_compliance_torque(..., printed_195=True)``
  evaluates the printed multipliers with h4 read as 1 so the two can be compared (a finding in
  cases/chapter7/example3.toml).

Slider mechanism (Fig. 7.2): crank R2 at theta2, coupler R3 at theta3, slider pin on a line parallel
to x at the offset (R2 sin theta2 + R3 sin theta3 = offset), slider position R1 = R2 cos theta2 +
R3 cos theta3; springs k1 (crank-ground), k2 (coupler-crank), k3 (coupler-slider block, which does
not turn) and a linear spring f_k on the slider travel:

* input at the crank (eq 196): g3 = dtheta3/dtheta2 = -R2 cos theta2/(R3 cos theta3),
  T_c = k1 D2 + k2 (D3 - D2)(g3 - 1) + k3 D3 g3 + f_k (R1 - R10) R2 cos theta2 (tan theta3 - tan theta2).
* input at the coupler (eq 197): g2 = dtheta2/dtheta3 = -R3 cos theta3/(R2 cos theta2),
  T_c = k1 D2 g2 + k2 (D3 - D2)(1 - g2) + k3 D3 + f_k (R1 - R10) R3 cos theta3 (tan theta2 - tan theta3).
* input at the slider (eq 198, a force): g2 = dtheta2/dR1 = -cos theta3/(R2 sin(theta2 - theta3)),
  g3 = dtheta3/dR1 = cos theta2/(R3 sin(theta2 - theta3)),
  F_c = k1 D2 g2 + k2 (D3 - D2)(g3 - g2) + k3 D3 g3 + f_k (R1 - R10).

Mechanical advantage (section 7.2, Salamon and Midha): MA = MA_R (1 - F_c/F_i) (eq 192), F_c the
compliance force at the input port (T_c/d_i for a torque input at distance d_i), MA_R the
rigid-body MA by power conservation and instant centres.  Three types by the variable the MA is
plotted against: Type 1 the work-piece location (F_i fixed), Type 2 the input force (location
fixed: ``type2_ma``), Type 3 the work-piece stiffness k_w (the work piece yields, so the location
follows from equilibrium F_i d_i = T_c(q) + k_w s(q) ds/dq: ``type3_equilibrium``).  Eq (205), the
rigid-body MA of a four-bar with the input on link 4 (link 1 fixed) and two output ports of equal
force on links 2 and 3 at d_out2, d_out3 (the Compliers of Example 3):
MA_R = d_i / ((|I14 I24|/|I12 I24|) d_out2 + (|I14 I34|/|I13 I34|) d_out3), i.e. d_i omega4 =
F_o (d_out2 omega2 + d_out3 omega3)/F_i with omega2/omega4 = 1/h4 and omega3/omega4 = h3/h4
(``two_port_rigid_ma``, both forms).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

__all__ = [
    "FourBarPose",
    "SliderPose",
    "fourbar_compliance_torque",
    "slider_compliance",
    "fourbar_instant_centres",
    "two_port_rigid_ma",
    "compliant_ma",
    "type2_ma",
    "type3_equilibrium",
    "Type3Point",
]

#: a quantity at one pose (a float) or at many (an array)
Value: TypeAlias = float | NDArray[np.float64]


@dataclass(frozen=True)
class FourBarPose:
    """Link lengths R2, R3, R4 and the angles (rad, arrays or floats) of a four-bar pose, with the
    energy-free angles theta20, theta30, theta40."""

    R2: float
    R3: float
    R4: float
    theta2: Value
    theta3: Value
    theta4: Value
    theta20: float
    theta30: float
    theta40: float


@dataclass(frozen=True)
class SliderPose:
    """Crank R2 and coupler R3 of a slider mechanism at angles theta2, theta3 (rad), energy-free
    theta20, theta30 and slider position R10 (R1 = R2 cos theta2 + R3 cos theta3)."""

    R2: float
    R3: float
    theta2: Value
    theta3: Value
    theta20: float
    theta30: float
    R10: float


def _fourbar_rates(p: FourBarPose, input_link: int) -> tuple[Value, Value, Value]:
    """(d theta2, d theta3, d theta4) per unit rotation of the input link (2, 3 or 4)."""
    t2, t3, t4 = (np.asarray(v, float) for v in (p.theta2, p.theta3, p.theta4))
    if input_link == 2:
        return (
            1.0,
            p.R2 * np.sin(t4 - t2) / (p.R3 * np.sin(t3 - t4)),
            p.R2 * np.sin(t3 - t2) / (p.R4 * np.sin(t3 - t4)),
        )
    if input_link == 3:
        return (
            p.R3 * np.sin(t3 - t4) / (p.R2 * np.sin(t4 - t2)),
            1.0,
            p.R3 * np.sin(t3 - t2) / (p.R4 * np.sin(t4 - t2)),
        )
    if input_link == 4:
        return (
            p.R4 * np.sin(t3 - t4) / (p.R2 * np.sin(t3 - t2)),
            p.R4 * np.sin(t4 - t2) / (p.R3 * np.sin(t3 - t2)),
            1.0,
        )
    raise ValueError(f"input_link must be 2, 3 or 4 (a moving link of the four-bar), got {input_link!r}")


def fourbar_compliance_torque(
    pose: FourBarPose, springs: tuple[float, float, float, float], input_link: int = 2, *, printed_195: bool = False
) -> Value:
    """T_c on the input link (2: eq 193, 3: eq 194, 4: eq 195 corrected; see the module docstring).

    springs: (k1, k2, k3, k4) in moment/rad.  ``printed_195`` (input_link 4 only): the multipliers as
    printed in eq (195), (h3 - 1), (h4 - h3), h4, with h4 read as 1 (it is not defined there)."""
    k1, k2, k3, k4 = springs
    D2 = np.asarray(pose.theta2, float) - pose.theta20
    D3 = np.asarray(pose.theta3, float) - pose.theta30
    D4 = np.asarray(pose.theta4, float) - pose.theta40
    w2, w3, w4 = _fourbar_rates(pose, input_link)
    if printed_195:
        if input_link != 4:
            raise ValueError("printed_195 applies to the input at link 4 (eq 195) only")
        return k1 * D2 * w2 + k2 * (D3 - D2) * (w3 - 1.0) + k3 * (D4 - D3) * (1.0 - w3) + k4 * D4
    return k1 * D2 * w2 + k2 * (D3 - D2) * (w3 - w2) + k3 * (D4 - D3) * (w4 - w3) + k4 * D4 * w4


def slider_compliance(
    pose: SliderPose, springs: tuple[float, float, float], f_k: float = 0.0, input_link: str = "crank"
) -> Value:
    """Compliance torque on the crank (eq 196) or coupler (eq 197), or compliance force on the
    slider (eq 198), per ``input_link`` = 'crank' | 'coupler' | 'slider'."""
    k1, k2, k3 = springs
    t2, t3 = np.asarray(pose.theta2, float), np.asarray(pose.theta3, float)
    D2, D3 = t2 - pose.theta20, t3 - pose.theta30
    dR1 = pose.R2 * np.cos(t2) + pose.R3 * np.cos(t3) - pose.R10
    compliance: Value
    if input_link == "crank":
        g3 = -pose.R2 * np.cos(t2) / (pose.R3 * np.cos(t3))
        compliance = (
            k1 * D2
            + k2 * (D3 - D2) * (g3 - 1.0)
            + k3 * D3 * g3
            + f_k * dR1 * pose.R2 * np.cos(t2) * (np.tan(t3) - np.tan(t2))
        )
        return compliance
    if input_link == "coupler":
        g2 = -pose.R3 * np.cos(t3) / (pose.R2 * np.cos(t2))
        compliance = (
            k1 * D2 * g2
            + k2 * (D3 - D2) * (1.0 - g2)
            + k3 * D3
            + f_k * dR1 * pose.R3 * np.cos(t3) * (np.tan(t2) - np.tan(t3))
        )
        return compliance
    if input_link == "slider":
        g2 = -np.cos(t3) / (pose.R2 * np.sin(t2 - t3))
        g3 = np.cos(t2) / (pose.R3 * np.sin(t2 - t3))
        compliance = k1 * D2 * g2 + k2 * (D3 - D2) * (g3 - g2) + k3 * D3 * g3 + f_k * dR1
        return compliance
    raise ValueError(f"input_link must be 'crank', 'coupler' or 'slider', got {input_link!r}")


def _line_intersection(
    p1: NDArray[np.complex128], p2: NDArray[np.complex128], q1: NDArray[np.complex128], q2: NDArray[np.complex128]
) -> NDArray[np.complex128]:
    """Intersection of line p1-p2 with line q1-q2 (complex points, arrays); inf if parallel."""
    u, v, w = p2 - p1, q2 - q1, q1 - p1
    det = u.real * v.imag - u.imag * v.real
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (w.real * v.imag - w.imag * v.real) / det
    return p1 + s * u


def fourbar_instant_centres(O4: complex, A: ArrayLike, B: ArrayLike) -> dict[str, NDArray[np.complex128]]:
    """Instant centres of a four-bar with O2 at the origin (link 1 fixed): I12 = O2, I14 = O4,
    I23 = A, I34 = B, I13 on lines O2-A and O4-B, I24 on lines O2-O4 and A-B (Kennedy)."""
    A, B = np.asarray(A, complex), np.asarray(B, complex)
    O2 = np.zeros_like(A)
    O4_arr = np.full_like(A, O4)
    return {
        "I12": O2,
        "I14": O4_arr,
        "I23": A,
        "I34": B,
        "I13": _line_intersection(O2, A, O4_arr, B),
        "I24": _line_intersection(O2, O4_arr, A, B),
    }


def two_port_rigid_ma(
    pose: FourBarPose, O4: complex, d_in: float, d_out2: float, d_out3: float, *, via: str = "instant_centres"
) -> Value:
    """Eq (205): MA_R of the four-bar with the input on link 4 and equal output forces on links 2
    and 3 at d_out2, d_out3.  via = 'instant_centres' (as printed) or 'coefficients' (omega2/omega4
    = 1/h4, omega3/omega4 = h3/h4 of the input-at-link-4 rates)."""
    if via == "coefficients":
        w2, w3, _ = _fourbar_rates(pose, 4)
        return d_in / (np.abs(w2) * d_out2 + np.abs(w3) * d_out3)
    if via != "instant_centres":
        raise ValueError(f"via must be 'instant_centres' or 'coefficients', got {via!r}")
    A = pose.R2 * np.exp(1j * np.asarray(pose.theta2, float))
    B = O4 + pose.R4 * np.exp(1j * np.asarray(pose.theta4, float))
    ic = fourbar_instant_centres(O4, A, B)
    ratio2 = np.abs(ic["I14"] - ic["I24"]) / np.abs(ic["I12"] - ic["I24"])
    ratio3 = np.abs(ic["I14"] - ic["I34"]) / np.abs(ic["I13"] - ic["I34"])
    return d_in / (ratio2 * d_out2 + ratio3 * d_out3)


def compliant_ma(rigid_ma: ArrayLike, compliance_force: ArrayLike, input_force: ArrayLike) -> NDArray[np.float64]:
    """Eq (192): MA = MA_R (1 - F_c/F_i)."""
    ma: NDArray[np.float64] = np.asarray(rigid_ma, float) * (
        1.0 - np.asarray(compliance_force, float) / np.asarray(input_force, float)
    )
    return ma


def type2_ma(rigid_ma: float, compliance_force: float, input_forces: ArrayLike) -> NDArray[np.float64]:
    """Type 2 MA: eq (192) at one work-piece location (MA_R and F_c fixed) over the input forces."""
    forces = np.asarray(input_forces, float)
    if np.any(forces == 0.0):
        raise ValueError("type2_ma: an input force of zero has no mechanical advantage")
    return compliant_ma(rigid_ma, compliance_force, forces)


@dataclass(frozen=True)
class Type3Point:
    """Equilibrium of a mechanism pressing a work piece of stiffness k_w: input coordinate q, output
    travel s past first contact, output force F_o = k_w s and MA = F_o / F_i."""

    q: float
    travel: float
    output_force: float
    ma: float


def type3_equilibrium(
    input_force: float,
    d_in: float,
    stiffness: float,
    compliance_torque: Callable[[float], float],
    travel: Callable[[float], float],
    q_contact: float,
    q_limit: float,
) -> Type3Point:
    """Type 3 MA: the input torque F_i d_i rotates the input link from first contact (q_contact, where
    travel = 0) against the springs (T_c) and a work piece of stiffness k_w on the output port:
    F_i d_i = T_c(q) + k_w s(q) s'(q) (virtual work), s' by central differences; solved for q between
    q_contact and q_limit (Brent).  Raises ValueError when no equilibrium lies in that range."""
    h = 1e-6 * max(abs(q_limit - q_contact), 1e-9)

    def rate(q: float) -> float:
        return (travel(q + h) - travel(q - h)) / (2.0 * h)

    def unbalanced(q: float) -> float:
        return input_force * d_in - compliance_torque(q) - stiffness * travel(q) * rate(q)

    r0, r1 = unbalanced(q_contact), unbalanced(q_limit)
    if not (math.isfinite(r0) and math.isfinite(r1)) or r0 * r1 > 0.0:
        raise ValueError(
            f"type3_equilibrium: no equilibrium between q = {q_contact:.6g} and {q_limit:.6g} "
            f"(unbalanced torque {r0:.4g} and {r1:.4g})"
        )
    q: float = brentq(unbalanced, q_contact, q_limit, xtol=1e-14)
    s = travel(q)
    return Type3Point(q, s, stiffness * s, stiffness * s / input_force)
