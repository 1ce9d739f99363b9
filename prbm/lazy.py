"""A module imported at its first use: ``LazyModule("scipy.optimize")`` stands for the module and
imports it when one of its attributes is first read, so the heavy dependencies (scipy.optimize,
slow to import) are paid for only by the code paths that call them, not by every ``import prbm``.

No mathematics and no angles here (radians everywhere in the library). The project's own modules
loaded this way are also named in an ``if TYPE_CHECKING:`` import beside the ``LazyModule``, so the
static import walks (the run cache's source hash, the layout test's cycle check) still see them.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

__all__ = ["LazyModule"]


class LazyModule:
    """The module ``name``, imported by ``importlib.import_module`` at the first attribute read."""

    __slots__ = ("_name", "_module")

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attr: str) -> Any:
        module = self._module
        if module is None:
            module = self._module = importlib.import_module(self._name)
        return getattr(module, attr)

    def __repr__(self) -> str:
        state = "imported" if self._module is not None else "not imported yet"
        return f"<LazyModule {self._name!r} ({state})>"
