import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from placeclust import UNKNOWN, OnlinePlaceClustering
from placeclust.kernel import UnionKernel
from placeclust.metrics import precision
from placeclust.synthetic import textured


@pytest.mark.parametrize("features", ["sift", "orb"])
def test_two_textures_form_two_places(two_places, features):
    frames, truth = two_places
    model = OnlinePlaceClustering(features=features)
    pred = np.array([model.learn_predict_one(f) for f in frames])
    assert model.n_places == 2
    assert precision(pred, truth) == 1.0
    assert model.graph.has_edge(0, 1)  # the new place is linked to the one it came from


def test_the_same_frame_twice_is_one_place(two_places):
    model = OnlinePlaceClustering()
    frame = two_places[0][0]
    assert model.learn_predict_one(frame) == model.learn_predict_one(frame) == 0
    assert model.n_places == 1


def test_revisiting_a_non_neighbour_closes_a_loop(two_places):
    frames, _ = two_places
    from placeclust.synthetic import textured

    model = OnlinePlaceClustering()
    for f in (frames[0], frames[25], textured(3), textured(4), frames[1]):
        last = model.learn_predict_one(f)
    assert last == 0 and model.n_places == 4  # back in place 0, not a duplicate
    assert model.graph.has_edge(3, 0)
    assert OnlinePlaceClustering(relocalize=False).relocalize is False


def test_a_recognised_frame_is_matched_with_its_place_alone(two_places):
    # tracking must not get slower as the current place gains neighbours (loop closures)
    frames, _ = two_places
    model = OnlinePlaceClustering(features="orb")
    for f in (frames[0], textured(3), frames[1], textured(4), frames[2], textured(5), frames[3]):
        model.learn_one(f)
    assert model.current == 0 and model.graph.degree(0) == 3
    compared = []
    model._compare = lambda place, desc, own=model._compare: compared.append(place) or own(
        place, desc)
    assert model.learn_predict_one(frames[0]) == 0
    assert compared == [0]


def test_a_full_map_stops_growing_and_still_recognises(two_places):
    frames, _ = two_places
    model = OnlinePlaceClustering(features="orb", max_places=2)
    assert [model.learn_predict_one(f) for f in (frames[0], frames[30])] == [0, 1]
    assert model.map_full
    sizes = {p: len(k) for p, k in model.kernels.items()}
    other = textured(7)  # would open a place: a full map localizes it instead
    assert model.learn_predict_one(other) == pickle.loads(pickle.dumps(model)).localize_one(other)
    assert model.n_places == 2 and {p: len(k) for p, k in model.kernels.items()} == sizes
    assert model.learn_predict_one(frames[1]) == 0  # known places are still recognised
    with pytest.raises(ValueError, match="max_places"):
        OnlinePlaceClustering(max_places=0)


def test_predict_one_does_not_learn(two_places):
    frames, _ = two_places
    model = OnlinePlaceClustering()
    model.learn_one(frames[0])
    assert model.predict_one(frames[30]) == UNKNOWN
    assert model.n_places == 1


def test_featureless_frames_are_unknown_and_change_nothing():
    model = OnlinePlaceClustering()
    assert model.learn_predict_one(np.zeros((128, 512, 3), np.uint8)) == UNKNOWN
    assert model.learn_predict_one(np.full((128, 512), 200, np.uint8)) == UNKNOWN
    assert model.n_places == 0


@pytest.mark.parametrize("frame,match", [
    (np.zeros((64, 256, 2), np.uint8), "shape"),
    (np.zeros((64, 256), np.int32), "dtype"),
    (np.full((64, 256), np.nan), "NaN"),
    (np.full((64, 256), 3.0), r"\[0, 1\]"),
    (np.zeros((8, 8), np.uint8), "too small"),
    ([[1, 2], [3, 4]], "numpy array"),
])
def test_bad_frames_are_refused(frame, match):
    with pytest.raises(ValueError, match=match):
        OnlinePlaceClustering().learn_one(frame)


def test_frames_of_another_size_are_refused(two_places):
    model = OnlinePlaceClustering()
    model.learn_one(two_places[0][0])
    with pytest.raises(ValueError, match="differs"):
        model.learn_one(np.zeros((32, 128, 3), np.uint8))


def test_thresholds_must_be_ordered():
    with pytest.raises(ValueError, match="t_update_cluster < t_new_cluster"):
        OnlinePlaceClustering(t_new_cluster=0.5, t_update_cluster=0.7)


def test_model_pickles_with_its_map(two_places):
    frames, _ = two_places
    model = OnlinePlaceClustering(features="orb")
    for f in frames[::4]:
        model.learn_one(f)
    clone = pickle.loads(pickle.dumps(model))
    assert clone.n_places == model.n_places
    assert clone.predict_one(frames[1]) == model.predict_one(frames[1])


_SHAPES = st.one_of(
    hnp.array_shapes(min_dims=1, max_dims=4, min_side=1, max_side=12),
    st.tuples(st.sampled_from([14, 64, 128]), st.sampled_from([14, 100, 512])),
    st.tuples(st.sampled_from([14, 128]), st.sampled_from([20, 512]),
              st.sampled_from([1, 2, 3, 4, 5])),
)


@settings(max_examples=60, deadline=None)
@given(frame=hnp.arrays(st.sampled_from([np.uint8, np.float32, np.float64, np.int16, np.bool_]),
                        _SHAPES))
def test_any_array_is_a_place_an_unknown_or_a_named_error(frame):
    """Whatever array comes in: a place id, UNKNOWN, or a ValueError; the map never breaks."""
    model = OnlinePlaceClustering(features="orb")
    base = textured(5)
    assert model.learn_predict_one(base) == 0
    before = (model.n_places, {p: len(k) for p, k in model.kernels.items()})
    try:
        place = model.learn_predict_one(frame)
    except ValueError as exc:
        assert str(exc)  # it names the problem
        assert (model.n_places, {p: len(k) for p, k in model.kernels.items()}) == before
    else:
        assert place == UNKNOWN or 0 <= place < model.n_places
        assert frame.shape[:2] == base.shape[:2]
    assert model.learn_predict_one(base) == 0  # still recognises its place


def test_side_view_ignores_what_lies_ahead_and_behind():
    """Two panoramas with the same sides but other things ahead of and behind the robot: with
    the same thresholds, one place when only the sides are looked at, two with the whole view."""
    from placeclust.synthetic import textured

    first, other = textured(1), textured(2)
    second, width = first.copy(), first.shape[1]
    for quarter in (slice(0, width // 8), slice(3 * width // 8, 5 * width // 8),
                    slice(7 * width // 8, width)):  # behind, ahead, behind
        second[:, quarter] = other[:, quarter]
    places = {}
    for view in ("sides", "full"):
        model = OnlinePlaceClustering(features="sift", view=view, t_new_cluster=0.5,
                                      t_update_cluster=0.1)
        places[view] = [model.learn_predict_one(f) for f in (first, second)]
    assert places == {"sides": [0, 0], "full": [0, 1]}


def _pan(seed: int, n: int, step: int) -> list[np.ndarray]:
    """``n`` 512-wide crops of a wide texture, each ``step`` px further: slow, steady drift."""
    wide = textured(seed, shape=(128, 512 + n * step))
    return [np.ascontiguousarray(wide[:, k * step: k * step + 512]) for k in range(n)]


def test_the_scene_change_gate_keeps_a_drifting_view_in_one_place():
    """A slow pan leaves a small kernel behind: without the gate it opens places along the way,
    with it the pan stays one place and only a sudden change (a doorway) opens another."""
    frames = _pan(5, 60, 16) + [textured(6)] * 5
    places, searches = {}, {}
    for gate in (None, 0.25):
        model = OnlinePlaceClustering(kernel_capacity=300, scene_change=gate, scene_lag=3)
        searched = []
        model._index.ranked = lambda desc, m=model, own=model._index.ranked, log=searched: (
            log.append(m._gate is not None and m._gate.is_open) or own(desc))
        places[gate] = [model.learn_predict_one(f) for f in frames]
        searches[gate] = searched
    assert max(places[None][:60]) >= 1  # the ungated map split the pan
    assert places[0.25] == [0] * 60 + [1] * 5
    # with the gate closed the robot is still in its room: the map is not searched
    assert len(searches[None]) > 0 and all(searches[0.25])
    with pytest.raises(ValueError, match="threshold"):
        OnlinePlaceClustering(scene_change=1.0)


def test_a_frame_the_closed_gate_keeps_is_matched_with_its_place_once(monkeypatch):
    """A frame beyond ``t_new_cluster`` that the closed gate keeps in its place is absorbed
    with the correspondences its comparison found: no kernel is matched twice per frame."""
    model = OnlinePlaceClustering(kernel_capacity=300, scene_change=0.25, scene_lag=3)
    matched, far = [], []
    own_match, own_compare = UnionKernel.match, model._compare
    monkeypatch.setattr(UnionKernel, "match",
                        lambda kernel, desc: matched.append(id(kernel)) or own_match(kernel, desc))

    def compare(place, desc):
        compared = own_compare(place, desc)
        far.append(compared.distance > model.t_new_cluster)
        return compared

    model._compare = compare
    kept = 0
    for frame in _pan(5, 60, 16):
        matched.clear()
        far.clear()
        assert model.learn_predict_one(frame) == 0
        assert len(matched) == len(set(matched))
        kept += bool(far) and all(far)
    assert kept > 0  # the pan did leave the kernel behind
