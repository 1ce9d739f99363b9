"""One dialect for the libraries (issue 24): every module of prbm/, fem/, elastica/ and bcm/ states the
unit of its angles in its docstring (radians; the synthesis mathematics, which takes the seed's design
tables, says it works in degrees), and the iteration limit has one name, ``maxiter``, in every public
signature."""

import ast
import inspect
from pathlib import Path

import pytest

import bcm
import elastica
import fem
import prbm

ROOT = Path(__file__).resolve().parents[2]
MODULES = sorted(p for package in ("prbm", "fem", "elastica", "bcm") for p in (ROOT / package).rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_module_docstring_states_the_angle_unit(path):
    doc = (ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or "").lower()
    expected = "degrees here" if "synthesis" in path.parts else "radians"
    assert expected in doc, f"{path.relative_to(ROOT)}: the docstring does not say its angles are in {expected}"


def public_callables():
    for package in (prbm, fem, elastica, bcm):
        for name in getattr(package, "__all__", []):
            obj = getattr(package, name)
            if callable(obj):
                yield f"{package.__name__}.{name}", obj


def test_the_iteration_limit_is_called_maxiter_everywhere():
    offenders = []
    for name, obj in public_callables():
        try:
            parameters = inspect.signature(obj).parameters
        except (TypeError, ValueError):
            continue
        offenders += [f"{name}({p})" for p in parameters if p in ("max_iter", "max_iterations", "maxit")]
    assert not offenders, offenders
