"""A data set's camera: size and colour from its images, field of view from its metadata."""

import json

import numpy as np
import pytest

from placeclust.camera import DEFAULT_FOV, CameraSpec, camera_of, is_grey, sensor_of
from placeclust.datasets import DatasetError, write_image_folder
from placeclust.vprbench import write_vpr_bench


def _frames(colour, n=4, size=(30, 40)):
    rng = np.random.default_rng(0)
    if colour:
        return rng.integers(0, 256, (n, *size, 3), np.uint8)
    return np.repeat(rng.integers(0, 256, (n, *size, 1), np.uint8), 3, axis=3)


def test_size_and_colour_come_from_the_images(tmp_path):
    write_image_folder(tmp_path / "colour", _frames(True))
    write_image_folder(tmp_path / "grey", _frames(False, size=(24, 64)))
    colour, grey = camera_of(tmp_path / "colour"), camera_of(tmp_path / "grey")
    assert (colour.width, colour.height, colour.colour) == (40, 30, True)
    assert (grey.width, grey.height, grey.colour) == (64, 24, False)
    assert grey.fov == DEFAULT_FOV and grey.fov_source == "default"


def test_a_grey_jpeg_is_grey_despite_chroma_rounding():
    frame = _frames(False)[0].astype(int)
    frame[..., 0] = np.clip(frame[..., 0] + 2, 0, 255)  # JPEG leaves a level or two
    assert is_grey(frame.astype(np.uint8)) and not is_grey(_frames(True)[0])


def test_camera_json_states_field_of_view_and_colour(tmp_path):
    write_image_folder(tmp_path, _frames(True))
    (tmp_path / "camera.json").write_text(json.dumps({"horizontal_fov": 90, "colour": False}))
    camera = camera_of(tmp_path)
    assert (camera.fov, camera.fov_source, camera.colour) == (90.0, "camera.json", False)
    assert camera.fovy == pytest.approx(2 * np.degrees(np.arctan(np.tan(np.radians(45)) * 0.75)))


def test_a_vpr_bench_folder_is_read_from_ref(tmp_path):
    frames = _frames(False, size=(20, 32))
    write_vpr_bench(tmp_path, frames, _frames(True, size=(50, 50)), [[0], [1], [2], [3]])
    camera = camera_of(tmp_path)
    assert (camera.width, camera.height, camera.colour) == (32, 20, False)


@pytest.mark.parametrize("text, message", [
    ("{", "is not JSON"), ("[1]", "JSON object"), ('{"horizontal_fov": "wide"}', "number of deg"),
    ('{"horizontal_fov": 200}', "out of"), ('{"colour": "yes"}', "true or false"),
    ('{"sensor": [1.5]}', "sensor must be an object"), ('{"sensor": {"blur": "soft"}}',
                                                        "sensor must be an object"),
])
def test_bad_metadata_is_named(tmp_path, text, message):
    write_image_folder(tmp_path, _frames(True))
    (tmp_path / "camera.json").write_text(text)
    with pytest.raises(DatasetError, match=message):
        camera_of(tmp_path)


def test_a_camera_too_small_to_render_is_refused():
    with pytest.raises(ValueError, match="too small"):
        CameraSpec(8, 8, True, 60.0)


def test_a_camera_file_states_sensor_effects_and_can_live_elsewhere(tmp_path):
    write_image_folder(tmp_path / "data", _frames(False))
    assert sensor_of(tmp_path / "data") == {}  # nothing stated: the simulator adds nothing
    (tmp_path / "data" / "camera.json").write_text(json.dumps({"sensor": {"blur": 1.5}}))
    assert sensor_of(tmp_path / "data") == {"blur": 1.5}
    elsewhere = tmp_path / "corridor.json"  # for a data set one cannot write to
    elsewhere.write_text(json.dumps({"horizontal_fov": 75, "sensor": {"jpeg": 80}}))
    assert sensor_of(tmp_path / "data", elsewhere) == {"jpeg": 80}
    camera = camera_of(tmp_path / "data", elsewhere)
    assert (camera.fov, camera.fov_source) == (75.0, "camera.json")
    with pytest.raises(DatasetError, match="camera file .*nowhere.json does not exist"):
        camera_of(tmp_path / "data", tmp_path / "nowhere.json")
