"""Planted errors: deliberate 10 % and sign errors in one method, for measuring what the case suite catches.

Each plant patches the running process (module attributes only, nothing on disk) and is meant for a
throw-away worker process: ``apply(name)`` is not undone. Two kinds:

adapter outputs   every value a method's adapter returns x 1.10, or the transverse ones (y, dy,
                  rotation, moments, transverse forces, input torque) with their sign flipped;
library constants the FEM's bending stiffness EI x 1.10 (every member the FEM builds), the PRBM's
                  stiffness coefficient K_Theta x 1.10 and characteristic radius factor gamma x 1.10
                  (every fit family, the pure-moment constants, the rule builder's defaults that the
                  networks built from geometry use, and the constant-parameter curved pinned-pinned
                  model's defaults), the elastica's EI x 1.10.

``validation.stress.audit`` runs the case suite under each plant; a good suite fails on every one of them.
"""
from __future__ import annotations

import importlib
import inspect
from dataclasses import dataclass
from typing import Callable

import fem.model
import prbm.builder
import prbm.fits
import prbm.segments

FACTOR = 1.10
# Quantities whose sign flips when the model is mirrored about its axis (what a sign error turns round).
TRANSVERSE = frozenset({"y", "dy", "rotation", "moment", "force_y", "reaction_y", "reaction_moment",
                        "input_torque", "input_angle", "prb_angle"})


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

    adapter.run = planted


def _scaled_outputs(method: str) -> Callable[[], None]:
    return lambda: _wrap_adapter(method, lambda quantity, value: FACTOR * value)


def _flipped_outputs(method: str) -> Callable[[], None]:
    return lambda: _wrap_adapter(method, lambda quantity, value: -value if quantity in TRANSVERSE else value)


def _fem_EI() -> None:
    original = fem.model.Model.add_member

    def add_member(self, start, end, section, *args, **kwargs):
        return original(self, start, end, section.scaled(factor_EI=FACTOR), *args, **kwargs)

    fem.model.Model.add_member = add_member


def _prbm_fit(prefix: str, pure_moment: tuple[str, ...], builder: str, keyword: str) -> Callable[[], None]:
    """The fitted value of every family whose name starts with ``prefix``, the pure-moment constants
    ``pure_moment``, the rule builder's default ``builder`` (prbm.builder, read when a network is built)
    and the ``keyword`` default of the constant-parameter segment models (prbm.segments), all x FACTOR."""
    def apply() -> None:
        original = prbm.fits.PiecewiseFit.__call__

        def call(self, n, extrapolate="raise"):
            value = original(self, n, extrapolate)
            return value * FACTOR if self.name.startswith(prefix) else value

        prbm.fits.PiecewiseFit.__call__ = call
        for module in (prbm.fits, prbm.segments):
            for name in pure_moment:
                if hasattr(module, name):
                    setattr(module, name, getattr(module, name) * FACTOR)
        setattr(prbm.builder, builder, getattr(prbm.builder, builder) * FACTOR)
        inspect.unwrap(prbm.segments.curved_pinned_pinned).__kwdefaults__[keyword] *= FACTOR
    return apply


def _elastica_EI() -> None:
    adapter = importlib.import_module("validation.methods.elastica")
    original = adapter._stiffness
    adapter._stiffness = lambda case, options: FACTOR * original(case, options)


PLANTS: dict[str, Plant] = {p.name: p for p in [
    Plant("fem-outputs-x1.10", "fem", "FEM adapter: every output x 1.10", _scaled_outputs("fem")),
    Plant("fem-sign-flip", "fem", "FEM adapter: transverse outputs with the sign flipped", _flipped_outputs("fem")),
    Plant("fem-EI-x1.10", "fem", "FEM library: every member's EI x 1.10", _fem_EI),
    Plant("prbm-outputs-x1.10", "prbm", "PRBM adapter: every output x 1.10", _scaled_outputs("prbm")),
    Plant("prbm-sign-flip", "prbm", "PRBM adapter: transverse outputs with the sign flipped", _flipped_outputs("prbm")),
    Plant("prbm-K_theta-x1.10", "prbm",
          "PRBM library: K_Theta x 1.10 (fits, pure-moment spring, rule-builder and constant-model defaults)",
          _prbm_fit("K_theta", ("PURE_MOMENT_SPRING", "PURE_MOMENT_K_THETA"), "K_THETA", "K_theta")),
    Plant("prbm-gamma-x1.10", "prbm",
          "PRBM library: gamma x 1.10 (fits, pure-moment gamma, rule-builder and constant-model defaults)",
          _prbm_fit("gamma", ("PURE_MOMENT_GAMMA",), "GAMMA", "gamma")),
    Plant("elastica-outputs-x1.10", "elastica", "elastica adapter: every output x 1.10", _scaled_outputs("elastica")),
    Plant("elastica-sign-flip", "elastica", "elastica adapter: transverse outputs with the sign flipped",
          _flipped_outputs("elastica")),
    Plant("elastica-EI-x1.10", "elastica", "elastica: EI x 1.10", _elastica_EI),
]}


def apply(name: str) -> None:
    """Plant the named error in this process (no undo: use a throw-away process)."""
    if name not in PLANTS:
        raise ValueError(f"unknown plant '{name}'; known: {', '.join(PLANTS)}")
    PLANTS[name].apply()
