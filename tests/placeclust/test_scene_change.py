import numpy as np
import pytest

from placeclust.scene_change import SceneChangeGate


def _features(seed: int, n: int = 120) -> np.ndarray:
    """``n`` unrelated unit descriptors (128-d, like SIFT after normalisation)."""
    desc = np.random.default_rng(seed).normal(size=(n, 128)).astype(np.float32)
    return desc / np.linalg.norm(desc, axis=1, keepdims=True)


def test_the_gate_opens_at_a_scene_change_and_closes_after_its_window():
    gate = SceneChangeGate(threshold=0.25, lag=2, window=3)
    room_a, room_b = _features(0), _features(1)
    similarities = [gate.update(room_a, room_a) for _ in range(4)]
    assert np.isnan(similarities[:2]).all() and similarities[2:] == [1.0, 1.0]
    assert not gate.is_open
    assert gate.update(room_b, room_b) == 0.0  # nothing of room B was in sight 2 frames ago
    opened = [gate.is_open]
    for _ in range(5):
        gate.update(room_b, room_b)
        opened.append(gate.is_open)
    # the first 2 frames of room B are compared with room A (lag 2), both scene changes; the
    # gate then stays open 3 frames more
    assert opened == [True, True, True, True, True, False]


def test_turning_on_the_spot_is_not_a_scene_change():
    """The view after a turn was in the whole frame before it: compared with the whole frame,
    the similarity stays 1 where view against view would fall to 0."""
    whole = _features(2, 240)
    gate = SceneChangeGate(threshold=0.25, lag=1, window=5)
    gate.update(whole[:120], whole)
    assert gate.update(whole[120:], whole) == 1.0
    assert not gate.is_open


def test_reset_forgets_the_past_frames_and_closes_the_gate():
    gate = SceneChangeGate(threshold=0.25, lag=1, window=5)
    gate.update(_features(0), _features(0))
    gate.update(_features(1), _features(1))
    assert gate.is_open
    gate.reset()
    assert not gate.is_open and np.isnan(gate.update(_features(3), _features(3)))


@pytest.mark.parametrize("kwargs, match", [
    ({"threshold": 0.0}, "threshold"), ({"threshold": 1.5}, "threshold"),
    ({"lag": 0}, "lag"), ({"window": -1}, "window"),
])
def test_bad_settings_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SceneChangeGate(**kwargs)
