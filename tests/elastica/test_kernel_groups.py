"""The compiled kernels' named argument groups (``elastica.integrator``: Beam, Loads, Tolerances,
UnknownForces, Structure, Corrector, PathControls, Parameters).

1. Every group is a ``typing.NamedTuple``, every place in ``elastica`` that builds one names every
   field by keyword (no positional field, no ``**`` mapping), and the builders put each value in its
   field (``_Shooter``'s Structure, ``solve_path``'s PathControls).
2. The fields are not interchangeable: a builder that swaps two same-shaped fields is caught on
   problems with an exact answer, while the real builder matches it:
   * a mechanism beam (length L, stiffness EI) under a pure end moment M is a circular arc of
     curvature M/EI, tip (EI/M) (sin(ML/EI), 1 - cos(ML/EI)): Beam with length and EI swapped bends
     it to the curvature M/L;
   * a cantilever under a transverse tip force P (P L^2/EI = 3) started from its exact root moment
     m(0) = P a L ends at the elliptic-integral tip (a, b) L [bapat2015, sec 2.1.1]: Loads with Fx and
     Fy swapped pushes it along its axis instead;
   * the fixed-pinned beam with its tip height prescribed, y(L) = b, and the unknown force along
     -y (so the multiplier is -P): the cantilever's tip (a, b) again; a Structure whose condition
     direction d and force direction f (``dirs``, ``forces.force_dirs``) are exchanged prescribes
     -y(L) = b, the mirror image (a, -b).
"""

from __future__ import annotations

import ast
import math
import typing
from pathlib import Path

import numpy as np
import pytest

import elastica.integrator as ig
from elastica import ElasticaProblem, MomentConstraint, TipConstraint, solve_path
from elastica.elliptic import cantilever_tip_load
from elastica.shooting import _Shooter

GROUPS = (
    ig.Beam,
    ig.Loads,
    ig.Tolerances,
    ig.UnknownForces,
    ig.Structure,
    ig.Corrector,
    ig.PathControls,
    ig.Parameters,
)
PACKAGE = Path(ig.__file__).resolve().parent


def _swapping(monkeypatch, group, a: str, b: str) -> None:
    """Replace ``group`` in ``elastica.integrator`` by a builder that swaps the fields ``a`` and ``b``."""

    def build(**fields):
        fields[a], fields[b] = fields[b], fields[a]
        return group(**fields)

    monkeypatch.setattr(ig, group.__name__, build)


# ---------------------------------------------------------------- 1. NamedTuples, built by keyword


@pytest.mark.parametrize("group", GROUPS, ids=lambda g: g.__name__)
def test_every_group_is_a_named_tuple(group):
    assert issubclass(group, tuple) and typing.NamedTuple in getattr(group, "__orig_bases__", ())
    assert tuple(group.__annotations__) == group._fields and group._field_defaults == {}


def _builds() -> list[tuple[str, int, str, ast.Call]]:
    """(file, line, group, call) of every call of a group's name in the ``elastica`` package."""
    names = {g.__name__ for g in GROUPS}
    found = []
    for path in sorted(PACKAGE.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call):
                f = node.func
                name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
                if name in names:
                    found.append((path.name, node.lineno, name, node))
    return found


def test_every_group_is_built_by_keyword_naming_every_field():
    fields = {g.__name__: set(g._fields) for g in GROUPS}
    builds = _builds()
    assert {name for _, _, name, _ in builds} == set(fields)  # each group is built somewhere
    wrong = [
        f"{file}:{line} {name}"
        for file, line, name, call in builds
        if call.args or any(k.arg is None for k in call.keywords) or {k.arg for k in call.keywords} != fields[name]
    ]
    assert wrong == []


def test_the_shooter_puts_each_direction_in_its_field():
    problem = ElasticaProblem(
        length=2.0,
        curvature=0.3,
        follower=(0.0, 1.0),
        constraints=(TipConstraint((3.0, 4.0), 1.0, (0.0, -2.0)),),
        moment_constraints=(MomentConstraint(0.5, 0.0, (1.0, 1.0)), MomentConstraint(2.0, 0.0, (-1.0, 0.0))),
    )
    shooter = _Shooter(problem, 1e-12, 1e-13)
    s = shooter.structure
    assert type(s) is ig.Structure and s.beam == ig.Beam(length=1.0, EI=1.0, EA=0.0, curvature=0.6)
    np.testing.assert_array_equal(s.dirs, [[0.6, 0.8]])
    assert type(s.forces) is ig.UnknownForces and s.forces.follower is True
    np.testing.assert_array_equal(s.forces.force_dirs, [[0.0, -1.0]])
    np.testing.assert_allclose(s.forces.moment_dirs, [[math.sqrt(0.5), math.sqrt(0.5)], [-1.0, 0.0]], rtol=1e-15)
    np.testing.assert_array_equal(s.bounds, [0.0, 0.25, 1.0])
    np.testing.assert_array_equal(s.site_at, [1, 2])
    assert s.angle_given is False
    assert shooter.tolerances == ig.Tolerances(rtol=1e-12, atol=1e-13)


def test_solve_path_puts_each_option_in_its_field(monkeypatch):
    seen = []
    real = ig.follow_path

    def recording(z, q0, q1, structure, controls):
        seen.append(controls)
        return real(z, q0, q1, structure, controls)

    monkeypatch.setattr(ig, "follow_path", recording)
    options = dict(
        rtol=1e-11,
        atol=2e-12,
        tol=3e-11,
        initial_step=0.2,
        min_step=2e-5,
        max_rotation_step=0.4,
        max_position_step=0.3,
        max_corrector=0.6,
        max_step_iterations=7,
        maxiter=21,
        path_rtol=2e-7,
    )
    assert solve_path(ElasticaProblem(force=(0.0, 2.0)), n_samples=2, **options).converged
    assert seen == [
        ig.PathControls(
            final=ig.Tolerances(rtol=1e-11, atol=2e-12),
            tol=3e-11,
            path=ig.Tolerances(rtol=2e-7, atol=2e-7 * 0.1),
            initial_step=0.2,
            min_step=2e-5,
            max_rotation_step=0.4,
            max_position_step=0.3,
            max_corrector=0.6,
            max_step_iterations=7,
            maxiter=21,
        )
    ]


# ---------------------------------------------------------------- 2. a swap is caught


def _arc_tip():
    """Tip (x, y) of a beam L = 2, EI = 3 under the end moment M = 1.7 (a circular arc), and the exact."""
    L, EI, M = 2.0, 3.0, 1.7
    end, ok = ig.integrate_beam([0.0, 0.0, 0.0, M, 0.0], L, 0.0, 0.0, 0.0, EI, 0.0, 1e-12, 1e-13)
    assert ok
    return end[:2], (EI / M) * np.array([math.sin(M * L / EI), 1.0 - math.cos(M * L / EI)])


def test_the_beam_is_the_exact_arc_and_a_swapped_beam_is_not(monkeypatch):
    tip, exact = _arc_tip()
    np.testing.assert_allclose(tip, exact, rtol=0, atol=1e-10)
    _swapping(monkeypatch, ig.Beam, "length", "EI")
    swapped, exact = _arc_tip()
    assert np.max(np.abs(swapped - exact)) > 1e-2


def _cantilever_tip():
    """Tip (x, y) of a beam L = 2, EI = 3 under the tip force (0, P), P L^2/EI = 3, from m(0) = P a L."""
    L, EI, load = 2.0, 3.0, 3.0
    exact = cantilever_tip_load(load)
    P = load * EI / L**2
    end, ok = ig.integrate_beam([0.0, 0.0, 0.0, P * exact.a * L, 0.0], L, 0.0, P, 0.0, EI, 0.0, 1e-12, 1e-13)
    assert ok
    return end[:2], L * np.array([exact.a, exact.b])


def test_the_loads_give_the_exact_cantilever_and_swapped_loads_do_not(monkeypatch):
    tip, exact = _cantilever_tip()
    np.testing.assert_allclose(tip, exact, rtol=0, atol=1e-10)
    _swapping(monkeypatch, ig.Loads, "Fx", "Fy")
    swapped, exact = _cantilever_tip()
    assert np.max(np.abs(swapped - exact)) > 1e-2


def test_the_structure_gives_the_exact_tip_and_a_swapped_structure_its_mirror(monkeypatch):
    load = 3.0  # P L^2 / EI, L = EI = 1
    exact = cantilever_tip_load(load)
    problem = ElasticaProblem(constraints=(TipConstraint((0.0, 1.0), float(exact.b), (0.0, -1.0)),))
    right = solve_path(problem, n_samples=2)
    assert right.converged, right.message
    assert abs(right.x - exact.a) < 1e-10 and abs(right.y - exact.b) < 1e-10
    assert abs(right.force[0]) < 1e-10 and abs(right.force[1] - load) < 1e-9
    real = ig.Structure

    def exchanged(**fields):
        d, forces = fields["dirs"], fields["forces"]
        fields["dirs"], fields["forces"] = forces.force_dirs, forces._replace(force_dirs=d)
        return real(**fields)

    monkeypatch.setattr(ig, "Structure", exchanged)
    swapped = solve_path(problem, n_samples=2)
    assert swapped.converged, swapped.message  # a problem of its own: -y(L) = b, force along +y
    assert abs(swapped.x - exact.a) < 1e-9 and abs(swapped.y + exact.b) < 1e-9
    assert abs(swapped.y - exact.b) > 1.0
