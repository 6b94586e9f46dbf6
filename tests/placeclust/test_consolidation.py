"""Consolidation (placeclust.consolidation): a room seen anew is merged back into its place."""

import numpy as np
import pytest

from placeclust import OnlinePlaceClustering, runner
from placeclust.checks import check_recognizer
from placeclust.consolidation import Rehearsal
from placeclust.mapfile import load_map, save_map
from placeclust.synthetic import jitter, places, textured

CONSOLIDATE = {"consolidate": 0.85, "consolidate_streak": 2}


@pytest.fixture(scope="module")
def room_seen_anew():
    """Room A, room B, then A again from a new side: the first frames show mostly new
    content (so a place opens), the later ones more and more of A."""
    rng = np.random.default_rng(0)
    a, b, new = textured(1), textured(2), textured(3)

    def seen_anew(share: float) -> np.ndarray:
        out = new.copy()
        out[:, : int(share * a.shape[1])] = a[:, : int(share * a.shape[1])]
        return jitter(out, rng)

    frames = [jitter(a, rng) for _ in range(4)] + [jitter(b, rng) for _ in range(4)]
    frames += [seen_anew(s) for s in (0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0)]
    return np.stack(frames), np.array([0] * 4 + [1] * 4 + [0] * 7)


@pytest.mark.parametrize("features", ["sift", "orb"])
def test_a_room_seen_anew_is_merged_into_its_place(room_seen_anew, features):
    frames, _ = room_seen_anew
    model = OnlinePlaceClustering(features=features, **CONSOLIDATE)
    ids = [model.learn_predict_one(f) for f in frames]
    assert ids[8] == 2, "the new side of room A opens a place"
    assert ids[-1] == 0, "once merged, the robot is in A's place"
    assert model.merged == {2: 0}
    assert model.resolve(ids).tolist() == [0] * 4 + [1] * 4 + [0] * 7
    assert model.n_places == 2 and sorted(model.graph.edges) == [(0, 1)]
    assert all(model.graph.nodes[p]["n_images"] == k.n_images for p, k in model.kernels.items())
    assert model.predict_one(frames[9]) == 0
    assert model.learn_predict_one(textured(4)) == 3, "a merged id is never reused"


def test_the_papers_recognizer_merges_nothing(room_seen_anew):
    frames, _ = room_seen_anew
    model = OnlinePlaceClustering()
    ids = [model.learn_predict_one(f) for f in frames]
    assert ids[8:] == [2] * 7 and model.merged == {} and model.n_places == 3


def test_distinct_places_stay_apart():
    frames, truth = places(5, n_places=3)
    plain = runner.run("online", frames).assignments
    consolidated = runner.run("online", frames, **CONSOLIDATE)
    assert consolidated.assignments.tolist() == plain.tolist() == [0] * 5 + [1] * 5 + [2] * 5
    assert consolidated.model.merged == {}


def test_run_scores_the_final_map(room_seen_anew):
    frames, truth = room_seen_anew
    result = runner.run("online", frames, **CONSOLIDATE)
    assert result.assignments.tolist() == truth.tolist()
    assert runner.evaluate(result, truth)["n_places"] == 2


def test_a_consolidated_map_saves_and_loads(room_seen_anew, tmp_path):
    frames, _ = room_seen_anew
    model = OnlinePlaceClustering(**CONSOLIDATE)
    for f in frames:
        model.learn_one(f)
    loaded = load_map(save_map(model, tmp_path / "map.npz"))
    assert loaded.merged == {2: 0} and sorted(loaded.kernels) == [0, 1]
    assert loaded.get_params() == model.get_params()
    assert loaded.resolve(np.array([2, 1, -1])).tolist() == [0, 1, -1]
    assert loaded.learn_predict_one(textured(4)) == 3


def test_a_map_whose_merged_ids_point_nowhere_is_refused():
    model = OnlinePlaceClustering()
    kernel = (np.ones((3, 128), np.float32), np.ones(3), np.zeros(3, np.int64), 1)
    with pytest.raises(ValueError, match="merged id points"):
        model.restore({0: kernel}, {0: 1}, [], 0, None, merged={1: 5})
    with pytest.raises(ValueError, match="0..n-1"):
        model.restore({0: kernel}, {0: 1}, [], 0, None, merged={2: 0})


def test_the_consolidating_recognizer_passes_the_protocol_checks():
    check_recognizer(OnlinePlaceClustering, CONSOLIDATE)


@pytest.mark.parametrize("kwargs, match", [
    ({"threshold": 1.0}, r"\[0, 1\)"), ({"threshold": 0.8, "probation": 0}, "at least 1"),
    ({"threshold": 0.8, "streak": 0}, "at least 1")])
def test_bad_rehearsal_settings_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Rehearsal(**kwargs)


def test_a_settled_place_is_never_merged_into_a_young_one():
    """Back in young place A, frames that also show much of settled place B leave B alone."""
    rng = np.random.default_rng(1)
    a, b = textured(1), textured(2)
    both = a.copy()
    both[:, 320:] = b[:, 320:]
    frames = [jitter(a, rng) for _ in range(2)] + [jitter(b, rng) for _ in range(6)]
    frames += [jitter(both, rng) for _ in range(4)]
    model = OnlinePlaceClustering(consolidate=0.85, consolidate_probation=3,
                                  consolidate_streak=2)
    ids = [model.learn_predict_one(f) for f in frames]
    assert ids[:8] == [0, 0] + [1] * 6 and set(ids[8:]) <= {0, 1}
    assert model.merged == {} and model.n_places == 2


def test_the_ratio_test_keeps_a_place_that_matches_two_places_alike():
    """Young place C shows as much of A as of B: without the ratio test it is merged into
    one of them, with it C stays."""
    rng = np.random.default_rng(2)
    a, b, new = textured(1), textured(2), textured(3)
    mixed = new.copy()
    mixed[:, :128], mixed[:, 384:] = a[:, :128], b[:, 384:]
    frames = [jitter(a, rng) for _ in range(3)] + [jitter(b, rng) for _ in range(3)]
    frames += [jitter(new, rng) for _ in range(2)] + [jitter(mixed, rng) for _ in range(4)]
    merged = {}
    for ratio in (None, 1.5):
        model = OnlinePlaceClustering(**CONSOLIDATE, consolidate_ratio=ratio)
        for f in frames:
            model.learn_one(f)
        merged[ratio] = model.merged
    assert merged[None] in ({2: 0}, {2: 1}) and merged[1.5] == {}


@pytest.mark.parametrize("kwargs, match", [
    ({"consolidate": 0.85, "consolidate_ratio": 0.5}, "consolidate_ratio"),
    ({"consolidate": 1.2}, r"\[0, 1\)"),
    ({"consolidate": 0.85, "consolidate_streak": 0}, "streak")])
def test_bad_consolidation_arguments_name_the_problem(kwargs, match):
    with pytest.raises(ValueError, match=match):
        OnlinePlaceClustering(**kwargs)
