"""The place map an agent acts on: built once from a scripted tour, then kept fixed.

Training on a fixed map keeps place ids stable while the policy learns them. The map is the
online recognizer of seed 000 run over a scripted tour of the world
(:func:`envs.tasks.tour.drive_tour`).
Beside the map, ``map_edges.json`` records for each pair of places (a, b) the compass heading
the robot drove in when the recognizer moved from a to b: what a classical topological planner
(:mod:`envs.agents.topological`) needs to drive along the graph.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the environments)
from envs.tasks.tour import drive_tour
from placeclust import OnlinePlaceClustering

MAP_FILE = "map.npz"
EDGES_FILE = "map_edges.json"


def build_map(out: str | Path, scene_seed: int = 0, n_rooms: int = 4, features: str = "orb",
              steps: int = 1500, seed: int = 0, progress: bool = True,
              recognizer: dict[str, Any] | None = None, **world: object) -> Path:
    """Drive a tour, map it, and write ``map.npz`` and ``map_edges.json`` into ``out``.

    ``recognizer`` takes more :class:`~placeclust.OnlinePlaceClustering` arguments (the
    training config's ``map`` section: ``t_new_cluster``...). ``world`` takes more
    ``PlaceNav-v0`` arguments (``panorama_width``, ``extra_doors``...); the map only fits envs
    made with the same ones.

    Returns:
        The path of the map file.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    env = gym.make("PlaceNav-v0", scene_seed=scene_seed, n_rooms=n_rooms, max_episode_steps=None,
                   **world)
    try:
        tour = drive_tour(env, steps, seed=seed, progress=progress)
        world = env.unwrapped.world_id
    finally:
        env.close()
    model = OnlinePlaceClustering(features, **(recognizer or {}))
    places = np.array([model.learn_predict_one(f) for f in tour.frames])
    model.save(out / MAP_FILE, world=world)
    edges = edge_headings(places, tour.pose[:, 2])
    (out / EDGES_FILE).write_text(json.dumps({"world": world, "edges": edges}, indent=1))
    return out / MAP_FILE


def edge_headings(places: np.ndarray, headings: np.ndarray, window: int = 10
                  ) -> list[tuple[int, int, float]]:
    """(a, b, heading) for each place transition a -> b seen in a sequence.

    The heading is the circular mean over all a -> b transitions of the robot's heading over the
    ``window`` frames before each transition (unknown frames, -1, are skipped).
    """
    sums: dict[tuple[int, int], complex] = {}
    last = -1
    for t, p in enumerate(places.tolist()):
        if p < 0:
            continue
        if last >= 0 and p != last:
            h = headings[max(t - window, 0):t]
            sums[(last, p)] = sums.get((last, p), 0j) + complex(np.exp(1j * h).sum())
        last = p
    return [(a, b, math.atan2(z.imag, z.real)) for (a, b), z in sorted(sums.items())]
