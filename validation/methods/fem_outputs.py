"""FEM outputs that the PRBM gives and that are not nodal fields: the largest bending stress, the number
of inflection points, and the mechanical advantage by a small increment of the input load.

- ``max_stress``: max over elements and layers of |E (N/EA +- M c/EI)| (``FemResult.max_bending_stress``);
  needs sections that know E and the extreme-fibre distance c.
- ``inflection_points``: along each beam, the sign changes of the deformed curvature
  kappa = kappa0 + m/EI at the element nodes (m the bending moment), values below ``1e-3`` of the
  beam's largest |kappa| ignored (a free or pinned end, where m -> 0, is not an inflection); summed
  over the beams (rigid bars excluded).
- ``mechanical_advantage``: MA = d F_out / d F_in at each level, F_out the force the mechanism exerts
  on the held output point along ``direction`` (minus the support reaction), F_in the value of the
  input load; by a second solve with the input load raised by ``step`` x its largest value
  (``[methods.fem] ma = {output = "S", direction = [1, 0], input = 0, step = 1e-4}``; ``input`` is the
  index of the load in ``[[loads]]``, default the first force or moment). With a moment as input and
  ``d_i`` given, F_in = T/d_i (the Type 1 input force of [bapat2015, ch. 7], at distance d_i). ``definition =
  "secant"`` gives instead MA = F_out/F_in at each level, the ratio [bapat2015, eq 192] uses when the
  output is held at a prescribed position: the compliance of the mechanism then takes its share of
  the input (MA = MA_R (1 - F_c/F_i)), which the tangent ratio does not see.  The secant ratio is the
  sign convention of ``validation.case.quantities.MEANINGS['mechanical_advantage']``: F_in = |input load|
  (an input moment T counts as |T|/d_i), F_out along the working motion.
- An output held in rotation (a prescribed ``rotation`` of a link at the point ``output``: the work
  piece on a rocker at distance d_o): ``ma = {output = "OUT", moment_arm = d_o, sense = 1}``,
  F_out = -sense M_hold / d_o with M_hold the moment the prescribed rotation needs (the mechanism
  presses on the work piece with the opposite moment; sense +1 for a counter-clockwise working motion).
"""

from __future__ import annotations

import numpy as np

from validation.case.method_options import HeldOutputOptions, MechanicalAdvantageOptions, PrbmMechanicalAdvantageOptions
from validation.methods.base import NotApplicable

INFLECTION_FLOOR = 1e-3
_NO_MA = HeldOutputOptions()  # no ``ma`` table: every field at its default


def max_stress(result, level: int) -> float:
    value = float(result.max_bending_stress[level])
    if not np.isfinite(value):
        raise NotApplicable(
            "max_stress needs sections that know E and the extreme-fibre distance "
            "(a rectangle, layers, or inertia with 'c')"
        )
    return value


def inflection_points(result, model, beams: list[int], level: int) -> int:
    """Curvature sign changes along the members ``beams`` (indices into the model's members)."""
    d = result.extra["disc"]
    moments = result.extra["element_moments"][level]
    EI = np.array([sec.EI for sec in d.el_section])
    count = 0
    for im in beams:
        els = d.member_elements[im]
        m = np.concatenate([[-moments[els[0], 0]], moments[els, 1]])  # bending moment at the nodes
        EI_nodes = np.concatenate([[EI[els[0]]], EI[els]])
        kappa = model.members[im].curvature + m / EI_nodes
        significant = kappa[np.abs(kappa) > INFLECTION_FLOOR * np.abs(kappa).max(initial=0.0)]
        count += int(np.count_nonzero(np.diff(np.sign(significant))))
    return count


def input_load_index(case, ma: HeldOutputOptions | None) -> int:
    """The index in ``[[loads]]`` of the input load: ``ma.input``, else the first force or moment."""
    if ma is not None and ma.input is not None:
        if not 0 <= ma.input < len(case.loads) or case.loads[ma.input].kind not in ("force", "moment"):
            raise NotApplicable(f"ma.input = {ma.input} is not a force or moment load")
        return ma.input
    for index, load in enumerate(case.loads):
        if load.kind in ("force", "moment"):
            return index
    raise NotApplicable("mechanical_advantage needs an input force or moment load")


def incremented_case(case, ma: HeldOutputOptions | None):
    """The case with its input load raised by ``step`` times its largest value, and that increment."""
    index = input_load_index(case, ma)
    load = case.loads[index]
    levels = np.asarray(load.levels(), float)
    delta = (ma or _NO_MA).step * float(np.abs(levels).max(initial=0.0))
    if delta == 0.0:
        raise NotApplicable("the input load is zero at every level: no increment to take")
    raised = load.model_copy(update={"values": list(levels + delta), "ramp": None})
    loads = list(case.loads)
    loads[index] = raised
    return case.model_copy(update={"loads": loads}), delta, load


def output_force(
    case, ma: MechanicalAdvantageOptions | PrbmMechanicalAdvantageOptions | None, reaction_of
) -> np.ndarray:
    """Per level, the force the mechanism exerts on the output support along ``ma.direction``."""
    reaction_of = _converged_only(reaction_of)
    needs = (
        "mechanical_advantage needs [methods.fem] ma = {output = point, direction = [dx, dy]} "
        "or {output = point, moment_arm = d_o}"
    )
    if ma is None or ma.output is None:
        raise NotApplicable(needs)
    output = ma.output
    if ma.moment_arm is not None:
        return np.array([-ma.sense * reaction_of(output, level)[2] / ma.moment_arm for level in range(case.n_levels())])
    if ma.direction is None:
        raise NotApplicable(needs)
    d = np.asarray(ma.direction, float)
    d = d / np.hypot(*d)
    return -np.array([reaction_of(output, level)[:2] @ d for level in range(case.n_levels())])


def _converged_only(reaction_of):
    """``reaction_of`` that says which level the solve did not reach instead of an IndexError."""

    def reaction(point, level):
        try:
            return reaction_of(point, level)
        except IndexError:
            raise NotApplicable(
                f"mechanical_advantage: the FEM solve stopped before level {level} "
                "(no converged state to read the output force from)"
            ) from None

    return reaction


def _input_force(ma: HeldOutputOptions | None, input_load, load_values):
    if input_load.kind != "moment":
        return load_values
    if ma is None or ma.d_i is None:
        raise NotApplicable("an input moment needs ma.d_i (the input force's distance) for a force ratio")
    return load_values / ma.d_i


def mechanical_advantage(ma: HeldOutputOptions | None, base, raised, delta: float, input_load) -> np.ndarray:
    """Tangent MA per level from the output forces of the base and raised solves (arrays per level)."""
    return (raised - base) / _input_force(ma, input_load, delta)


def secant_mechanical_advantage(ma: HeldOutputOptions | None, base, input_load) -> np.ndarray:
    """F_out / F_in per level, F_in = |input load| (quantities.MEANINGS['mechanical_advantage']); NaN where
    the input load is zero (the caller leaves those out)."""
    f_in = np.abs(_input_force(ma, input_load, np.asarray(input_load.levels(), float)))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(f_in != 0.0, base / np.where(f_in != 0.0, f_in, 1.0), np.nan)
