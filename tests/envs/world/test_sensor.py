"""A camera's effects: each does what a real camera's does, and none leaves a frame alone."""

import numpy as np
import pytest

from envs.world.sensor import Sensor


def _frame(value=128, shape=(40, 60, 3)):
    return np.full(shape, value, np.uint8)


def _rng():
    return np.random.default_rng(0)


def test_no_effect_is_the_rendered_frame():
    frame = _frame()
    assert Sensor().apply(frame, _rng(), blur_px=30) is frame
    assert not Sensor().active and Sensor(jpeg=90).active


def test_grey_gives_luminance_in_every_channel():
    frame = np.zeros((4, 4, 3), np.uint8)
    frame[..., 0] = 255  # pure red: BT.601 luminance 0.299 * 255
    out = Sensor(grey=True).apply(frame, _rng())
    assert (out[..., 0] == out[..., 1]).all() and (out[..., 1] == out[..., 2]).all()
    assert out[0, 0, 0] == round(0.299 * 255)


def test_exposure_is_a_gain_in_stops_that_clips():
    frame = np.array([[[50, 100, 200]]], np.uint8)
    assert Sensor(exposure=1).apply(frame, _rng()).tolist() == [[[100, 200, 255]]]
    assert Sensor(exposure=-1).apply(frame, _rng()).tolist() == [[[25, 50, 100]]]


def test_shot_noise_grows_with_the_light_and_read_noise_does_not():
    dark, bright = _frame(20, (200, 200, 3)), _frame(200, (200, 200, 3))

    def spread(sensor, frame):
        return float(sensor.apply(frame, _rng()).astype(float).std())

    shot, read = Sensor(shot_noise=1.0), Sensor(read_noise=5.0)
    assert spread(shot, bright) > 2.5 * spread(shot, dark)  # sqrt(200 / 20) ~ 3.2
    assert spread(read, bright) == pytest.approx(spread(read, dark), rel=0.1)
    assert spread(read, bright) == pytest.approx(5.0, rel=0.1)


def test_grey_noise_is_the_same_in_every_channel():
    out = Sensor(grey=True, read_noise=10).apply(_frame(100), _rng())
    assert (out[..., 0] == out[..., 2]).all() and out.std() > 5


def test_motion_blur_smears_along_the_turn_only():
    frame = np.zeros((40, 60, 3), np.uint8)
    frame[:, 30] = 255  # a vertical edge: a yaw smears it sideways
    frame[20, :] = 255  # a horizontal line: a yaw leaves it sharp
    out = Sensor(motion_blur=0.01).apply(frame, _rng(), blur_px=9)
    assert (out[5, 26:35, 0] > 0).all() and out[5, 30, 0] < 100
    assert out[20, 10, 0] == 255 and out[19, 10, 0] == 0
    assert (Sensor(motion_blur=0.01).apply(frame, _rng(), blur_px=0) == frame).all()


def test_lens_blur_softens_an_edge_on_both_axes():
    frame = np.zeros((21, 21, 3), np.uint8)
    frame[10, 10] = 255
    out = Sensor(blur=1.0).apply(frame, _rng())
    assert 0 < out[10, 10, 0] < 255 and out[10, 11, 0] > 0 and out[11, 10, 0] > 0


def test_vignetting_darkens_the_corners_not_the_centre():
    out = Sensor(vignetting=0.4).apply(_frame(200, (41, 61, 3)), _rng())
    assert int(out[20, 30, 0]) == 200 and int(out[0, 0, 0]) == 120 == int(out[40, 60, 2])


def test_jpeg_loses_detail_but_keeps_the_picture():
    rng = np.random.default_rng(1)
    frame = rng.integers(0, 256, (48, 64, 3), np.uint8)
    low, high = Sensor(jpeg=10).apply(frame, _rng()), Sensor(jpeg=95).apply(frame, _rng())
    err = [np.abs(x.astype(int) - frame).mean() for x in (low, high)]
    assert err[0] > err[1] > 0 and low.shape == frame.shape and low.dtype == np.uint8


@pytest.mark.parametrize("kwargs, message", [
    ({"read_noise": -1}, "non-negative"), ({"exposure": float("nan")}, "finite"),
    ({"exposure": 9}, "±8 stops"), ({"vignetting": 1.5}, "[0, 1]"), ({"jpeg": 101}, "1-100"),
    ({"jpeg": 50.5}, "1-100"),
])
def test_bad_settings_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        Sensor(**kwargs)


def test_parse_reads_the_command_line_and_names_mistakes():
    assert Sensor.parse(["grey=1", "jpeg=75", "read_noise=2.5"]) == Sensor(
        grey=True, jpeg=75, read_noise=2.5)
    assert Sensor.parse(None) == Sensor()
    with pytest.raises(ValueError, match="NAME one of grey"):
        Sensor.parse(["gain=2"])
    with pytest.raises(ValueError, match="not a number"):
        Sensor.parse(["exposure=bright"])
    with pytest.raises(ValueError, match="not a true/false"):
        Sensor.parse(["grey=maybe"])
    base = Sensor(blur=1.5, read_noise=2.0)
    assert Sensor.parse(["blur=3"], base) == Sensor(blur=3.0, read_noise=2.0)  # one replaced


def test_a_camera_files_settings_are_checked_and_named():
    assert Sensor.of({"grey": True, "jpeg": 75, "blur": 1}) == Sensor(grey=True, jpeg=75,
                                                                      blur=1.0)
    assert Sensor.of({}) == Sensor()
    for settings, message in [({"gain": 2}, "unknown sensor setting 'gain'"),
                              ({"grey": 1}, "grey must be true or false"),
                              ({"jpeg": 7.5}, "jpeg must be a whole number"),
                              ({"blur": True}, "blur must be a number"),
                              ({"blur": -1}, "non-negative")]:
        with pytest.raises(ValueError, match=f"^cam.json: .*{message}"):
            Sensor.of(settings, "cam.json")
