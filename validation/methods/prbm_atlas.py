"""The PRBM adapter's applicability flags from the error atlas (``validation.atlas``).

A segment case's levels are put in the atlas's terms: the atlas model that is the model the adapter
ran, and its dimensionless inputs (load angle, F L^2/EI, M L/EI, moment ratio M/(F L), follower angle,
kappa0 = L/R), mirrored into the half-plane the atlas maps (a load with P < 0 is the mirror image about
the undeformed axis of one with P > 0: the fits are read at -n, the tip lands at -b).  Each level gets
the atlas's expected tip error (% of L, ``MethodRun.expected_error``), and a level outside the model's
5 % region or outside the mapped inputs is flagged ``Applicability.OUTSIDE_VALIDITY`` with the reason in
its message.  A model the atlas does not map (a curved segment with an end moment, a family the curved
atlas was not built with) gets no expected error, and the run's message says so.
"""

from __future__ import annotations

import math

from validation.atlas.expected import expectation
from validation.methods.base import Applicability, MethodRun

_FAMILY_MODEL = {
    "pauly-midha": "fixed_pinned_pauly_midha",
    "howell": "fixed_pinned_howell",
    "constant": "fixed_pinned_constant",
}


def half_plane(Fx: float, Fy: float, M: float = 0.0, kappa0: float = 0.0) -> tuple[float, float, float, float, float]:
    """The level as the atlas maps it, (F_x, F_y, M, kappa0, sign): a segment curved the other way as the
    mirror image about the undeformed axis of one curved this way, then a force with P < 0 (or, without a
    transverse force, a clockwise moment) as the mirror image of one with P > 0; ``sign`` is -1 where the
    level was mirrored an odd number of times (its y and angles change sign), else 1."""
    sign = 1.0
    if kappa0 < 0.0:
        kappa0, Fy, M, sign = -kappa0, -Fy, -M, -sign
    if Fy < 0.0 or (Fy == 0.0 and M < 0.0):
        Fy, M, sign = -Fy, -M, -sign
    return Fx, Fy, M, kappa0, sign


def atlas_inputs(
    boundary: str, kappa0: float, family: str, Fx: float, Fy: float, M: float, follower: bool, L: float, EI: float
) -> tuple[str | None, dict[str, float], float]:
    """(atlas model, its inputs, the mirror sign of ``half_plane``) of one level of a segment case; the model
    None and no inputs where the atlas has no model."""
    fx, fy, m, kappa0, sign = half_plane(Fx, Fy, M, kappa0)
    F = math.hypot(fx, fy)
    force = F * L * L / EI
    angle = math.degrees(math.atan2(fy, fx)) if F > 0 else 90.0
    free = boundary in ("fixed-free", "fixed-pinned")
    if follower:
        return (
            ("follower", {"follower_angle_deg": angle, "load": force}, sign)
            if free and kappa0 == 0.0
            else (None, {}, sign)
        )
    if kappa0 != 0.0:
        if not free or M != 0.0 or family != "pauly-midha":
            return None, {}, sign
        return "curved_fixed_pinned", {"kappa0": kappa0, "load_angle_deg": angle, "load": force}, sign
    if M != 0.0 and F == 0.0:
        return ("pure_moment", {"load": m * L / EI}, sign) if free else (None, {}, sign)
    if M != 0.0:
        if family != "pauly-midha":
            return None, {}, sign
        return "force_moment", {"moment_ratio": m / (F * L), "load_angle_deg": angle, "load": force}, sign
    if free:
        return _FAMILY_MODEL.get(family), {"load_angle_deg": angle, "load": force}, sign
    if family == "pauly-midha":
        return "fixed_guided", {"load_angle_deg": angle, "load": force}, sign
    return None, {}, sign


def flag_levels(
    info: MethodRun,
    boundary: str,
    kappa0: float,
    family: str,
    Fx: list[float],
    Fy: list[float],
    M: list[float],
    follower: bool,
    L: float,
    EI: float,
    prescribed: bool = False,
) -> None:
    """Set ``expected_error`` and the ``OUTSIDE_VALIDITY`` flags of every level of a segment-model run
    (module docstring).  ``prescribed``: the loads are those the PRBM found for a prescribed motion; the
    atlas's error is at equal load, so a tip-position comparison of the case is not what it predicts
    (``atlas_equal_load``)."""
    levels = {}
    for level, (fx, fy, m) in enumerate(zip(Fx, Fy, M)):
        levels[level] = atlas_inputs(boundary, kappa0, family, fx, fy, m, follower, L, EI)
    flag_atlas_levels(info, levels, equal_load=not prescribed)


def flag_atlas_levels(
    info: MethodRun, levels: dict[int, tuple[str | None, dict[str, float], float]], equal_load: bool = True
) -> None:
    """Per level (atlas model or None, its inputs, mirror sign): the expected error, and the flag and its
    reason where the level lies outside the model's 5 % region or outside the map.  A level of a model the
    atlas does not map gets no expected error and the run's message says so.  Each level's inputs (a dict
    of its own) are kept in ``extras['atlas_inputs']``."""
    extras = info.extras
    extras["atlas_equal_load"] = equal_load
    expected, messages = info.expected_error, info.level_messages
    unmapped = mapped = None
    # the levels in the atlas's terms, so that a measured error can be split as the atlas splits it
    atlas_inputs: dict[int, dict[str, float]] = {}
    atlas_mirror: dict[int, float] = {}
    for level, (model, inputs, mirror) in sorted(levels.items()):
        found = expectation(model, inputs) if model else None
        if found is None:
            unmapped = model or "this load on this segment"
            continue
        expected[level] = found.expected_error
        mapped = model
        atlas_inputs[level] = inputs
        atlas_mirror[level] = mirror
        if found.outside:
            info.flag(level, Applicability.OUTSIDE_VALIDITY)
            previous = messages.get(level, "")
            messages[level] = f"{previous}; {found.reason}" if previous else found.reason
    if mapped is not None:
        extras["atlas_model"] = mapped
        extras.setdefault("atlas_inputs", {}).update(atlas_inputs)
        extras.setdefault("atlas_mirror", {}).update(atlas_mirror)
    if unmapped is not None and not expected:
        extras["atlas_model"] = None
        note = f"the PRBM error atlas does not map {unmapped}: no expected error"
        info.message = f"{info.message}; {note}" if info.message else note


def theta_dependent_levels(
    fit: str, loads: list[tuple[float, float, float]], L: float, EI: float
) -> dict[int, tuple[str | None, dict[str, float], float]]:
    """The levels of a Theta-dependent K_Theta run (eq 51 or 52; end force only) in the atlas's terms."""
    model = {"51": "theta_dependent_51", "52": "theta_dependent_52"}.get(fit)
    out = {}
    for level, (fx, fy, m) in enumerate(loads):
        mx, my, _, _, sign = half_plane(fx, fy)
        out[level] = (
            model,
            {"load_angle_deg": math.degrees(math.atan2(my, mx)), "load": math.hypot(fx, fy) * L * L / EI},
            sign,
        )
    return out


def chain_levels(
    elements: int, distributed: list[tuple[float, float]], tip_loaded: bool, L: float, EI: float
) -> dict[int, tuple[str | None, dict[str, float], float]]:
    """The levels of a Chain Algorithm run under a uniform dead load (w_x, w_y) per length in the atlas's
    terms; the atlas maps 40 links under a distributed load alone, so a coarser chain or an added end load
    is not mapped (a finer chain errs less than the map says)."""
    model = "chain" if elements >= 40 and not tip_loaded else None
    out = {}
    for level, (wx, wy) in enumerate(distributed):
        mx, my, _, _, sign = half_plane(wx, wy)
        out[level] = (
            model,
            {"load_angle_deg": math.degrees(math.atan2(my, mx)), "load": math.hypot(wx, wy) * L**3 / EI},
            sign,
        )
    return out
