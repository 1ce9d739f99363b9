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
