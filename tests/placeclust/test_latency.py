import functools

import numpy as np
import pytest

from placeclust.latency import TIMINGS, _median_ms, best_of_sweeps, main
from placeclust.online import OnlinePlaceClustering
from placeclust.synthetic import jitter, textured


def test_a_loop_closure_probe_leaves_the_graph_and_place_as_they_were():
    model = OnlinePlaceClustering(features="orb")
    for seed in (1, 2, 3):
        model.learn_one(textured(seed))
    edges, current = set(model.graph.edges), model.current
    revisit = jitter(textured(1), np.random.default_rng(0))
    total, detection, own = _median_ms(model, [revisit], from_here=True)
    assert set(model.graph.edges) == edges and model.current == current
    assert 0 < detection < total and own == pytest.approx(total - detection)
    assert "extract_pair" not in vars(model._extractor)  # the timer is gone afterwards
    _median_ms(model, [revisit])  # a plain probe closes the loop, as learning does
    assert model.graph.has_edge(2, 0) and model.current == 0


def test_a_probe_that_opens_a_place_keeps_the_map_consistent():
    model = OnlinePlaceClustering(features="orb")
    for seed in (1, 2, 3):
        model.learn_one(textured(seed))
    _median_ms(model, [textured(99)], from_here=True)  # matches nothing: a new place
    assert set(model.graph.nodes) == set(model.kernels) == {0, 1, 2, 3}
    model.learn_one(textured(1))  # a loop closure from the new place
    assert all("n_images" in data for _, data in model.graph.nodes(data=True))


def test_best_of_sweeps_gives_the_lowest_and_highest_median_per_size():
    rows = best_of_sweeps("orb", [3, 5], repeats=2)
    assert [r["places"] for r in rows] == [3, 5]
    for r in rows:
        for key in TIMINGS:
            assert 0 < r[key] <= r[f"{key}_max"]
        assert r["track_own_ms"] < r["track_ms"] and r["loop_own_ms"] < r["loop_ms"]
    with pytest.raises(ValueError, match="repeats"):
        best_of_sweeps("orb", [3], repeats=0)


def test_the_command_prints_a_table_with_the_growth_ratio(capsys):
    assert main(["--features", "orb", "--sizes", "2", "4", "--repeats", "1"]) == 0
    out = capsys.readouterr().out
    assert "| orb | 4 |" in out and "| orb | 4 / 2 |" in out
    with pytest.raises(SystemExit):
        main(["--sizes", "1"])


def test_the_command_times_the_recognizer_with_the_given_parameters(capsys, monkeypatch):
    seen = []
    original = OnlinePlaceClustering.__init__

    @functools.wraps(original)  # check_params reads the constructor's signature
    def spy(self, *args, **kwargs):
        seen.append(kwargs)
        original(self, *args, **kwargs)

    monkeypatch.setattr(OnlinePlaceClustering, "__init__", spy)
    assert main(["--features", "orb", "--sizes", "2", "3", "--repeats", "1",
                 "--param", "consolidate=0.85"]) == 0
    assert seen and all(kw == {"consolidate": 0.85} for kw in seen)
    assert "`consolidate=0.85`" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["--param", "no_such_argument=1"])
