"""The photographic-statistics lever: what it changes, what it keeps, its spectrum."""

import numpy as np
import pytest

from envs.tasks.photo_textures import SURFACES, Photo, pink_field, retexture
from envs.world.scene import build_scene


def _textures(model):
    out = {}
    for i in range(model.ntex):
        n = int(model.tex_height[i] * model.tex_width[i] * model.tex_nchannel[i])
        out[model.texture(i).name] = model.tex_data[model.tex_adr[i]:model.tex_adr[i] + n].copy()
    return out


@pytest.fixture(scope="module")
def plain():
    return _textures(build_scene(3, n_rooms=2).model)


def test_surfaces_change_and_posters_stay(plain):
    model = build_scene(3, n_rooms=2).model
    assert retexture(model, seed=3) == sum(n.startswith(SURFACES) for n in plain)
    after = _textures(model)
    for name, data in plain.items():
        if name.startswith(SURFACES):
            assert np.abs(after[name].astype(int) - data).mean() > 2, name
        else:  # posters: the printed things a real room has too
            assert np.array_equal(after[name], data), name


def test_the_same_seed_gives_the_same_pixels():
    a, b, c = (build_scene(3, n_rooms=2).model for _ in range(3))
    retexture(a, 7), retexture(b, 7), retexture(c, 8)
    assert np.array_equal(a.tex_data, b.tex_data)
    assert not np.array_equal(a.tex_data, c.tex_data)


def test_no_lever_on_is_the_plain_texture(plain):
    model = build_scene(3, n_rooms=2).model
    retexture(model, 3, Photo(detail=1.0, grain=0.0, stains=0))
    after = _textures(model)
    assert all(np.abs(after[n].astype(int) - plain[n]).max() <= 1 for n in plain)


def test_the_field_falls_as_one_over_f():
    """Fails on white noise (slope 0) or on a field of one scale."""
    field = pink_field(np.random.default_rng(0), 256, 256)
    amp = np.abs(np.fft.rfft2(field))
    f = np.hypot(np.fft.fftfreq(256)[:, None], np.fft.rfftfreq(256)[None, :])
    keep = (f > 0.01) & (f < 0.4)
    slope = np.polyfit(np.log(f[keep]), np.log(amp[keep]), 1)[0]
    assert -1.15 < slope < -0.85
    assert abs(field.mean()) < 1e-3 and abs(field.std() - 1) < 1e-3


@pytest.mark.parametrize("bad", [dict(detail=1.5), dict(grain=-0.1), dict(stains=-1)])
def test_out_of_range_settings_are_named(bad):
    with pytest.raises(ValueError, match="photo settings out of range"):
        Photo(**bad)
