"""Offscreen rendering: culling changes no pixel, contexts stay apart, walls stay solid."""

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401 - registers PlaceNav-v0
from envs.world.rendering import SceneRenderer
from envs.world.scene import CORE_GROUP, NEAR_CLIP


def _poses(plan, rng, n_random=12):
    """Room centres, both sides of and inside every doorway, 0.3 m from walls looking along
    them, and random free points."""
    poses = [(*room.center, h) for room in plan.rooms for h in (0.3, 2.4)]
    for wall in plan.walls[::2]:
        mx, my = (wall.x0 + wall.x1) / 2, (wall.y0 + wall.y1) / 2
        for side, room in zip((-1, 1), wall.sides):
            if room >= 0:
                x, y = (mx, my + side * 0.3) if wall.axis == "x" else (mx + side * 0.3, my)
                along = 0.0 if wall.axis == "x" else np.pi / 2
                poses += [(x, y, along + 0.6), (x, y, along + np.pi - 0.6)]
    for door in plan.doors:
        normal = np.array([0.0, 1.0] if door.axis == "x" else [1.0, 0.0])
        for side in (-0.6, 0.0, 0.6):
            x, y = np.array([door.x, door.y]) + side * normal
            poses += [(x, y, h) for h in (0.0, 1.6, 3.9)]
    for _ in range(n_random):
        room = int(rng.integers(len(plan.rooms)))
        poses.append((*plan.free_point(room, rng, clearance=0.25), rng.uniform(-np.pi, np.pi)))
    return poses


@pytest.mark.parametrize("world", [dict(scene_seed=1000, n_rooms=8),
                                   dict(scene_seed=2001, n_rooms=12),
                                   dict(scene_seed=5, n_rooms=6, layout="corridor"),
                                   dict(scene_seed=1001, n_rooms=6, doors=0.5),
                                   dict(scene_seed=1002, n_rooms=6, local_light=True,
                                        lighting="night")])
def test_culling_draws_the_same_panorama_as_drawing_everything(make_env, world):
    env = make_env(**world).unwrapped
    env.reset(seed=0)
    everything = SceneRenderer(env.model, env.scene.camera_names, env.geometry, cull=False)
    # culled explicitly, not the renderer's default: the test compares the two whatever it is
    culling = SceneRenderer(env.model, env.scene.camera_names, env.geometry, plan=env.plan,
                            geom_rooms=env.scene.geom_rooms, cull=True)
    try:
        for pose in _poses(env.plan, np.random.default_rng(0)):
            env.reset(options={"pose": pose})
            np.testing.assert_array_equal(culling.panorama(env.data),
                                          everything.panorama(env.data), err_msg=pose)
    finally:
        everything.close()
        culling.close()


def test_culling_draws_the_same_forward_image_as_drawing_everything(make_env):
    env = make_env(scene_seed=1000, n_rooms=8, camera="forward", image_width=160,
                   image_height=120).unwrapped
    env.reset(seed=0)
    assert env.renderer._culling  # noqa: SLF001  the env's own images are the culled ones
    everything = SceneRenderer(env.model, env.scene.camera_names, env.geometry, cull=False)
    try:
        for pose in _poses(env.plan, np.random.default_rng(1)):
            obs, _ = env.reset(options={"pose": pose})
            np.testing.assert_array_equal(
                obs["image"], everything.perspective(env.data, "robot/forward", 160, 120))
    finally:
        everything.close()


def test_culling_skips_most_of_a_large_building(make_env):
    env = make_env(scene_seed=2001, n_rooms=12).unwrapped
    env.reset(seed=0)
    renderer = env.renderer
    shown = renderer._in_view(env.data, renderer._camera_ids, renderer._ring_half)  # noqa: SLF001
    # every camera draws less than half of the building's geoms
    assert shown.mean(axis=1).max() < 0.5


def test_skipping_the_wall_boxes_leaves_the_panorama_unchanged(make_env):
    # the robot's cameras draw door-jamb caps instead of the walls' boxes (envs.world.scene): from
    # anywhere a robot stands, looking through doorways or along walls, the pixels are the same
    env = make_env(scene_seed=1000, n_rooms=8)
    shown = []
    for pose in _poses(env.unwrapped.plan, np.random.default_rng(2), n_random=0):
        env.reset(options={"pose": pose})
        renderer = env.unwrapped.renderer
        skipped = renderer.panorama(env.unwrapped.data)
        renderer._option.geomgroup[CORE_GROUP] = 1  # noqa: SLF001 - draw the boxes too
        try:
            with_boxes = renderer.panorama(env.unwrapped.data)
        finally:
            renderer._option.geomgroup[CORE_GROUP] = 0  # noqa: SLF001
        shown.append(np.abs(skipped.astype(int) - with_boxes).max())
    assert len(shown) > 30
    assert max(shown) == 0


def test_closing_one_env_leaves_another_envs_pictures_alone():
    # each renderer frees its GL objects in its own context: freed with another context
    # current, they would be that context's objects, and the other env would go on returning
    # its last picture
    def drive(env, n=6):
        return [env.step(np.array([0.5, 0.4], np.float32))[0]["panorama"] for _ in range(n)]

    kwargs = dict(panorama_width=128, panorama_height=32, n_rooms=3)
    alone = gym.make("PlaceNav-v0", **kwargs)
    alone.reset(seed=0)
    expected = drive(alone)
    alone.close()
    other = gym.make("PlaceNav-v0", **kwargs, scene_seed=7)
    env = gym.make("PlaceNav-v0", **kwargs)
    try:
        other.reset(seed=0)
        env.reset(seed=0)
        other.close()  # while env's context is current
        for got, want in zip(drive(env), expected):
            np.testing.assert_array_equal(got, want)
    finally:
        env.close()


def test_a_wall_the_robot_stands_against_is_not_see_through(make_env):
    # MuJoCo scales the near clipping plane by the model's size: at 0.01 of a 16-room
    # building's extent it lay ~0.25 m out and cut away the wall in front of the robot
    env = make_env(scene_seed=3, n_rooms=16).unwrapped
    assert env.model.vis.map.znear * env.model.stat.extent == pytest.approx(NEAR_CLIP)
    room = env.plan.rooms[0]  # x0 and y0 are outer walls: nothing behind them
    obs, _ = env.reset(options={"pose": (room.x0 + 0.25, room.center[1], np.pi)})
    ahead = obs["panorama"][16:48, 126:130]  # the middle rows of the column facing the wall
    assert (ahead.max(axis=-1) > 0).all()  # no background shows through


def test_the_renderer_draws_the_stored_reference_pixels():
    """The render fingerprint of the reference frames, stored with what drew them: on a machine
    like one that drew a stored reference (Mesa, MuJoCo and CPU), a change that moves one pixel
    of a benchmark's worlds fails here (and is then a new reference, and a new suite version's
    business). What a reference did not record (``null``: the first one's CPU) matches any
    value; a machine like none of them skips, naming what it has."""
    import json
    from pathlib import Path

    from envs.runs.suite import render_fingerprint, renderer_info

    stored = json.loads((Path(__file__).parent / "render_reference.json").read_text())
    here = renderer_info()
    alike = [ref for ref in stored["references"]
             if all(ref[k] in (v, None) for k, v in here.items())]
    if not alike:
        pytest.skip(f"no stored reference was drawn by a machine like this one ({here})")
    assert render_fingerprint() in {ref["render_fingerprint"] for ref in alike}


def test_the_simulator_drives_the_stored_reference_path():
    """The physics fingerprint of the fixed drive, stored with the MuJoCo that simulated it (the
    pinned environment's among them): with that MuJoCo a change that moves the robot by one bit
    fails here (the pixels alone cannot tell: MuJoCo 3.17 draws 4.0's pixels but drives
    elsewhere, and 4.0.1 drives otherwise than 4.0.0)."""
    import json
    import platform
    from pathlib import Path

    import mujoco

    from envs.runs.suite import physics_fingerprint

    stored = json.loads((Path(__file__).parent / "physics_reference.json").read_text())
    here = {"mujoco": mujoco.__version__, "machine": platform.machine()}
    alike = [ref for ref in stored["references"] if here == {k: ref[k] for k in here}]
    if not alike:  # the pinned environment (constraints.txt) has one: a fresh install runs it
        drove = [{k: ref[k] for k in here} for ref in stored["references"]]
        pytest.skip(f"not the pinned environment: the references were driven by {drove}; "
                    f"this machine has {here}")
    assert physics_fingerprint() in {ref["physics_fingerprint"] for ref in alike}
