"""Light that falls where real light falls: windows, sun patches, lamps and dark corners.

A world option (``PlaceNav-v0(local_light=True)``, off by default). The lightings of
:mod:`envs.world.conditions` light a building with directional suns, an ambient term and a
headlight: each face's brightness changes as a whole, and SIFT, whose descriptors are
normalized, hardly notices (``day>night`` localizes as well as ``day>day``). Real light changes
*what* is lit. With ``local_light=True``:

- exterior walls get **windows** (planes in front of their lining, clear of posters) that show
  the outside: a bright skyline by day, the same skyline greyed under cloud, a dark sky with a
  few lit windows at night;
- every room gets **ceiling lamps** (downlights, some near a wall), on only at night;
- every surface of a room (its floor, its wall linings, posters, furniture) is lit by a gain
  baked into its texture: by day the light from its windows, strongest near them, plus the
  **sun patches** the day's sun throws through them onto the floor and the far walls; under
  cloud the window light without patches; at night the lamps' pools and the scallops they cast
  on the walls near them, and dark corners where SIFT finds no contrast.

The gains are computed per texel (128 per metre, the walls' own texture density) from the
geometry, so a lamp's pool and a patch have sharp edges, as the renderer's per-vertex lighting
could not draw them; rendering costs the same triangles with more texture memory
(``docs/benchmarks.md``). Everything is drawn from its own random stream (``[scene_seed, 3]``),
so the plan, textures and furniture are those of the building without it, and the fixtures are
the same under every lighting.

Examples:
    >>> import numpy as np
    >>> from envs.world.layout import generate_floor_plan
    >>> plan = generate_floor_plan(4, np.random.default_rng(0))
    >>> fixtures = place_fixtures(plan, scene_seed=0, posters={})
    >>> len(fixtures.lamps) >= len(plan.rooms), all(w.z1 > w.z0 for w in fixtures.windows)
    (True, True)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from . import textures
from .conditions import LIGHTS
from .layout import WALL_THICKNESS, FloorPlan, Room

#: baked texels per metre: the density of the walls' tiled textures (256 texels per 2 m)
TEXELS_PER_M = 128
#: lamps hang this high (the walls are 2.2 m); their cone's half-angle, fully lit within
#: ``LAMP_CONE[0]``, dark beyond ``LAMP_CONE[1]`` (degrees)
LAMP_HEIGHT = 2.15
LAMP_CONE = (36.0, 44.0)
#: a lamp's intensity: the floor straight under it gets ``LAMP_POWER / LAMP_HEIGHT**2``
LAMP_POWER = 6.0
#: the gain of a surface no lamp reaches at night, and the highest any gain goes (texels clip)
NIGHT_FLOOR = 0.35
MAX_GAIN = 2.2
#: by day and under cloud: the gain far from any window, what a window adds near it and how
#: fast that fades (m), and what the day's sun adds inside a patch
WINDOW_LIGHT = {"day": (0.7, 0.5, 2.0), "cloudy": (0.72, 0.3, 2.0)}
SUN_PATCH = 0.7
WINDOW_BOTTOM, WINDOW_TOP = 0.85, 2.0


@dataclass(frozen=True)
class Window:
    """A window on an exterior wall: centre (x, y), the wall's horizontal direction ``along``,
    the normal into ``room``, half its width, its sill and head heights, its view's seed."""

    room: int
    x: float
    y: float
    along: tuple[float, float]
    normal: tuple[float, float]
    half_width: float
    z0: float
    z1: float
    seed: int


@dataclass(frozen=True)
class Fixtures:
    """A building's windows and ceiling lamps (x, y, room)."""

    windows: tuple[Window, ...]
    lamps: tuple[tuple[float, float, int], ...]


def place_fixtures(plan: FloorPlan, scene_seed: int,
                   posters: Mapping[str, tuple[float, float, float]]) -> Fixtures:
    """Windows on the exterior walls, clear of the posters there, and lamps over every room.

    Args:
        plan: the floor plan.
        scene_seed: the building's seed; the fixtures use the stream ``[scene_seed, 3]``.
        posters: ``poster{wall}_{side}_{k}`` -> (x, y, half width) of the posters hung.

    Returns:
        The :class:`Fixtures`, the same for every lighting of the building.
    """
    rng = np.random.default_rng([scene_seed, 3])
    windows = []
    for i, w in enumerate(plan.walls):
        for side, rid in enumerate(w.sides):
            if rid < 0 or w.sides[1 - side] >= 0:
                continue  # only a room's face of an exterior wall has windows
            windows += _windows_on(plan, i, side, rng, posters)
    lamps = []
    for room in plan.rooms:
        area = (room.x1 - room.x0) * (room.y1 - room.y0)
        for _ in range(1 + min(2, int(area // 12))):
            lamps.append((*_lamp_spot(room, rng), room.id))
    return Fixtures(tuple(windows), tuple(lamps))


def _windows_on(plan: FloorPlan, i: int, side: int, rng: np.random.Generator,
                posters: Mapping[str, tuple[float, float, float]]) -> list[Window]:
    w = plan.walls[i]
    sign = -1.0 if side == 0 else 1.0  # as the lining: the normal points into the room
    normal = (0.0, sign) if w.axis == "x" else (sign, 0.0)
    along = (1.0, 0.0) if w.axis == "x" else (0.0, 1.0)
    cx, cy = (w.x0 + w.x1) / 2, (w.y0 + w.y1) / 2
    taken = [(p[0] - cx) * along[0] + (p[1] - cy) * along[1] for name, p in posters.items()
             if name.startswith(f"poster{i}_{side}_")]
    half_taken = [p[2] for name, p in posters.items() if name.startswith(f"poster{i}_{side}_")]
    n = int(w.length // 2.4)
    out = []
    for k in range(n):
        t = -w.length / 2 + (k + 0.5) * w.length / n + float(rng.uniform(-0.2, 0.2))
        half = float(rng.uniform(0.35, 0.7))
        seed = int(rng.integers(2**31))
        if any(abs(t - u) < half + h + 0.1 for u, h in zip(taken, half_taken)):
            continue
        if abs(t) + half > w.length / 2 - 0.25:
            continue
        offset = WALL_THICKNESS / 2 + 0.003
        out.append(Window(w.sides[side], cx + along[0] * t + normal[0] * offset,
                          cy + along[1] * t + normal[1] * offset, along, normal, half,
                          WINDOW_BOTTOM, WINDOW_TOP, seed))
    return out


def _lamp_spot(room: Room, rng: np.random.Generator) -> tuple[float, float]:
    """A downlight's (x, y): half of them 0.4 m from a wall, where they cast scallops on it."""
    x = float(rng.uniform(room.x0 + 0.6, room.x1 - 0.6))
    y = float(rng.uniform(room.y0 + 0.6, room.y1 - 0.6))
    if rng.random() < 0.5:
        wall = int(rng.integers(4))
        x = (room.x0 + 0.4, room.x1 - 0.4, x, x)[wall]
        y = (y, y, room.y0 + 0.4, room.y1 - 0.4)[wall]
    return x, y


def gain(points: np.ndarray, normal: np.ndarray, room: int, fixtures: Fixtures,
         lighting: str) -> np.ndarray:
    """How bright the light leaves ``points`` (N, 3) of a surface facing ``normal`` in
    ``room`` under ``lighting``, relative to the building without local light; shape (N,)."""
    if lighting == "night":
        g = np.full(len(points), NIGHT_FLOOR)
        for x, y, r in fixtures.lamps:
            if r == room:
                g += _lamp(points, normal, np.array([x, y, LAMP_HEIGHT]))
        return np.minimum(g, MAX_GAIN)
    base, near, fade = WINDOW_LIGHT[lighting]
    mine = [w for w in fixtures.windows if w.room == room]
    g = np.full(len(points), base)
    if mine:
        centres = np.array([(w.x, w.y, (w.z0 + w.z1) / 2) for w in mine])
        dist = np.linalg.norm(points[:, None, :] - centres[None], axis=2).min(axis=1)
        g += near * np.exp(-dist / fade)
    if lighting == "day":
        sun = np.asarray(LIGHTS["day"]["sun"][0][0], float)
        to_sun = -sun / np.linalg.norm(sun)
        if float(normal @ to_sun) > 0:
            g += SUN_PATCH * _in_sun(points, to_sun, mine)
    return np.minimum(g, MAX_GAIN)


def _lamp(points: np.ndarray, normal: np.ndarray, lamp: np.ndarray) -> np.ndarray:
    """A downlight's contribution: inverse square, Lambert's cosine, a soft-edged cone."""
    v = lamp - points
    r2 = np.maximum((v * v).sum(axis=1), 0.04)
    r = np.sqrt(r2)
    facing = np.clip(v @ normal / r, 0.0, None)
    cos_down = v[:, 2] / r  # the angle from straight down, seen from the lamp
    lo, hi = np.cos(np.radians(LAMP_CONE[1])), np.cos(np.radians(LAMP_CONE[0]))
    cone = np.clip((cos_down - lo) / (hi - lo), 0.0, 1.0)
    return LAMP_POWER * cone * facing / r2


def _in_sun(points: np.ndarray, to_sun: np.ndarray, windows: list[Window]) -> np.ndarray:
    """1 where the line from a point towards the sun leaves the room through a window."""
    lit = np.zeros(len(points), bool)
    for w in windows:
        n = np.array([*w.normal, 0.0])
        toward = float(to_sun @ n)
        if toward >= 0:
            continue  # the sun is on the room's side of this wall: no light through it
        centre = np.array([w.x, w.y, 0.0])
        t = ((points - centre) @ n) / -toward
        hit = points + t[:, None] * to_sun
        u = (hit[:, :2] - centre[:2]) @ np.asarray(w.along)
        lit |= (t > 0) & (np.abs(u) <= w.half_width) & (hit[:, 2] >= w.z0) & (hit[:, 2] <= w.z1)
    return lit.astype(float)


def window_view(seed: int, lighting: str, size: tuple[int, int] = (192, 160)) -> np.ndarray:
    """The outside through a window, (H, W, 3) uint8: the same skyline under every lighting
    (drawn from ``seed``), bright by day, greyed under cloud, dark with a few lit windows at
    night; a frame and a mullion."""
    rng = np.random.default_rng(seed)
    h, w = size
    horizon = int(h * rng.uniform(0.45, 0.65))
    rows = np.linspace(0.0, 1.0, horizon)[:, None, None]
    img: np.ndarray = np.empty((h, w, 3), np.float32)
    img[:horizon] = (1 - rows) * np.array([150, 185, 235]) + rows * np.array([225, 235, 245])
    img[horizon:] = (95, 110, 80)
    lit_windows = []
    for _ in range(int(rng.integers(2, 5))):  # buildings across the street, their windows
        x0 = int(rng.integers(-20, w - 20))
        bw, top = int(rng.integers(30, 80)), int(rng.integers(h // 6, horizon - 10))
        img[top:, max(0, x0):x0 + bw] = rng.integers(110, 200, 3)
        for wy in range(top + 6, h - 8, 14):
            for wx in range(x0 + 5, x0 + bw - 8, 12):
                if 0 <= wx < w - 6:
                    img[wy:wy + 8, wx:wx + 6] = (60, 70, 85)
                    lit_windows.append((wy, wx, rng.random() < 0.25))
    for _ in range(int(rng.integers(1, 4))):  # trees
        tx, ty = int(rng.integers(w)), int(rng.integers(horizon - 10, h))
        tr = int(rng.integers(12, 30))
        yy, xx = np.ogrid[:h, :w]
        img[(yy - ty) ** 2 + (xx - tx) ** 2 < tr * tr] = rng.integers(40, 110, 3) * (0.6, 1.0, 0.5)
    if lighting == "cloudy":
        img = 0.45 * img + 0.55 * np.array([175, 178, 182])
    elif lighting == "night":
        img = 0.1 * img + np.array([6, 8, 18])
        for wy, wx, lit in lit_windows:
            if lit:
                img[wy:wy + 8, wx:wx + 6] = (235, 205, 130)
    frame = (70, 70, 75) if lighting != "night" else (30, 30, 34)
    img[:6], img[-6:], img[:, :6], img[:, -6:] = frame, frame, frame, frame
    img[:, w // 2 - 3:w // 2 + 3] = frame
    return np.clip(img, 0, 255).astype(np.uint8)


def light_locally(spec: mujoco.MjSpec, plan: FloorPlan, lighting: str, scene_seed: int,
                  rooms: dict[str, tuple[int, ...]]) -> Fixtures:
    """Hang the windows and bake the light into ``spec``'s room surfaces (before compiling).

    Args:
        spec: the building as :func:`envs.world.scene.build_scene` made it, not compiled.
        plan: its floor plan.
        lighting: one of :data:`envs.world.conditions.LIGHTING`.
        scene_seed: the building's seed.
        rooms: geom name -> rooms (``Scene.geom_rooms``); the windows are added to it.

    Returns:
        The :class:`Fixtures` hung.
    """
    posters = {g.name: (float(g.pos[0]), float(g.pos[1]), float(g.size[0]))
               for g in spec.geoms if g.name.startswith("poster")}
    fixtures = place_fixtures(plan, scene_seed, posters)
    bake_surfaces(spec, plan, fixtures, lighting, rooms)
    add_windows(spec, fixtures, lighting, rooms)
    return fixtures


def _stretched_material(spec: mujoco.MjSpec, name: str, img: np.ndarray,
                        emission: float = 0.0) -> str:
    """A material showing ``img`` once across a plane, as a poster's."""
    mat = spec.add_material(name=name, texrepeat=[1, 1], texuniform=False, emission=emission)
    texture = textures.add_texture(spec, f"{name}_tex", img)
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = texture
    mat.specular, mat.shininess = 0.05, 0.1
    return name


def _rotation(geom: mujoco.MjsGeom) -> np.ndarray:
    """The geom's orientation as a 3x3 matrix (its columns: its local axes in the world)."""
    flat = np.zeros(9)
    mujoco.mju_quat2Mat(flat, np.asarray(geom.quat, float))
    return flat.reshape(3, 3)


def _plane_texels(geom: mujoco.MjsGeom) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """The world points of a plane's texels (N, 3), row 0 at its local +y edge, its normal,
    and the texture's (height, width)."""
    sx, sy = float(geom.size[0]), float(geom.size[1])
    w, h = max(2, round(2 * sx * TEXELS_PER_M)), max(2, round(2 * sy * TEXELS_PER_M))
    rot = _rotation(geom)
    u = -sx + (np.arange(w) + 0.5) * 2 * sx / w
    v = sy - (np.arange(h) + 0.5) * 2 * sy / h
    uu, vv = np.meshgrid(u, v)
    local = np.stack([uu.ravel(), vv.ravel(), np.zeros(uu.size)], axis=1)
    return np.asarray(geom.pos, float) + local @ rot.T, rot[:, 2], (h, w)


def _tiled(spec: mujoco.MjSpec, material: str, shape: tuple[int, int]) -> np.ndarray:
    """The material's tile repeated at :data:`TEXELS_PER_M` over ``shape`` texels: the
    pattern a uniformly mapped plane shows, as one image."""
    tex = spec.texture(spec.material(material).textures[mujoco.mjtTextureRole.mjTEXROLE_RGB])
    tile = np.frombuffer(bytes(tex.data), np.uint8).reshape(tex.height, tex.width, 3)[::-1]
    scale = tex.width / (2 * TEXELS_PER_M)  # a wall or floor tile spans 2 m (texrepeat 0.5)
    rows = (np.arange(shape[0]) * scale).astype(int) % tex.height
    cols = (np.arange(shape[1]) * scale).astype(int) % tex.width
    return tile[rows][:, cols]


def bake_surfaces(spec: mujoco.MjSpec, plan: FloorPlan, fixtures: Fixtures, lighting: str,
                  rooms: Mapping[str, tuple[int, ...]]) -> None:
    """Give every floor and wall lining a texture of its own with :func:`gain` baked in, and
    every poster and piece of furniture the gain at its centre as its colour."""
    for geom in list(spec.geoms):
        owner = rooms.get(geom.name, ())
        if len(owner) != 1:
            continue  # jambs and doors belong to two rooms: left as they are
        room = owner[0]
        if geom.name.startswith(("floor", "lining")):
            points, normal, shape = _plane_texels(geom)
            g = gain(points, normal, room, fixtures, lighting).reshape(*shape, 1)
            img = np.clip(_tiled(spec, geom.material, shape) * g, 0, 255).astype(np.uint8)
            geom.material = _stretched_material(spec, f"lit_{geom.name}", img)
        elif geom.name.startswith(("poster", "furniture")):
            normal = _rotation(geom)[:, 2]
            centre = np.asarray(geom.pos, float)[None]
            if geom.name.startswith("furniture"):  # lit from above: its top's light
                normal, centre = np.array([0.0, 0.0, 1.0]), centre + [0, 0, geom.size[2]]
            level = float(min(1.0, gain(centre, normal, room, fixtures, lighting)[0]))
            source = spec.material(geom.material)
            mat = spec.add_material(name=f"lit_{geom.name}", texrepeat=list(source.texrepeat),
                                    texuniform=source.texuniform, rgba=[level, level, level, 1])
            mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = source.textures[
                mujoco.mjtTextureRole.mjTEXROLE_RGB]
            mat.specular, mat.shininess = source.specular, source.shininess
            geom.material = mat.name


def add_windows(spec: mujoco.MjSpec, fixtures: Fixtures, lighting: str,
                rooms: dict[str, tuple[int, ...]]) -> None:
    """A plane for each window, showing :func:`window_view` by its own light (emissive)."""
    for k, w in enumerate(fixtures.windows):
        name = f"window{k}"
        height = w.z1 - w.z0
        view = window_view(w.seed, lighting, (160, max(32, round(160 * 2 * w.half_width
                                                                   / height))))
        x_axis = np.array([-w.normal[1], w.normal[0], 0.0])  # so that the normal is x cross up
        frame = np.stack([x_axis, [0.0, 0.0, 1.0], [w.normal[0], w.normal[1], 0.0]], axis=1)
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, frame.ravel())
        spec.worldbody.add_geom(
            name=name, type=mujoco.mjtGeom.mjGEOM_PLANE, contype=0, conaffinity=0,
            material=_stretched_material(spec, f"{name}_mat", view, emission=1.0),
            size=[w.half_width, height / 2, 1], pos=[w.x, w.y, (w.z0 + w.z1) / 2],
            quat=quat.tolist())
        rooms[name] = (w.room,)
