"""The ranges of a case that depend on its own scale, and the bounds on the work it asks for, checked on
the whole case before any solve (``schema.Case`` lists every problem as ``field: what is wrong``).

Each field alone is already finite and representable (``validation.case.strict``); here the numbers are
judged against each other, in the non-dimensional groups the mechanics is written in:

- stiffness: EI and EA of every beam are finite and positive once multiplied out (E w t^3 / 12 can
  underflow where each factor is representable), and the slenderness EA L^2 / EI (12 (L/t)^2 for a
  rectangle) is at most ``SLENDERNESS_MAX`` = 1e12: past it the axial and bending stiffnesses of one
  element differ by more than double precision resolves in a stiffness matrix (the shipped cases reach
  1e10). A stubby beam (a small ratio) is solvable, so it is not refused;
- curvature: a segment's arc is at most one full turn (|kappa| L <= 2 pi: longer, the beam runs through
  itself), and a mechanism beam's arc must pass through both its nodes (|kappa| chord <= 2);
- loads: the non-dimensional load of each level (``nondimensional_load``) is at most ``LOAD_LIMIT`` =
  1e4: P L^2/EI, M L/EI, w L^3/EI with the stiffest beam's EI and L (a mechanism without beams: its
  stiffest torsion spring k, with P L/k, M/k). Past 1e4 the bending is confined to a boundary layer
  sqrt(EI/P) of 1 % of L at the clamp, which no method of the harness resolves (the exact elastica's
  continuation already stalls near 1e2, the shipped cases reach 47); a modulus of 1e-300 gives 1e300.
  A prescribed displacement is at most ``DISPLACEMENT_LIMIT`` = 10 characteristic lengths, a prescribed
  rotation at most ``ROTATION_LIMIT`` = 3600 degrees (ten turns);
- tolerances: a length tolerance is shorter than the characteristic length, an angle tolerance smaller
  than 180 degrees (either larger accepts any position or direction);
- an input force the PRBM's mechanical advantage divides by (``[methods.prbm] ma.F_i``): its torque
  F_i d_i is at least ``INPUT_FORCE_FLOOR`` = 1e-6 of the stiffest spring's torque per radian (the
  compliance term T_c/(F_i d_i) of eq 192 is then at most ~1e6 per radian turned; F_i = 1e-300 gave an
  MA of -1.4e301);
- per-level options (lists) have one value per load level; an inverse problem needs a clamped segment
  and its inflection point l1 inside it; a level an option names exists; a hand-given PRB four-bar's
  loop closes (|Z2 + Z3 - Z1 - Z4| within 1 % of its longest link, ``prbm.FourBar``'s rule);
- bounded work (``[limits]``, ``schema.Limits``): load levels per load at most ``limits.levels``, elements
  of the finest mesh a method may solve at most ``limits.elements``; both checked before any level list
  or mesh is built, so a ramp of 10^7 levels is refused at once.
"""

from __future__ import annotations

import math
from typing import Any, Iterator

from validation.case.capabilities import QUANTITIES
from validation.case.method_options import OPTIONS, FemOptions, OpenSeesOptions, PrbmOptions

SLENDERNESS_MAX = 1e12
LOAD_LIMIT = 1e4
DISPLACEMENT_LIMIT = 10.0
ROTATION_LIMIT = 3600.0
ANGLE_TOLERANCE = 180.0
INPUT_FORCE_FLOOR = 1e-6
LOOP_TOLERANCE = 0.01  # prbm.mechanisms.LOOP_TOLERANCE (not imported: it would load scipy into every ``list``)

# the options whose list values are one per load level
PER_LEVEL = {"elastica": ("b", "theta0", "l1"), "prbm": ("a", "b", "n", "l1", "theta0_deg")}
INVERSE_PER_LEVEL = ("b", "theta0_deg", "a", "n", "axial_load", "l1")


def characteristic_length(case) -> float:
    """The length errors are normalised by: the segment's length, or the mechanism's extent."""
    if case.segment is not None:
        return case.segment.length
    xs = [n.x for n in case.mechanism.nodes]
    ys = [n.y for n in case.mechanism.nodes]
    return max(max(xs) - min(xs), max(ys) - min(ys)) or 1.0


def load_count(load) -> int:
    """Levels of a load, without building them (a ramp's count, or its list's length)."""
    return load.ramp.count if load.ramp is not None else len(load.values)


def work_problems(case) -> list[str]:
    """The load levels over ``limits.levels`` (checked first: nothing else may build the levels then)."""
    limit = case.limits.levels
    out = []
    for i, load in enumerate(case.loads):
        count = load_count(load)
        if count > limit:
            where = f"loads.{i}.ramp.count" if load.ramp is not None else f"loads.{i}.values"
            out.append(
                f"{where}: {count} load levels exceed the limit of {limit} (limits.levels; raise it in "
                "[limits] if the case needs more)"
            )
    return out


def _beams(case) -> Iterator[tuple[str, float, float, float, float, Any]]:
    """(field, length (a beam's chord), EI, EA, curvature, section) of the segment or of every beam."""
    if case.segment is not None:
        seg = case.segment
        EA, EI = seg.section.stiffness(seg.E)
        yield "segment", seg.length, EI, EA, seg.initial_curvature(), seg.section
        return
    mech = case.mechanism
    nodes = {n.name: (n.x, n.y) for n in mech.nodes}
    for i, beam in enumerate(mech.beams):
        (ax, ay), (bx, by) = nodes[beam.start], nodes[beam.end]
        EA, EI = beam.section.stiffness(beam.E if beam.E is not None else mech.E)
        yield f"mechanism.beams.{i}", math.hypot(bx - ax, by - ay), EI, EA, beam.curvature, beam.section


def stiffness_problems(case) -> list[str]:
    """EI, EA finite and positive; slenderness in range; arcs that exist (module docstring)."""
    out = []
    for field, length, EI, EA, kappa, _ in _beams(case):
        if not (0.0 < EI < math.inf):
            out.append(
                f"{field}.section: the bending stiffness EI = {EI:g} is not a positive finite number "
                "(the product of the modulus and the section's dimensions under- or overflows)"
            )
            continue
        if not math.isnan(EA):
            ratio = EA * length**2 / EI
            if not (0.0 < EA < math.inf) or not ratio <= SLENDERNESS_MAX:
                out.append(
                    f"{field}.section: slenderness EA L^2/EI = {ratio:.3g} above {SLENDERNESS_MAX:g}: the "
                    "stiffness matrix cannot resolve bending beside stretching (is A or I in another unit?)"
                )
        if field == "segment" and abs(kappa) * length > 2.0 * math.pi:
            name = "radius" if case.segment.radius is not None else "curvature"
            out.append(
                f"segment.{name}: the arc turns {math.degrees(abs(kappa) * length):.4g} degrees, more than "
                "one full turn (|curvature| x length <= 2 pi): the segment would run through itself"
            )
        elif field != "segment" and abs(kappa) * length > 2.0:
            out.append(
                f"{field}.curvature: no circular arc of curvature {kappa:g} joins nodes {length:g} apart "
                "(|curvature| x chord <= 2)"
            )
    return out


def stiffness_scales(case) -> dict[str, float] | None:
    """The stiffest beam's EI/L^2 (force), EI/L (moment) and EI/L^3 (force per length), or the stiffest
    torsion spring's k/L, k and k/L^2 (L the mechanism's extent); None where the case has neither."""
    beams = [(length, EI) for _, length, EI, _, _, _ in _beams(case) if 0.0 < EI < math.inf and length > 0.0]
    if beams:
        return {
            "force": max(EI / L**2 for L, EI in beams),
            "moment": max(EI / L for L, EI in beams),
            "distributed": max(EI / L**3 for L, EI in beams),
        }
    springs = [j.spring for j in case.mechanism.joints] if case.mechanism is not None else []
    k = max(springs, default=0.0)
    if k <= 0.0:
        return None
    L = characteristic_length(case)
    return {"force": k / L, "moment": k, "distributed": k / L**2}


def nondimensional_load(case, load, scales: dict[str, float]) -> tuple[float, str] | None:
    """The largest non-dimensional magnitude of a load over its levels and its formula, or None for
    a load whose kind has no stiffness scale (prescribed motions are judged on lengths and angles);
    the direction is a unit vector (``LoadSpec``), so a value is the magnitude."""
    largest = max((abs(v) for v in load.levels()), default=0.0)
    if load.kind == "force":
        return largest / scales["force"], "P L^2/EI"
    if load.kind == "moment":
        return largest / scales["moment"], "M L/EI"
    if load.kind == "distributed":
        return largest / scales["distributed"], "w L^3/EI"
    if load.kind == "self_weight":
        sections = [s for f, _, _, _, _, s in _beams(case)]
        weight = max((s.weight_per_length() or 0.0 for s in sections), default=0.0)
        return largest * weight / scales["distributed"], "q L^3/EI (the weight per length q)"
    return None


def load_problems(case) -> list[str]:
    """Every load inside its non-dimensional range (module docstring)."""
    out = []
    scales = stiffness_scales(case)
    length = characteristic_length(case)
    for i, load in enumerate(case.loads):
        where = f"loads.{i}.{'ramp' if load.ramp is not None else 'values'}"
        largest = max((abs(v) for v in load.levels()), default=0.0)
        if load.kind == "displacement" and largest > DISPLACEMENT_LIMIT * length:
            out.append(
                f"{where}: a prescribed displacement of {largest:g} is more than {DISPLACEMENT_LIMIT:g} "
                f"times the characteristic length {length:g}"
            )
        elif load.kind == "rotation" and largest > ROTATION_LIMIT:
            out.append(
                f"{where}: a prescribed rotation of {largest:g} degrees is more than {ROTATION_LIMIT:g} (ten turns)"
            )
        elif scales is not None:
            measure = nondimensional_load(case, load, scales)
            if measure is not None and not measure[0] <= LOAD_LIMIT:
                out.append(
                    f"{where}: non-dimensional load {measure[1]} = {measure[0]:.3g} with the stiffest "
                    f"beam (or spring), above {LOAD_LIMIT:g}: the bending would be confined to the "
                    "first ~1 % of the beam, which no method resolves (is the modulus, a section "
                    "dimension or the load's unit wrong?)"
                )
    return out


def tolerance_problems(case) -> list[str]:
    """Length and angle tolerances smaller than what accepts any position or direction."""
    from_quantity = {name: q.dimension for name, q in QUANTITIES.items()}
    length = characteristic_length(case)
    out = []

    def judge(where: str, quantity: str, tolerance) -> None:
        if tolerance is None or tolerance.abs is None:
            return
        dimension = from_quantity.get(quantity)
        if dimension == "length" and tolerance.abs >= length:
            out.append(
                f"{where}.abs: {tolerance.abs:g} is not shorter than the characteristic length {length:g}: "
                "it accepts any position"
            )
        elif dimension == "deg" and tolerance.abs >= ANGLE_TOLERANCE:
            out.append(f"{where}.abs: {tolerance.abs:g} degrees accepts any direction (at most {ANGLE_TOLERANCE:g})")

    for i, ref in enumerate(case.references):
        judge(f"references.{i}.tolerance", ref.quantity, ref.tolerance)
        if ref.finding is not None:
            judge(f"references.{i}.finding.tolerance", ref.quantity, ref.finding.tolerance)
    for i, agreement in enumerate(case.agreements):
        for quantity in agreement.quantities:
            judge(f"agreements.{i}.tolerance", quantity, agreement.tolerance)
    return out


def element_count(case) -> list[tuple[str, int]]:
    """(option field, elements of the finest mesh it makes a method solve) for each meshing method: the FEM's
    elements per member x its finest refinement x members, the OpenSees peer's, the PRBM's Chain Algorithm."""
    members = (
        1
        if case.segment is not None
        else max(1, len(case.mechanism.beams)) + sum(1 for j in case.mechanism.joints if j.spring > 0)
    )
    counts = []
    for method, raw in case.methods.items():
        model = OPTIONS.get(method)
        if model is None:
            continue
        options = model.model_validate(raw or {})
        if isinstance(options, FemOptions):
            refine = (
                max(2 ** (options.levels - 1), options.max_refine) if (options.error_estimate or options.tol) else 1
            )
            finest = [options.elements * refine, 2 * options.elements]
            if options.inverse is not None and options.inverse.elements is not None:
                finest.append(options.inverse.elements * refine)
            counts.append(("methods.fem.elements", members * max(finest)))
        elif isinstance(options, OpenSeesOptions):
            counts.append(("methods.opensees.elements", members * options.elements))
        elif isinstance(options, PrbmOptions):
            counts.append(("methods.prbm.chain_elements", options.chain_elements))
    return counts


def mesh_problems(case) -> list[str]:
    """Meshes over ``limits.elements``."""
    limit = case.limits.elements
    return [
        f"{field}: the finest mesh has {count} elements, over the limit of {limit} (limits.elements; the FEM "
        "counts elements per member x its finest refinement (levels, max_refine) x members)"
        for field, count in element_count(case)
        if count > limit
    ]


def option_problems(case) -> list[str]:
    """Per-level option lists as long as the load path, inverse problems a segment can pose, levels that
    exist, the PRBM input force against the springs (module docstring)."""
    n = case.n_levels()
    out = []
    for method, names in PER_LEVEL.items():
        options = case.methods.get(method) or {}
        out += _per_level(f"methods.{method}", options, names, n)
    for method in ("fem", "elastica"):
        inverse = (case.methods.get(method) or {}).get("inverse")
        if inverse is not None:
            out += _inverse(case, f"methods.{method}.inverse", inverse, n)
    for method in ("fem", "prbm"):
        zero = (case.methods.get(method) or {}).get("zero_level")
        if zero is not None and zero >= n:
            out.append(f"methods.{method}.zero_level: level {zero}, but the case has {n} load levels")
    prbm = case.methods.get("prbm") or {}
    out += _four_bar_loop(prbm.get("links") or {})
    if prbm.get("ma"):
        out += _per_level("methods.prbm.ma", prbm["ma"], ("F_i",), n) + _input_force(case, prbm["ma"])
    if prbm.get("precision") and _driven_by_precision(case, prbm):
        out += _per_level("methods.prbm.precision", prbm["precision"], ("phi", "psi"), n)
    out += [
        f"methods.prbm.free_levels: level {lv}, but the case has {n} load levels"
        for lv in prbm.get("free_levels", [])
        if lv >= n
    ]
    return out


def _four_bar_loop(links: dict) -> list[str]:
    """The hand-given PRB four-bar closes: |Z2 + Z3 - Z1 - Z4| within ``LOOP_TOLERANCE`` of its longest link
    (prbm.FourBar's own rule, which would otherwise refuse it in the solve)."""
    if not {"r1", "r2", "r3", "r4"} <= set(links):
        return []
    Z1, Z2, Z3, Z4 = (complex(*links[k]) for k in ("r1", "r2", "r3", "r4"))
    error, longest = abs(Z2 + Z3 - Z1 - Z4), max(abs(Z1), abs(Z2), abs(Z3), abs(Z4))
    if error > LOOP_TOLERANCE * longest:
        return [
            f"methods.prbm.links: the four-bar loop Z2 + Z3 = Z1 + Z4 does not close: |Z2 + Z3 - Z1 - Z4| = "
            f"{error:.4g}, more than {LOOP_TOLERANCE:.0%} of the longest link ({longest:.4g})"
        ]
    return []


def _driven_by_precision(case, options: dict) -> bool:
    """The PRB four-bar is driven through its precision positions (phi or psi per level): ``drive =
    'precision'``, or no drive given and no moment or force to drive it (validation.methods.prbm_fourbar)."""
    if "drive" in options:
        return options["drive"] == "precision"
    return not any(load.kind in ("moment", "force") for load in case.loads)


def _per_level(where: str, options: dict, names: tuple[str, ...], n: int) -> list[str]:
    return [
        f"{where}.{name}: {len(options[name])} values for {n} load levels (give one per level, or one number)"
        for name in names
        if isinstance(options.get(name), list) and len(options[name]) != n
    ]


def _inverse(case, where: str, inverse: dict, n: int) -> list[str]:
    if case.segment is None:
        return [f"{where}: the inverse tip problem is posed on a single segment, not a mechanism"]
    if case.segment.boundary == "pinned-pinned":
        return [f"{where}: the inverse tip problem needs a segment clamped at its root (boundary is pinned-pinned)"]
    out = _per_level(where, inverse, INVERSE_PER_LEVEL, n)
    l1 = inverse.get("l1")
    values = l1 if isinstance(l1, list) else [l1] if l1 is not None else []
    if any(not 0.0 < v < case.segment.length for v in values):
        out.append(f"{where}.l1: the inflection point must lie inside the segment (0, {case.segment.length:g})")
    return out


def _input_force(case, ma: dict) -> list[str]:
    """F_i d_i at least INPUT_FORCE_FLOOR of the stiffest spring's torque per radian."""
    if "F_i" not in ma:
        return []
    forces = ma["F_i"] if isinstance(ma["F_i"], list) else [ma["F_i"]]
    arm = ma.get("d_i", ma.get("d_in"))
    springs = [float(v) for k, v in ((case.methods.get("prbm") or {}).get("springs") or {}).items() if k != "f_k"]
    if case.mechanism is not None:
        springs += [j.spring for j in case.mechanism.joints]
    stiffest = max(springs, default=0.0)
    if arm is None or stiffest <= 0.0 or not forces:
        return []
    torque = min(abs(float(f)) for f in forces) * float(arm)
    if torque < INPUT_FORCE_FLOOR * stiffest:
        return [
            f"methods.prbm.ma.F_i: the input torque F_i d_i = {torque:.3g} is below {INPUT_FORCE_FLOOR:g} of the "
            f"stiffest spring's {stiffest:.4g} per radian: the mechanical advantage 1 - T_c/(F_i d_i) would "
            "measure the springs, not the input (is F_i in the case's force unit?)"
        ]
    return []
