"""Builds a MuJoCo world from a :class:`~envs.world.layout.FloorPlan` with ``mujoco.MjSpec``.

Walls are grey collision boxes; each room lines its side of every wall with a thin,
non-colliding textured plane, so the two faces of one wall show the two rooms' textures. The
robot's cameras never see a box's long faces (the linings hide them) nor its top (the cameras are
below it), so they skip the boxes (geom group :data:`CORE_GROUP`) and draw only a small grey cap
where a wall ends at a doorway: the same pixels wherever the robot does not touch a wall, for
less rasterization (``placeclust speed``). Posters
hang in front of the linings, furniture stands along the walls, and the robot of
``assets/robot.xml`` is attached at the origin with ``n_cameras`` cameras on its mast.

Everything is drawn from ``np.random.default_rng(scene_seed)``, so a seed fixes every pixel.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from . import textures
from .changes import Changes, rearrange_furniture, swap_posters
from .conditions import LIGHTS, check_lighting
from .corridor import corridor_floor_plan
from .doors import add_doors, hang_doors
from .layout import WALL_THICKNESS, FloorPlan, Room, Wall, generate_floor_plan
from .local_light import light_locally
from .panorama import camera_yaw
from .robot import MAX_RANGE, N_RANGES, RADIUS
from .textures import add_texture

WALL_HEIGHT = 2.2
# Geom groups (MuJoCo's ``geom_group``): every geom made here is in one of these, and the
# renderers (:mod:`envs.world.rendering`) draw by group. Groups 0-2 are on in MuJoCo's default
# options, 3-5 off.
#: linings, floors, posters, furniture, door-jamb caps, the robot: drawn by every camera
DRAWN_GROUP = 0
#: the walls' collision boxes: drawn in the top-down view, not by the robot's cameras
CORE_GROUP = 2
#: the ground's collision plane, under the rooms' floors: drawn by no view
GROUND_GROUP = 3
#: off in every renderer's options: the renderer moves culled geoms here for one draw
HIDDEN_GROUP = 5
CAMERA_HEIGHT = 1.0
#: metres from a camera to its near clipping plane. MuJoCo scales ``visual.map.znear`` by the
#: model's extent, so a fixed fraction would clip walls the robot stands next to in large
#: buildings (0.235 m in 12 rooms); nothing the robot can reach comes closer than its radius.
NEAR_CLIP = 0.05
#: building generators: ``grid`` rooms of random sizes (:mod:`envs.world.layout`), ``corridor``
#: identical offices along a corridor (:mod:`envs.world.corridor`)
LAYOUTS = ("grid", "corridor")

@dataclass
class Scene:
    """A compiled world: the plan it came from, the model, and names of its parts."""

    plan: FloorPlan
    spec: mujoco.MjSpec
    model: mujoco.MjModel
    camera_names: tuple[str, ...]
    lighting: str
    #: the rooms each drawn geom of the building belongs to, by geom name: the room it lines,
    #: stands or lies in; a door jamb belongs to both sides of its wall (:mod:`envs.world.portals`)
    geom_rooms: dict[str, tuple[int, ...]]


def build_scene(
    scene_seed: int,
    n_rooms: int = 4,
    lighting: str = "day",
    n_cameras: int = 4,
    camera_fovy: float = 90.0,
    extra_doors: float = 0.5,
    changes: Changes | None = None,
    layout: str = "grid",
    forward_fovy: float = 55.4,
    doors: float | None = None,
    local_light: bool = False,
) -> Scene:
    """Generate a floor plan from ``scene_seed`` and compile it into a MuJoCo model.

    Args:
        scene_seed: seed of the plan, textures and furniture.
        n_rooms: number of rooms.
        lighting: one of :data:`envs.world.conditions.LIGHTING`. It changes only the lights,
            never the geometry.
        n_cameras: cameras on the mast, evenly spaced in yaw, for the panorama.
        camera_fovy: vertical field of view of each camera, degrees.
        extra_doors: see :func:`envs.world.layout.generate_floor_plan`.
        changes: furniture and posters moved since the building was new
            (:class:`~envs.world.changes.Changes`; its camera fields are the env's business).
        layout: one of :data:`LAYOUTS`; ``corridor`` ignores ``extra_doors``.
        forward_fovy: vertical field of view of the forward-looking camera, degrees.
        doors: ``None`` for open doorways of 1 m (the default: no door, no frame); else the
            fraction of doorways with a leaf, every doorway framed and of a width drawn from a
            range (:mod:`envs.world.doors`).
        local_light: windows, lamps, sun patches and dark corners baked into the surfaces
            (:mod:`envs.world.local_light`); off by default: the building is lit as before.

    Returns:
        The compiled :class:`Scene`.
    """
    check_lighting(lighting)
    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}; choose one of {LAYOUTS}")
    rng = np.random.default_rng(scene_seed)
    if layout == "corridor":
        plan = corridor_floor_plan(n_rooms, rng)
    else:
        plan = generate_floor_plan(n_rooms, rng, extra_doors=extra_doors)
    changes = changes or Changes()
    plan = rearrange_furniture(plan, changes)  # its own random stream: textures stay the same
    if doors is not None:
        plan = hang_doors(plan, doors, scene_seed)  # its own random stream too
    spec = mujoco.MjSpec()
    spec.modelname = f"placenav_{scene_seed}_{n_rooms}"
    _setup_visual(spec, plan, lighting)
    spec.option.timestep = 0.005
    # velocity actuators on light wheels are stiff: implicit damping keeps 5 ms steps stable
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    rooms: dict[str, tuple[int, ...]] = {}
    posters: list[str] = []
    _add_floor(spec, plan, rng, rooms)
    _add_walls(spec, plan, rng, rooms, posters)
    if doors is not None:
        add_doors(spec, plan, WALL_HEIGHT, rooms)
    swap_posters(spec, posters, changes)
    _add_furniture(spec, plan, rng, rooms)
    if local_light:
        light_locally(spec, plan, lighting, scene_seed, rooms)
    cams = _add_robot(spec, n_cameras, camera_fovy, forward_fovy)
    model = spec.compile()
    model.vis.map.znear = NEAR_CLIP / model.stat.extent
    return Scene(plan, spec, model, cams, lighting, rooms)


def _setup_visual(spec: mujoco.MjSpec, plan: FloorPlan, lighting: str) -> None:
    q = spec.visual.quality
    q.shadowsize = 0  # shadows and multisampling cost ~20x in software GL
    q.offsamples = 0
    # one quad per box face, not 16: a face's lighting is flat (directional lights, no
    # specular), so only a few edge pixels change, for a tenth of the simulator's time
    q.numquads = 1
    cond = LIGHTS[lighting]
    hl = spec.visual.headlight
    hl.ambient = [cond["ambient"]] * 3
    hl.diffuse = [cond["headlight"]] * 3
    hl.specular = [0.0] * 3
    for i, (direction, color) in enumerate(cond["sun"]):
        light = spec.worldbody.add_light(name=f"sun{i}")
        light.type = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
        x0, y0, x1, y1 = plan.bounds
        light.pos = [(x0 + x1) / 2, (y0 + y1) / 2, 6.0]
        light.dir = list(direction)
        light.diffuse = list(color)
        light.specular = [0.0, 0.0, 0.0]
        light.castshadow = False



def _material(spec: mujoco.MjSpec, name: str, texture: str, repeat: tuple[float, float],
              uniform: bool) -> str:
    mat = spec.add_material(name=name, texrepeat=list(repeat), texuniform=uniform)
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = texture
    mat.specular = 0.05
    mat.shininess = 0.1
    return name


def _add_floor(spec: mujoco.MjSpec, plan: FloorPlan, rng: np.random.Generator,
               rooms: dict[str, tuple[int, ...]]) -> None:
    x0, y0, x1, y1 = plan.bounds
    spec.worldbody.add_geom(  # one collision plane; per-room visual floors sit on top of it
        name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], group=GROUND_GROUP,
        pos=[(x0 + x1) / 2, (y0 + y1) / 2, 0], rgba=[0.2, 0.2, 0.2, 1],
    )
    for room in plan.rooms:
        tex = add_texture(spec, f"floor_tex{room.id}", textures.floor_texture(room.kind, rng))
        mat = _material(spec, f"floor_mat{room.id}", tex, (0.5, 0.5), True)
        cx, cy = room.center
        spec.worldbody.add_geom(
            name=f"floor{room.id}", type=mujoco.mjtGeom.mjGEOM_PLANE, material=mat,
            size=[(room.x1 - room.x0) / 2, (room.y1 - room.y0) / 2, 1], pos=[cx, cy, 0.001],
            contype=0, conaffinity=0,
        )
        rooms[f"floor{room.id}"] = (room.id,)


def _frame_quat(x_axis: tuple[float, float, float]) -> list[float]:
    """Quaternion of a frame whose x axis is horizontal ``x_axis`` and whose y axis is up."""
    x = np.asarray(x_axis, float)
    y = np.array([0.0, 0.0, 1.0])
    z = np.cross(x, y)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.stack([x, y, z], axis=1).ravel())
    return quat.tolist()


def _add_walls(spec: mujoco.MjSpec, plan: FloorPlan, rng: np.random.Generator,
               rooms: dict[str, tuple[int, ...]], posters: list[str]) -> None:
    """The walls' boxes, jamb caps and linings; the names of the posters hung go to
    ``posters``, in the order they were made."""
    grey = spec.add_material(name="wall_core", rgba=[0.55, 0.55, 0.55, 1]).name
    wall_mats = {}
    for room in plan.rooms:
        tex = add_texture(spec, f"wall_tex{room.id}", textures.wall_texture(room.kind, rng))
        wall_mats[room.id] = _material(spec, f"wall_mat{room.id}", tex, (0.5, 0.5), True)
    half_t = WALL_THICKNESS / 2
    for i, w in enumerate(plan.walls):
        cx, cy = (w.x0 + w.x1) / 2, (w.y0 + w.y1) / 2
        # extend by half the thickness so perpendicular walls meet without gaps
        half_len = w.length / 2 + half_t
        size = [half_len, half_t, WALL_HEIGHT / 2] if w.axis == "x" else [
            half_t, half_len, WALL_HEIGHT / 2]
        spec.worldbody.add_geom(name=f"wall{i}", type=mujoco.mjtGeom.mjGEOM_BOX, size=size,
                                pos=[cx, cy, WALL_HEIGHT / 2], material=grey, group=CORE_GROUP)
        for k, end in enumerate(_door_ends(w, plan.walls)):
            _add_jamb(spec, end, f"jamb{i}_{k}", grey)
            rooms[f"jamb{i}_{k}"] = tuple(r for r in w.sides if r >= 0)
        for side, room_id in enumerate(w.sides):
            if room_id >= 0:
                for name in _line_wall(spec, plan.rooms[room_id], w, side, i,
                                       wall_mats[room_id], rng, posters):
                    rooms[name] = (room_id,)


def _add_jamb(spec: mujoco.MjSpec, end: tuple[float, float], name: str, material: str) -> None:
    """The last wall thickness of a wall's box where it ends at a doorway: the part the linings
    leave visible (its end face and the edges of its long faces), as a visual-only cube."""
    half_t = WALL_THICKNESS / 2
    spec.worldbody.add_geom(
        name=name, type=mujoco.mjtGeom.mjGEOM_BOX, material=material,
        size=[half_t, half_t, WALL_HEIGHT / 2], pos=[*end, WALL_HEIGHT / 2],
        contype=0, conaffinity=0,
    )


def _door_ends(w: Wall, walls: Sequence[Wall]) -> list[tuple[float, float]]:
    """The ends of ``w``'s centre line that meet no other wall: the jambs of its doorways."""
    def touches(x: float, y: float, o: Wall) -> bool:
        return (min(o.x0, o.x1) - 1e-6 <= x <= max(o.x0, o.x1) + 1e-6
                and min(o.y0, o.y1) - 1e-6 <= y <= max(o.y0, o.y1) + 1e-6)

    return [(x, y) for x, y in ((w.x0, w.y0), (w.x1, w.y1))
            if not any(touches(x, y, o) for o in walls if o is not w)]


def _line_wall(spec: mujoco.MjSpec, room: Room, w: Wall, side: int, wall_index: int,
               material: str, rng: np.random.Generator, posters: list[str]) -> list[str]:
    """Texture ``room``'s face of wall ``w`` (side 0: the room is on the low side) and hang
    posters (their names also appended to ``posters``); returns the names of the geoms added."""
    sign = -1.0 if side == 0 else 1.0  # the face normal points from the wall into the room
    offset = WALL_THICKNESS / 2 + 0.002
    if w.axis == "x":
        normal = (0.0, sign, 0.0)
        along = (-sign, 0.0, 0.0)  # x axis of the plane, so that normal = along x up
    else:
        normal = (sign, 0.0, 0.0)
        along = (0.0, sign, 0.0)
    cx, cy = (w.x0 + w.x1) / 2, (w.y0 + w.y1) / 2
    quat = _frame_quat(along)
    pos = [cx + normal[0] * offset, cy + normal[1] * offset, WALL_HEIGHT / 2]
    names = [f"lining{wall_index}_{side}"]
    spec.worldbody.add_geom(
        name=names[0], type=mujoco.mjtGeom.mjGEOM_PLANE, material=material,
        size=[w.length / 2, WALL_HEIGHT / 2, 1], pos=pos, quat=quat, contype=0, conaffinity=0,
    )
    n_posters = int(rng.integers(0, 2 + int(w.length // 2.5)))
    for k in range(n_posters):
        width = float(rng.uniform(0.5, 0.9))
        slot = w.length / n_posters
        if slot < width + 0.2:
            break
        t = -w.length / 2 + slot * k + float(rng.uniform(width / 2 + 0.1, slot - width / 2 - 0.1))
        tex = add_texture(spec, f"poster_tex{wall_index}_{side}_{k}", textures.poster_texture(rng))
        mat = _material(spec, f"poster_mat{wall_index}_{side}_{k}", tex, (1, 1), False)
        height = width * 1.25
        z = float(rng.uniform(0.9, 1.5))
        names.append(f"poster{wall_index}_{side}_{k}")
        posters.append(names[-1])
        spec.worldbody.add_geom(
            name=names[-1], type=mujoco.mjtGeom.mjGEOM_PLANE,
            material=mat, size=[width / 2, height / 2, 1], quat=quat, contype=0, conaffinity=0,
            pos=[pos[0] + along[0] * t + normal[0] * 0.004,
                 pos[1] + along[1] * t + normal[1] * 0.004, z],
        )
    return names


def _add_furniture(spec: mujoco.MjSpec, plan: FloorPlan, rng: np.random.Generator,
                   rooms: dict[str, tuple[int, ...]]) -> None:
    for room in plan.rooms:
        tex = add_texture(spec, f"furniture_tex{room.id}", textures.furniture_texture(rng))
        mat = _material(spec, f"furniture_mat{room.id}", tex, (1, 1), True)
        for i, f in enumerate(fi for fi in plan.furniture if fi.room == room.id):
            spec.worldbody.add_geom(
                name=f"furniture{room.id}_{i}", type=mujoco.mjtGeom.mjGEOM_BOX, material=mat,
                size=[f.hx, f.hy, f.height / 2], pos=[f.x, f.y, f.height / 2],
            )
            rooms[f"furniture{room.id}_{i}"] = (room.id,)


def _add_robot(spec: mujoco.MjSpec, n_cameras: int, fovy: float, forward_fovy: float
               ) -> tuple[str, ...]:
    robot = mujoco.MjSpec.from_file(str(textures.ASSETS / "robot.xml"))
    mount = robot.site("camera_mount")
    base = robot.body("base")
    names = []
    for k in range(n_cameras):
        yaw = float(camera_yaw(k, n_cameras))
        cam = base.add_camera(name=f"pano{k}", pos=list(mount.pos), fovy=fovy)
        right = (math.sin(yaw), -math.cos(yaw), 0.0)  # camera x; it looks along -z = (cos, sin, 0)
        cam.alt.type = mujoco.mjtOrientation.mjORIENTATION_XYAXES
        cam.alt.xyaxes = [*right, 0.0, 0.0, 1.0]
        names.append(f"pano{k}")
    # one perspective camera looking ahead, as the monocular camera of seed 001 (COLD)
    forward = base.add_camera(name="forward", pos=list(mount.pos), fovy=forward_fovy)
    forward.alt.type = mujoco.mjtOrientation.mjORIENTATION_XYAXES
    forward.alt.xyaxes = [0.0, -1.0, 0.0, 0.0, 0.0, 1.0]
    _add_range_sites(base)
    frame = spec.worldbody.add_frame()
    frame.attach_body(base, "robot/", "")
    for k in range(N_RANGES):
        sensor = spec.add_sensor(name=f"range{k}", type=mujoco.mjtSensor.mjSENS_RANGEFINDER,
                                 objtype=mujoco.mjtObj.mjOBJ_SITE, objname=f"robot/range{k}")
        sensor.cutoff = MAX_RANGE
        sensor.intprm[0] = 1 << int(mujoco.mjtRayDataField.mjRAYDATA_DIST)  # distance only
    return tuple(f"robot/{n}" for n in names)


def _add_range_sites(base: mujoco.MjsBody) -> None:
    """A ring of rangefinder sites above the chassis, range 0 looking ahead, then CCW.

    At 0.3 m above the floor the rays clear the wheels and hit walls and every piece of furniture.
    """
    for k in range(N_RANGES):
        yaw = 2 * math.pi * k / N_RANGES
        c, s = math.cos(yaw), math.sin(yaw)
        site = base.add_site(name=f"range{k}", pos=[RADIUS * c, RADIUS * s, 0.25])
        site.alt.type = mujoco.mjtOrientation.mjORIENTATION_ZAXIS  # rangefinders look along +z
        site.alt.zaxis = [c, s, 0.0]
