"""Local linear element matrices of a member, computed once with scikit-fem.

Along a member the arc-length coordinate s is meshed with a `skfem.MeshLine`
(one cell per corotational element, cell length = element chord length L0).
In the chord frame of an element the corotational (basic) deformations are
the stretch u_bar and the end rotations theta_1, theta_2 relative to the
chord, with zero transverse end displacements, so the basic stiffness is

    k_l = diag(k_a, k_b),   k_a = int EA phi_i' phi_j'  (P1, the (0,0) entry),
    k_b = int EI w_i'' w_j''  restricted to the two rotation DOFs (Hermite),

by Gauss quadrature, so EA(s) and EI(s) may vary along the member (tapered
or layered sections).  For constant properties k_a = EA/L0 and
k_b = EI/L0 [[4, 2], [2, 4]] (Crisfield 1991, sec. 7.2; Battini 2002).
The forms are assembled here only, at model build time, never in Newton.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np
from skfem import Basis, BilinearForm, ElementLineHermite, ElementLineP1, MeshLine
from skfem.helpers import dd, grad

from .types import FloatArray

__all__ = ["member_local_stiffness", "prismatic_local_stiffness"]


@BilinearForm  # type: ignore[untyped-decorator]  # scikit-fem carries no annotations
def _bending(u: Any, v: Any, w: Any) -> Any:
    return w["EI"] * dd(u)[0, 0] * dd(v)[0, 0]


@BilinearForm  # type: ignore[untyped-decorator]  # scikit-fem carries no annotations
def _axial(u: Any, v: Any, w: Any) -> Any:
    return w["EA"] * grad(u)[0] * grad(v)[0]


def member_local_stiffness(
    s_nodes: FloatArray,
    EA_of_xi: Callable[[FloatArray], FloatArray],
    EI_of_xi: Callable[[FloatArray], FloatArray],
    intorder: int = 6,
) -> tuple[FloatArray, FloatArray]:
    """Axial k_a (n_el,) and bending k_b (n_el, 2, 2) for cells with nodes s_nodes.

    EA_of_xi, EI_of_xi: callables of xi = s / s_total in [0, 1] (arrays in, arrays out).
    """
    mesh = MeshLine(np.asarray(s_nodes, dtype=float))
    total = float(s_nodes[-1] - s_nodes[0])
    hermite = Basis(mesh, ElementLineHermite(), intorder=intorder)
    linear = Basis(mesh, ElementLineP1(), intorder=intorder)
    xi_h = (hermite.global_coordinates()[0] - s_nodes[0]) / total
    xi_l = (linear.global_coordinates()[0] - s_nodes[0]) / total
    kb_full = _bending.coo_data(hermite, EI=EI_of_xi(xi_h)).tolocal()  # (n_el, 4, 4)
    ka_full = _axial.coo_data(linear, EA=EA_of_xi(xi_l)).tolocal()  # (n_el, 2, 2)
    # C-contiguous: the views picked out of scikit-fem's local matrices are strided, and the compiled
    # FEM kernel is typed (and compiled) once per array layout it is given
    kb: FloatArray = np.ascontiguousarray(kb_full[:, [1, 3]][:, :, [1, 3]])
    ka: FloatArray = np.ascontiguousarray(ka_full[:, 0, 0])
    return ka, kb


@lru_cache(maxsize=1)
def _unit_element() -> tuple[float, FloatArray]:
    """k_a, k_b of one element of unit length with EA = EI = 1 (by scikit-fem)."""
    ka, kb = member_local_stiffness(np.array([0.0, 1.0]), lambda xi: 1.0 + 0 * xi, lambda xi: 1.0 + 0 * xi, intorder=4)
    return float(ka[0]), kb[0]


def prismatic_local_stiffness(L0: FloatArray, EA: float, EI: float) -> tuple[FloatArray, FloatArray]:
    """Constant section: k_a = EA/L0 * k_a(1), k_b = EI/L0 * k_b(1) (exact scaling)."""
    ka1, kb1 = _unit_element()
    return EA * ka1 / L0, (EI / L0)[:, None, None] * kb1
