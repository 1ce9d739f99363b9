"""The compiled kernels take their arrays in named groups (`fem.kernel`, `fem.warm_kernel`), each built
by keyword, so that two same-shaped arrays cannot be swapped by position.

1. Every group is a named tuple, and every place in fem/ that builds one names each of its fields once
   as a keyword (no positional argument, none left out); no compiled function takes more than 12
   arguments.
2. A swap the groups make impossible to write by accident, planted on purpose, is caught: a cantilever
   (EI = 1, L = 1) under a tip moment M bends into a circular arc of radius EI/M, tip at
   (EI/M) (sin(ML/EI), 1 - cos(ML/EI)) (the exact elastica). Solved with the groups as built, the tip
   is that point to the discretisation error; with two same-shaped fields of `kernel.Beams` swapped
   (start and end nodes, or reference length and axial stiffness) the solve misses it.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

import fem
from fem import assembly, kernel, warm_kernel

ROOT = Path(__file__).resolve().parents[2]
GROUPS = {
    cls.__name__: cls
    for cls in (
        kernel.Beams,
        kernel.DofMap,
        kernel.Couplings,
        kernel.Band,
        kernel.Storage,
        kernel.Load,
        kernel.Start,
        kernel.Controls,
        kernel.Work,
        kernel.ElementState,
        kernel.Outcome,
        kernel._Chord,
        kernel._Forces,
        warm_kernel.Coarse,
        warm_kernel.Fine,
        warm_kernel.Refinement,
    )
}
MAX_ARGUMENTS = 12

EI, LENGTH = 1.0, 1.0


def _calls_of_groups() -> list[tuple[str, int, str, list[str], int]]:
    """(file, line, group, keywords, positional count) of every call of a group class in fem/."""
    found = []
    for path in sorted((ROOT / "fem").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in GROUPS:
                found.append((path.name, node.lineno, name, [k.arg for k in node.keywords], len(node.args)))
    return found


def test_every_group_is_a_named_tuple_built_by_keyword():
    calls = _calls_of_groups()
    built = {name for _, _, name, _, _ in calls}
    assert built == set(GROUPS), f"groups never built in fem/: {set(GROUPS) - built}"
    for cls in GROUPS.values():
        assert issubclass(cls, tuple) and cls._fields == tuple(inspect.signature(cls).parameters), cls
    for file, line, name, keywords, positional in calls:
        where = f"fem/{file}:{line} {name}"
        assert positional == 0, f"{where}: a field passed by position"
        assert None not in keywords, f"{where}: fields passed by ** unpacking"
        assert sorted(keywords) == sorted(GROUPS[name]._fields), f"{where}: fields {keywords}"


def test_a_system_s_groups_hold_its_arrays():
    """The groups `assembly.System` builds for the compiled corrector hold the system's own arrays
    under their own names."""
    system = _system(moment=1.0)
    d = system.disc
    assert system.storage is not None
    for group, expected in (
        (system.beams, dict(X1=system.X1, X2=system.X2, L0=d.L0, beta0=d.beta0, ka=d.ka, kb=d.kb)),
        (
            system.dofs,
            dict(
                I0=system.I0, C0=system.C0_flat, edofs=d.edofs, prescribed=d.prescribed_dofs, rotation=d.red_is_rotation
            ),
        ),
        (system.couplings, dict(springs=d.springs, spring_k=d.spring_k)),
        (
            system.storage,
            dict(
                source=system.valid_src, coef=system.coef_const, rows_full=system.rows_full, cols_full=system.cols_full
            ),
        ),
    ):
        for name, array in expected.items():
            assert getattr(group, name) is array, (type(group).__name__, name)
    assert system.dofs.ground == d.ground and system.storage.band == system.compiled.band


def test_no_compiled_function_takes_more_than_a_few_arguments():
    for module in (kernel, warm_kernel):
        for name, value in vars(module).items():
            if isinstance(value, CPUDispatcher):
                count = len(inspect.signature(value.py_func).parameters)
                assert count <= MAX_ARGUMENTS, f"{module.__name__}.{name} takes {count} arguments"


def _model(moment: float, elements: int = 16) -> fem.Model:
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", LENGTH, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e6, EI), n_elements=elements)
    m.add_support("root", "fixed")
    m.add_moment("tip", [moment])
    return m


def _system(moment: float) -> assembly.System:
    from fem import solver
    from fem.options import SolveOptions

    system = solver._prepare(_model(moment), SolveOptions(), None)
    assert system.compiled is not None
    return system


def _tip_error(moment: float) -> float:
    """|tip - exact tip| / L of the solve, inf when it does not converge."""
    try:
        result = fem.solve(_model(moment))
    except (ArithmeticError, ValueError):
        return np.inf
    if not result.converged:
        return np.inf
    R = EI / moment
    exact = R * np.array([np.sin(LENGTH / R), 1.0 - np.cos(LENGTH / R)])
    tip = result.position("tip")
    return float(np.hypot(*(tip - exact))) / LENGTH


@pytest.mark.parametrize("swap", [None, ("X1", "X2"), ("L0", "ka")])
def test_a_swap_of_two_same_shaped_fields_misses_the_exact_arc(monkeypatch, swap):
    """With the fields as built the tip is the exact arc's to 1e-3 L (the discretisation error of 16
    elements); with two same-shaped fields of `kernel.Beams` swapped where the system builds them, the
    solve misses it by more than that (or fails)."""
    if swap is not None:
        a, b = swap

        def swapped(**fields):
            assert np.shape(fields[a]) == np.shape(fields[b])  # same-shaped: no type error would tell
            fields[a], fields[b] = fields[b], fields[a]
            return kernel.Beams(**fields)

        monkeypatch.setattr(assembly, "Beams", swapped)
    for moment in (1.0, 2.0):
        error = _tip_error(moment)
        if swap is None:
            assert error < 1e-3, (moment, error)
        else:
            assert error > 1e-2, (swap, moment, error)
