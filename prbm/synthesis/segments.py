"""Compliant segments realising PRBM torsional springs: dimensions from k, and a stress check.

[bapat2015]:

* small-length flexural pivot (SLFP), eq. (72)/(186): k = E I / l, the pivot at the middle of the
  flexure (71), so l/2 + L + l/2 = R with the flexure length l = f L (Example 1 of section 6.7:
  f = 0.05); stress sigma = M t / (2 I) with M = k Delta-beta (186);
* fixed-pinned segment, eq. (187): k = gamma K_Theta E I / l with gamma l = R;
* fixed-guided segment (two equal springs), eq. (188): k = 2 gamma K_Theta E I / l with gamma l = R.

For the fixed-pinned and fixed-guided segments the stress is estimated the same way, from the spring
torque M = k Delta-beta and sigma = M c / I -- a PRBM estimate, not the clamp moment of the elastica.
A rectangular section of width w gives t = (12 I / w)^(1/3) and c = t/2.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class SegmentDesign:
    """One sized segment: its type, the springs it realises, and its dimensions (consistent units)."""

    kind: str  # 'slfp', 'fixed-pinned' or 'fixed-guided'
    link: str  # PRB link it lies along, e.g. 'Z2'
    springs: list[int]
    k: float  # spring constant of each of its springs
    E: float
    width: float
    length: float  # flexible length l
    I: float
    thickness: float
    rigid_length: float = 0.0  # L of an SLFP link, 0 otherwise
    gamma: float | None = None
    K_theta: float | None = None
    max_moment: float = 0.0
    max_stress: float = 0.0

    def stress(self, moment: float) -> float:
        """sigma = M c / I with c = t/2 (0 for a spring of zero stiffness: no segment)."""
        return 0.0 if self.I == 0 else abs(moment) * self.thickness / (2.0 * self.I)


def rectangle_thickness(I: float, width: float) -> float:
    thickness: float = (12.0 * I / width) ** (1.0 / 3.0)
    return thickness


def slfp(
    k: float,
    *,
    R: float,
    E: float,
    width: float,
    fraction: float = 0.05,
    link: str = "",
    springs: list[int] | None = None,
) -> SegmentDesign:
    """SLFP on a PRB link of length R: L = R / (1 + f), l = f L; I = k l / E (eq. 186)."""
    L = R / (1.0 + fraction)
    l = fraction * L
    I = k * l / E
    return SegmentDesign("slfp", link, springs or [], k, E, width, l, I, rectangle_thickness(I, width), rigid_length=L)


def fixed_pinned(
    k: float,
    *,
    R: float,
    E: float,
    width: float,
    gamma: float,
    K_theta: float,
    link: str = "",
    springs: list[int] | None = None,
) -> SegmentDesign:
    """Fixed-pinned segment: l = R / gamma, I = k l / (gamma K_Theta E) (eq. 187)."""
    l = R / gamma
    I = k * l / (gamma * K_theta * E)
    return SegmentDesign(
        "fixed-pinned",
        link,
        springs or [],
        k,
        E,
        width,
        l,
        I,
        rectangle_thickness(I, width),
        gamma=gamma,
        K_theta=K_theta,
    )


def fixed_guided(
    k: float,
    *,
    R: float,
    E: float,
    width: float,
    gamma: float,
    K_theta: float,
    link: str = "",
    springs: list[int] | None = None,
) -> SegmentDesign:
    """Fixed-guided segment (two springs k): l = R / gamma, I = k l / (2 gamma K_Theta E) (eq. 188)."""
    l = R / gamma
    I = k * l / (2.0 * gamma * K_theta * E)
    return SegmentDesign(
        "fixed-guided",
        link,
        springs or [],
        k,
        E,
        width,
        l,
        I,
        rectangle_thickness(I, width),
        gamma=gamma,
        K_theta=K_theta,
    )


def slfp_stress_from_k(
    k: float, delta_beta: float, *, R: float, E: float, width: float, fraction: float = 0.05
) -> float:
    """sigma = M t / (2 I) of the SLFP realising k at spring rotation delta_beta (rad): used as a
    constraint while k is still unknown (t and I both depend on k)."""
    seg = slfp(k, R=R, E=E, width=width, fraction=fraction)
    return seg.stress(k * delta_beta)
