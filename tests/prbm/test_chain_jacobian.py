"""The Chain Algorithm's exact Jacobian (``prbm.chain.march_jacobian``) against central differences of
the march itself (eqs 26-40): the forward solve's Newton steps use it, so a wrong sign or factor in the
differentiated march would slow or mislead that solve without this check."""

from __future__ import annotations

import numpy as np
import pytest

from prbm.chain import ChainBeam, NodalLoads, march, march_jacobian


def _central_differences(beam, loads, nodes, h=1e-6):
    x = nodes[1:].ravel()

    def out(z):
        return march(beam, loads, np.vstack([[0.0, 0.0], z.reshape(-1, 2)])).nodes[1:].ravel()

    columns = []
    for k in range(x.size):
        step = np.zeros_like(x)
        step[k] = h
        columns.append((out(x + step) - out(x - step)) / (2 * h))
    return np.column_stack(columns)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_exact_jacobian_is_the_march_differentiated(seed):
    """A curved chain with per-element EI, compressive and tensile element forces and nodal moments,
    at a perturbed (not equilibrium) shape: every entry agrees with central differences."""
    rng = np.random.default_rng(seed)
    n = 7
    beam = ChainBeam(2.0, tuple(rng.uniform(1.0, 4.0, n)), n, orientations=tuple(rng.uniform(-0.4, 0.4, n)))
    loads = NodalLoads(rng.normal(size=n + 1), rng.normal(size=n + 1), rng.normal(size=n + 1))
    nodes = beam.undeformed() + np.vstack([[0.0, 0.0], rng.normal(scale=0.05, size=(n, 2))])
    exact = march_jacobian(beam, loads, nodes)
    assert exact.shape == (2 * n, 2 * n)
    assert np.abs(exact).max() > 0.1  # the loads are not negligible: a zero Jacobian would not pass
    assert exact == pytest.approx(_central_differences(beam, loads, nodes), abs=1e-8)


@pytest.mark.parametrize("held", [("rz",), ("uy",), ("uy", "rz"), ("ux", "uy", "rz")])
def test_the_held_path_jacobian_is_its_residual_differentiated(held):
    """``chain_held_path``'s Jacobian (``_held_jacobian``: node columns through the moments, a tip
    moment's column as the moments' sum, a tip force's by central differences) against central
    differences of the residual it solves (node positions fed back, the held freedoms' end conditions),
    on a curved chain with per-element EI under a distributed load, at a perturbed shape with nonzero
    tip loads."""
    from prbm.chain import HELD_FREEDOMS, _held_jacobian, lumped_uniform_load

    rng = np.random.default_rng(len(held))
    n = 9
    beam = ChainBeam(1.3, tuple(rng.uniform(1.0, 3.0, n)), n, orientations=tuple(np.linspace(0.0, 0.8, n)))
    kept = [HELD_FREEDOMS.index(h) for h in held]
    applied = lumped_uniform_load(beam, 0.7, -1.9)
    rest = beam.undeformed()
    target = (rest[-1, 0], rest[-1, 1], 0.0)
    z = np.concatenate([(rest[1:] + rng.normal(scale=0.05, size=(n, 2))).ravel(), rng.normal(size=len(kept))])

    def tip_loads(reactions):
        components = [0.0, 0.0, 0.0]
        for k, r in zip(kept, reactions):
            components[k] = float(r)
        return NodalLoads.at_tip(beam, *components)

    def residual(x, level):
        nodes = np.vstack([[0.0, 0.0], x[: 2 * n].reshape(-1, 2)])
        state = march(beam, applied.scaled(level).plus(tip_loads(x[2 * n :])), nodes)
        tip = (state.nodes[-1, 0], state.nodes[-1, 1], state.rotations[-1])
        ends = [(tip[k] - target[k]) / (beam.length if k < 2 else 1.0) for k in kept]
        return np.concatenate([(state.nodes[1:] - nodes[1:]).ravel(), ends])

    exact = _held_jacobian(beam, applied.scaled(0.8), tip_loads, kept, z, residual, 0.8)
    h = 1e-6
    numeric = np.column_stack([(residual(z + h * e, 0.8) - residual(z - h * e, 0.8)) / (2 * h) for e in np.eye(z.size)])
    assert np.abs(exact[2 * n :]).max() > 0.1  # the end-condition rows are not trivially zero
    assert exact == pytest.approx(numeric, abs=1e-7)
