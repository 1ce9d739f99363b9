"""Node numbering in reverse Cuthill-McKee order (small bandwidth of the banded tangent), compiled
(numba, ``cache=True``).

The graph: element nodes joined by elements and by rigid links (slave to master). Cuthill-McKee
(Cuthill & McKee 1969): starting from the unvisited node of smallest degree, a breadth-first search
that visits each node's neighbours in order of increasing degree; every connected component in
turn; the order reversed (George 1971). Ties are broken by position: nodes by index, neighbours in
the order their edges are listed (stable sorts), so the numbering is a function of the model alone.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .types import IntArray

__all__ = ["rcm_order"]


@njit(cache=True, no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # an option numba's annotations omit
def _rcm(n_nodes: int, a: IntArray, b: IntArray) -> IntArray:
    """Reverse Cuthill-McKee order of the nodes 0 .. n_nodes-1 of the graph with edges (a[k], b[k]).

    One compiled function (numba compiles and optimises each jitted function on its own: the two sorts
    as functions of their own would add their own compile in every fresh checkout): each node's
    neighbours sorted by degree by an insertion sort, equal degrees kept in the order their edges are
    listed; the search's starting nodes by degree, equal degrees by index (``np.argsort(degree,
    kind='stable')``), by a counting sort (the degrees are small integers)."""
    degree = np.empty(n_nodes, np.int64)
    for v in range(n_nodes):
        degree[v] = 0
    for k in range(a.shape[0]):
        degree[a[k]] += 1
        degree[b[k]] += 1
    start = np.empty(n_nodes + 1, np.int64)
    start[0] = 0
    for v in range(n_nodes):
        start[v + 1] = start[v] + degree[v]
    fill = np.empty(n_nodes, np.int64)  # where each node's next neighbour goes
    for v in range(n_nodes):
        fill[v] = start[v]
    adj = np.empty(start[n_nodes], np.int64)
    for k in range(a.shape[0]):  # neighbours in the order the edges are listed
        adj[fill[a[k]]] = b[k]
        fill[a[k]] += 1
        adj[fill[b[k]]] = a[k]
        fill[b[k]] += 1
    top = 0
    for v in range(n_nodes):  # each node's neighbours by degree (stable insertion sort)
        for i in range(start[v] + 1, start[v + 1]):
            w = adj[i]
            j = i - 1
            while j >= start[v] and degree[adj[j]] > degree[w]:
                adj[j + 1] = adj[j]
                j -= 1
            adj[j + 1] = w
        if degree[v] > top:
            top = degree[v]
    first = np.empty(top + 2, np.int64)  # the starting nodes by degree: first[d], where degree d begins
    for d in range(top + 2):
        first[d] = 0
    for v in range(n_nodes):
        first[degree[v] + 1] += 1
    for d in range(top + 1):
        first[d + 1] += first[d]
    roots = np.empty(n_nodes, np.int64)
    for v in range(n_nodes):
        roots[first[degree[v]]] = v
        first[degree[v]] += 1
    seen = np.empty(n_nodes, np.int64)  # 1: visited
    for v in range(n_nodes):
        seen[v] = 0
    order = np.empty(n_nodes, np.int64)
    tail = 0
    for i in range(n_nodes):
        r = roots[i]
        if seen[r]:
            continue
        seen[r] = 1
        head = tail
        order[tail] = r
        tail += 1
        while head < tail:
            v = order[head]
            head += 1
            for k in range(start[v], start[v + 1]):
                w = adj[k]
                if not seen[w]:
                    seen[w] = 1
                    order[tail] = w
                    tail += 1
    reverse = np.empty(n_nodes, np.int64)
    for i in range(n_nodes):
        reverse[i] = order[n_nodes - 1 - i]
    return reverse


def rcm_order(n_nodes: int, conn: IntArray, slaves: IntArray, masters: IntArray) -> IntArray:
    """Nodes in reverse Cuthill-McKee order, for the elements ``conn`` (n_el, 2) and the rigid links
    (``slaves[k]`` to ``masters[k]``)."""
    a = np.concatenate([np.asarray(conn[:, 0], np.int64), np.asarray(slaves, np.int64)])
    b = np.concatenate([np.asarray(conn[:, 1], np.int64), np.asarray(masters, np.int64)])
    order: IntArray = _rcm(int(n_nodes), a, b)
    return order
