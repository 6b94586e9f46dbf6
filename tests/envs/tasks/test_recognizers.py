"""The closed loop's one parse of recognizer names: kind, camera and a clear error."""

import pytest

from envs.tasks.recognizers import parse_recognizer


@pytest.mark.parametrize("name, camera", [
    ("panorama", "panorama"), ("nested", "forward"), ("oracle-cells:2", "panorama"),
    # a user's class says its camera: seed 001's mapper at another density reads forward
    # frames as the built-in name does (a fault: own classes always on the panorama)
    ("placeclust.nested:NestedMapper", "forward"),
    ("placeclust.online:OnlinePlaceClustering", "panorama"),
])
def test_the_camera_is_the_one_the_recognizer_was_built_for(name, camera):
    assert parse_recognizer(name).camera == camera


def test_an_unknown_name_is_one_line_naming_the_choices():
    with pytest.raises(ValueError, match="unknown recognizer 'panoramaa'; choose one of") as e:
        parse_recognizer("panoramaa")
    assert "\n" not in str(e.value)
