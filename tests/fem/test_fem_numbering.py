"""The compiled reverse Cuthill-McKee numbering (`fem.numbering`) and the all-levels field series.

Expected orders come from the algorithm as Cuthill & McKee (1969) and George (1971) state it, written
here independently in plain Python (start at the unvisited node of least degree, visit neighbours by
increasing degree, reverse), and from the bandwidth of graphs whose optimum is known by inspection.
"""

from __future__ import annotations

import numpy as np
import pytest

import fem
from fem.numbering import rcm_order


def _textbook_rcm(n, edges):
    adj = [[] for _ in range(n)]
    for a, b in edges:
        adj[a].append(b)
        adj[b].append(a)
    degree = [len(x) for x in adj]
    seen, order = [False] * n, []
    for start in sorted(range(n), key=degree.__getitem__):
        if seen[start]:
            continue
        seen[start] = True
        queue = [start]
        for v in queue:
            for w in sorted(adj[v], key=degree.__getitem__):
                if not seen[w]:
                    seen[w] = True
                    queue.append(w)
        order += queue
    return order[::-1]


@pytest.mark.parametrize("seed", range(5))
def test_rcm_order_is_the_textbook_order_on_random_graphs(seed):
    rng = np.random.default_rng(seed)
    for _ in range(200):
        n = int(rng.integers(1, 30))
        conn = rng.integers(0, n, (int(rng.integers(0, 45)), 2))
        k = int(rng.integers(0, 3))
        slaves, masters = rng.integers(0, n, k), rng.integers(0, n, k)
        edges = [tuple(e) for e in conn.tolist()] + list(zip(slaves.tolist(), masters.tolist()))
        assert rcm_order(n, conn, slaves, masters).tolist() == _textbook_rcm(n, edges)


def _bandwidth(order, conn):
    position = np.empty(len(order), int)
    position[order] = np.arange(len(order))
    return int(np.max(np.abs(position[conn[:, 0]] - position[conn[:, 1]])))


def test_a_shuffled_chain_is_numbered_along_the_chain():
    """A chain (a beam's element nodes) in any labelling: RCM numbers it end to end, bandwidth 1."""
    labels = np.random.default_rng(3).permutation(40)
    conn = np.column_stack([labels[:-1], labels[1:]])
    order = rcm_order(40, conn, np.zeros(0, int), np.zeros(0, int))
    assert sorted(order.tolist()) == list(range(40))
    assert _bandwidth(order, conn) == 1


def test_a_ladder_has_bandwidth_two():
    """Two chains of m nodes joined rung by rung: the optimal bandwidth is 2 (rung by rung)."""
    m = 12
    rails = [(i, i + 1) for i in range(m - 1)] + [(m + i, m + i + 1) for i in range(m - 1)]
    rungs = [(i, m + i) for i in range(m)]
    conn = np.array(rails + rungs)
    order = rcm_order(2 * m, conn, np.zeros(0, int), np.zeros(0, int))
    assert _bandwidth(order, conn) == 2


def test_field_series_is_nodal_fields_at_every_level():
    """The all-levels field series (one pass) against the per-level `nodal_fields`, bit for bit, on a
    frame with a stress-aware section loaded in three levels."""
    model = fem.Model()
    model.add_node("a", 0.0, 0.0)
    model.add_node("b", 0.0, 1.0)
    model.add_node("c", 1.0, 1.0)
    section = fem.Section.rectangle(2e5, 0.05, 0.01)
    model.add_member("a", "b", section, n_elements=5)
    model.add_member("b", "c", section, n_elements=7)
    model.add_support("a", "fixed")
    model.add_force("c", [1e-4, 2e-4, 3e-4], [-2e-4, -4e-4, -6e-4])  # P L^2/EI up to about 0.8
    result = fem.solve(model)
    assert result.converged
    series = result.field_series()
    assert len(series.nodal) == 3
    for k in range(3):
        one = result.nodal_fields(k)
        for name in ("displacement", "rotation", "curvature", "bending_moment", "axial_force", "bending_stress"):
            assert np.array_equal(getattr(series.nodal[k], name), getattr(one, name)), (k, name)
    assert np.max(np.abs(series.nodal[2].bending_moment)) > 0.0


@pytest.mark.parametrize("n, edges", [(1, 0), (7, 2), (200, 150), (3000, 2500)])
def test_large_graphs_with_many_ties_are_numbered_in_the_textbook_order(n, edges):
    """Many components and isolated nodes, degrees 0-4 with many ties: the starting nodes are taken by
    degree, equal degrees by index, and neighbours by degree, equal degrees in edge order (the stable
    sorts of the textbook order), on graphs far larger than the random ones above."""
    rng = np.random.default_rng(n)
    conn = rng.integers(0, n, (edges, 2))
    none = np.zeros(0, int)
    assert rcm_order(n, conn, none, none).tolist() == _textbook_rcm(n, [tuple(e) for e in conn.tolist()])
