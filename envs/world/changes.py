"""Appearance changes between visits to one building, as in the COLD database's recordings.

The building (rooms, walls, doors, textures) stays the one ``scene_seed`` fixes; a
:class:`Changes` redraws some of what people move — furniture moved along another wall or taken
away, posters swapped between walls — and degrades the camera with pixel noise and blur. Every
change is drawn from its own ``seed``, never from the scene's random stream, so a world with
``Changes()`` (none) is pixel for pixel the world without.

:data:`envs.world.conditions.CONDITIONS` names the changes the benchmark crosses
(``day>moved``...).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import cv2
import mujoco
import numpy as np

from .layout import FloorPlan, clear_of, draw_item
from .robot import RADIUS


@dataclass(frozen=True)
class Changes:
    """What differs from the building as ``scene_seed`` made it.

    Args:
        furniture_moved: fraction of furniture items redrawn at another free spot along a wall
            of their room (an item with no free spot stays).
        furniture_removed: fraction of furniture items taken out of the building.
        posters_swapped: fraction of posters whose pictures are exchanged among themselves.
        camera_noise: standard deviation of Gaussian pixel noise, grey levels (0-255).
        camera_blur: standard deviation of a Gaussian blur, pixels.
        seed: seed of every draw above (the noise is also reseeded by ``reset(seed=...)``).
    """

    furniture_moved: float = 0.0
    furniture_removed: float = 0.0
    posters_swapped: float = 0.0
    camera_noise: float = 0.0
    camera_blur: float = 0.0
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("furniture_moved", "furniture_removed", "posters_swapped"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ValueError(f"{name} must be a fraction in [0, 1], got {value}")
        for name in ("camera_noise", "camera_blur"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be finite and non-negative, got {value}")

    @property
    def camera(self) -> bool:
        """True when frames are degraded after rendering."""
        return self.camera_noise > 0 or self.camera_blur > 0


def rearrange_furniture(plan: FloorPlan, changes: Changes) -> FloorPlan:
    """``plan`` with a fraction of its furniture moved and another fraction removed."""
    if not (changes.furniture_moved or changes.furniture_removed):
        return plan
    rng = np.random.default_rng([changes.seed, 1])
    items = list(plan.furniture)
    n = len(items)
    order = rng.permutation(n)
    n_removed = round(changes.furniture_removed * n)
    removed = set(order[:n_removed].tolist())
    moved = order[n_removed:n_removed + round(changes.furniture_moved * n)].tolist()
    kept = {i: f for i, f in enumerate(items) if i not in removed}
    for i in moved:
        f = kept.pop(i)
        room = plan.rooms[f.room]
        others = [o for o in kept.values() if o.room == f.room]
        for _ in range(20):
            candidate = draw_item(room, f.kind, rng)
            if clear_of(candidate, others, list(plan.doors)):
                f = candidate
                break
        kept[i] = f
    return replace(plan, furniture=tuple(kept[i] for i in sorted(kept)))


def swap_posters(spec: mujoco.MjSpec, names: Sequence[str], changes: Changes) -> int:
    """Exchange the materials of a fraction of the posters ``names`` (geoms of ``spec``, as
    :func:`envs.world.scene.build_scene` hung them); returns how many moved."""
    posters = [spec.geom(name) for name in names]
    k = round(changes.posters_swapped * len(posters))
    if k < 2:
        return 0
    rng = np.random.default_rng([changes.seed, 2])
    chosen = [posters[i] for i in rng.choice(len(posters), k, replace=False)]
    materials = [g.material for g in chosen]
    shift = int(rng.integers(1, k))  # a cyclic shift: every chosen poster changes picture
    for g, mat in zip(chosen, materials[shift:] + materials[:shift]):
        g.material = mat
    return k


def degrade(frame: np.ndarray, changes: Changes, rng: np.random.Generator,
            wrap: bool = True) -> np.ndarray:
    """``frame`` (H, W, 3) uint8 blurred and with pixel noise, as a cheap camera would see it.

    ``wrap``: the frame is a 360° panorama, whose left and right edges are neighbours, so the
    blur wraps around them; a forward image's edges are not (``wrap=False``: mirrored edges).
    """
    out = frame
    if changes.camera_blur > 0 and wrap:
        pad = int(np.ceil(3 * changes.camera_blur))
        wide = cv2.copyMakeBorder(out, 0, 0, pad, pad, cv2.BORDER_WRAP)
        out = cv2.GaussianBlur(wide, (0, 0), changes.camera_blur)[:, pad:pad + frame.shape[1]]
    elif changes.camera_blur > 0:
        out = cv2.GaussianBlur(out, (0, 0), changes.camera_blur)
    if changes.camera_noise > 0:
        noise = rng.normal(0.0, changes.camera_noise, out.shape)
        out = np.clip(out + noise, 0, 255).astype(np.uint8)
    return np.ascontiguousarray(out)


def clear_pose(plan: FloorPlan, pose: Sequence[float] | np.ndarray, clearance: float = RADIUS + 0.05
               ) -> tuple[float, float, float]:
    """``pose``, or where furniture moved onto it since, the nearest pose of the same room
    (within 2 m) that clears it: the robot stays where the tour left it, not inside a desk."""
    x, y, yaw = (float(v) for v in pose)

    def clear(px: float, py: float) -> bool:
        return all(abs(px - f.x) > f.hx + clearance or abs(py - f.y) > f.hy + clearance
                   for f in plan.furniture)

    if clear(x, y):
        return x, y, yaw
    room = plan.room_at(x, y)
    for r in np.arange(0.1, 2.0, 0.1):
        for a in np.linspace(0.0, 2 * math.pi, 16, endpoint=False):
            px, py = x + r * math.cos(a), y + r * math.sin(a)
            if plan.room_at(px, py) == room and plan.is_free(px, py, clearance):
                return float(px), float(py), yaw
    return x, y, yaw
