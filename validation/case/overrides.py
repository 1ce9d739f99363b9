"""Writing a value into case data at a dotted path (``segment.E``, ``loads.0.values``,
``methods.fem.elements``), as sweeps and readings variants do:

    set     data[path] = v
    scale   data[path] = v * base          (numbers and lists elementwise; a load or a ramp:
                                            its values, or its ramp start and stop)
    offset  data[path] = v + base          (numbers and lists elementwise)
    angle   data[path] = |base| (cos v, sin v), v in degrees   (a direction vector)
"""

from __future__ import annotations

import math
from typing import Any

MODES = ("set", "scale", "offset", "angle")


class PathError(ValueError):
    """A dotted path that does not lead anywhere in the case data."""


def split_path(path: str) -> list[str | int]:
    return [int(part) if part.lstrip("-").isdigit() else part for part in path.split(".")]


def parent_of(data: Any, path: str) -> tuple[Any, str | int]:
    parts = split_path(path)
    node = data
    for i, key in enumerate(parts[:-1]):
        node = _step(node, key, ".".join(map(str, parts[: i + 1])))
    last = parts[-1]
    if isinstance(node, list):
        if not isinstance(last, int) or not -len(node) <= last < len(node):
            raise PathError(f"'{path}': no item {last} (the list has {len(node)})")
    elif isinstance(node, dict):
        last = str(last)
    else:
        raise PathError(f"'{path}': {'.'.join(map(str, parts[:-1]))} is a value, not a table or list")
    return node, last


def _step(node: Any, key: str | int, where: str) -> Any:
    if isinstance(node, list):
        if isinstance(key, int) and -len(node) <= key < len(node):
            return node[key]
        raise PathError(f"'{where}': no item {key} (the list has {len(node)})")
    if isinstance(node, dict):
        if str(key) in node:
            return node[str(key)]
        raise PathError(f"'{where}': no such table or field in the case")
    raise PathError(f"'{where}': reaches into a value")


def check_path(data: dict, path: str, mode: str) -> None:
    """Raise ``PathError`` if ``path`` cannot be applied to the base case ``data`` in ``mode``."""
    node, key = parent_of(data, path)
    if mode != "set" and (isinstance(node, dict) and key not in node):
        raise PathError(f"'{path}': mode '{mode}' needs a value in the base case, and it has none")


def _scaled(base: Any, factor: float, path: str) -> Any:
    if isinstance(base, bool):
        raise PathError(f"'{path}': cannot scale a true/false value")
    if isinstance(base, (int, float)):
        return base * factor
    if isinstance(base, list):
        return [_scaled(item, factor, path) for item in base]
    if isinstance(base, dict) and ("values" in base or "ramp" in base):  # a load
        out = dict(base)
        for key in ("values", "ramp"):
            if key in out:
                out[key] = _scaled(out[key], factor, path)
        return out
    if isinstance(base, dict) and {"start", "stop"} <= set(base):  # a ramp
        return base | {"start": base["start"] * factor, "stop": base["stop"] * factor}
    raise PathError(f"'{path}': cannot scale a {type(base).__name__}")


def _offset(base: Any, delta: float, path: str) -> Any:
    if isinstance(base, (int, float)) and not isinstance(base, bool):
        return base + delta
    if isinstance(base, list):
        return [_offset(item, delta, path) for item in base]
    raise PathError(f"'{path}': cannot offset a {type(base).__name__}")


def apply(data: dict, path: str, mode: str, value: Any) -> None:
    """Write one parameter value into the case data (in place)."""
    node, key = parent_of(data, path)
    if mode == "set":
        node[key] = value
        return
    base = node[key]
    if mode == "scale":
        node[key] = _scaled(base, value, path)
    elif mode == "offset":
        node[key] = _offset(base, value, path)
    elif mode == "angle":
        if not (isinstance(base, list) and len(base) == 2):
            raise PathError(f"'{path}': mode 'angle' needs a direction [dx, dy]")
        size = math.hypot(*base) or 1.0
        angle = math.radians(value)
        node[key] = [size * math.cos(angle), size * math.sin(angle)]
    else:
        raise PathError(f"unknown mode '{mode}'")
