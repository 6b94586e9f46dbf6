import math

import cv2
import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env


def test_gymnasium_check_env(make_env):
    check_env(make_env(render_mode="rgb_array").unwrapped)


def test_stable_baselines3_check_env(make_env):
    sb3 = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3.check_env(make_env(), warn=True)


def test_observation_and_info(make_env):
    env = make_env()
    obs, info = env.reset(seed=0)
    assert obs["panorama"].shape == (64, 256, 3) and obs["panorama"].dtype == np.uint8
    assert obs["panorama"].std() > 10  # a real picture, not a blank frame
    assert set(info) >= {"room_id", "room_name", "pose"}
    assert info["room_name"] == env.unwrapped.plan.rooms[info["room_id"]].name


def test_same_seeds_same_pixels_other_scene_other_pixels(make_env):
    a, b, c = make_env(scene_seed=5), make_env(scene_seed=5), make_env(scene_seed=6)
    oa, _ = a.reset(seed=1)
    ob, _ = b.reset(seed=1)
    oc, _ = c.reset(seed=1)
    np.testing.assert_array_equal(oa["panorama"], ob["panorama"])
    assert not np.array_equal(oa["panorama"], oc["panorama"])
    for _ in range(5):
        oa, *_ = a.step(np.array([0.5, 0.3], np.float32))
        ob, *_ = b.step(np.array([0.5, 0.3], np.float32))
    np.testing.assert_array_equal(oa["panorama"], ob["panorama"])


def test_turning_90_degrees_rolls_the_panorama_a_quarter(make_env):
    env = make_env(panorama_width=512, panorama_height=128)
    x, y = env.unwrapped.plan.rooms[0].center
    p0 = env.reset(options={"pose": (x, y, 0.3)})[0]["panorama"].astype(int)
    p1 = env.reset(options={"pose": (x, y, 0.3 + math.pi / 2)})[0]["panorama"].astype(int)
    errors = [np.abs(np.roll(p0, s, axis=1) - p1).mean() for s in range(512)]
    assert int(np.argmin(errors)) == 512 // 4  # counter-clockwise turn: rolls right by W/4
    assert errors[128] < 2.0


def test_ground_truth_room_at_known_poses(make_env):
    env = make_env(n_rooms=6, scene_seed=2)
    for room in env.unwrapped.plan.rooms:
        _, info = env.reset(options={"pose": (*room.center, 0.0)})
        assert info["room_id"] == room.id and info["room_name"] == room.name
        _, info = env.reset(options={"room": room.name})
        assert info["room_id"] == room.id


def test_driving_forward_moves_along_the_heading(make_env):
    env = make_env()
    x, y = env.unwrapped.plan.rooms[0].center
    env.reset(options={"pose": (x - 0.6, y, 0.0)})
    for _ in range(10):
        _, _, _, _, info = env.step(np.array([1.0, 0.0], np.float32))
    dx, dy = info["pose"][0] - (x - 0.6), info["pose"][1] - y
    assert 0.25 < dx < 0.55 and abs(dy) < 0.05  # ~0.5 m/s for 1 s, with spin-up


def test_walls_stop_the_robot(make_env):
    env = make_env()
    room = env.unwrapped.plan.rooms[0]
    env.reset(options={"pose": (room.x0 + 0.6, (room.y0 + room.y1) / 2, math.pi)})
    for _ in range(40):
        _, _, _, _, info = env.step(np.array([1.0, 0.0], np.float32))
    assert info["pose"][0] > room.x0  # still inside


def test_every_wall_direction_has_sift_keypoints(make_env):
    env = make_env(panorama_width=512, panorama_height=128, n_rooms=8, scene_seed=1)
    sift = cv2.SIFT_create()
    for room in env.unwrapped.plan.rooms:
        obs, _ = env.reset(options={"pose": (*room.center, 0.0)})
        gray = cv2.cvtColor(obs["panorama"], cv2.COLOR_RGB2GRAY)
        xs = np.array([k.pt[0] for k in sift.detect(gray, None)])
        counts = np.histogram(xs, bins=8, range=(0, 512))[0]
        assert counts.min() >= 5, f"{room.name}: keypoints per 45 degrees {counts}"


def test_lighting_changes_pixels_not_the_world(make_env):
    day, night = make_env(lighting="day"), make_env(lighting="night")
    od, _ = day.reset(seed=0)
    on, _ = night.reset(seed=0)
    assert day.unwrapped.plan == night.unwrapped.plan
    assert on["panorama"].mean() < od["panorama"].mean()


@pytest.mark.parametrize("action,match", [
    ([np.nan, 0.0], "NaN"), ([0.0, np.inf], "NaN or inf"), ([1.5, 0.0], "outside"),
    ([0.1, 0.2, 0.3], "shape"),
])
def test_bad_actions_are_refused(make_env, action, match):
    env = make_env()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=match):
        env.step(np.array(action, np.float32))


@pytest.mark.parametrize("kwargs,error,match", [
    ({"n_rooms": 0}, ValueError, "n_rooms"),
    ({"panorama_width": 8}, ValueError, "too small"),
    ({"lighting": "dusk"}, ValueError, "lighting"),
    ({"render_mode": "depth_array"}, ValueError, "render_mode"),
    ({"colour": "red"}, TypeError, "colour"),
])
def test_bad_arguments_are_refused(kwargs, error, match):
    with pytest.raises(error, match=match):
        gym.make("PlaceNav-v0", **kwargs)


def test_reset_options_are_checked(make_env):
    env = make_env()
    with pytest.raises(ValueError, match="outside the building"):
        env.reset(options={"pose": (-50.0, 0.0, 0.0)})
    with pytest.raises(KeyError, match="unknown room"):
        env.reset(options={"room": "ballroom"})
    with pytest.raises(ValueError, match="unknown reset options"):
        env.reset(options={"goal": 1})


def test_render_shows_the_building_and_panorama(make_env):
    env = make_env(render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[1] == 480 and frame.shape[0] > 480
    assert frame.std() > 20


def test_async_vector_env():
    # spawn: workers forked from a process that already holds EGL contexts deadlock in Mesa
    envs_ = gym.vector.AsyncVectorEnv([
        lambda: gym.make("envs:PlaceNav-v0", panorama_width=128, panorama_height=32)
        for _ in range(2)], context="spawn")
    try:
        obs, info = envs_.reset(seed=[0, 1])
        assert obs["panorama"].shape == (2, 32, 128, 3)
        obs, reward, term, trunc, info = envs_.step(np.zeros((2, 2), np.float32))
        assert reward.shape == (2,) and set(info) >= {"room_id", "pose"}
    finally:
        envs_.close()


def test_sensors_read_once_per_step_read_as_if_every_substep(make_env):
    """Rangefinders are skipped in all but the last physics substep; the readings are those
    of evaluating them in every substep."""
    import mujoco

    fast = make_env(panorama=False).unwrapped
    reference = make_env(panorama=False).unwrapped
    fast.reset(seed=3)
    reference.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(60):
        action = rng.uniform(-1, 1, 2).astype(np.float32)
        obs = fast.step(action)[0]
        reference.robot.command(reference.data, action)
        mujoco.mj_step(reference.model, reference.data, nstep=reference.n_substeps)
        expected = reference._observation()
        for key in expected:
            np.testing.assert_array_equal(obs[key], expected[key], err_msg=key)
    assert fast.model.opt.disableflags == reference.model.opt.disableflags == 0
