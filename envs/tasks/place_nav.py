"""``PlaceNav-v0``: a wheeled robot with a 360° camera in a procedurally generated building."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces

from ..world.changes import Changes, degrade
from ..world.conditions import check_lighting
from ..world.doors import DoorOpener
from ..world.layout import FloorPlan
from ..world.panorama import PanoramaGeometry
from ..world.rendering import SceneRenderer
from ..world.robot import MAX_RANGE, MAX_SPEED, MAX_TURN, N_RANGES, Robot, check_action
from ..world.scene import Scene, build_scene

_NO_SENSORS = int(mujoco.mjtDisableBit.mjDSBL_SENSOR)
#: ``panorama``: the 360° ring (observation key ``panorama``); ``forward``: one perspective
#: camera looking ahead, as seed 001's monocular camera (observation key ``image``)
CAMERAS = ("panorama", "forward")


@dataclass(frozen=True)
class NavSnapshot:
    """Everything a :class:`PlaceNavEnv` episode goes on from (:meth:`PlaceNavEnv.snapshot`):
    the physics (pose, velocities, the wheels' commands, the doors), the random streams and
    the last frame; ``world_id`` says which building it belongs to."""

    world_id: str
    data: mujoco.MjData
    rng: np.random.Generator
    camera_rng: np.random.Generator
    visited: frozenset[int]
    panorama: np.ndarray | None


class PlaceNavEnv(gym.Env, gym.utils.EzPickle):
    """A differential-drive robot explores a building of named, textured rooms.

    The building (rooms, doors, textures, furniture) is fixed by ``scene_seed`` at construction;
    ``reset(seed=...)`` only draws the start pose. Ground truth (room, pose) is in ``info`` and
    never in the observation, so place recognizers and agents can be scored against it.

    ## Action Space
    ``Box(-1, 1, (2,), float32)``:

    | index | meaning | unit at 1.0 |
    |-------|---------|-------------|
    | 0 | forward speed | 0.5 m/s |
    | 1 | turn rate, counter-clockwise positive | 1.5 rad/s |

    Both become wheel speeds that the wheels' velocity actuators track, so the motion has inertia
    and slips on collisions. Actions outside [-1, 1] or with NaN/inf raise ``ValueError``.

    ## Observation Space
    ``Dict``:

    | key | space | meaning |
    |-----|-------|---------|
    | ``panorama`` | ``Box(0, 255, (H, W, 3), uint8)`` | unwrapped 360° cylindrical panorama; the heading is the centre column, the robot's left at W/4 (see :mod:`envs.world.panorama`) |
    | ``odometry`` | ``Box(-10, 10, (2,), float32)`` | measured forward speed (m/s) and turn rate (rad/s) from the wheel encoders |
    | ``heading`` | ``Box(-1, 1, (2,), float32)`` | compass: (cos, sin) of the heading |
    | ``ranges`` | ``Box(0, 4, (16,), float32)`` | ring of rangefinders 0.3 m above the floor, m, counter-clockwise from ahead |

    | ``image`` | ``Box(0, 255, (h, w, 3), uint8)`` | with ``camera="forward"``, instead of ``panorama``: one perspective camera looking ahead from the same mast |

    ``panorama=False`` leaves the camera image out and skips rendering, for agents that do not
    look.

    ## Rewards
    +1 the first time in an episode the robot enters each room (the start room counts as
    entered), 0 otherwise: an exploration reward. Tasks with goals come as wrappers.

    ## Episode End
    Never terminates. Truncation comes from the registered ``max_episode_steps`` (500 steps of
    ``control_dt`` = 0.1 s, i.e. 50 s of driving).

    ## Info
    ``room_id`` (int), ``room_name`` (str), ``pose`` (x, y, heading: float64 array),
    ``rooms_visited`` (int).

    ## Arguments
    | argument | default | meaning |
    |----------|---------|---------|
    | ``scene_seed`` | 0 | seed of the building; same seed, same pixels |
    | ``n_rooms`` | 4 | rooms, 1 to 32 |
    | ``panorama_width`` | 512 | panorama width, pixels (at least 32) |
    | ``panorama_height`` | 128 | panorama height, pixels (at least 8) |
    | ``lighting`` | ``"day"`` | ``"day"``, ``"cloudy"`` or ``"night"``, as in COLD |
    | ``n_cameras`` | 4 | cameras in the ring the panorama is stitched from |
    | ``extra_doors`` | 0.5 | fraction of non-tree walls with a door (loops); 0 gives a tree |
    | ``doors`` | ``None`` | ``None``: open doorways, 1 m wide; a fraction F in [0, 1]: every doorway framed and 0.8-1.0 m wide, F of them with an automatic door, shut until the robot is within 0.7 m (:mod:`envs.world.doors`) |
    | ``local_light`` | ``False`` | windows on the outer walls and lamps over every room, the light baked where it falls: sun patches and window light by day, lamp pools and dark corners at night (:mod:`envs.world.local_light`) |
    | ``layout`` | ``"grid"`` | ``"grid"``: rooms of random sizes; ``"corridor"``: ``n_rooms - 1`` identical offices along a corridor, told apart only by how they look (:mod:`envs.world.corridor`) |
    | ``control_dt`` | 0.1 | seconds of simulation per step (physics runs at 5 ms) |
    | ``panorama`` | ``True`` | render the panorama into the observation |
    | ``furniture_moved`` | 0 | fraction of furniture moved to another wall of its room |
    | ``furniture_removed`` | 0 | fraction of furniture taken away |
    | ``posters_swapped`` | 0 | fraction of posters whose pictures are exchanged |
    | ``camera_noise`` | 0 | Gaussian pixel noise, standard deviation in grey levels |
    | ``camera_blur`` | 0 | Gaussian blur, standard deviation in pixels |
    | ``changes_seed`` | 0 | seed of the changes above (see :mod:`envs.world.changes`); the noise also follows ``reset(seed=...)`` |
    | ``camera`` | ``"panorama"`` | ``"panorama"``: the 360° ring; ``"forward"``: one perspective camera looking ahead, as the monocular camera of seed 001 (COLD's perspective cameras) |
    | ``image_width``, ``image_height`` | 320, 240 | the forward camera's image, pixels |
    | ``image_fov`` | 70.0 | the forward camera's horizontal field of view, degrees |
    | ``render_mode`` | ``None`` | ``"rgb_array"``: top-down view with the robot above the panorama |

    ``reset(options=...)`` accepts ``{"pose": (x, y, heading)}`` or ``{"room": name}`` to choose
    the start.

    ``pickle`` and ``copy.deepcopy`` rebuild the env from its constructor arguments
    (``gymnasium.utils.EzPickle``): the copy is a fresh env, to be reset before use.

    ## Version History
    - v0: first version. Since placeclust 0.12.0 the near clipping plane lies 5 cm from the
      cameras (it was 1% of the building's extent, which cut away a wall the robot stood next
      to in large buildings) and box faces are drawn as one quad: frames differ from 0.11.0's
      in about 13 pixels by one grey level.
      Since 0.13.0 ``camera_blur`` no longer wraps a forward image's left and right edges
      into each other (panoramas wrap, as before). Since 0.15.0 ``doors`` (off by default:
      buildings without doors are drawn as before). Since 0.15.0 ``local_light`` (off by
      default: buildings are lit as before).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    observation_space: spaces.Dict

    def __init__(
        self,
        scene_seed: int = 0,
        n_rooms: int = 4,
        panorama_width: int = 512,
        panorama_height: int = 128,
        lighting: str = "day",
        n_cameras: int = 4,
        extra_doors: float = 0.5,
        control_dt: float = 0.1,
        render_mode: str | None = None,
        panorama: bool = True,
        furniture_moved: float = 0.0,
        furniture_removed: float = 0.0,
        posters_swapped: float = 0.0,
        camera_noise: float = 0.0,
        camera_blur: float = 0.0,
        changes_seed: int = 0,
        layout: str = "grid",
        camera: str = "panorama",
        image_width: int = 320,
        image_height: int = 240,
        image_fov: float = 70.0,
        doors: float | None = None,
        local_light: bool = False,
    ) -> None:
        # pickle and deepcopy rebuild the env from these arguments (a MjSpec cannot be pickled),
        # as Gymnasium's MuJoCo envs do: the copy is a fresh env that needs a reset
        gym.utils.EzPickle.__init__(self, **{k: v for k, v in locals().items()
                                             if k not in ("self", "__class__")})
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, "
                             f"got {render_mode!r}")
        check_lighting(lighting)
        if not 0.005 <= control_dt <= 1.0:
            raise ValueError(f"control_dt must be in [0.005, 1] s, got {control_dt}")
        if camera not in CAMERAS:
            raise ValueError(f"unknown camera {camera!r}; choose one of {CAMERAS}")
        if not (16 <= image_width <= 2048 and 16 <= image_height <= 2048 and 10 <= image_fov < 170):
            raise ValueError(f"forward image {image_width}x{image_height} with {image_fov}° "
                             "field of view: need 16-2048 pixels a side and 10-170°")
        self.camera = camera
        self.image_key = "panorama" if camera == "panorama" else "image"
        self._image_size = (image_width, image_height)
        self.render_mode = render_mode
        self.changes = Changes(furniture_moved, furniture_removed, posters_swapped, camera_noise,
                               camera_blur, changes_seed)
        self._camera_rng = np.random.default_rng(changes_seed)
        self._world_id = (f"PlaceNav scene_seed={scene_seed} n_rooms={n_rooms} "
                          f"extra_doors={extra_doors} panorama={panorama_width}x{panorama_height} "
                          f"n_cameras={n_cameras}")
        if layout != "grid":  # grid worlds keep the fingerprint their saved maps were made with
            self._world_id += f" layout={layout}"
        if doors is not None:  # a building with doors is another building
            self._world_id += f" doors={doors}"
        if local_light:  # windows and lamps: what the camera sees changes everywhere
            self._world_id += " local_light"
        if camera != "panorama":  # a map of forward images is not a map of panoramas
            self._world_id += f" camera={camera} {image_width}x{image_height} fov={image_fov}"
        # vertical field of view of the forward camera from its horizontal one and its aspect
        forward_fovy = math.degrees(2 * math.atan(math.tan(math.radians(image_fov) / 2)
                                                  * image_height / image_width))
        self.geometry = PanoramaGeometry(panorama_width, panorama_height, n_cameras)
        self.scene: Scene = build_scene(scene_seed, n_rooms, lighting, n_cameras,
                                        self.geometry.fovy, extra_doors, self.changes, layout,
                                        forward_fovy, doors, local_light)
        self.model = self.scene.model
        self.data = mujoco.MjData(self.model)
        self.robot = Robot(self.model)
        self._doors = DoorOpener(self.model, self.plan)
        self.n_substeps = max(1, round(control_dt / self.model.opt.timestep))
        self._renderer: SceneRenderer | None = None
        self._visited: set[int] = set()
        self._panorama: np.ndarray | None = None

        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.with_panorama = panorama
        obs_spaces: dict[str, spaces.Space] = {
            "odometry": spaces.Box(-10.0, 10.0, (2,), np.float32),
            "heading": spaces.Box(-1.0, 1.0, (2,), np.float32),
            "ranges": spaces.Box(0.0, MAX_RANGE, (N_RANGES,), np.float32),
        }
        if panorama:
            shape = ((panorama_height, panorama_width, 3) if camera == "panorama"
                     else (image_height, image_width, 3))
            obs_spaces = {self.image_key: spaces.Box(0, 255, shape, np.uint8), **obs_spaces}
        self.observation_space = spaces.Dict(obs_spaces)

    @property
    def world_id(self) -> str:
        """Fingerprint of what a map depends on: the building and the camera, not the light or
        the :class:`~envs.world.changes.Changes` (a map of a changed building is still its map)."""
        return self._world_id

    @property
    def plan(self) -> FloorPlan:
        """The building's floor plan (rooms, doors, walls, furniture)."""
        return self.scene.plan

    @property
    def renderer(self) -> SceneRenderer:
        if self._renderer is None:  # created lazily: vector-env workers build their own
            self._renderer = SceneRenderer(self.model, self.scene.camera_names, self.geometry,
                                           plan=self.plan, geom_rooms=self.scene.geom_rooms)
        return self._renderer

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        mujoco.mj_resetData(self.model, self.data)
        x, y, heading = self._start_pose(options or {})
        if self.changes.camera:  # drawn after the start pose, which stays the unchanged world's
            episode = int(self.np_random.integers(2**63))
            self._camera_rng = np.random.default_rng([self.changes.seed, episode])
        self.robot.place(self.data, x, y, heading)
        self._doors.update(self.data, x, y)
        mujoco.mj_forward(self.model, self.data)
        info = self._info()
        self._visited = {info["room_id"]}
        info["rooms_visited"] = 1
        return self._observation(), info

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        action = check_action(action)
        self.robot.command(self.data, action)
        x, y, _ = self.robot.pose(self.data)
        self._doors.update(self.data, x, y)  # the doors the step's physics and frame see
        self._physics()
        info = self._info()
        reward = 0.0
        if info["room_id"] >= 0 and info["room_id"] not in self._visited:
            self._visited.add(info["room_id"])
            reward = 1.0
        info["rooms_visited"] = len(self._visited)
        return self._observation(), reward, False, False, info

    def snapshot(self) -> NavSnapshot:
        """A copy of the episode's state as it stands: :meth:`restore` on this env, or on
        another of the same building, goes on from it as this one would have gone on."""
        return NavSnapshot(self.world_id, copy.copy(self.data), copy.deepcopy(self.np_random),
                           copy.deepcopy(self._camera_rng), frozenset(self._visited),
                           None if self._panorama is None else self._panorama.copy())

    def restore(self, snapshot: NavSnapshot) -> None:
        """Go on from ``snapshot`` (:meth:`snapshot`), without drawing or rendering anything.

        Raises:
            ValueError: the snapshot is of another building (another ``world_id``).
        """
        if snapshot.world_id != self.world_id:
            raise ValueError(f"a snapshot of {snapshot.world_id!r} cannot go on in "
                             f"{self.world_id!r}")
        mujoco.mj_copyData(self.data, self.model, snapshot.data)
        self.np_random = copy.deepcopy(snapshot.rng)
        self._camera_rng = copy.deepcopy(snapshot.camera_rng)
        self._visited = set(snapshot.visited)
        self._panorama = None if snapshot.panorama is None else snapshot.panorama.copy()

    def render(self) -> np.ndarray | None:
        """Top-down view of the building with the robot, above the current panorama."""
        if self.render_mode != "rgb_array":
            return None
        top = self.renderer.top_down(self.data, self.plan.bounds)
        pano = self._panorama if self._panorama is not None else self._image()
        h = max(1, round(pano.shape[0] * top.shape[1] / pano.shape[1]))
        import cv2  # only rendering for people needs resizing

        strip = cv2.resize(pano, (top.shape[1], h), interpolation=cv2.INTER_AREA)
        return np.concatenate([top, strip], axis=0)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # -- helpers ---------------------------------------------------------------------------

    def _physics(self) -> None:
        """``n_substeps`` physics steps, the sensors evaluated in the last one only.

        Sensors do not act on the dynamics, and the observation reads them once per control
        step, so the 16 rangefinders' ray casts are skipped in every substep but the last: the
        same readings as evaluating them every substep, at a fraction of the cost.
        """
        opt = self.model.opt
        if self.n_substeps > 1:
            opt.disableflags |= _NO_SENSORS
            try:
                mujoco.mj_step(self.model, self.data, nstep=self.n_substeps - 1)
            finally:
                opt.disableflags &= ~_NO_SENSORS
        mujoco.mj_step(self.model, self.data)

    def _start_pose(self, options: dict[str, Any]) -> tuple[float, float, float]:
        unknown = set(options) - {"pose", "room"}
        if unknown:
            raise ValueError(f"unknown reset options {sorted(unknown)}; use 'pose' or 'room'")
        if "pose" in options:
            pose = np.asarray(options["pose"], dtype=np.float64)
            if pose.shape != (3,) or not np.all(np.isfinite(pose)):
                raise ValueError(f"options['pose'] must be finite (x, y, heading), got {pose}")
            if self.plan.room_at(pose[0], pose[1]) < 0:
                raise ValueError(f"start pose {pose.tolist()} is outside the building "
                                 f"(bounds {self.plan.bounds})")
            return float(pose[0]), float(pose[1]), float(pose[2])
        if "room" in options:
            room = self.plan.room_by_name(options["room"]).id
        else:
            room = int(self.np_random.integers(len(self.plan.rooms)))
        x, y = self.plan.free_point(room, self.np_random)
        return x, y, float(self.np_random.uniform(-math.pi, math.pi))

    def _observation(self) -> dict[str, np.ndarray]:
        obs = {
            # clipped: a wheel spinning against a wall must not leave the declared space
            "odometry": np.clip(self.robot.velocity(self.data), -10.0, 10.0).astype(np.float32),
            "heading": self.robot.heading(self.data).astype(np.float32),
            "ranges": self.robot.ranges(self.data).astype(np.float32),
        }
        if self.with_panorama:
            self._panorama = self._image()
            if self.changes.camera:
                self._panorama = degrade(self._panorama, self.changes, self._camera_rng,
                                         wrap=self.camera == "panorama")
            obs[self.image_key] = self._panorama
        return obs

    def _image(self) -> np.ndarray:
        if self.camera == "panorama":
            return self.renderer.panorama(self.data)
        return self.renderer.perspective(self.data, "robot/forward", *self._image_size)

    def _info(self) -> dict[str, Any]:
        pose = self.robot.pose(self.data)
        room = self.plan.room_at(pose[0], pose[1])
        return {
            "room_id": room,
            "room_name": self.plan.rooms[room].name if room >= 0 else "outside",
            "pose": pose,
        }


__all__ = ["PlaceNavEnv", "NavSnapshot", "MAX_SPEED", "MAX_TURN"]
