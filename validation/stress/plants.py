"""Planted errors: deliberate 10 % and sign errors in one method, for measuring what the case suite catches.

Each plant patches the running process (module attributes only, nothing on disk) and is meant for a
throw-away worker process: ``apply(name)`` is not undone. Two kinds:

adapter outputs   every value a method's adapter returns x 1.10, or the transverse ones (y, dy,
                  rotation, moments, transverse forces, input torque) with their sign flipped;
library constants the FEM's bending stiffness EI x 1.10 (every member the FEM builds), the PRBM's
                  stiffness coefficient K_Theta x 1.10 and characteristic radius factor gamma x 1.10
                  (every fit family, the pure-moment constants, the rule builder's defaults that the
                  networks built from geometry use, and the constant-parameter curved pinned-pinned
                  model's defaults), the Chain Algorithm's element EI x 1.10 (prbm.chain, the
                  'chain' model of the PRBM adapter), the elastica's EI x 1.10 (segments and every
                  beam of the elastica mechanism model), the BCM's linear stiffness coefficients
                  K0 x 1.10 with their compliance C0 / 1.10 ([chen2021, Table 1, eqs 3, 16]: the
                  linear term of EI x 1.10).

Methods that are options of another method's adapter carry that method's plants: the small-length
flexural pivot joints (``validation.methods.slfp``, an FEM option) are FEM members, the turning-load
and Chain Algorithm readings (``validation.methods.prbm_readings``) run inside the PRBM adapter.

``validation.stress.audit`` runs the case suite under each plant; a good suite fails on every one of them.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
from dataclasses import dataclass
from typing import Callable

import bcm.beam
import fem.model
import prbm.builder
import prbm.chain
import prbm.feasible_l1
import prbm.fits
import prbm.inflection
import prbm.segments

FACTOR = 1.10
# Quantities whose sign flips when the model is mirrored about its axis (what a sign error turns round).
TRANSVERSE = frozenset(
    {
        "y",
        "dy",
        "rotation",
        "moment",
        "force_y",
        "reaction_y",
        "reaction_moment",
        "input_torque",
        "input_angle",
        "prb_angle",
    }
)


@dataclass(frozen=True)
class Plant:
    """One planted error: which method it touches and how to apply it."""

    name: str
    method: str
    description: str
    apply: Callable[[], None]


def _wrap_adapter(method: str, change: Callable[[str, float], float]) -> None:
    adapter = importlib.import_module(f"validation.methods.{method}")
    original = adapter.run

    def planted(case, requests, options):
        run = original(case, requests, options)
        run.values = {req: change(req.quantity, value) for req, value in run.values.items()}
        return run

    setattr(adapter, "run", planted)


def _scaled_outputs(method: str) -> Callable[[], None]:
    return lambda: _wrap_adapter(method, lambda quantity, value: FACTOR * value)


def _flipped_outputs(method: str) -> Callable[[], None]:
    return lambda: _wrap_adapter(method, lambda quantity, value: -value if quantity in TRANSVERSE else value)


def _fem_EI() -> None:
    original = fem.model.Model.add_member

    def add_member(self, start, end, section, *args, **kwargs):
        return original(self, start, end, section.scaled(factor_EI=FACTOR), *args, **kwargs)

    setattr(fem.model.Model, "add_member", add_member)


def _prbm_fit(prefix: str, pure_moment: tuple[str, ...], builder: str, keyword: str) -> Callable[[], None]:
    """The fitted value of every family whose name starts with ``prefix``, the pure-moment constants
    ``pure_moment``, the rule builder's default ``builder`` (prbm.builder, read when a network is built)
    and the ``keyword`` default of the constant-parameter segment models (prbm.segments), all x FACTOR.

    The fits are planted in their printed coefficients (every coefficient of every branch x FACTOR, so
    the polynomial's value is x FACTOR exactly), in place on the shared fit objects: every evaluation
    path reads them, including the plain-float Horner twins that bypass ``PiecewiseFit.__call__``
    (prbm.inflection, the chapter-3/5 inflection models) and the module constants computed from them
    at import (prbm.feasible_l1's average gamma, which its functions also hold as a keyword default)."""

    def apply() -> None:
        for family in prbm.fits.FAMILIES.values():
            for fit in (family.gamma, family.c_theta, family.K_theta):
                if fit is not None and fit.name.startswith(prefix):
                    _scale_fit(fit)
        prbm.inflection._PLAIN_FITS.clear()  # Horner twins made before the plant hold the old coefficients
        if prefix == "gamma":
            _scale_loop_gamma()
        for module in (prbm.fits, prbm.segments):
            for name in pure_moment:
                if hasattr(module, name):
                    setattr(module, name, getattr(module, name) * FACTOR)
        setattr(prbm.builder, builder, getattr(prbm.builder, builder) * FACTOR)
        _scale_rules_default(builder.lower() if builder == "GAMMA" else "K_theta")
        inspect.unwrap(prbm.segments.curved_pinned_pinned).__kwdefaults__[keyword] *= FACTOR

    return apply


def _scale_loop_gamma() -> None:
    """Section 3.6's loop average gamma(0) x FACTOR: the module constant and the keyword default that
    ``loop_closure``, ``feasible_l1`` and ``approximate_domain`` bound to it at import (the adapter
    calls them without a gamma)."""
    module = prbm.feasible_l1
    module.GAMMA_AVERAGE *= FACTOR
    for function in (module.loop_closure, module.feasible_l1, module.approximate_domain):
        inspect.unwrap(function).__kwdefaults__["gamma"] *= FACTOR


def _scale_fit(fit: prbm.fits.PiecewiseFit) -> None:
    """Every printed coefficient of ``fit`` x FACTOR, in place (the fit objects are frozen and shared)."""
    scaled = tuple(
        dataclasses.replace(branch, coefficients=tuple(FACTOR * c for c in branch.coefficients))
        for branch in fit.branches
    )
    object.__setattr__(fit, "branches", scaled)


def _scale_rules_default(field_name: str) -> None:
    """``prbm.builder.Rules``' default for ``field_name`` x FACTOR: a dataclass bakes its defaults into
    ``__init__`` when the class is made, so re-binding the module constant alone changes nothing."""
    init = prbm.builder.Rules.__init__
    names = [f.name for f in dataclasses.fields(prbm.builder.Rules)]
    if init.__defaults__ is None:
        raise TypeError("prbm.builder.Rules has no field with a default")
    defaults = list(init.__defaults__)
    first = len(names) - len(defaults)  # the defaults belong to the last fields
    index = names.index(field_name) - first
    defaults[index] = defaults[index] * FACTOR
    init.__defaults__ = tuple(defaults)


def _chain_EI() -> None:
    original = prbm.chain.ChainBeam.stiffness
    setattr(prbm.chain.ChainBeam, "stiffness", lambda self: FACTOR * original(self))


def _elastica_EI() -> None:
    adapter = importlib.import_module("validation.methods.elastica")
    original = adapter._stiffness
    setattr(adapter, "_stiffness", lambda case, options: FACTOR * original(case, options))
    network = importlib.import_module("validation.methods.elastica_network")
    build = network.model

    def model(case):
        mech, owner = build(case)
        mech.beams = [dataclasses.replace(beam, EI=FACTOR * beam.EI) for beam in mech.beams]
        return mech, owner

    setattr(network, "model", model)


def _bcm_K0() -> None:
    bcm.beam.K0 *= FACTOR  # in place: bcm.mechanisms holds the same arrays
    bcm.beam.C0 /= FACTOR


PLANTS: dict[str, Plant] = {
    p.name: p
    for p in [
        Plant("fem-outputs-x1.10", "fem", "FEM adapter: every output x 1.10", _scaled_outputs("fem")),
        Plant("fem-sign-flip", "fem", "FEM adapter: transverse outputs with the sign flipped", _flipped_outputs("fem")),
        Plant("fem-EI-x1.10", "fem", "FEM library: every member's EI x 1.10", _fem_EI),
        Plant("prbm-outputs-x1.10", "prbm", "PRBM adapter: every output x 1.10", _scaled_outputs("prbm")),
        Plant(
            "prbm-sign-flip", "prbm", "PRBM adapter: transverse outputs with the sign flipped", _flipped_outputs("prbm")
        ),
        Plant(
            "prbm-K_theta-x1.10",
            "prbm",
            "PRBM library: K_Theta x 1.10 (fits, pure-moment spring, rule-builder and constant-model defaults)",
            _prbm_fit("K_theta", ("PURE_MOMENT_SPRING", "PURE_MOMENT_K_THETA"), "K_THETA", "K_theta"),
        ),
        Plant(
            "prbm-gamma-x1.10",
            "prbm",
            "PRBM library: gamma x 1.10 (fits, pure-moment gamma, rule-builder and constant-model defaults)",
            _prbm_fit("gamma", ("PURE_MOMENT_GAMMA",), "GAMMA", "gamma"),
        ),
        Plant("prbm-chain-EI-x1.10", "prbm", "PRBM library: the Chain Algorithm's element EI x 1.10", _chain_EI),
        Plant(
            "elastica-outputs-x1.10", "elastica", "elastica adapter: every output x 1.10", _scaled_outputs("elastica")
        ),
        Plant(
            "elastica-sign-flip",
            "elastica",
            "elastica adapter: transverse outputs with the sign flipped",
            _flipped_outputs("elastica"),
        ),
        Plant("elastica-EI-x1.10", "elastica", "elastica: EI x 1.10 (segments and mechanism beams)", _elastica_EI),
        Plant("bcm-outputs-x1.10", "bcm", "BCM adapter: every output x 1.10", _scaled_outputs("bcm")),
        Plant("bcm-sign-flip", "bcm", "BCM adapter: transverse outputs with the sign flipped", _flipped_outputs("bcm")),
        Plant(
            "bcm-K0-x1.10",
            "bcm",
            "BCM library: linear stiffness K0 x 1.10, compliance C0 / 1.10 (seed 003 Table 1)",
            _bcm_K0,
        ),
    ]
}


def apply(name: str) -> None:
    """Plant the named error in this process (no undo: use a throw-away process)."""
    if name not in PLANTS:
        raise ValueError(f"unknown plant '{name}'; known: {', '.join(PLANTS)}")
    PLANTS[name].apply()
