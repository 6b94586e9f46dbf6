"""``placeclust like``: the simulator through a data set's camera, its question asked
on both sides, the rankings compared; resumable; bad input one line, nothing written."""

import json

import numpy as np
import pytest

from envs.commands.cli import main
from placeclust.datasets import write_image_folder
from placeclust.vprbench import write_vpr_bench


@pytest.fixture
def real(tmp_path, two_places):
    """A small VPR-Bench data set of two places, 48x32 grey: every 2nd view maps, the rest
    query."""
    frames, truth = two_places
    grey = np.repeat(frames[..., :1], 3, axis=3)[:, :32, :48]
    ref, query = grey[::2], grey[1::2]
    gt = [np.flatnonzero(truth[::2] == t).tolist() for t in truth[1::2]]
    write_vpr_bench(tmp_path / "real", ref, query, gt)
    return tmp_path / "real"


def _like(real, out, *extra):
    """``placeclust like``; raises SystemExit with its status, as the command line exits."""
    main(["like", str(real), "--scenes", "1000", "--rooms", "2",
          "--steps-per-room", "12", "--features", "orb", "--out", str(out), "--workers", "1",
          *extra])


def test_both_sides_run_the_same_configurations_and_resume(real, tmp_path, capsys):
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as done:
        _like(real, out)
    assert done.value.code == 0
    text = (out / "results.md").read_text()
    assert "48×32 grey, 60° wide (default)" in text
    for name in ("online (orb)", "nested (orb)"):
        assert f"| {name} |" in text
    assert "Spearman's rank correlation over 2 configurations" in text
    kept = json.loads((out / "sim" / "scene_1000.json").read_text())
    assert kept["queries"] > 0 and set(kept["configs"]) == {"online (orb)", "nested (orb)"}
    real_kept = json.loads((out / "real.json").read_text())
    assert len(real_kept["configs"]["online (orb)"]["hits"]) == 20  # every query has truth
    assert real_kept["revisit"]["revisit_pairs"] == 20 and kept["revisit"]["revisit_pairs"] > 0
    assert "What a localizer sees" in text
    stamp = (out / "sim" / "scene_1000.json").stat().st_mtime_ns
    capsys.readouterr()
    with pytest.raises(SystemExit):  # the same command: kept buildings and data are reused
        _like(real, out)
    assert (out / "sim" / "scene_1000.json").stat().st_mtime_ns == stamp
    assert "| online (orb) |" in capsys.readouterr().out


def test_a_loop_closure_drive_asks_the_vpr_bench_question(tmp_path, two_places):
    import cv2

    frames, _ = two_places
    write_image_folder(tmp_path / "loop", frames[[*range(0, 40, 4), *range(0, 20, 4)], :96, :128])
    same = np.zeros((15, 15), np.uint8)
    for q in range(5):
        same[10 + q, q] = 255
    cv2.imwrite(str(tmp_path / "loop" / "same_place.bmp"), same)
    with pytest.raises(SystemExit) as done:
        _like(tmp_path / "loop", tmp_path / "out")
    assert done.value.code == 0
    real = json.loads((tmp_path / "out" / "real.json").read_text())
    assert len(real["configs"]["online (orb)"]["hits"]) == 5
    text = (tmp_path / "out" / "results.md").read_text()
    assert "| simulated top-1 above chance [95%] | real top-1 above chance [95%] |" in text
    assert "Ranked by raw top-1" in text


def test_a_labelled_folder_is_clustered_on_both_sides(tmp_path, two_places):
    frames, truth = two_places
    folder = tmp_path / "labelled"
    write_image_folder(folder, frames[:, :96, :128], [f"room {t}" for t in truth])
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as done:
        _like(folder, out, "--algos", "online", "stream")
    assert done.value.code == 0
    text = (out / "results.md").read_text()
    assert "| simulated NMI [95%] | real NMI [95%] |" in text
    assert "| stream (orb) |" in text and "128×96 colour" in text
    real = json.loads((out / "real.json").read_text())
    assert len(real["configs"]["online (orb)"]["places"]) == len(truth) == len(real["labels"])


def test_a_map_of_one_place_ranks_last_above_chance_though_its_raw_top1_is_best():
    """One place for the whole drive is right on every query by chance alone: ranked above
    chance it is last on both sides, and the raw ranking, which puts it first, is kept beside.
    Fault it catches: ranking by ``top1`` (raw) instead of ``score`` (above chance)."""
    from envs.commands.like import report, transfer_of
    from envs.runs.sim2real import Matched
    from envs.world.sensor import Sensor
    from placeclust.camera import CameraSpec

    m = Matched(CameraSpec(32, 24, True, 60.0), Sensor(), (("online", "sift"), ("nested", "sift")))
    one_place = {"hits": [1.0] * 20, "chances": [1.0] * 20, "top1": 1.0, "chance": 1.0,
                 "n_places": 1}
    fine = {"hits": [1.0, 0.0] * 10, "chances": [0.1] * 20, "top1": 0.5, "chance": 0.1,
            "n_places": 10}
    real = {"configs": {"online (sift)": fine, "nested (sift)": one_place}, "image_stats": {}}
    sims = [{"scene": s, "queries": 20, "image_stats": {}, "configs": {
        "online (sift)": {"score": 0.9 - s / 10, "top1": 0.91 - s / 10, "chance": 0.1},
        "nested (sift)": {"score": 0.0, "top1": 1.0, "chance": 1.0}}} for s in range(3)]
    above, raw = transfer_of(real, sims, m), transfer_of(real, sims, m, raw=True)
    assert above.real_means == pytest.approx(((0.5 - 0.1) / 0.9, 0.0))
    assert above.concordant == 1 and above.sim_means[0] > above.sim_means[1]
    assert raw.real_means == (0.5, 1.0) and raw.sim_means[0] < raw.sim_means[1]
    text = report("real", real, sims, m)
    assert "| nested (sift) | 0.000 [0.000, 0.000] | 0.000 [0.000, 0.000] | 1.000 (1.000) | " \
           "1.000 (1.000) | 1 |" in text


@pytest.mark.parametrize("setup, extra, message", [
    ("unlabelled", (), "has no labels.csv"),
    ("vpr", ("--algos", "kmeans"), "kmeans cannot localize on a fixed map"),
    ("vpr", ("--algos", "knn"), "invalid choice: 'knn'"),
    ("vpr", ("--radius", "-1"), "--radius must be a positive"),
    ("vpr", ("--stride", "0"), "must be at least 1"),
    ("vpr", ("--split", "val", "--scenes", "5"), "are not in the 'val' split"),
    ("vpr", ("--sensor", "gain=2"), "NAME one of grey"),
    ("vpr", ("--camera-file", "missing.json"), "camera file missing.json does not exist"),
    ("vpr", ("--query-condition", "dusk"), "invalid choice: 'dusk'"),
    ("labelled", ("--query-condition", "night"), "asks no queries"),
    ("labelled", ("--query-route", "lap"), "asks no queries"),
    ("vpr", ("--query-route", "loop"), "invalid choice: 'loop'"),
    ("vpr", ("--query-condition", "night", "cloudy"), "both set lighting"),
])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(real, tmp_path, capsys, setup, extra,
                                                         message):
    folder = real
    if setup == "unlabelled":
        folder = tmp_path / "unlabelled"
        write_image_folder(folder, np.zeros((3, 20, 20, 3), np.uint8))
    elif setup == "labelled":
        folder = tmp_path / "labelled"
        write_image_folder(folder, np.zeros((3, 20, 20, 3), np.uint8), ["a", "b", "b"])
    with pytest.raises(SystemExit) as code:
        _like(folder, tmp_path / "out", *extra)
    err = capsys.readouterr().err.strip()
    assert code.value.code == 2 and message in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_a_camera_file_is_the_same_camera_as_its_settings_on_the_command_line(real, tmp_path):
    """A camera written down once (assets/cameras/) asks exactly what its flags asked: the
    same settings, so the same kept figures are reused."""
    from envs.commands.like import build_parser, matched_from_args

    def matched(*extra):
        args = build_parser("placeclust like").parse_args([str(real), "--scenes", "1000",
                                                           *extra])
        return matched_from_args(args)[2]

    camera = tmp_path / "corridor.json"
    camera.write_text(json.dumps({"sensor": {"vignetting": 0.3, "blur": 1.5}}))
    flags = matched("--sensor", "vignetting=0.3", "blur=1.5")
    assert matched("--camera-file", str(camera)) == flags
    assert matched("--camera-file", str(camera)).stamp() == flags.stamp()
    assert matched("--camera-file", str(camera), "--sensor", "blur=2").sensor.blur == 2.0
    (real / "camera.json").write_text(camera.read_text())  # the data set's own file
    assert matched() == flags


def test_photo_textures_are_an_option_stated_in_the_report(real, tmp_path):
    """Fault caught: ``--textures photo`` dropped on the way to the buildings, or a report
    that does not say its buildings were retextured."""
    from envs.commands.like import build_parser, matched_from_args

    def matched(*extra):
        args = build_parser("placeclust like").parse_args([str(real), "--scenes", "1000",
                                                           *extra])
        return matched_from_args(args)[2]

    assert matched().photo is None and matched("--textures", "plain").photo is None
    photo = matched("--textures", "photo")
    assert photo.photo is not None and photo.photo.detail == 0.35
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as done:
        _like(real, out, "--algos", "online", "--textures", "photo")
    assert done.value.code == 0
    assert "surfaces with photographic statistics (detail 0.35" in (out / "results.md").read_text()


@pytest.mark.parametrize("name", ["vpr-bench-corridor", "rtabmap-loop"])
def test_the_shipped_cameras_read(tmp_path, name):
    from pathlib import Path

    from envs.world.sensor import Sensor
    from placeclust.camera import sensor_of

    shipped = Path(__file__).parents[3] / "assets" / "cameras" / f"{name}.json"
    assert Sensor.of(sensor_of(tmp_path, shipped), str(shipped)).active


def test_a_lever_is_compared_paired_against_the_run_without_it(real, tmp_path, capsys):
    """Fault caught: ``--against`` read another run's buildings than this one's, or a
    missing baseline noticed only after the buildings ran (it must be one line, nothing
    written)."""
    plain, photo = tmp_path / "plain", tmp_path / "photo"
    with pytest.raises(SystemExit) as done:
        _like(real, photo, "--against", str(plain))
    err = capsys.readouterr().err.strip()
    assert done.value.code == 2 and "no building 1000 kept" in err and len(err.splitlines()) == 1
    assert not photo.exists()
    with pytest.raises(SystemExit):
        _like(real, plain)
    with pytest.raises(SystemExit) as done:
        _like(real, plain / "again", "--against", str(plain))  # the same run: no difference
    assert done.value.code == 0
    text = (plain / "again" / "results.md").read_text()
    assert f"Against `{plain}` (the same 1 building," in text
    assert "Spearman undefined, pairs ordered alike +0.00 [+0.00, +0.00]" in text


def test_a_lap_query_drive_is_asked_for_and_stated_in_the_report(real, tmp_path):
    """Fault caught: ``--query-route lap`` dropped on the way to the buildings, or a report
    that does not say how its query drive was made."""
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as done:
        _like(real, out, "--algos", "online", "--query-route", "lap")
    assert done.value.code == 0
    assert "the same path driven again up to 0.3 m to one side" in (out / "results.md").read_text()
    kept = json.loads((out / "sim" / "scene_1000.json").read_text())
    assert '"query_route": "lap"' in kept["stamp"]
