"""A classical agent, no learning: shortest path over the recognizer's places, then steering.

The graph is the online recognizer's own topological map (seed 000); the goal place is where
the recognizer puts the goal panorama. Each edge a -> b carries the compass heading the robot
drove in when the recognizer moved from a to b on the mapping tour (:mod:`train.mapping`). At
each step the agent takes the first edge of the shortest path from its current place to the goal
place and steers along that edge's heading, avoiding obstacles with its rangefinders. Where it has
no edge to follow (lost, or already at the goal place but not yet in the goal room) it wanders.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import networkx as nx
import numpy as np

from placeclust import UNKNOWN, OnlinePlaceClustering
from placeclust.protocol import place_of

from ..world.robot import N_RANGES


def steer(heading: np.ndarray, ranges: np.ndarray, target: float | None,
          rng: np.random.Generator) -> np.ndarray:
    """(forward, turn) towards compass heading ``target`` (radians), or a wander when None.

    Obstacles closer than 0.5 m on one side push the turn to the other side; the forward speed
    falls as the nearest obstacle ahead comes within 0.8 m.
    """
    yaw = math.atan2(heading[1], heading[0])
    err = 0.0 if target is None else math.remainder(target - yaw, math.tau)
    turn = 2.0 * err if target is not None else float(rng.normal(0.0, 0.3))
    k = N_RANGES // 8
    left, right = ranges[1:2 * k].min(), ranges[-2 * k + 1:].min()
    ahead = min(ranges[0], ranges[1], ranges[-1])
    if min(left, right) < 0.5:
        turn += 1.0 if right < left else -1.0
    if ahead < 0.45 and target is None:
        turn = 1.0 if left > right else -1.0
    forward = float(np.clip((ahead - 0.3) / 0.5, 0.0, 1.0)) * max(0.0, math.cos(err)) ** 2
    return np.array([forward, float(np.clip(turn, -1.0, 1.0))], np.float32)


class TopologicalPlanner:
    """Drives along the recognizer's place graph to the place of the goal panorama.

    Args:
        recognizer: the fixed map (the same object the env's ``PlaceIdWrapper`` localizes on).
        edges: ``(a, b, heading)`` triples, as :func:`train.mapping.edge_headings` gives them.
        seed: for the wander.
    """

    def __init__(self, recognizer: OnlinePlaceClustering, edges: list, seed: int = 0) -> None:
        self.recognizer = recognizer
        self.headings = {(int(a), int(b)): float(h) for a, b, h in edges}
        self.rng = np.random.default_rng(seed)
        self.goal_place = UNKNOWN
        self.place = UNKNOWN

    @classmethod
    def from_files(cls, recognizer: OnlinePlaceClustering, edges_path: str | Path,
                   seed: int = 0) -> TopologicalPlanner:
        return cls(recognizer, json.loads(Path(edges_path).read_text())["edges"], seed)

    def reset(self, goal_panorama: np.ndarray) -> None:
        """Start an episode: find the goal panorama's place anywhere on the map."""
        # asked of a copy: the robot is not where the panorama was taken
        self.goal_place = place_of(self.recognizer, goal_panorama, rank=False)
        self.place = UNKNOWN

    def next_heading(self, place: int) -> float | None:
        """Heading of the first edge on the shortest path from ``place`` to the goal place."""
        g = self.recognizer.graph
        if place == UNKNOWN or self.goal_place == UNKNOWN or place == self.goal_place:
            return None
        try:
            path = nx.shortest_path(g, place, self.goal_place)
        except (nx.NetworkXNoPath, nx.NodeNotFound):
            return None
        a, b = path[0], path[1]
        if (a, b) in self.headings:
            return self.headings[(a, b)]
        if (b, a) in self.headings:  # only driven the other way: go back the way it came
            return math.remainder(self.headings[(b, a)] + math.pi, math.tau)
        return None

    def act(self, obs: dict[str, np.ndarray], info: dict) -> np.ndarray:
        """The action for one step, from the observation and the wrapper's raw ``place_id``."""
        if info.get("place_id", UNKNOWN) != UNKNOWN:
            self.place = info["place_id"]
        return steer(obs["heading"], obs["ranges"], self.next_heading(self.place), self.rng)
