"""Beam cross-sections for the corotational FEM.

A section supplies the axial stiffness EA and the bending stiffness EI of a
beam (consistent units: force for EA, force x length^2 for EI) and, when the
material and geometry are known, what is needed for the largest bending
stress.

Stack of sliding layers (a composite beam whose layers slide freely on each
other, e.g. a laminate without shear connection): every layer bends about its
own centroid with the common curvature kappa, so

    EA = sum_i E_i w_i h_i,        EI = sum_i E_i w_i h_i^3 / 12,

and the extreme-fibre stress of layer i is  sigma_i = E_i (eps +- kappa h_i/2),
with the common axial strain eps = N/EA.  A rectangle is the one-layer stack.

`Section.from_EI(EA, EI, c, E)` gives the stiffnesses directly; the bending
stress sigma = E (eps +- kappa c) is available only when both the extreme-fibre
distance c and the modulus E are given.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .types import FloatArray

__all__ = ["Section"]


@dataclass(frozen=True)
class Section:
    """Axial stiffness EA, bending stiffness EI and stress data (E_i, c_i) per layer.

    ``stress_layers`` is a tuple of (E, c) pairs: modulus and extreme-fibre
    distance from the layer's own bending axis; empty when unknown.
    """

    EA: float
    EI: float
    stress_layers: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        for name in ("EA", "EI"):
            value = getattr(self, name)
            if isinstance(value, (int, float)):  # the usual case (np.float64 too): no numpy call
                ok = math.isfinite(value) and value > 0
            else:
                ok = bool(np.isfinite(value) and value > 0)
            if not ok:
                raise ValueError(f"Section: {name} must be finite and > 0, got {value!r}")

    @classmethod
    def from_EI(cls, EA: float, EI: float, c: float | None = None, E: float | None = None) -> "Section":
        """Section from the stiffnesses; stress needs both ``c`` and ``E``."""
        layers = ((float(E), float(c)),) if (c is not None and E is not None) else ()
        return cls(float(EA), float(EI), layers)

    @classmethod
    def rectangle(cls, E: float, width: float, thickness: float) -> "Section":
        """Solid rectangle of modulus E, width (out of plane) and thickness (in plane)."""
        return cls.layers([(E, width, thickness)])

    @classmethod
    def layers(cls, stack: Iterable[tuple[float, float, float]]) -> Section:
        """Stack of sliding layers, each ``(E, width, thickness)``."""
        layers = [(float(E), float(w), float(h)) for E, w, h in stack]
        if not layers:
            raise ValueError("a layered section needs at least one layer")
        EA = sum(E * w * h for E, w, h in layers)
        EI = sum(E * w * h**3 / 12.0 for E, w, h in layers)
        return cls(EA, EI, tuple((E, h / 2.0) for E, _, h in layers))

    @property
    def has_stress(self) -> bool:
        return len(self.stress_layers) > 0

    def max_stress(self, N: ArrayLike, M: ArrayLike) -> FloatArray:
        """Largest |sigma| over the layers for axial force N and moment M (arrays)."""
        if not self.has_stress:
            return np.full(np.shape(M), np.nan)
        eps = np.asarray(N) / self.EA
        kappa = np.asarray(M) / self.EI
        layer = (-1,) + (1,) * max(eps.ndim, kappa.ndim)  # layers along the first axis
        E = np.array([E for E, _ in self.stress_layers]).reshape(layer)
        c = np.array([c for _, c in self.stress_layers]).reshape(layer)
        stress: FloatArray = np.max(np.abs(E * eps) + np.abs(E * kappa * c), axis=0)
        return stress

    def scaled(self, factor_EA: float = 1.0, factor_EI: float = 1.0) -> "Section":
        return Section(self.EA * factor_EA, self.EI * factor_EI, self.stress_layers)
