"""Appearance changes: the same building, things moved, a worse camera; all seeded."""

import numpy as np
import pytest

from envs.world.changes import Changes, degrade, rearrange_furniture
from envs.world.layout import clear_of


def _first_panorama(env, seed=0):
    obs, _ = env.reset(seed=seed, options={"pose": (*env.unwrapped.plan.rooms[0].center, 0.0)})
    return obs["panorama"]


def test_no_changes_is_the_same_world(make_env):
    plain = _first_panorama(make_env())
    assert np.array_equal(plain, _first_panorama(make_env(changes_seed=7)))


def test_furniture_moved_and_removed(make_env):
    plan = make_env().unwrapped.plan
    changed = rearrange_furniture(plan, Changes(furniture_moved=0.5, furniture_removed=0.25,
                                                seed=3))
    n = len(plan.furniture)
    assert len(changed.furniture) == n - round(0.25 * n)
    assert len(set(changed.furniture) - set(plan.furniture)) >= 1  # some stand elsewhere
    for f in changed.furniture:  # still clear of doors and of each other
        others = [o for o in changed.furniture if o is not f and o.room == f.room]
        assert clear_of(f, others, list(plan.doors))
    assert changed.rooms == plan.rooms and changed.doors == plan.doors


def test_changed_world_looks_different_but_is_the_same_building(make_env):
    plain_env = make_env()
    moved_env = make_env(furniture_moved=0.5, furniture_removed=0.3, posters_swapped=1.0)
    plain, moved = _first_panorama(plain_env), _first_panorama(moved_env)
    assert (plain != moved).any(-1).mean() > 0.02
    assert moved_env.unwrapped.world_id == plain_env.unwrapped.world_id
    assert moved_env.unwrapped.plan.rooms == plain_env.unwrapped.plan.rooms


def test_camera_noise_follows_the_reset_seed(make_env):
    env = make_env(camera_noise=8.0, camera_blur=1.0, changes_seed=1)
    a, b = _first_panorama(env, seed=0), _first_panorama(env, seed=0)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, _first_panorama(env, seed=1))
    clean = _first_panorama(make_env())
    assert 3 < np.abs(a.astype(int) - clean).mean() < 20


@pytest.mark.parametrize("kwargs, message", [
    ({"furniture_moved": 1.5}, "furniture_moved must be a fraction"),
    ({"posters_swapped": -0.1}, "posters_swapped must be a fraction"),
    ({"camera_noise": float("nan")}, "camera_noise must be finite"),
    ({"camera_blur": -1.0}, "camera_blur must be finite and non-negative"),
])
def test_bad_changes_are_named(make_env, kwargs, message):
    with pytest.raises(ValueError, match=message):
        make_env(**kwargs)


def test_blur_wraps_the_panorama_but_not_a_forward_image():
    """A bright right edge bleeds into the left column of a panorama (its neighbour across
    360°) and never into a forward image's, whose edges are not neighbours."""
    frame = np.zeros((8, 32, 3), np.uint8)
    frame[:, -2:] = 255
    blur = Changes(camera_blur=1.0)
    rng = np.random.default_rng(0)
    panorama = degrade(frame, blur, rng, wrap=True)
    forward = degrade(frame, blur, rng, wrap=False)
    assert panorama[:, 0].min() > 0 and forward[:, 0].max() == 0
    assert np.array_equal(panorama[:, 8:24], forward[:, 8:24])  # the same blur away from edges


def test_the_forward_camera_blurs_without_wrapping(make_env):
    size = {"camera": "forward", "image_width": 64, "image_height": 48}
    clean = make_env(**size).reset(seed=0)[0]["image"]
    blurred = make_env(camera_blur=1.0, **size).reset(seed=0)[0]["image"]
    expected = degrade(clean, Changes(camera_blur=1.0), np.random.default_rng(0), wrap=False)
    assert np.array_equal(blurred, expected)
