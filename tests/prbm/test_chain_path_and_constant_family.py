"""The Chain Algorithm's continuation along growing load, and the constant-parameter fit family."""

from __future__ import annotations

import math

import numpy as np
import pytest

import elastica
import prbm
from prbm import chain


def test_the_chain_path_lands_where_the_chain_does_level_by_level():
    """Continuation and the level's own load steps solve the same equations (eqs 26-40): one equilibrium."""
    beam = chain.ChainBeam(1.0, 1.0, 20)
    unit = chain.lumped_uniform_load(beam, 0.0, 1.0)
    path = chain.chain_path(beam, unit, [0.5, 2.0, 6.0])
    for factor, res in zip([0.5, 2.0, 6.0], path):
        alone = chain.chain_tip(beam, unit.scaled(factor), steps=10)
        assert res.converged and alone.converged
        assert float(res.outputs["b"]) == pytest.approx(float(alone.outputs["b"]), abs=1e-9)
        assert float(res.outputs["theta0"]) == pytest.approx(float(alone.outputs["theta0"]), abs=1e-9)


def test_the_chain_path_under_a_tip_force_tends_to_the_elastica():
    """40 links at P L^2/EI = 5 against the elliptic solution [bapat2015, eqs 4-7]: O(1/N^2) close."""
    beam = chain.ChainBeam(1.0, 1.0, 40)
    res = chain.chain_path(beam, chain.NodalLoads.at_tip(beam, 0.0, 1.0), [5.0])[0]
    exact = elastica.cantilever_tip_load(5.0)
    assert float(res.outputs["b"]) == pytest.approx(exact.b, abs=2e-3)
    assert float(res.outputs["a"]) == pytest.approx(exact.a, abs=2e-3)


def test_after_a_failed_level_the_path_says_so_for_every_later_level():
    beam = chain.ChainBeam(1.0, 1.0, 4)
    results = chain.chain_path(beam, chain.NodalLoads.at_tip(beam, 0.0, 1.0), [1.0, 1e9, 2e9], max_step=1.0)
    assert results[0].converged
    assert not results[1].converged and not results[2].converged
    assert results[2].message == results[1].message
    assert math.isnan(float(results[2].outputs["b"]))


def test_the_constant_family_is_the_lecture_averages_at_every_n():
    fam = prbm.fit_family("constant")
    g, c, k = fam.parameters(np.array([-3.0, 0.0, 7.5]))
    assert np.all(g == 0.85) and np.all(c == 1.24) and np.all(k == 2.65)
    tip = prbm.fixed_pinned_tip(2.0, 0.0, length=1.0, EI=1.0, family="constant")
    # (F L^2/EI) sin(90 deg - Theta) = K_Theta Theta at F = 2, then b = gamma sin Theta
    Theta = float(tip.outputs["Theta"])
    assert 2.0 * math.cos(Theta) == pytest.approx(2.65 * Theta, rel=1e-10)
    assert float(tip.outputs["b"]) == pytest.approx(0.85 * math.sin(Theta), rel=1e-12)


def test_a_stalled_level_is_retried_in_smaller_steps():
    """At 100 deg the first solve of w L^3/EI = 4.24 from the level below stalls (hybr); the retry in two
    sub-steps reaches it, and every level up to 60 is solved."""
    beam = chain.ChainBeam(1.0, 1.0, 40)
    phi = math.radians(100.0)
    unit = chain.lumped_uniform_load(beam, math.cos(phi), math.sin(phi))
    results = chain.chain_path(beam, unit, np.geomspace(0.1, 60.0, 310))
    assert all(r.converged for r in results)
