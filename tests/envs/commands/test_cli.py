import json
import subprocess
import sys

import numpy as np
import pytest

from envs.commands.cli import COMMANDS, build_parser, main


def test_cluster_cli_writes_consistent_metrics(tmp_path, two_places):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth, pose=np.zeros((len(truth), 3)))
    out = tmp_path / "res"
    proc = subprocess.run([sys.executable, "-m", "envs.commands.cli", "cluster", "--algo", "online",
                           "--features", "orb", "--tour", str(tmp_path / "tour.npz"), "--out",
                           str(out), "--quiet"], capture_output=True, text=True, check=True)
    assert "precision" in proc.stdout
    metrics = json.loads((out / "metrics.json").read_text())
    assign = np.load(out / "assignments.npy")
    assert len(assign) == len(truth)
    assert metrics["n_places"] == len(np.unique(assign[assign >= 0]))
    assert {"precision", "recall", "nmi", "ari", "n_places", "n_rooms", "ms_per_frame"} <= set(
        metrics)


def refused(capsys, *args: str) -> tuple[int, str]:
    """``placeclust ARGS`` run in this process, as the command line would end it: its exit
    status and what it wrote to stderr (a ``SystemExit`` message is printed there, status 1).
    In-process, because each interpreter started for the command costs seconds of imports."""
    capsys.readouterr()
    with pytest.raises(SystemExit) as done:
        main(list(args))
    code, err = done.value.code, capsys.readouterr().err
    if isinstance(code, str):
        return 1, err + code
    return code or 0, err


def test_cluster_cli_names_bad_input(tmp_path, capsys):
    out = ("--out", str(tmp_path / "o"))
    code, err = refused(capsys, "cluster", "--tour", str(tmp_path / "nope.npz"), *out)
    assert code != 0 and "does not exist" in err
    np.savez(tmp_path / "bad.npz", frames=np.zeros((3, 8)), room=np.zeros(3))
    code, err = refused(capsys, "cluster", "--tour", str(tmp_path / "bad.npz"), *out)
    assert code != 0 and "'frames' must be uint8" in err
    assert not (tmp_path / "o").exists()


def test_bad_input_leaves_earlier_results_alone(tmp_path, two_places, capsys):
    """A failed run names the problem, exits non-zero and keeps what an earlier run wrote."""
    out = tmp_path / "res"
    out.mkdir()
    (out / "metrics.json").write_text('{"precision": 0.9}')
    np.save(out / "assignments.npy", np.arange(3))
    frames, truth = two_places
    np.savez(tmp_path / "short.npz", frames=frames, room=truth[:-1])
    np.savez(tmp_path / "noroom.npz", frames=frames)

    for args, message in [
        (("cluster", "--tour", str(tmp_path / "short.npz")), "'room' has shape"),
        (("cluster", "--tour", str(tmp_path / "noroom.npz")), "no 'room' array"),
        (("cluster", "--tour", str(tmp_path / "short.npz"), "--features", "surf64"),
         "invalid choice"),
    ]:
        code, err = refused(capsys, *args, "--out", str(out))
        assert code != 0 and message in err, (args, err)
    assert (out / "metrics.json").read_text() == '{"precision": 0.9}'
    assert np.array_equal(np.load(out / "assignments.npy"), np.arange(3))
    code, err = refused(capsys, "demo", "--steps", "-1", "--out", str(tmp_path / "d"))
    assert code != 0 and "steps must be positive" in err
    code, err = refused(capsys, "bench", "--quick", "--workers", "-2", "--out",
                        str(tmp_path / "b"))
    assert code != 0 and "--workers" in err
    assert not (tmp_path / "b").exists()


def test_cluster_cli_passes_and_records_recognizer_parameters(tmp_path, two_places):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    out = tmp_path / "res"
    main(["cluster", "--features", "orb", "--tour", str(tmp_path / "tour.npz"), "--out", str(out),
          "--quiet", "--param", "t_new_cluster=0.99", "--param", "max_places=1",
          "--param", "normalize=clahe"])
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["params"] == {"t_new_cluster": 0.99, "max_places": 1, "normalize": "clahe"}
    assert metrics["n_places"] == 1  # max_places reached the recognizer


@pytest.mark.parametrize("param, message", [
    ("t_new=0.9", "online has no parameter 't_new'; it takes ['max_features'"),
    ("t_new_cluster", "--param takes NAME=VALUE"),
    ("t_new_cluster=0.5", "t_update_cluster < t_new_cluster"),
])
def test_cluster_cli_names_a_bad_parameter_and_writes_nothing(tmp_path, two_places, capsys,
                                                               param, message):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    with pytest.raises(SystemExit) as exc:
        main(["cluster", "--tour", str(tmp_path / "tour.npz"), "--out", str(tmp_path / "o"),
              "--param", param])
    assert exc.value.code == 2 and message in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_presets_name_configurations_and_params_override_them(tmp_path, two_places):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth, scene_seed=2001)

    def cluster(out: str, *args: str) -> dict:
        main(["cluster", "--features", "orb", "--tour", str(tmp_path / "tour.npz"),
              "--out", str(tmp_path / out), "--quiet", *args])
        return json.loads((tmp_path / out / "metrics.json").read_text())

    preset = cluster("a", "--preset", "panorama")
    spelled = cluster("b", "--param", "view=sides", "--param", "kernel_capacity=600",
                      "--param", "scene_change=0.25", "--param", "scale=0.75",
                      "--param", "consolidate=0.85")
    assert preset["params"] == spelled["params"] == {
        "view": "sides", "kernel_capacity": 600, "scene_change": 0.25, "scale": 0.75,
        "consolidate": 0.85}
    np.testing.assert_array_equal(np.load(tmp_path / "a" / "assignments.npy"),
                                  np.load(tmp_path / "b" / "assignments.npy"))
    assert preset["scene_seed"] == 2001 and preset["split"] == "test"
    assert cluster("c", "--preset", "panorama", "--param", "scale=1.0")["params"]["scale"] == 1.0
    assert cluster("d")["params"] == {}  # paper: the library defaults
    orb = cluster("e", "--preset", "panorama-orb")["params"]
    assert orb == {**preset["params"], "scene_change": 0.12, "t_new_cluster": 0.94}


def test_a_preset_the_algorithm_cannot_take_is_one_line_of_error(tmp_path, two_places, capsys):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    with pytest.raises(SystemExit) as exc:
        main(["cluster", "--algo", "kmeans", "--preset", "panorama", "--tour",
              str(tmp_path / "tour.npz"), "--out", str(tmp_path / "o")])
    assert exc.value.code == 2
    assert "kernel_capacity" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("argv, scenes, error", [
    (["--split", "test"], (2000, 2001, 2002, 2003), None),
    (["--split", "val", "--scenes", "1007"], (1007,), None),
    (["--split", "test", "--scenes", "3"], None, "not in the 'test' split"),
    (["--scenes", "5"], (5,), None),
])
def test_bench_takes_its_scenes_from_a_split(argv, scenes, error):
    from envs.commands.cli import bench_plan, build_parser

    args = build_parser().parse_args(["bench", "--quick", "--algos", "online", "--preset",
                                      "panorama", *argv])
    if error:
        with pytest.raises(ValueError, match=error):
            bench_plan(args)
        return
    matrix, out = bench_plan(args)
    assert matrix.scenes == scenes and out.name == "bench-quick"
    assert dict(matrix.params)["view"] == "sides"


def test_whole_commands_run_under_placeclust(capsys, tmp_path):
    """``placeclust errands`` (and leaderboard, seed001, longrun, speed, latency) are the
    modules' own command lines, under the installed command."""
    scores = tmp_path / "scores.json"
    with pytest.raises(SystemExit) as exc:
        main(["errands", "--scene-seeds", "0", "--rooms", "3", "--recognizer", "oracle",
              "--errands", "1", "--json", str(scores)])
    assert exc.value.code == 0 and "success_rate=" in capsys.readouterr().out
    assert scores.is_file()
    with pytest.raises(SystemExit) as exc:  # the closed loop's old name for PANORAMA
        main(["errands", "--scene-seeds", "0", "--recognizer", "online"])
    assert exc.value.code == 2 and "'online' was renamed 'panorama'" in capsys.readouterr().err
    listed = build_parser().format_help()
    assert all(name in listed for name in COMMANDS)


@pytest.mark.parametrize("content, message", [
    (b"", "is empty"),
    (b"frames,room\n", "is not a .npz archive"),
    (None, "does not exist"),
])
def test_a_tour_file_that_is_not_one_is_one_line_and_exit_2(tmp_path, capsys, content, message):
    tour = tmp_path / "tour.npz"
    if content is not None:
        tour.write_bytes(content)
    with pytest.raises(SystemExit) as exc:
        main(["cluster", "--tour", str(tour), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def _image_folder(path, frames, truth, labels=True):
    from placeclust.datasets import write_image_folder

    write_image_folder(path, frames, [f"room{r}" for r in truth] if labels else None)
    return path


def test_cluster_takes_an_image_folder_and_queries_on_its_map(tmp_path, two_places, capsys):
    frames, truth = two_places
    mapped = _image_folder(tmp_path / "map", frames, truth)
    query = _image_folder(tmp_path / "query", frames[::-1], truth[::-1])
    main(["cluster", "--images", str(mapped), "--query", str(query), "--features", "orb",
          "--out", str(tmp_path / "out"), "--quiet"])
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert metrics["precision"] == 1.0 and metrics["query_top1"] == 1.0
    for name in ("assignments.npy", "query_assignments.npy", "places.png"):
        assert (tmp_path / "out" / name).is_file()
    assert "query_top1" in capsys.readouterr().out
    assert not (tmp_path / "out" / "place_map.png").exists()  # labels.csv has no poses


def test_an_exported_tour_clusters_as_its_npz_does_with_a_map_of_its_poses(tmp_path):
    main(["tour", "--rooms", "2", "--steps", "30", "--width", "128", "--height", "32",
          "--out", str(tmp_path / "t"), "--export-images", str(tmp_path / "img"), "--quiet"])
    main(["cluster", "--tour", str(tmp_path / "t" / "tour.npz"), "--features", "orb",
          "--out", str(tmp_path / "a"), "--quiet"])
    main(["cluster", "--images", str(tmp_path / "img"), "--features", "orb",
          "--out", str(tmp_path / "b"), "--quiet"])
    npz, folder = (json.loads((tmp_path / d / "metrics.json").read_text()) for d in "ab")
    for key in ("precision", "recall", "nmi", "n_places", "n_rooms"):
        assert npz[key] == folder[key], key
    assert np.array_equal(np.load(tmp_path / "a" / "assignments.npy"),
                          np.load(tmp_path / "b" / "assignments.npy"))
    assert (tmp_path / "b" / "place_map.png").is_file()


def test_cluster_takes_a_vpr_bench_folder(tmp_path, two_places):
    from placeclust.vprbench import write_vpr_bench

    frames, truth = two_places
    write_vpr_bench(tmp_path / "vpr", frames, frames, [np.flatnonzero(truth == r) for r in truth])
    main(["cluster", "--images", str(tmp_path / "vpr"), "--features", "orb",
          "--out", str(tmp_path / "out"), "--quiet"])
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert metrics["query_top1"] == 1.0 and "query_recall@5" in metrics


@pytest.mark.parametrize("setup, extra, message", [
    ("missing", (), "does not exist"),
    ("empty", (), "holds no image"),
    ("not an image", (), "000001.png: not a png or jpg"),
    ("mislabelled", (), "labels.csv has no row for 5 of the 6 images"),
    ("bad truth", (), "ground_truth_new.npy"),
    ("unlabelled", ("--query", "{map}"), "has no labels.csv"),
    ("vpr", ("--query", "{map}"), "leave out --query"),
    ("labelled", ("--algo", "kunion", "--query", "{map}"), "cannot localize"),
])
def test_bad_image_input_is_one_line_exit_2_and_writes_nothing(tmp_path, two_places, capsys,
                                                              setup, extra, message):
    from placeclust.vprbench import write_vpr_bench

    frames, truth = two_places
    folder = tmp_path / "map"
    if setup in ("unlabelled", "labelled"):
        _image_folder(folder, frames[:6], truth[:6], labels=setup == "labelled")
    elif setup in ("vpr", "bad truth"):
        write_vpr_bench(folder, frames[:3], frames[:3], [[0], [1], [2]])
        if setup == "bad truth":
            (folder / "ground_truth_new.npy").write_bytes(b"damaged")
    elif setup == "empty":
        folder.mkdir()
    elif setup == "not an image":
        _image_folder(folder, frames[:3], truth[:3])
        (folder / "000001.png").write_text("a text file named like an image")
    elif setup == "mislabelled":
        _image_folder(folder, frames[:6], truth[:6], labels=False)
        (folder / "labels.csv").write_text("frame,label\n0,a\n")
    with pytest.raises(SystemExit) as code:
        main(["cluster", "--images", str(folder), "--features", "orb",
              *(a.format(map=folder) for a in extra), "--out", str(tmp_path / "out"),
              "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code.value.code == 2 and message in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_a_tour_exports_as_a_folder_and_a_vpr_bench_dataset(tmp_path):
    from placeclust.datasets import ImageFolder
    from placeclust.vprbench import VPRBench

    main(["tour", "--rooms", "2", "--steps", "6", "--width", "64", "--height", "16", "--out",
          str(tmp_path / "t"), "--export-images", str(tmp_path / "img"), "--export-vpr-bench",
          str(tmp_path / "vpr"), "--quiet"])
    tour = np.load(tmp_path / "t" / "tour.npz")
    folder = ImageFolder(tmp_path / "img")
    assert np.array_equal(np.stack(list(folder)), tour["frames"])
    names = [str(n) for n in tour["room_names"]]
    assert [folder.label_names[i] for i in folder.labels] == [names[r] for r in tour["room"]]
    assert np.allclose(folder.poses, tour["pose"], atol=1e-4) and folder.conditions[0] == "day"
    data = VPRBench(tmp_path / "vpr")
    assert np.array_equal(data.ref[0], tour["frames"][0])
    assert not np.array_equal(data.query[0], data.ref[0])  # the same pose at night
    assert all(t.size for t in data.ground_truth)  # each query has its own pose's reference


def test_stats_is_a_command_of_its_own():
    assert COMMANDS["stats"][0] == "placeclust.imagestats"


def test_tour_renders_a_forward_camera_of_any_field_of_view_through_a_sensor(tmp_path, capsys):
    def frames(*extra):
        out = tmp_path / "_".join(extra).replace("=", "")
        main(["tour", "--rooms", "2", "--steps", "3", "--camera", "forward", "--width", "48",
              "--height", "32", "--quiet", "--out", str(out), *extra])
        with np.load(out / "tour.npz") as z:
            return z["frames"]

    plain, wide = frames(), frames("--fov", "120")
    assert plain.shape == wide.shape == (3, 32, 48, 3) and not np.array_equal(plain, wide)
    grey = frames("--sensor", "grey=1", "jpeg=80")
    assert (grey[..., 0] == grey[..., 2]).all() and not (plain[..., 0] == plain[..., 2]).all()
    capsys.readouterr()
    with pytest.raises(SystemExit) as code:
        main(["tour", "--rooms", "2", "--steps", "3", "--fov", "90", "--out",
              str(tmp_path / "pano")])
    err = capsys.readouterr().err.strip()
    assert code.value.code == 2 and "--camera forward" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "pano").exists()
