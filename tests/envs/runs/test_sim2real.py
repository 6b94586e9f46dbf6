"""A simulated building made like a data set: its camera, two drives, VPR-Bench's truth."""

from dataclasses import replace

import numpy as np
import pytest

from envs.runs.sim2real import Matched, condition_kwargs, matched_truth, record
from envs.tasks.tour import Tour
from envs.world.sensor import Sensor
from placeclust.camera import CameraSpec


def test_queries_match_references_nearby_in_the_same_room_looking_the_same_way():
    pose = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.0, np.pi], [3.0, 0.0, 0.0]])
    ref = Tour(np.zeros((4, 2, 2, 3), np.uint8), np.array([0, 0, 0, 0]), pose, ["a"])
    query = Tour(np.zeros((2, 2, 2, 3), np.uint8), np.array([0, 1]),
                 np.array([[0.2, 0.0, 0.1], [0.2, 0.0, 0.0]]), ["a", "b"])
    assert matched_truth(ref, query, 1.0, 60.0) == [[0, 1], []]


def test_a_grey_data_set_makes_a_grey_simulated_camera(tmp_path):
    m = Matched(CameraSpec(32, 24, False, 60.0), Sensor(), (("online", "orb"),), rooms=2,
                steps_per_room=4, stride=2)
    ref, query = record(1000, m)
    assert ref.frames.shape == (8, 24, 32, 3) == query.frames.shape
    assert (ref.frames[..., 0] == ref.frames[..., 2]).all()


def test_a_query_drive_under_another_light_is_the_same_route_darker():
    """Fault caught: the condition applied to the reference drive too, or to another route
    (the ground truth would then pair other poses)."""
    m = Matched(CameraSpec(32, 24, True, 60.0), Sensor(), (("online", "orb"),), rooms=2,
                steps_per_room=6)
    ref, query = record(1000, m)
    night_ref, night = record(1000, replace(m, query_conditions=("night",)))
    assert np.array_equal(night_ref.frames, ref.frames)
    assert np.allclose(night.pose, query.pose) and np.array_equal(night.room, query.room)
    assert night.frames.mean() < 0.8 * query.frames.mean()


def test_conditions_go_together_one_of_each_kind():
    assert condition_kwargs(("night", "moved"))["lighting"] == "night"
    assert condition_kwargs(("night", "moved"))["furniture_moved"] > 0
    with pytest.raises(ValueError, match="both set lighting"):
        condition_kwargs(("night", "cloudy"))


def test_photo_textures_change_the_frames_not_the_route():
    """Fault caught: the textures applied after the first frame (the renderer would keep the
    plain ones) or to only one of the two drives, or the lever moving the robot."""
    from envs.tasks.photo_textures import Photo

    m = Matched(CameraSpec(32, 24, True, 60.0), Sensor(), (("online", "orb"),), rooms=2,
                steps_per_room=4)
    ref, query = record(1000, m)
    photo_ref, photo_query = record(1000, replace(m, photo=Photo()))
    for plain, photo in ((ref, photo_ref), (query, photo_query)):
        assert np.allclose(photo.pose, plain.pose) and np.array_equal(photo.room, plain.room)
        assert np.abs(photo.frames.astype(int) - plain.frames).mean() > 2
    assert m.stamp() != replace(m, photo=Photo()).stamp()  # kept figures are not mixed up


def test_a_lap_gives_every_query_a_reference_and_keeps_the_reference_drive():
    """Fault caught: the lap driven along another path than the reference's (queries without
    references), or the reference drive changed by the query route."""
    m = Matched(CameraSpec(32, 24, True, 60.0), Sensor(), (("online", "orb"),), rooms=3,
                steps_per_room=30)
    ref, query = record(1001, m)
    lap_ref, lap = record(1001, replace(m, query_route="lap"))
    assert np.array_equal(lap_ref.frames, ref.frames) and np.allclose(lap_ref.pose, ref.pose)
    truth = matched_truth(lap_ref, lap, m.radius, m.camera.fov)
    tour_truth = matched_truth(ref, query, m.radius, m.camera.fov)
    assert np.mean([bool(t) for t in truth]) > 0.9 > np.mean([bool(t) for t in tour_truth])
    assert m.stamp() != replace(m, query_route="lap").stamp()
