"""Options a method would not read for this case: each is an error, not a no-op.

The option models (``validation.case.method_options``) refuse unknown names and values out of range;
an option can still be well formed and have no effect, because the adapter reads it only on another
path: a continuation setting without a limit load to trace, an error-estimate setting with the
estimate off, a mechanism's setting on a single segment. Such an option is almost always a mistake
(a misplaced table, a setting the author believes is in force), so it is refused before any solve with
the option's field and the reason. ``USES`` states, per method and option, the case in which the adapter
reads it; an option absent from ``USES`` is read on every path of its method.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from validation.case.method_options import FemOptions


def asks(case, method: str, quantity: str) -> bool:
    """The case asks ``method`` for ``quantity`` (an output naming the method, or every method)."""
    return any(out.quantity == quantity and (out.methods is None or method in out.methods) for out in case.outputs)


def _inertia_without_area(case) -> bool:
    sections = [case.segment.section] if case.segment is not None else [b.section for b in case.mechanism.beams]
    return any(s.kind == "inertia" and s.A is None for s in sections)


def _estimate(options: dict) -> bool:
    """The FEM's error estimate is on (the options as the file gives them, each default from ``FemOptions``)."""
    fem = FemOptions.model_validate(options)
    return fem.error_estimate or fem.tol is not None


def _sprung(case) -> bool:
    return case.mechanism is not None and any(j.spring > 0 for j in case.mechanism.joints)


@dataclass(frozen=True)
class Use:
    """When a method reads an option: ``reads(case, options)``, and ``otherwise`` says why it would not."""

    reads: Callable[[Any, dict], bool]  # (the schema's Case, which calls this module while it validates)
    otherwise: str


SEGMENT_ONLY = Use(
    lambda case, options: case.segment is not None, "read for a single segment only, this case is a mechanism"
)
MECHANISM_ONLY = Use(
    lambda case, options: case.mechanism is not None, "read for a mechanism only, this case is a single segment"
)


def _limit(method: str) -> Use:
    return Use(
        lambda case, options: asks(case, method, "limit_load"),
        f"read only when the case asks the {method} for a limit_load (a continuation); it asks for none",
    )


def _output(method: str, quantity: str) -> Use:
    return Use(
        lambda case, options: asks(case, method, quantity),
        f"read only when the case asks the {method} for {quantity}; it does not",
    )


def _model(name: str) -> Use:
    return Use(
        lambda case, options: options.get("model") == name, f"read only by the PRBM model '{name}' (model = \"{name}\")"
    )


def _along_segment(case) -> bool:
    """A single segment carrying a distributed or self-weight load (the PRBM's chain carries it)."""
    return case.segment is not None and any(ld.kind in ("distributed", "self_weight") for ld in case.loads)


CHAIN = Use(
    lambda case, options: options.get("model") == "chain" or (options.get("model") is None and _along_segment(case)),
    'read only by the Chain Algorithm: model = "chain", or a load along a single segment without a model',
)
CHAIN_CHOICE = Use(
    lambda case, options: options.get("model") is None and _along_segment(case) and "chain_elements" not in options,
    "read only when the PRBM chooses the Chain Algorithm's elements itself: a load along a single "
    "segment, without a model and without chain_elements",
)
ESTIMATE = Use(
    lambda case, options: _estimate(options),
    "read only with the error estimate (error_estimate = true or tol), which is off",
)
INFLECTION = Use(
    lambda case, options: options.get("problem") == "inflection",
    'read only by the inflection problem (problem = "inflection")',
)
MECHANISM_ELASTICA = Use(
    lambda case, options: case.segment is not None, "not read for a mechanism (its exact elastica reads only rtol)"
)

USES: dict[str, dict[str, Use]] = {
    "fem": {
        **{name: _limit("fem") for name in ("arc_length", "limit_control", "control_step", "max_steps")},
        "ma": _output("fem", "mechanical_advantage"),
        "dof": _output("fem", "dof"),
        **{name: ESTIMATE for name in ("levels", "max_refine", "richardson")},
        "rigid_ratio": Use(
            lambda case, options: case.mechanism is not None and bool(case.mechanism.links),
            "read only for a mechanism's rigid links; this case has none",
        ),
        "slfp": Use(
            lambda case, options: _sprung(case),
            "read only for a mechanism with sprung joints (spring > 0); this case has none",
        ),
        "input_moment_at": MECHANISM_ONLY,
        "inextensible_ratio": Use(
            lambda case, options: _inertia_without_area(case),
            "read only for a section of kind 'inertia' without an area A; every section here gives its area",
        ),
        "inverse": SEGMENT_ONLY,
    },
    "elastica": {
        **{name: INFLECTION for name in ("b", "theta0", "l1")},
        **{name: MECHANISM_ELASTICA for name in ("I", "EI", "tol", "samples", "problem", "inverse")},
    },
    "bcm": {name: SEGMENT_ONLY for name in ("I", "EI")},
    "opensees": {**{name: _limit("opensees") for name in ("control_step", "max_steps")}, "rigid_ratio": MECHANISM_ONLY},
    "prbm": {
        **{
            name: MECHANISM_ONLY
            for name in (
                "links",
                "springs",
                "spring_joints",
                "slfp",
                "energy_free",
                "precision",
                "free_levels",
                "drive",
                "coupler_point",
                "origin",
                "ma",
                "rules",
                "segment_model",
            )
        },
        **{name: CHAIN for name in ("chain_elements", "chain_steps")},
        "chain_tol": CHAIN_CHOICE,
        "theta_fit": _model("theta-dependent"),
        "max_mode": _output("prbm", "dof"),
    },
}


def unused_options(case) -> list[str]:
    """'methods.<method>.<option>: ...' for every option of the case its method would not read."""
    out = []
    for method, options in case.methods.items():
        uses = USES.get(method, {})
        options = options or {}
        for name in options:
            use = uses.get(name)
            if use is not None and not use.reads(case, options):
                out.append(f"methods.{method}.{name}: the {method} does not use this option here: {use.otherwise}")
    return out
