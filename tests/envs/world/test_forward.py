"""``camera="forward"``: one perspective camera looking ahead, as seed 001's monocular camera."""

import json

import gymnasium as gym
import numpy as np
import pytest

from envs import PlaceIdWrapper
from envs.commands.cli import main
from placeclust import PANORAMA, OnlinePlaceClustering


def _profile(img: np.ndarray, n: int = 16) -> np.ndarray:
    """Mean colour of ``n`` vertical bands, left to right: where things are, not how."""
    return np.stack([b.reshape(-1, 3).mean(0) for b in np.array_split(img, n, axis=1)]).ravel()


def test_the_forward_image_is_what_lies_ahead_in_the_panorama(make_env):
    forward = make_env(camera="forward")
    pano = make_env(panorama_width=512, panorama_height=128)
    assert "image" in forward.observation_space.spaces
    assert "panorama" not in forward.observation_space.spaces
    ahead, behind = [], []
    for seed in range(6):
        img = forward.reset(seed=seed)[0]["image"]
        p = pano.reset(seed=seed)[0]["panorama"]
        assert img.shape == (240, 320, 3) and forward.observation_space.contains(
            forward.reset(seed=seed)[0])
        # 70° of the 512-column panorama around its centre (the heading), and the same behind
        half = round(512 * 35 / 360)
        front = p[16:112, 256 - half:256 + half]
        back = np.roll(p, 256, axis=1)[16:112, 256 - half:256 + half]
        ahead.append(np.corrcoef(_profile(img), _profile(front))[0, 1])
        behind.append(np.corrcoef(_profile(img), _profile(back))[0, 1])
    assert np.mean(ahead) > np.mean(behind) + 0.2, (ahead, behind)


def test_a_forward_world_is_another_map_world(make_env):
    assert make_env(camera="forward").unwrapped.world_id != make_env().unwrapped.world_id


def test_bad_camera_arguments_are_named(make_env):
    with pytest.raises(ValueError, match="unknown camera 'fisheye'"):
        make_env(camera="fisheye")
    with pytest.raises(ValueError, match="field of view"):
        make_env(camera="forward", image_fov=180)


def test_the_place_id_wrapper_reads_the_forward_image(made):
    env = gym.make("PlaceNav-v0", camera="forward")
    made.append(env)
    wrapped = PlaceIdWrapper(env, max_places=8)
    obs, info = wrapped.reset(seed=0)
    assert obs["place_id"] in wrapped.observation_space["place_id"]
    with pytest.raises(ValueError, match="looks forward"):
        PlaceIdWrapper(env, recognizer=OnlinePlaceClustering(**PANORAMA))


def test_tour_records_the_forward_camera_and_cluster_refuses_side_views(tmp_path, capsys):
    main(["tour", "--camera", "forward", "--rooms", "2", "--steps", "30", "--out",
          str(tmp_path / "t"), "--quiet"])
    with np.load(tmp_path / "t" / "tour.npz") as z:
        assert z["frames"].shape == (30, 240, 320, 3) and str(z["camera"]) == "forward"
    main(["cluster", "--algo", "nested", "--tour", str(tmp_path / "t" / "tour.npz"),
          "--out", str(tmp_path / "c"), "--quiet"])
    assert json.loads((tmp_path / "c" / "metrics.json").read_text())["camera"] == "forward"
    with pytest.raises(SystemExit) as exc:
        main(["cluster", "--preset", "panorama", "--tour", str(tmp_path / "t" / "tour.npz"),
              "--out", str(tmp_path / "p")])
    assert exc.value.code == 2 and "forward camera" in capsys.readouterr().err
    assert not (tmp_path / "p").exists()


def test_the_goal_panorama_needs_the_panorama(make_task):
    with pytest.raises(ValueError, match="needs the 360° panorama"):
        make_task(panorama=True, camera="forward", goal_panorama=True)
