import json
import subprocess
import sys

import numpy as np

from envs.tasks.tour import drive_tour, room_route


def test_route_visits_every_room_through_doors(make_env):
    plan = make_env(n_rooms=8, scene_seed=1).unwrapped.plan
    route = room_route(plan, 0, 20, np.random.default_rng(0))
    assert set(route) == set(range(8))
    g = plan.graph()
    assert all(g.has_edge(a, b) for a, b in zip(route[:-1], route[1:]))
    assert len(route) > 8  # revisits


def test_scripted_tour_visits_every_room_with_its_actuators(make_env):
    tour = drive_tour(make_env(n_rooms=4), 900, seed=0)
    assert tour.frames.shape == (900, 64, 256, 3)
    assert set(tour.room.tolist()) == {0, 1, 2, 3}
    assert (np.diff(tour.room) != 0).sum() >= 4  # several room changes: revisits


def test_tour_cli_writes_npz_and_floorplan(tmp_path):
    out = tmp_path / "tour"
    subprocess.run([sys.executable, "-m", "envs.commands.cli", "tour", "--scene-seed", "3",
                    "--rooms", "4", "--steps", "30", "--width", "128", "--height", "32",
                    "--out", str(out), "--quiet"], check=True)
    z = np.load(out / "tour.npz")
    assert z["frames"].shape == (30, 32, 128, 3) and z["frames"].dtype == np.uint8
    assert z["room"].shape == (30,) and z["pose"].shape == (30, 3)
    assert (out / "floorplan.png").stat().st_size > 10_000
    bad = subprocess.run([sys.executable, "-m", "envs.commands.cli", "tour", "--steps", "-3",
                          "--out", str(tmp_path / "x")], capture_output=True, text=True)
    assert bad.returncode != 0 and "--steps" in bad.stderr
    assert not (tmp_path / "x").exists()
    json.dumps(z["room_names"].tolist())
