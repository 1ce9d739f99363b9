"""Small pieces the PRBM adapter's parts share: picking the requested values out of per-level
columns, plain (JSON-able) constants, polylines for the shapes, the root preference option, the crank
angles of a slider travel.

Nothing here knows a model; ``prbm.py`` (segments), ``prbm_fourbar.py`` (hand-given four-bars and
slider-cranks), ``prbm_body.py`` (one beam carrying a rigid body, the curved pinned-pinned beam) and
``prbm_network.py`` (mechanisms built by rule) use it.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from validation.case.method_options import PrbmOptions
from validation.methods.base import Misconfigured, NotApplicable

DEG = math.pi / 180.0


def pick(out: dict, requests, what: str) -> dict:
    """The requested values from ``out`` (quantity -> its levels as a list of floats or an array, or one
    value for every level)."""
    values = {}
    # quantity -> its levels as plain floats (one conversion per quantity, not per request)
    columns: dict[str, list] = {}
    for req in requests:
        quantity, _, level = req
        column = columns.get(quantity)
        if column is None:
            if quantity not in out:
                raise NotApplicable(f"the PRBM gives no '{quantity}' for this {what}")
            column = out[quantity]
            if type(column) is not list:
                column = np.atleast_1d(column).ravel().tolist()
            columns[quantity] = column
        values[req] = float(column[level] if len(column) > 1 else column[0])
    return values


def per_level(v, n: int) -> np.ndarray:
    """v as an array over the n load levels (a scalar repeated); np.broadcast_to without its overhead."""
    v = np.asarray(v)
    return v if v.shape == (n,) else np.broadcast_to(v, (n,))


def per_input_force(ma_at: Callable[[float], object], forces: float | list[float], n: int) -> np.ndarray:
    """A mechanical advantage over the n levels under the input force F_i, given as one value for every level
    or one per level: ``ma_at(F)`` (the model's MA over every level under the force F) at each distinct
    force, each level's value taken at its own force."""
    per = per_level(np.asarray(forces, float), n)
    out = np.empty(n)
    for force in np.unique(per):
        at = per == force
        out[at] = np.broadcast_to(np.asarray(ma_at(float(force)), float), (n,))[at]
    return out


def levels(v, n: int) -> list:
    """v over the n load levels as a list of Python numbers (a scalar or a one-element array repeated)."""
    kind = type(v)
    if kind is list and len(v) == n:
        return v
    if kind is float:
        return [v] * n
    v = np.asarray(v)
    if v.shape == (n,):
        return v.tolist()
    if v.size == 1 and v.ndim <= 1:  # one value for every level (np.broadcast_to without its cost)
        return [v.reshape(()).item()] * n
    return np.broadcast_to(v, (n,)).tolist()


def plain(d: dict) -> dict:
    """The dict with numpy arrays and scalars turned into lists and Python numbers."""
    out = {}
    for k, v in d.items():
        if isinstance(v, np.ndarray):
            out[k] = v.tolist()
        elif isinstance(v, (np.floating, np.integer)):
            out[k] = v.item()
        else:
            out[k] = v
    return out


def polyline(points) -> np.ndarray:
    """Complex points -> an (n, 2) polyline."""
    z = np.asarray(points, complex)
    return np.column_stack([z.real, z.imag])


def prefer(options: PrbmOptions):
    """The ``prefer`` option: 'energy' (default), another rule's name, or {key = value} -> (key, value)."""
    chosen = options.prefer
    return next(iter(chosen.items())) if isinstance(chosen, dict) else chosen


def slider_angles(sc, dx) -> np.ndarray:
    """The crank angle of every slider travel ``dx``; a travel the linkage cannot reach is the case's input
    (its links and its displacement load), not a solver failure: ``Misconfigured`` naming them."""
    try:
        return np.array([sc.theta2_at(float(d)) for d in dx])
    except ValueError as exc:
        raise Misconfigured(f"links r11, r2, r3 and the slider travel of the 'displacement' load: {exc}") from None
