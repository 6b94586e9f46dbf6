import json
import signal
import subprocess
import sys
import time

import networkx as nx
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from placeclust import OnlinePlaceClustering
from placeclust.mapfile import VERSION, read_meta
from placeclust.synthetic import textured


@pytest.fixture(scope="module")
def frames():
    return [textured(s) for s in (1, 2, 3)]


@pytest.fixture
def mapped(frames):
    model = OnlinePlaceClustering(features="orb")
    for f in frames + frames:
        model.learn_one(f)
    return model


def test_round_trip_keeps_the_map(mapped, frames, tmp_path):
    mapped.save(tmp_path / "m.npz", world="w1")
    loaded = OnlinePlaceClustering.load(tmp_path / "m.npz", world="w1")
    assert loaded.get_params() == mapped.get_params()
    assert nx.utils.graphs_equal(loaded.graph, mapped.graph)
    assert loaded.current == mapped.current and loaded.frame_shape == mapped.frame_shape
    for p, k in mapped.kernels.items():
        np.testing.assert_array_equal(loaded.kernels[p].descriptors, k.descriptors)
        np.testing.assert_array_equal(loaded.kernels[p].weights, k.weights)
    assert [loaded.predict_one(f) for f in frames] == [mapped.predict_one(f) for f in frames]


def test_localize_one_never_changes_the_map(mapped, frames):
    n, sizes = mapped.n_places, {p: len(k) for p, k in mapped.kernels.items()}
    other = textured(99)
    assert [mapped.localize_one(f) for f in frames] == [0, 1, 2]
    mapped.localize_one(other)
    assert mapped.n_places == n and {p: len(k) for p, k in mapped.kernels.items()} == sizes


def test_a_failed_save_leaves_the_old_map(mapped, tmp_path, monkeypatch):
    path = tmp_path / "m.npz"
    mapped.save(path)
    before = path.read_bytes()

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez", boom)
    with pytest.raises(OSError, match="disk full"):
        mapped.save(path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["m.npz"]  # no temporary file left


def test_version_1_maps_keep_reading_raw_frames(mapped, tmp_path):
    """Maps written before contrast normalization existed load with ``normalize=None``."""
    mapped.save(tmp_path / "m.npz")
    meta, arrays = read_meta(tmp_path / "m.npz")
    meta["version"] = 1
    del meta["params"]["normalize"]
    np.savez(tmp_path / "v1.npz", meta=np.array(json.dumps(meta)), **arrays)
    assert OnlinePlaceClustering.load(tmp_path / "v1.npz").normalize is None
    assert OnlinePlaceClustering.load(tmp_path / "m.npz").normalize == "clahe"


@pytest.mark.parametrize("name, value, version, before", [
    ("scale", 0.75, 2, 1.0),  # maps before ``scale`` were made from full-size frames
    ("view", "sides", 3, "full"),  # maps before ``view`` hold features of the whole frame
    ("scene_change", 0.25, 4, None),  # maps before the gate opened places without one
])
def test_older_maps_load_as_they_were_made_and_new_parameters_round_trip(
        frames, tmp_path, name, value, version, before):
    model = OnlinePlaceClustering(features="sift", **{name: value})
    for f in frames:
        model.learn_one(f)
    model.save(tmp_path / "m.npz")
    meta, arrays = read_meta(tmp_path / "m.npz")
    meta["version"] = version
    del meta["params"][name]
    np.savez(tmp_path / "old.npz", meta=np.array(json.dumps(meta)), **arrays)
    assert getattr(OnlinePlaceClustering.load(tmp_path / "old.npz"), name) == before
    loaded = OnlinePlaceClustering.load(tmp_path / "m.npz")
    assert getattr(loaded, name) == value
    assert [loaded.predict_one(f) for f in frames] == [model.predict_one(f) for f in frames]


def test_foreign_future_and_other_world_files_are_refused(mapped, tmp_path):
    np.savez(tmp_path / "foreign.npz", x=np.arange(3))
    with pytest.raises(ValueError, match="not a readable placeclust map|not a placeclust map"):
        OnlinePlaceClustering.load(tmp_path / "foreign.npz")
    mapped.save(tmp_path / "m.npz", world="kitchen world")
    meta, arrays = read_meta(tmp_path / "m.npz")
    meta["version"] = VERSION + 1
    np.savez(tmp_path / "future.npz", meta=np.array(json.dumps(meta)), **arrays)
    with pytest.raises(ValueError, match="upgrade placeclust"):
        OnlinePlaceClustering.load(tmp_path / "future.npz")
    with pytest.raises(ValueError, match="is a map of world 'kitchen world'"):
        OnlinePlaceClustering.load(tmp_path / "m.npz", world="garage world")
    with pytest.raises(FileNotFoundError, match="no map file"):
        OnlinePlaceClustering.load(tmp_path / "missing.npz")


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cut=st.integers(min_value=0, max_value=10_000), flip=st.integers(min_value=0))
def test_truncated_or_corrupt_files_give_a_clear_error(mapped, tmp_path, cut, flip):
    path = tmp_path / "m.npz"
    mapped.save(path)
    data = bytearray(path.read_bytes())
    bad = tmp_path / "bad.npz"
    if cut < len(data) - 1:
        bad.write_bytes(bytes(data[:cut]))
    else:
        data[flip % len(data)] ^= 0xFF
        bad.write_bytes(bytes(data))
    try:
        loaded = OnlinePlaceClustering.load(bad)
    except ValueError as e:
        assert "placeclust map" in str(e)
    else:  # a flipped byte in descriptor data is not detectable; the map must still be whole
        assert loaded.n_places == mapped.n_places


_SAVER = """
import sys
from placeclust import OnlinePlaceClustering
from placeclust.synthetic import textured
small, big = OnlinePlaceClustering(features="orb"), OnlinePlaceClustering(features="orb")
for s in (1, 2):
    small.learn_one(textured(s))
for s in (1, 2, 3, 4):
    big.learn_one(textured(s))
small.save(sys.argv[1])
print("saved", flush=True)
while True:  # replace the map over and over until killed
    big.save(sys.argv[1])
    small.save(sys.argv[1])
"""


def test_a_map_killed_mid_save_is_the_old_or_the_new_one(tmp_path):
    """SIGKILL while saving in a loop: the file on disk is always one whole map."""
    path = tmp_path / "m.npz"
    for delay in (0.05, 0.2, 0.5):
        proc = subprocess.Popen([sys.executable, "-c", _SAVER, str(path)],
                                stdout=subprocess.PIPE, text=True)
        assert proc.stdout.readline().strip() == "saved"
        time.sleep(delay)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        assert OnlinePlaceClustering.load(path).n_places in (2, 4)
