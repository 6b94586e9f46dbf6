"""Scripted tours: the robot drives itself through every room, with revisits and loops.

A route is a sequence of rooms: unvisited rooms first (nearest by door count), then random rooms,
so rooms are revisited, often along another path when the building has loops. Each hop between
rooms becomes waypoints (in front of the door, through it, into the next room) that a
proportional heading controller follows with the robot's own actuators. The result is the
kind of sequence the seed papers record with a driven robot: frames with ground truth.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Protocol, cast

import gymnasium as gym
import networkx as nx
import numpy as np
from numpy.typing import ArrayLike

from placeclust.progress import progress as progress_bar

from ..world.layout import FloorPlan
from ..world.sensor import Sensor
from .camera_sensor import CameraSensor
from .records import TourRecord


class Building(Protocol):
    """What a tour needs of the env under the wrappers: ``PlaceNav-v0``, or a task around it."""

    @property
    def plan(self) -> FloorPlan: ...

    @property
    def image_key(self) -> str: ...


def building(env: gym.Env) -> Building:
    """``env.unwrapped`` (which gymnasium types as a bare ``Env``) as the :class:`Building`."""
    return cast(Building, env.unwrapped)


@dataclass
class Tour:
    """A recorded tour: ``frames`` (T, H, W, 3) uint8, ``room`` (T,) int, ``pose`` (T, 3)."""

    frames: np.ndarray
    room: np.ndarray
    pose: np.ndarray
    room_names: list[str]

    def save(self, path: str, **meta: ArrayLike) -> None:
        """Write ``tour.npz``: the arrays above plus ``room_names`` and any ``meta`` scalars.

        Compressed (zlib): 1000 panoramas of 512x128 take 95 MB instead of 197 MB, for 14 s
        of writing instead of 1.5 s and 3 s of reading instead of 1.5 s (``docs/design.md``,
        "Tour files"); ``np.load`` reads it either way.
        """
        # numpy's stub gives savez a bool ``allow_pickle`` keyword, which mypy lets **meta fill
        # (no caller names a scalar so); passing it would store it on numpy < 2.1
        np.savez_compressed(path, frames=self.frames, room=self.room, pose=self.pose,
                            room_names=np.array(self.room_names),
                            **meta)  # type: ignore[arg-type]

    def export_images(self, folder: str, condition: str) -> None:
        """Write the tour as an image folder (:mod:`placeclust.datasets`): png frames and
        ``labels.csv`` with each frame's room name, pose (metres, radians) and ``condition``,
        as ``placeclust cluster --images`` reads it."""
        from placeclust.datasets import write_image_folder

        names = [self.room_names[r] if r >= 0 else "" for r in self.room]
        write_image_folder(folder, self.frames, names, self.pose, condition)

    def export_vpr_bench(self, folder: str, query: Tour, radius: float) -> list[list[int]]:
        """Write this tour as VPR-Bench's ``ref/``, ``query`` (the same route under another
        condition) as ``query/``, and as ground truth each query's references within
        ``radius`` metres in its room (:func:`placeclust.vprbench.nearby_truth`); returns it."""
        from placeclust.vprbench import nearby_truth, write_vpr_bench

        truth = nearby_truth(self.pose, query.pose, radius, self.room, query.room)
        write_vpr_bench(folder, self.frames, query.frames, truth)
        return truth


def room_route(plan: FloorPlan, start: int, n_hops: int, rng: np.random.Generator) -> list[int]:
    """Rooms to visit in order, starting at ``start``: all rooms first, then random revisits.

    Returns:
        Room ids with consecutive entries adjacent (joined by a door), at least ``n_hops`` long
        when the building has more than one room.
    """
    g = plan.graph()
    route = [start]
    unvisited = set(g.nodes) - {start}
    while len(route) <= n_hops and len(g) > 1:
        here = route[-1]
        lengths = nx.single_source_shortest_path_length(g, here)
        if unvisited:
            nearest = min(lengths[r] for r in unvisited)
            candidates = sorted(r for r in unvisited if lengths[r] == nearest)
        else:  # revisit: prefer rooms not seen recently, so loops get closed
            recent = set(route[-3:])
            candidates = sorted(r for r in g.nodes if r not in recent) or sorted(g.nodes)
        goal = candidates[int(rng.integers(len(candidates)))]
        paths = list(nx.all_shortest_paths(g, here, goal))
        path = paths[int(rng.integers(len(paths)))]
        route += path[1:]
        unvisited -= set(path)
    return route


def waypoints(plan: FloorPlan, route: list[int], rng: np.random.Generator) -> list[tuple]:
    """(x, y, tolerance) points that drive the robot along ``route`` through the doorways."""
    g = plan.graph()
    points: list[tuple] = []
    for a, b in zip(route[:-1], route[1:]):
        door = g.edges[a, b]["door"]
        ra, rb = plan.rooms[a], plan.rooms[b]
        points += [(*door.approach(ra, 0.7), 0.2), (door.x, door.y, 0.25),
                   (*door.approach(rb, 0.7), 0.3)]
        points.append((*_interior_point(plan, b, points[-1][:2], rng), 0.4))
    return points


def _interior_point(plan: FloorPlan, room: int, start: tuple[float, float],
                    rng: np.random.Generator) -> tuple[float, float]:
    """A free point of ``room`` reachable from ``start`` in a straight line, else the centre."""
    for _ in range(20):
        p = plan.free_point(room, rng, clearance=0.5)
        if _segment_free(plan, start, p):
            return p
    return plan.rooms[room].center


def _segment_free(plan: FloorPlan, a: tuple[float, float], b: tuple[float, float]) -> bool:
    n = max(2, int(math.dist(a, b) / 0.1))
    return all(plan.is_free(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, 0.3)
               for t in np.linspace(0.15, 1.0, n))


class WaypointController:
    """Follows waypoints with a proportional heading controller; backs off when stuck."""

    def __init__(self, points: list[tuple], gain: float = 2.0) -> None:
        self.points = list(points)
        self.index = 0
        self.gain = gain
        self._progress: list[float] = []
        self._recover = 0

    @property
    def done(self) -> bool:
        return self.index >= len(self.points)

    def action(self, pose: np.ndarray) -> np.ndarray:
        """Normalised (forward, turn) for the robot at ``pose`` = (x, y, heading)."""
        while not self.done:
            x, y, tol = self.points[self.index]
            if math.dist(pose[:2], (x, y)) > tol:
                break
            self.index += 1
            self._progress.clear()
        if self.done:
            return np.zeros(2)
        if self._recover > 0:  # back up while turning away from whatever blocks the way
            self._recover -= 1
            return np.array([-0.5, 0.8])
        dist = math.dist(pose[:2], (x, y))
        self._progress.append(dist)
        if len(self._progress) > 40 and self._progress[-40] - dist < 0.05:
            self._progress.clear()
            self._recover = 8
        err = math.remainder(math.atan2(y - pose[1], x - pose[0]) - pose[2], math.tau)
        turn = float(np.clip(self.gain * err, -1.0, 1.0))
        forward = 0.8 * max(0.0, math.cos(err)) ** 4 * min(1.0, dist / 0.5 + 0.3)
        return np.array([forward, turn])


def tour_steps(env: gym.Env, steps: int, seed: int = 0) -> Iterator[tuple[dict, dict]]:
    """Drive a scripted tour in a ``PlaceNav`` env, one step at a time, storing nothing.

    Args:
        env: a ``PlaceNav-v0`` env (wrapped or not); it is reset with ``seed``.
        steps: number of observations to yield, at least 1.
        seed: seeds the start pose and the route.

    Yields:
        ``(observation, info)``: the first after the reset, then one after every step, so long
        tours run in constant memory.
    """
    if steps < 1:
        raise ValueError(f"steps must be a positive number of frames, got {steps}")
    plan = building(env).plan
    obs, info = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    controller = WaypointController([])
    for t in range(steps):
        yield obs, info
        if t == steps - 1:
            return
        if controller.done:  # plan the next stretch from wherever the robot is now
            here = max(info["room_id"], 0)
            route = room_route(plan, here, max(2, len(plan.rooms)), rng)
            start = (*plan.rooms[here].center, 0.5) if len(route) == 1 else None
            controller = WaypointController(([start] if start else [])
                                            + waypoints(plan, route, rng))
        obs, _, _, _, info = env.step(controller.action(info["pose"]).astype(np.float32))


def drive_tour(env: gym.Env, steps: int, seed: int = 0, progress: bool = False) -> Tour:
    """Drive ``steps`` steps of a scripted tour (:func:`tour_steps`) and record it.

    Returns:
        The recorded :class:`Tour`; frame ``t`` is the camera's image (the panorama, or the
        forward camera's) after ``t`` steps.
    """
    key = building(env).image_key
    frames = None  # allocated at the first frame, whose size it takes
    rooms, poses = np.empty(steps, np.int64), np.empty((steps, 3))
    bar = progress_bar(total=steps, enabled=progress, desc="tour", unit="frame")
    for t, (obs, info) in enumerate(tour_steps(env, steps, seed)):
        if frames is None:
            frames = np.empty((steps, *obs[key].shape), np.uint8)
        frames[t], rooms[t], poses[t] = obs[key], info["room_id"], info["pose"]
        bar.update(1)
    bar.close()
    assert frames is not None  # tour_steps yields ``steps`` >= 1 frames, or raises
    return Tour(frames, rooms, poses, [r.name for r in building(env).plan.rooms])


def record_tour(scene_seed: int, n_rooms: int, steps: int, seed: int = 0, width: int = 512,
                height: int = 128, lighting: str = "day", progress: bool = True,
                sensor: Sensor | None = None, **env_kwargs: Any) -> tuple[Tour, FloorPlan]:
    """Drive a scripted tour of ``steps`` frames; returns it with the world's floor plan.

    ``env_kwargs`` go to ``PlaceNav-v0`` (appearance changes, see :mod:`envs.world.changes`);
    ``sensor`` puts a real camera's effects on its frames (:class:`CameraSensor`).
    """
    env: gym.Env = gym.make("PlaceNav-v0", scene_seed=scene_seed, n_rooms=n_rooms,
                            panorama_width=width, panorama_height=height, lighting=lighting,
                            max_episode_steps=None, **env_kwargs)
    if sensor is not None and sensor.active:
        env = CameraSensor(env, sensor)
    try:
        tour = drive_tour(env, steps, seed=seed, progress=progress)
        return tour, building(env).plan
    finally:
        env.close()


def guided_tour(env: gym.Env, plan: FloorPlan, read_place: Callable[[dict], int],
                steps_per_room: int, name_after: int, seed: int, control_dt: float
                ) -> tuple[TourRecord, np.ndarray, dict, dict]:
    """The guide's tour of ``PlaceNav-GuidedTour-v1``: :func:`tour_steps` through every room,
    ``steps_per_room`` a room, longer (at most three times) until the guide has named each,
    ``name_after`` steps after the robot first enters it.

    Args:
        env: the env the tour drives (a ``PlaceNav-v0``, or it wrapped with a recognizer).
        plan: its building.
        read_place: the place of a step's ``info``, as the task reads it (-1 unknown).
        steps_per_room, name_after, seed, control_dt: the tour's length, naming and route, and
            seconds per step.

    Returns:
        The :class:`~envs.tasks.records.TourRecord` (raw places), the true room of each step
        (-1 in a doorway), and the last step's observation and info.
    """
    planned = steps_per_room * len(plan.rooms)
    places, heard, odometry, heading, ranges, rooms = [], [], [], [], [], []
    named: set[int] = set()
    run, last_room = 0, -1
    for t, (obs, info) in enumerate(tour_steps(env, 3 * planned, seed=seed)):
        room = info["room_id"]
        run = run + 1 if room == last_room else 1
        last_room = room
        say = ""
        if room >= 0 and room not in named and run >= name_after:
            named.add(room)
            say = plan.rooms[room].name
        places.append(read_place(info))
        heard.append(say)
        odometry.append(obs["odometry"])
        heading.append(obs["heading"])
        ranges.append(obs["ranges"])
        rooms.append(room)
        if t + 1 >= planned and len(named) == len(plan.rooms):
            break
    record = TourRecord(np.array(places, np.int64), np.array(heard, dtype=object),
                        np.array(odometry), np.array(heading), control_dt, np.array(ranges))
    return record, np.array(rooms), obs, info
