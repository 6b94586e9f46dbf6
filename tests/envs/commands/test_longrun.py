import numpy as np
import pytest

from envs.commands.longrun import long_run, main
from envs.tasks.tour import drive_tour, tour_steps


def test_long_run_reports_every_window():
    rows = long_run(steps=25, n_rooms=2, features="orb", window=10, progress=False)
    assert [r["step"] for r in rows] == [10, 20, 25]
    last = rows[-1]
    assert last["places"] >= 1 and last["kernel_features"] > 0 and last["rss_mb"] > 0
    assert 0.0 < last["precision"] <= 1.0
    assert all(r["ms_median"] > 0 for r in rows)
    # the places opened per window add up to the map: the column that shows saturation
    assert sum(r["new_places"] for r in rows) == last["places"]


def test_a_capped_map_stays_at_its_cap():
    rows = long_run(steps=30, n_rooms=2, features="orb", window=10, progress=False,
                    max_places=1)
    assert all(r["places"] == 1 for r in rows)


def test_long_run_cli_refuses_negative_steps(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--steps", "-5"])
    assert exc.value.code != 0
    assert "--steps" in capsys.readouterr().err


def test_streamed_tour_is_the_recorded_tour(make_env):
    """tour_steps (constant memory) yields exactly the frames drive_tour records."""
    recorded = drive_tour(make_env(n_rooms=2), 15, seed=3)
    streamed = [obs["panorama"] for obs, _ in tour_steps(make_env(n_rooms=2), 15, seed=3)]
    assert np.array_equal(np.stack(streamed), recorded.frames)


def test_tour_steps_refuses_no_steps(make_env):
    with pytest.raises(ValueError, match="positive"):
        next(tour_steps(make_env(), 0))
