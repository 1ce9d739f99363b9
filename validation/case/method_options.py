"""Each method's ``[methods.X]`` options as a typed model: a misspelled or unknown option is an error.

The schema validates a case's options with the model of its method (``OPTIONS[name]``) and reports
the first problem as ``methods.<method>.<option>: <what is wrong>``; the adapters still receive the
options as a plain dict (only the keys the file gives). Adding an option to an adapter means adding
it here (``tests/test_method_options.py`` checks that every option an adapter reads is declared).
"""
from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

from validation.case.strict import Positive, Strict

NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Count = Annotated[int, Field(ge=1)]
PerLevel = float | list[float]  # one value for every level, or one per level


class Options(Strict):
    """Base: unknown options are errors."""


class MechanicalAdvantageOptions(Options):
    """``[methods.fem] ma``: the FEM's mechanical advantage (validation.methods.fem_outputs)."""

    output: str = Field(description="the held output point")
    direction: tuple[float, float] | None = Field(None, description="the output force's direction "
                                                  "(the working motion of a held output point)")
    moment_arm: Positive | None = Field(None, description="d_o: the output is a held rotation at 'output'; "
                                        "F_o = its holding moment / d_o")
    sense: Literal[1, -1] = Field(1, description="with moment_arm: +1 if the working motion of the output "
                                  "is counter-clockwise, -1 if clockwise")
    input: Annotated[int, Field(ge=0)] | None = Field(None, description="index of the input load in [[loads]]")
    step: Positive = Field(1e-4, description="tangent: input increment over its largest value")
    d_i: Positive | None = Field(None, description="input force distance, for an input moment")
    definition: Literal["tangent", "secant"] = "tangent"


class SoftModeOptions(Options):
    """``[methods.fem] dof``: soft modes of the tangent condensed to actuation points (fem.soft_modes)."""

    points: list[str] = Field(min_length=1, description="actuation points (ux, uy, rz each)")
    ratio: Positive = Field(1e-2, description="soft: stiffness below ratio x the members' largest EA/l")


class FemOptions(Options):
    elements: Count = Field(16, description="elements per member")
    error_estimate: bool = Field(True, description="solve on n and 2n elements, report |u_2n - u_n|/3")
    richardson: bool = Field(False, description="report the Richardson-extrapolated value")
    tol: Positive | None = Field(None, description="refine until the estimate is below it")
    levels: Count = Field(2, description="meshes in the error estimate")
    rtol: Positive = Field(1e-10, description="Newton residual tolerance")
    inextensible_ratio: Positive = Field(1e6, description="EA L^2/EI when a section gives no area")
    rigid_ratio: Positive = Field(1e6, description="stiffness of pinned rigid links over the stiffest beam")
    arc_length: Positive | None = None
    max_steps: Count | None = None
    limit_control: Literal["arclength", "displacement"] = "arclength"
    control_step: Positive | None = None
    inverse: dict[str, Any] | None = Field(None, description="inverse tip problem; keys checked by "
                                           "validation.methods.inverse_problem")
    slfp: dict[str, Any] | None = Field(None, description="sprung joints built as small-length flexural "
                                        "pivots (validation.methods.slfp)")
    input_moment_at: str | None = Field(None, description="reach the prescribed displacement by a moment "
                                        "at this node")
    zero_level: Annotated[int, Field(ge=0)] | None = Field(None, description="positions measured from this "
                                                          "level's state (a scale zeroed under self-weight)")
    ma: MechanicalAdvantageOptions | None = None
    dof: SoftModeOptions | None = None


class ElasticaOptions(Options):
    I: Positive | None = Field(None, description="replaces the section's second moment of area")
    EI: Positive | None = Field(None, description="replaces EI")
    rtol: Positive | None = None
    tol: Positive | None = None
    samples: Annotated[int, Field(ge=2)] = 41
    problem: Literal["inflection"] | None = None
    b: PerLevel | None = None
    theta0: PerLevel | None = None
    l1: PerLevel | None = None
    inverse: dict[str, Any] | None = Field(None, description="inverse tip problem; keys checked by "
                                           "validation.methods.inverse_problem")


class BcmOptions(Options):
    I: Positive | None = None
    EI: Positive | None = None


class OpenSeesOptions(Options):
    elements: Count = 16
    max_steps: Count | None = None
    steps_per_level: Count | None = None
    max_halvings: Annotated[int, Field(ge=0)] = Field(12, description="load-step halvings on failure")
    control_step: Positive | None = None
    rigid_ratio: Positive = Field(1e6, description="stiffness of the rigid links' elements over the stiffest beam")


class PrbmOptions(Options):
    family: Literal["pauly-midha", "howell"] = "pauly-midha"
    extrapolate: Literal["raise", "warn", "allow"] = "raise"
    friction_mu: NonNegative = 0.0
    contact_angle_deg: NonNegative = 0.0
    # chapter-3 fixed-guided segment with an inflection point
    problem: Literal["loads", "displacement"] = "loads"
    prefer: str | dict[str, float] = "energy"
    a: PerLevel | None = None
    b: PerLevel | None = None
    n: PerLevel | None = None
    l1: PerLevel | None = None
    theta0_deg: PerLevel | None = None
    # mechanisms
    links: dict[str, tuple[float, float]] | None = None
    springs: dict[str, float] | None = None
    spring_joints: dict[str, str] | None = None
    slfp: dict[str, Any] | None = None
    energy_free: dict[str, float] | None = None
    precision: dict[str, Any] | None = None
    free_levels: list[int] = Field(default_factory=list)
    drive: Literal["torque", "precision"] | None = None
    coupler_point: str = "P"
    origin: tuple[float, float] = (0.0, 0.0)
    ma: dict[str, Any] | None = Field(None, description="four-bar: {F_i, d_i, d_o} (eqs 190, 192); network: "
                                          "as [methods.fem] ma, {output, direction, input, step, d_i, definition}")
    max_mode: Count = 2
    segment_model: Literal["inflection", "fixed-pinned", "fixed-free"] | None = None
    model: Literal["network", "chain", "theta-dependent", "lyon", "feasible-l1"] | None = Field(
        None, description="'network': solve a mechanism by the general network built from the geometry even where "
        "a special path applies; 'chain', 'theta-dependent', 'lyon': seed 000 chapter 2's other segment models, "
        "'feasible-l1': section 3.6's vector loop "
        "(validation.methods.prbm_alternatives)")
    theta_fit: Literal["51", "52", "52-tension"] = Field("51", description="K_Theta(n, Theta) of seed 000 eq (51) or "
                                                         "(52) for model = 'theta-dependent'")
    chain_elements: Count = Field(40, description="Chain Algorithm elements (section 3.4 used 40)")
    chain_steps: Count = Field(10, description="Chain Algorithm load (or displacement) increments")
    zero_level: Annotated[int, Field(ge=0)] | None = Field(None, description="positions measured from this "
                                                          "level's state, as the FEM option (prbm_readings)")
    rules: dict[str, Any] | None = Field(None, description="the PRB builder's rules; keys checked by "
                                         "validation.methods.prbm_network.rules")
    # the seeds' synthesis data (chapters 5-7), kept beside the model for the reader and the synthesis;
    # the forward PRBM does not read them
    input: str | None = None
    T: list[float] | None = None
    U: list[float] | None = None
    F: list[float] | None = None
    E: Positive | None = None
    EI: dict[str, float] | float | None = None
    fixed_guided: dict[str, Any] | None = None
    theta1: float | None = None
    theta5: float | None = None
    R5: float | None = None
    R6: float | None = None
    d1: float | None = None
    d2: float | None = None
    n1: list[float] | None = None
    gamma: list[float] | None = None
    delta: list[list[float]] | None = None
    segments: list[dict[str, Any]] | None = None


OPTIONS: dict[str, type[Options]] = {"fem": FemOptions, "elastica": ElasticaOptions, "bcm": BcmOptions,
                                     "opensees": OpenSeesOptions, "prbm": PrbmOptions}
