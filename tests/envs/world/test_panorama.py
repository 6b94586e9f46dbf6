import numpy as np
import pytest

from envs.world.panorama import PanoramaGeometry


@pytest.mark.parametrize("size", [(512, 128), (256, 64), (300, 50)])
@pytest.mark.parametrize("n", [3, 4, 6])
def test_remap_tables_stay_inside_the_strip(size, n):
    g = PanoramaGeometry(*size, n_cameras=n)
    mx, my = g.remap_tables()
    h, w = g.strip_shape
    assert mx.shape == my.shape == (size[1], size[0])
    assert mx.min() >= 0 and mx.max() <= w - 1
    assert my.min() >= 0 and my.max() <= h - 1


def test_heading_is_the_centre_column():
    g = PanoramaGeometry(512, 128)
    phi = g.azimuth()
    assert abs(phi[256]) < 2 * np.pi / 512
    assert abs(phi[128] - np.pi / 2) < 2 * np.pi / 512  # the robot's left at W/4


@pytest.mark.parametrize("size", [(16, 128), (512, 4)])
def test_too_small_panoramas_are_refused(size):
    with pytest.raises(ValueError, match="too small"):
        PanoramaGeometry(*size)


def test_the_camera_does_not_see_the_rangefinder_rays(make_env):
    """MuJoCo draws rangefinder rays in yellow by default; a panorama must show the room only."""
    env = make_env(panorama_width=512, panorama_height=128)
    obs, _ = env.reset(seed=0)
    p = obs["panorama"].astype(int)
    ray_yellow = (p[..., 0] > 200) & (p[..., 1] > 200) & (p[..., 2] < 80)
    assert ray_yellow.sum() == 0
