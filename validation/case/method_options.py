"""Each method's ``[methods.X]`` options as a typed model: a misspelled or unknown option is an error, and
so is a number outside its range.

The schema validates a case's options with the model of its method (``OPTIONS[name]``) and reports
the first problem as ``methods.<method>.<option>: <what is wrong>``; the case keeps the file's dict (the
cache key hashes it), and each adapter receives its method's model (``options_of``) and reads its fields,
so a default is written here and nowhere else. Adding an option to an adapter means adding it here
(``tests/validation/test_method_options.py`` checks that every option an adapter reads is declared).

Ranges: every number is finite and representable (``validation.case.strict``), a direction is longer than
1e-100; tolerances are fractions
(0 < rtol < 1: a residual tolerance of the load itself or more accepts any state); stiffness ratios lie
between 1 and 1e12 (a ratio past 1e12 of the stiffest beam leaves the stiffness matrix singular in
double precision); counts of work are bounded (``strict.Count``) and, for the meshes, by the case's
``[limits]`` (``validation.case.scale``). Options that depend on the case (per-level lists as long as the
load path, an option the method does not read for this case) are checked by ``validation.case.scale``.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, StrictBool, model_validator

from validation.case.strict import REPRESENTABLE, TINY, Count, Finite, Fraction, Index, NonNegative, Positive, Strict

PerLevel = Finite | list[Finite]  # one value for every level, or one per level
PositivePerLevel = Positive | list[Positive]
Ratio = Annotated[float, Field(ge=1.0, le=1e12, allow_inf_nan=False)]  # of two stiffnesses
ThicknessRatio = Annotated[float, Field(ge=1e-3, le=1.0, allow_inf_nan=False), REPRESENTABLE]
Degrees = Annotated[float, Field(ge=-360.0, le=360.0, allow_inf_nan=False), REPRESENTABLE]
Friction = Annotated[float, Field(ge=0.0, le=10.0, allow_inf_nan=False), REPRESENTABLE]
ContactAngle = Annotated[float, Field(ge=0.0, le=180.0, allow_inf_nan=False), REPRESENTABLE]
Vector = tuple[Finite, Finite]


def _nonzero(vector: tuple[float, float] | None, name: str) -> None:
    if vector is not None and math.hypot(*vector) < TINY:
        raise ValueError(f"'{name}' must not be the zero vector (its length is below 1e-100)")


class Options(Strict):
    """Base: unknown options are errors."""


class HeldOutputOptions(Options):
    """The mechanical advantage of a held output point, as the FEM computes it (and the PRBM network
    built from the geometry): the output's working direction or moment arm, the input load, the step."""

    direction: Vector | None = Field(
        default=None, description="the output force's direction (the working motion of a held output point)"
    )
    moment_arm: Positive | None = Field(
        default=None, description="d_o: the output is a held rotation at 'output'; F_o = its holding moment / d_o"
    )
    sense: Literal[1, -1] = Field(
        default=1,
        description="with moment_arm: +1 if the working motion of the output is counter-clockwise, -1 if clockwise",
    )
    input: Index | None = Field(default=None, description="index of the input load in [[loads]]")
    step: Fraction = Field(default=1e-4, description="tangent: input increment over its largest value")
    d_i: Positive | None = Field(default=None, description="input force distance, for an input moment")
    definition: Literal["tangent", "secant"] = "tangent"

    @model_validator(mode="after")
    def _direction(self) -> "HeldOutputOptions":
        _nonzero(self.direction, "direction")
        return self


class MechanicalAdvantageOptions(HeldOutputOptions):
    """``[methods.fem] ma``: the FEM's mechanical advantage (validation.methods.fem_outputs)."""

    output: str = Field(description="the held output point")


class SoftModeOptions(Options):
    """``[methods.fem] dof``: soft modes of the tangent condensed to actuation points (fem.soft_modes)."""

    points: list[str] = Field(min_length=1, description="actuation points (ux, uy, rz each)")
    ratio: Fraction = Field(default=1e-2, description="soft: stiffness below ratio x the members' largest EA/l")


class InverseOptions(Options):
    """``inverse``: the inverse tip problem (validation.methods.inverse_problem): per level the tip's y ``b``
    and absolute slope ``theta0_deg``, and exactly one of ``a``, ``n``, ``axial_load``, ``l1``."""

    b: PerLevel
    theta0_deg: PerLevel
    a: PerLevel | None = None
    n: PerLevel | None = None
    axial_load: PerLevel | None = None
    l1: PositivePerLevel | None = None
    I: Positive | None = None
    EI: Positive | None = None

    @model_validator(mode="after")
    def _one_tie(self) -> "InverseOptions":
        ties = [name for name in ("a", "n", "axial_load", "l1") if getattr(self, name) is not None]
        if len(ties) != 1:
            raise ValueError(f"give exactly one of a, n, axial_load, l1 (got {', '.join(ties) or 'none'})")
        return self


class FemInverseOptions(InverseOptions):
    """``[methods.fem] inverse``: as ``InverseOptions``, with the FEM's own mesh for this problem."""

    elements: Count | None = None
    richardson: bool | None = None
    tip_x: StrictBool = Field(default=False, description="the tip's x from the inverse solution (true or false)")


class FemSlfpOptions(Options):
    """``[methods.fem] slfp``: sprung joints built as small-length flexural pivots (validation.methods.slfp)."""

    length: Positive
    E: Positive
    thickness_ratio: ThicknessRatio = Field(
        default=0.1,
        description="flexure thickness over its length: at most 1 (thicker than long is no beam), at "
        "least 1e-3 (the width w = 12 I / t^3 of a thinner one is a plate a thousand times its length)",
    )


class FemOptions(Options):
    elements: Count = Field(default=16, description="elements per member")
    error_estimate: bool = Field(default=True, description="solve on n and 2n elements, report |u_2n - u_n|/3")
    richardson: bool = Field(default=False, description="report the Richardson-extrapolated value")
    tol: Positive | None = Field(default=None, description="refine until the estimate is below it")
    levels: Annotated[int, Field(ge=1, le=12)] = Field(default=2, description="meshes in the error estimate")
    max_refine: Count = Field(
        default=64,
        description="finest mesh of the estimate: at most max_refine x elements (the "
        "meshes are doubled until tol is met and the outputs are in the asymptotic range)",
    )
    rtol: Fraction = Field(default=1e-10, description="Newton residual tolerance")
    inextensible_ratio: Ratio = Field(default=1e6, description="EA L^2/EI when a section gives no area")
    rigid_ratio: Ratio = Field(default=1e6, description="stiffness of pinned rigid links over the stiffest beam")
    arc_length: Positive | None = None
    max_steps: Count | None = Field(
        default=None,
        description="limit load: steps of the continuation (none: the adapter's LIMIT_STEPS of its limit_control)",
    )
    limit_control: Literal["arclength", "displacement"] = "arclength"
    control_step: Positive | None = Field(
        default=None,
        description="limit load by displacement: the step (none: 0.005 x the model's characteristic length)",
    )
    inverse: FemInverseOptions | None = Field(
        default=None, description="inverse tip problem (validation.methods.inverse_problem)"
    )
    slfp: FemSlfpOptions | None = Field(
        default=None, description="sprung joints built as small-length flexural pivots (validation.methods.slfp)"
    )
    input_moment_at: str | None = Field(
        default=None, description="reach the prescribed displacement by a moment at this node"
    )
    zero_level: Index | None = Field(
        default=None, description="positions measured from this level's state (a scale zeroed under self-weight)"
    )
    ma: MechanicalAdvantageOptions | None = None
    dof: SoftModeOptions | None = None


class ElasticaOptions(Options):
    I: Positive | None = Field(default=None, description="replaces the section's second moment of area")
    EI: Positive | None = Field(default=None, description="replaces EI")
    rtol: Fraction | None = None
    tol: Fraction | None = None
    samples: Annotated[int, Field(ge=2, le=100_000)] = 41
    problem: Literal["inflection"] | None = None
    b: PerLevel | None = None
    theta0: PerLevel | None = None
    l1: PositivePerLevel | None = None
    inverse: InverseOptions | None = Field(
        default=None, description="inverse tip problem (validation.methods.inverse_problem)"
    )


class BcmOptions(Options):
    I: Positive | None = None
    EI: Positive | None = None


class OpenSeesOptions(Options):
    elements: Count = 16
    max_steps: Count = Field(default=2000, description="limit load: displacement-control steps at most")
    steps_per_level: Count = Field(default=1, description="load steps per load level (each halved on failure)")
    max_halvings: Annotated[int, Field(ge=0, le=40)] = Field(default=12, description="load-step halvings on failure")
    control_step: Positive | None = Field(
        default=None, description="limit load: the displacement step (none: 0.002 x the model's largest extent)"
    )
    rigid_ratio: Ratio = Field(default=1e6, description="stiffness of the rigid links' elements over the stiffest beam")


class PrbmMechanicalAdvantageOptions(HeldOutputOptions):
    """``[methods.prbm] ma``: chapter 7's mechanical advantage of a hand-given four-bar or slider ([bapat2015,
    eqs 190-206]: ``F_i``, ``d_i``, ``d_o``; with ``model = 'compliance'`` the two-port four-bar's ``d_in``,
    ``d_out2``, ``d_out3``, ``location_deg``), or, for the network built from the geometry, the FEM's
    ``output``, ``direction``, ``input``, ``step``, ``definition``. ``F_i`` is an input force the MA divides
    by; a positive magnitude, not tiny against the model's springs (``validation.case.scale``)."""

    type: Literal[1, 2] | None = Field(default=None, description="the seed's MA type (1: one input and output)")
    model: Literal["compliance"] | None = None
    F_i: PositivePerLevel | None = None
    d_o: Positive | None = None
    d_in: Positive | None = None
    d_out2: Positive | None = None
    d_out3: Positive | None = None
    location_deg: Degrees | None = None
    rigid_body: str | None = Field(default=None, description="the equation of the rigid-body MA, for the reader")
    compliance: str | None = Field(default=None, description="the equation of the compliance term, for the reader")
    output: str | None = None


class FourBarSlfpOptions(Options):
    """``[methods.prbm] slfp``: the four-bar's small-length flexural pivots, k_i = E w t_i^3 / (12 l_i)
    [bapat2015, eq 186], and the rigid lengths beside them (for the reader)."""

    width: Positive
    t: list[Positive] = Field(min_length=1, max_length=4)
    l: list[Positive] = Field(min_length=1, max_length=4)
    L2: Positive | None = None
    L4: Positive | None = None

    @model_validator(mode="after")
    def _pairs(self) -> "FourBarSlfpOptions":
        if len(self.t) != len(self.l):
            raise ValueError(f"'t' has {len(self.t)} thicknesses for {len(self.l)} lengths 'l'")
        return self


class BeamRuleOptions(Options):
    """One beam's entry of ``rules.beams`` (prbm.builder.BeamRule)."""

    model: str | None = None
    gamma: Fraction | None = None
    K_theta: Positive | None = None
    stiffness: NonNegative | None = None
    clamp: str | None = None


class RulesOptions(Options):
    """``[methods.prbm] rules``: the PRB builder's rules (validation.methods.prbm_network.rules)."""

    gamma: Fraction | None = None
    K_theta: Positive | None = None
    slfp_ratio: Positive | None = None
    beams: dict[str, BeamRuleOptions] | None = None
    fixed_guided_fits: StrictBool = Field(
        default=False,
        description="give each fixed-guided beam gamma(n), K_Theta(n) of the Pauly-Midha fits at its own end-load "
        "ratio n, iterated level by level to the n the PRB model's solve gives (else gamma = 0.85, K_Theta = 2.65, "
        "as the seeds' fixed-guided PRBM)",
    )


DesignValue = Finite | list[Finite] | list[list[Finite]] | str


class PrecisionOptions(Options):
    """``[methods.prbm] precision``: the four-bar's precision positions [bapat2015, chs. 5-7]. ``phi`` (input
    rotations) or ``psi`` (output rotations) from position 1, in degrees, one per level, drive the PRB four-bar
    when no load does (validation.methods.prbm_fourbar); the others are the synthesis data, for the reader."""

    phi: list[Finite] | None = None
    psi: list[Finite] | None = None
    gamma: list[Finite] | None = None
    delta: list[Vector] | None = None
    theta1: Finite | None = None
    theta21: Finite | None = None
    theta31: Finite | None = None
    theta41: Finite | None = None
    offset: Finite | None = None
    dx: Finite | None = None
    R2: Positive | None = None
    delta2: Vector | None = None
    phi2: Finite | None = None
    gamma2: Finite | None = None


class PrbmOptions(Options):
    family: Literal["pauly-midha", "howell", "constant"] = "pauly-midha"
    extrapolate: Literal["raise", "warn", "allow"] = "raise"
    friction_mu: Friction = 0.0
    contact_angle_deg: ContactAngle = 0.0
    # chapter-3 fixed-guided segment with an inflection point
    problem: Literal["loads", "displacement"] = "loads"
    prefer: str | dict[str, Finite] = "energy"
    a: PerLevel | None = None
    b: PerLevel | None = None
    n: PerLevel | None = None
    l1: PositivePerLevel | None = None
    theta0_deg: PerLevel | None = None
    # mechanisms
    links: dict[str, Vector] | None = None
    springs: dict[str, NonNegative] | None = Field(
        default=None, description="torsion springs k1..k4 (torque/rad) and the slider's f_k: finite and not negative"
    )
    spring_joints: dict[str, str] | None = None
    slfp: FourBarSlfpOptions | None = None
    energy_free: dict[str, Finite] | None = None
    precision: PrecisionOptions | None = None
    free_levels: list[Index] = Field(default_factory=list)
    drive: Literal["torque", "precision"] | None = None
    coupler_point: str = "P"
    origin: Vector = (0.0, 0.0)
    ma: PrbmMechanicalAdvantageOptions | None = Field(
        default=None,
        description="four-bar: {F_i, d_i, d_o} (eqs 190, 192); network: as [methods.fem] ma, "
        "{output, direction, input, step, d_i, definition}",
    )
    max_mode: Annotated[int, Field(ge=1, le=10)] = 2
    segment_model: Literal["inflection", "fixed-pinned", "fixed-free"] | None = None
    model: Literal["network", "chain", "theta-dependent", "lyon", "feasible-l1"] | None = Field(
        default=None,
        description="'network': solve a mechanism by the general network built from the geometry even "
        "where a special path applies; 'chain', 'theta-dependent', 'lyon': seed 000 chapter 2's other segment models, "
        "'feasible-l1': section 3.6's vector loop "
        "(validation.methods.prbm_alternatives). A load along a segment without a model takes the chain, its "
        "elements chosen for chain_tol; any model but 'chain' there is refused",
    )
    theta_fit: Literal["51", "52", "52-tension"] = Field(
        default="51", description="K_Theta(n, Theta) of seed 000 eq (51) or (52) for model = 'theta-dependent'"
    )
    chain_elements: Count = Field(
        default=40,
        description="Chain Algorithm elements (section 3.4 used 40); on a load "
        "along the segment without a model, fixes the count the adapter would choose",
    )
    chain_steps: Count = Field(default=10, description="Chain Algorithm load (or displacement) increments")
    chain_tol: Fraction = Field(
        default=1e-3,
        description="a load along the segment without a model: the Chain "
        "Algorithm's elements are doubled from 10 until two successive chains' tips differ by "
        "less than chain_tol x L at every level (validation.methods.prbm_readings.chain_count)",
    )
    zero_level: Index | None = Field(
        default=None, description="positions measured from this level's state, as the FEM option (prbm_readings)"
    )
    rules: RulesOptions | None = Field(
        default=None, description="the PRB builder's rules (validation.methods.prbm_network.rules)"
    )
    # the dissertation's synthesis data (chapters 5-7), kept beside the model for the reader and the synthesis;
    # the forward PRBM does not read them, but they are held to the same ranges
    input: str | None = None
    T: list[Finite] | None = None
    U: list[Finite] | None = None
    F: list[Finite] | None = None
    E: Positive | None = None
    EI: dict[str, Positive] | Positive | None = None
    fixed_guided: dict[str, Positive] | None = None
    theta1: Finite | None = None
    theta5: Finite | None = None
    R5: Finite | None = None
    R6: Finite | None = None
    d1: Finite | None = None
    d2: Finite | None = None
    n1: list[Finite] | None = None
    gamma: list[Finite] | None = None
    delta: list[list[Finite]] | None = None
    segments: list[dict[str, DesignValue]] | None = None

    def spring(self, name: str) -> float:
        """The torsion spring ``name`` (k1..k4) or the slider's ``f_k``; one the case does not give is none (0)."""
        return (self.springs or {}).get(name, 0.0)


OPTIONS: dict[str, type[Options]] = {
    "fem": FemOptions,
    "elastica": ElasticaOptions,
    "bcm": BcmOptions,
    "opensees": OpenSeesOptions,
    "prbm": PrbmOptions,
}


def options_of(method: str, given: dict | None) -> Options:
    """The options of ``[methods.<method>]`` as its method's model, every option not given at its default."""
    return OPTIONS[method].model_validate(given or {})
