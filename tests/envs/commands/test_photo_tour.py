"""``python -m envs.commands.photo_tour``: a retextured tour, and bad input refused."""

import numpy as np

import envs  # noqa: F401  (registers PlaceNav-v0)
from envs.commands.photo_tour import main


def test_a_tour_of_the_retextured_building(tmp_path):
    size = ["--scene-seed", "1", "--rooms", "2", "--steps", "4", "--width", "64", "--height", "48"]
    assert main([*size, "--out", str(tmp_path / "photo")]) == 0
    assert main([*size, "--detail", "1", "--grain", "0", "--stains", "0",
                 "--out", str(tmp_path / "plain")]) == 0
    with (np.load(tmp_path / "photo" / "tour.npz") as p,
          np.load(tmp_path / "plain" / "tour.npz") as q):
        assert p["frames"].shape == (4, 48, 64, 3) and str(p["camera"]) == "forward"
        assert str(p["textures"]) == "photo detail=0.35 grain=0.12 stains=6"
        assert np.array_equal(p["pose"], q["pose"])  # the same route: only the surfaces differ
        assert np.abs(p["frames"].astype(int) - q["frames"]).mean() > 1


def test_bad_settings_are_one_line_and_exit_2(tmp_path, capsys):
    assert main(["--detail", "2", "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "detail" in err[0]
    assert not (tmp_path / "x").exists()
