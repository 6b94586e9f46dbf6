"""The guided tour's path as a graph of free space: the one roadmap every tour-taught agent uses.

A robot that drove a path can drive it again, and where the path passed close to itself (a
door driven through twice) it can cross from one pass to the other. :class:`Roadmap` keeps the
tour's dead-reckoned positions as nodes (every step, or one every ``spacing`` metres), joins
each node to the next and to any other within ``join`` metres, and, given the recognizer's
labels of the steps, also to any node of the same place within a farther radius: a place the
recognizer reports as one room has no wall inside it.

Two kinds of question are asked of it, each with the search that suits it:

- :meth:`Roadmap.route`: the nodes from one node to another, the whole map or only some of its
  nodes (the planners of :mod:`~envs.agents.teach_repeat`, asked once a hop);
- :meth:`Roadmap.way`: the "carrot" ``ahead`` metres on toward a goal from any position, and
  the distance left (:mod:`~envs.agents.tour_features`, asked every step; the shortest-path
  tree to each goal is computed once and kept).

The agents choose their own resolution. The planners use every step and join within
``OVERLAP`` (0.4 m) and ``SAME_PLACE`` (1.2 m) of a place (:mod:`~envs.agents.teach_repeat`);
the learned agents' features use a node every 0.2 m joined within 0.3 m and no place labels,
because the ``noplace`` agent must see the same roadmap as the others
(:mod:`~envs.agents.tour_features`).

Examples:
    >>> import numpy as np
    >>> from envs.agents.roadmap import Roadmap
    >>> east = np.stack([np.linspace(0, 2, 21), np.zeros(21)], axis=1)
    >>> back = np.stack([np.linspace(2, 0, 21), np.full(21, 0.1)], axis=1)
    >>> road = Roadmap(np.concatenate([east, back]), join=0.15)
    >>> len(road.route(0, 41))  # across from the first pass to the second, not round the end
    2
    >>> carrot, left = road.way(goal=20, position=np.array([0.0, 0.0]), ahead=1.0)
    >>> carrot.round(2).tolist(), round(left, 2)
    ([1.0, 0.0], 2.0)
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import networkx as nx
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree


class Roadmap:
    """The tour's path as a weighted graph of its nodes (edge weights are metres).

    Args:
        path: (T, 2) tour positions (m), in driving order.
        spacing: metres between consecutive nodes; 0 keeps every step (node ``i`` is step ``i``).
        join: nodes this close (m) are joined wherever they lie on the path.
        places: (T,) place of each step (negative: unknown); with ``same_place``, nodes of one
            place within ``same_place`` metres are joined too.
        same_place: the radius (m) of those joins; ignored without ``places``.
    """

    def __init__(self, path: np.ndarray, spacing: float = 0.0, join: float = 0.4,
                 places: np.ndarray | None = None, same_place: float = 0.0) -> None:
        self.steps = _every(path, spacing)
        self.nodes = np.asarray(path, float)[self.steps]
        self.tree = cKDTree(self.nodes)
        near = self.tree.query_pairs(join)
        if places is not None and same_place > 0:
            label = np.asarray(places)[self.steps]
            same = {(i, j) for i, j in self.tree.query_pairs(same_place)
                    if label[i] == label[j] >= 0}
            near = near | same
        self._joins = near
        self._graph: nx.Graph | None = None
        self._matrix = None
        self._ways: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def __len__(self) -> int:
        return len(self.nodes)

    def node_of_step(self, step: int) -> int:
        """The node at or last before tour step ``step``."""
        return int(np.searchsorted(self.steps, step, side="right") - 1)

    @property
    def graph(self) -> nx.Graph:
        """The roadmap as a networkx graph: the path's edges first, then the joins."""
        if self._graph is None:
            graph = nx.Graph()
            n = len(self.nodes)
            step = np.linalg.norm(np.diff(self.nodes, axis=0), axis=1)
            graph.add_weighted_edges_from(zip(range(n - 1), range(1, n), step.tolist()))
            pairs = np.array(list(self._joins), np.int64).reshape(-1, 2)  # the set's order kept
            length = np.linalg.norm(self.nodes[pairs[:, 0]] - self.nodes[pairs[:, 1]], axis=1)
            graph.add_weighted_edges_from(zip(*pairs.T.tolist(), length.tolist()))
            self._graph = graph
        return self._graph

    def route(self, start: int, target: int, within: Iterable[int] | None = None
              ) -> list[int] | None:
        """The shortest chain of nodes from ``start`` to ``target`` (both included), through
        the nodes ``within`` only if given (``start`` and ``target`` among them); ``None``
        where no chain leads there."""
        graph = self.graph if within is None else self.graph.subgraph(within)
        try:
            return list(nx.shortest_path(graph, start, target, weight="weight"))
        except (nx.NetworkXNoPath, nx.NodeNotFound):
            return None

    def way(self, goal: int, position: np.ndarray, ahead: float) -> tuple[np.ndarray, float]:
        """The carrot, the node ``ahead`` metres on from the node nearest ``position`` toward
        node ``goal``, and the distance (m) left: to that nearest node, then along the map."""
        if goal not in self._ways:  # the next node toward the goal, from every node
            dist, pred = dijkstra(self._csr(), directed=False, indices=goal,
                                  return_predecessors=True)
            self._ways[goal] = (dist, pred)
        dist, pred = self._ways[goal]
        gap, node = self.tree.query(position)
        left = float(dist[node]) + float(gap)
        walked = 0.0
        while walked < ahead and pred[node] >= 0:
            walked += float(np.linalg.norm(self.nodes[pred[node]] - self.nodes[node]))
            node = int(pred[node])
        return self.nodes[node], left

    def _csr(self):
        """The roadmap as a sparse matrix for scipy's shortest paths; each weight is raised by
        1 micrometre (as the learned agents were trained with), so no hop is free."""
        if self._matrix is None:
            n = len(self.nodes)
            pairs = {(i, i + 1) for i in range(n - 1)} | self._joins
            i, j = np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2).T
            w = np.linalg.norm(self.nodes[i] - self.nodes[j], axis=1) + 1e-6
            self._matrix = coo_matrix((w, (i, j)), shape=(n, n)).tocsr()
        return self._matrix


def _every(path: np.ndarray, spacing: float) -> np.ndarray:
    """The steps kept as nodes: the first, then each at least ``spacing`` m from the last kept."""
    if spacing <= 0:
        return np.arange(len(path))
    keep = [0]
    for t in range(1, len(path)):
        if math.dist(path[t], path[keep[-1]]) >= spacing:
            keep.append(t)
    return np.asarray(keep)
