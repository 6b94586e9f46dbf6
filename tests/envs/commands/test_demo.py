import json

import imageio.v3 as iio
import numpy as np

from envs.commands.demo import run_demo


def test_tiny_demo_writes_a_consistent_report(tmp_path):
    table = run_demo(str(tmp_path), steps=40)
    for name in ("report.md", "metrics.json", "map.png", "map_panorama.png", "confusion.png",
                 "tour.gif", "floorplan.png", "panoramas.png", "tour.npz"):
        assert (tmp_path / name).is_file(), name
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    assert metrics == table
    online = np.load(tmp_path / "assignments_online.npy")
    assert len(online) == 40
    row = metrics["online (seed 000)"]
    assert row["n_places"] == len(np.unique(online[online >= 0]))
    assert "online (seed 000)" in (tmp_path / "report.md").read_text()
    sides = np.load(tmp_path / "assignments_online_panorama.npy")
    assert metrics["online, PANORAMA settings"]["n_places"] == len(np.unique(sides[sides >= 0]))
    for name in ("map.png", "map_panorama.png", "confusion.png"):
        img = iio.imread(tmp_path / name)
        assert img.shape[0] > 100 and img.shape[1] > 100 and img.std() > 5, name
    gif = iio.imread(tmp_path / "tour.gif", index=None)
    assert gif.shape[0] == 4 and gif[0].std() > 5  # one frame in 10
    # the same route seen by the forward camera: a row for each seed's recognizer
    for name, label in (("nested_forward", "nested (seed 001), forward camera"),
                        ("online_forward", "online (seed 000), forward camera")):
        places = np.load(tmp_path / f"assignments_{name}.npy")
        assert len(places) == 40 and metrics[label]["n_rooms"] >= 1
