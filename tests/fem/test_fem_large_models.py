"""A mesh too fine for double precision is refused before the first step, with the reason, instead of
being stepped for ever (`fem.conditioning`).

The quantity: rcond_1 of the Jacobi-scaled unloaded tangent S = D K0 D. A Newton correction computed
from K has a relative error up to about u kappa; a beam's kappa grows as the fourth power of its
elements per member (the discrete biharmonic operator), so a cantilever reaches 1/u near 5500 elements.
Stepped anyway, such a mesh gets corrections without a correct digit: Newton converges linearly, a step
takes about as many iterations however short it is, the step control stops growing the steps, and
the load is crawled through in ever more of them.
"""

import numpy as np
import pytest

import fem
from fem.assembly import System
from fem.conditioning import UNIT_ROUNDOFF, beyond_precision, scaled_rcond
from fem.discretise import discretise
from fem.linear_solver import inverse_norm1


def _cantilever(n_elements: int) -> fem.Model:
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.from_EI(EA=1e4, EI=1.0), n_elements=n_elements)
    model.add_support("root", "fixed")
    model.add_force("tip", 0.0, [0.5, 1.0, 2.0])
    return model


def _system(n_elements: int, kind: str = "auto") -> System:
    model = _cantilever(n_elements)
    return System(model, discretise(model), solver_kind=kind)


def _scaled_unloaded_tangent(system: System) -> np.ndarray:
    """The definition: D K0 D of the dense unloaded tangent, D = diag(|K0_ii|^-1/2)."""
    F_fixed, F0, presc = system.loads_at(-1, 0, 0.0)
    K0 = system.layout.to_dense(
        system.evaluate(np.zeros(system.n), system.disc.beta0.copy(), 0.0, F_fixed, F0, presc)["K"]
    )
    d = 1.0 / np.sqrt(np.abs(np.diag(K0)))
    return K0 * d[:, None] * d[None, :]


@pytest.mark.parametrize("kind", ["dense", "banded", "sparse"])
def test_scaled_rcond_is_an_estimate_of_the_exact_one_never_below_it(kind):
    """Every storage kind: the estimate of rcond_1(D K0 D) from the factors lies between the exact value
    and three times it (Hager-Higham: ||S^-1||_1 never overestimated, in practice within a factor 3)."""
    system = _system(60, kind)
    assert system.layout.kind == kind
    S = _scaled_unloaded_tangent(system)
    exact = 1.0 / np.linalg.cond(S, 1)
    estimate = scaled_rcond(system)
    assert exact <= estimate * (1 + 1e-9) and estimate <= 3.0 * exact


@pytest.mark.parametrize("kind", ["dense", "banded", "sparse"])
def test_scaled_storage_diagonal_and_norm_are_those_of_the_dense_matrix(kind):
    layout = _system(9, kind).layout
    data = np.zeros(layout.size)
    data[layout.entry_flat] = np.random.default_rng(1).normal(size=len(layout.entry_flat))
    A = layout.to_dense(data)
    s = np.linspace(0.5, 2.0, layout.n)
    assert np.array_equal(layout.to_dense(layout.scaled(data, s)), A * (s[:, None] * s[None, :]))
    assert np.array_equal(layout.diagonal(data), np.diag(A))
    assert layout.norm1(data) == pytest.approx(np.abs(A).sum(axis=0).max(), rel=1e-14)


def test_condition_number_grows_as_the_fourth_power_of_the_elements():
    """What made the large models hang: kappa(S) u, the relative error of a correction, 16 times larger
    for every doubling of the mesh, about 1 near 5500 elements."""
    rc = [scaled_rcond(_system(n)) for n in (250, 500, 1000)]
    for coarse, fine in zip(rc, rc[1:]):
        assert 12.0 < coarse / fine < 20.0
    assert 1e-4 < UNIT_ROUNDOFF / rc[-1] < 1e-2  # 1000 elements: far within working precision


def test_the_limit_lies_between_4000_and_8000_elements():
    assert beyond_precision(_system(4000)) is None
    why = beyond_precision(_system(8000))
    assert why is not None and "singular to working precision" in why and "fewer elements" in why


@pytest.mark.parametrize("control", ["load", "displacement", "arclength"])
def test_a_mesh_too_fine_for_double_precision_stops_with_why(control):
    """Every control mode stops at its first failed Newton attempt or its PRECISION_STEPS-th step,
    whichever comes first, and says why (the previous code stepped on for ~80 steps under load
    control, and ran 452 s at 20,000 elements)."""
    from fem.solver import PRECISION_STEPS

    model = _cantilever(8000)
    kwargs = {
        "load": {},
        "displacement": dict(control_dof=("tip", "uy"), targets=[0.1]),
        "arclength": dict(lambda_max=1.0),
    }[control]
    result = fem.solve(model, control=control, **kwargs)
    assert not result.converged and result.status == "not converged"
    assert result.steps <= PRECISION_STEPS
    assert "singular to working precision" in result.message


def test_a_run_that_steps_cleanly_is_not_tested_for_precision(monkeypatch):
    """The precision test is made only when a run shows trouble: a small cantilever whose steps all
    converge at once never calls it."""
    from fem import solver

    monkeypatch.setattr(solver, "beyond_precision", lambda system: pytest.fail("tested"))
    assert fem.solve(_cantilever(16)).converged


def test_inverse_norm_estimate_is_a_lower_bound_and_costs_a_few_solves():
    """`inverse_norm1` on matrices whose ||A^-1||_1 is known: a lower bound of it, within a factor 3, with
    at most 11 solves (dlacn2's iteration), so that the refusal of a large band costs O(n)."""
    rng = np.random.default_rng(3)
    for n in (1, 2, 7, 40):
        A = rng.normal(size=(n, n)) + n * np.eye(n)
        count = []

        def solve(b, transposed=False):
            count.append(1)
            return np.linalg.solve(A.T if transposed else A, b)

        exact = np.abs(np.linalg.inv(A)).sum(axis=0).max()
        estimate = inverse_norm1(solve, n)
        assert estimate <= exact * (1 + 1e-12) and estimate >= exact / 3.0
        assert len(count) <= 11
