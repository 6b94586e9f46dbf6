"""``placeclust bench`` at a tiny size: files, consistency with the stored assignments, resume,
the same rows from the process pool, in-process and Ray."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

from envs.commands import bench
from envs.commands.bench import Matrix, RunStore, run_bench
from envs.commands.cli import main
from placeclust.metrics import score

# 2 rooms, 12 frames a room: a few seconds a tour
TINY = Matrix(algos=("online", "kmeans"), features=("orb",), scenes=(0,), rooms=(2,),
              conditions=("day", "day>night"), tour_seeds=(0,), steps_per_room=12,
              latency_features=("orb",), latency_sizes=(3, 6))
TIMING = {"ms_per_frame", "ms_p95", "ms_mean"}


def _read_csv(path) -> list[dict]:
    with open(path) as f:
        return list(csv.DictReader(f))


def _stable(rows: list[dict]) -> list[dict]:
    """Rows without timings, the only columns that may differ between identical runs."""
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


@pytest.fixture(scope="module")
def tiny_bench(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    rows = run_bench(TINY, out, workers=1, progress=False)
    return out, rows


def test_matrix_gives_cross_condition_to_recognizers_that_localize() -> None:
    runs = TINY.runs()
    assert [(r.algo, r.condition) for r in runs] == [
        ("online", "day"), ("kmeans", "day"), ("online", "day>night")]
    assert len({r.key for r in runs}) == len(runs)
    assert runs[0].key == replace(runs[0]).key  # a hash of the configuration, not of identity
    assert TINY.skipped() == ["kmeans on day>night"]
    nested = replace(TINY, algos=("nested", "kmeans", "stream"))
    assert [r.algo for r in nested.runs() if ">" in r.condition] == ["nested"]
    assert nested.skipped() == ["kmeans on day>night", "stream on day>night"]


@pytest.mark.parametrize("bad, message", [
    ({"algos": ("online", "dbscan")}, "unknown algorithm 'dbscan'"),
    ({"features": ("surf64",)}, "unknown features"),
    ({"conditions": ("dusk",)}, "unknown conditions"),
    ({"conditions": ("day>night>day",)}, "one change"),
    ({"rooms": (0,)}, "at least 1"),
    ({"scenes": (-1,)}, "non-negative"),
    ({"latency_sizes": (1,)}, "at least 2"),
    ({"params": (("t_new_cluster", 0.9),)}, "kmeans has no parameter 't_new_cluster'"),
])
def test_matrix_names_bad_axes(bad: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        replace(TINY, **bad)


def test_report_files(tiny_bench) -> None:
    out, rows = tiny_bench
    for name in ("results.csv", "results.md", "config.json", "precision.png", "latency.png"):
        assert (out / name).stat().st_size > 0, name
    import imageio.v3 as iio

    for name in ("precision.png", "latency.png"):
        img = iio.imread(out / name)
        assert img.shape[0] >= 300 and img.shape[1] >= 500
        assert img[..., :3].std() > 10, f"{name} is blank"
    table = (out / "results.md").read_text()
    assert "| online (orb) | day |" in table and "| online (orb) | day>night |" in table
    assert "cannot localize on a fixed map: kmeans on day>night." in table
    config = json.loads((out / "config.json").read_text())
    assert config["matrix"]["steps_per_room"] == 12 and config["versions"]["numpy"]


def test_csv_agrees_with_stored_assignments(tiny_bench) -> None:
    out, _ = tiny_bench
    store = RunStore(out / "runs")
    lines = _read_csv(out / "results.csv")
    assert [r["key"] for r in lines] == [s.key for s in TINY.runs()]
    for line in lines:
        arrays = store.arrays(line["key"])
        assert len(arrays["assignments"]) == 2 * 12  # every frame of the tour has a place
        again = score(arrays["assignments"], arrays["truth"])
        assert int(line["n_places"]) == again["n_places"]
        assert float(line["nmi"]) == pytest.approx(again["nmi"])
        if ">" not in line["condition"]:  # cross-condition precision uses the day rooms
            assert float(line["precision"]) == pytest.approx(again["precision"])
        assert line["numpy"] == np.__version__


def test_resume_does_not_redo_finished_runs(tiny_bench, monkeypatch) -> None:
    out, rows = tiny_bench

    def fail(*args, **kwargs):
        raise AssertionError("a finished run was run again")

    monkeypatch.setattr(bench, "run_job", fail)
    again = run_bench(TINY, out, workers=1, progress=False)
    assert again == rows


def test_a_stale_run_is_run_again_and_said(tiny_bench, tmp_path, monkeypatch, capsys) -> None:
    import shutil

    out, rows = tiny_bench
    copy = tmp_path / "bench"
    shutil.copytree(out, copy)
    monkeypatch.setattr(bench, "run_stamp", lambda algo: {"code": "the recognizer edited"})
    jobs, done = bench.plan_jobs(TINY, RunStore(copy / "runs", bench.row_stamp))
    assert done == 0 and sum(len(j.specs) or 1 for j in jobs) == 4  # 3 runs, 1 sweep
    redone = run_bench(TINY, copy, workers=1, progress=True)
    assert "4 kept runs" in capsys.readouterr().err
    assert all(r.pop("stamp") == {"code": "the recognizer edited"} for r in redone)
    assert _stable(redone) == _stable([{k: v for k, v in r.items() if k != "stamp"}
                                       for r in rows])


def test_damaged_run_file_is_redone(tiny_bench, tmp_path) -> None:
    out, rows = tiny_bench
    import shutil

    copy = tmp_path / "bench"
    shutil.copytree(out, copy)
    key = rows[1]["key"]
    (copy / "runs" / f"{key}.json").write_text('{"key": "trunc')  # a torn write
    jobs, done = bench.plan_jobs(TINY, RunStore(copy / "runs"))
    assert done == 2 + 1  # the two intact runs and the latency sweep
    assert [s.key for j in jobs for s in j.specs] == [key]
    redone = run_bench(TINY, copy, workers=1, progress=False)
    assert _stable(redone) == _stable(rows)


def test_process_pool_gives_the_same_rows(tiny_bench, tmp_path) -> None:
    """Spawned workers give the same places and metrics as the main process (determinism)."""
    _, rows = tiny_bench
    pooled = run_bench(replace(TINY, latency_sizes=()), tmp_path, workers=2, progress=False)
    assert _stable(pooled) == _stable(rows)


def test_ray_gives_the_same_rows(tiny_bench, tmp_path) -> None:
    ray = pytest.importorskip("ray")
    _, rows = tiny_bench
    try:
        on_ray = run_bench(replace(TINY, latency_sizes=()), tmp_path, workers=2,
                           executor="ray", progress=False)
    finally:
        ray.shutdown()
    assert _stable(on_ray) == _stable(rows)
    assert (tmp_path / "runs" / f"{rows[0]['key']}.npz").is_file()  # the driver stored them


def test_params_reach_every_run_and_name_it(tmp_path) -> None:
    """``--param`` values go to the recognizer of every run (the same places as a direct run
    with them), into the run's key, the CSV and the table's method name."""
    from envs.tasks.tour import record_tour
    from placeclust.runner import run

    matrix = replace(TINY, algos=("online",), conditions=("day",), latency_sizes=(),
                     params=(("view", "sides"), ("kernel_capacity", 600)))
    assert matrix.runs()[0].key != replace(matrix, params=()).runs()[0].key
    rows = run_bench(matrix, tmp_path, workers=1, progress=False)
    tour, _ = record_tour(0, 2, 24, 0, progress=False)
    direct = run("online", tour.frames, "orb", view="sides", kernel_capacity=600)
    stored = RunStore(tmp_path / "runs").arrays(rows[0]["key"])["assignments"]
    np.testing.assert_array_equal(stored, direct.assignments)
    assert _read_csv(tmp_path / "results.csv")[0]["params"] == "view=sides, kernel_capacity=600"
    assert "| online (orb, view=sides, kernel_capacity=600) | day |" in (
        tmp_path / "results.md").read_text()


def test_cli_bench_rejects_bad_axes(capsys, tmp_path) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["bench", "--quick", "--conditions", "dusk", "--out", str(tmp_path)])
    assert exc.value.code == 2
    assert "unknown conditions" in capsys.readouterr().err
    assert not (tmp_path / "results.csv").exists()


def test_one_table_of_conditions_serves_the_scene_the_cli_and_the_bench():
    from envs.commands.cli import build_parser
    from envs.world.conditions import CONDITIONS, LIGHTING, LIGHTS

    assert bench.CONDITIONS is CONDITIONS and tuple(LIGHTS) == LIGHTING
    assert set(LIGHTING) < set(CONDITIONS)
    tour = build_parser()._subparsers._group_actions[0].choices["tour"]
    (lighting,) = [a for a in tour._actions if a.dest == "lighting"]
    assert tuple(lighting.choices) == LIGHTING


def test_summary_reports_intervals_the_worst_run_and_the_share_meeting_the_bar() -> None:
    from envs.commands.bench_report import summary_table

    def row(precision: float, nmi: float, places: int, scene: int = 0) -> dict:
        return {"algo": "online", "features": "sift", "condition": "day", "params": (),
                "precision": precision, "recall": 0.5, "nmi": nmi, "ari": 0.5,
                "n_places": places, "n_rooms": 4, "ms_per_frame": 10.0, "scene_seed": scene}

    # one building: no interval to give
    table = summary_table([row(0.99, 0.85, 6), row(0.93, 0.90, 8), row(0.97, 0.82, 9)])
    line = table.splitlines()[2]
    assert "| 0.963 (0.930) |" in line  # precision: mean (worst)
    assert "| 1.92 (2.25) |" in line  # places per room: mean (most)
    assert "| 1/3 |" in line  # only the first run meets all three bars
    orb = [{**r, "features": "orb"} for r in (row(0.99, 0.5, 12), row(0.93, 0.5, 13))]
    assert "| 1/2 |" in summary_table(orb).splitlines()[2]  # ORB's bar: 3 places per room
    # three buildings: each figure with its interval over them
    line = summary_table([row(0.99, 0.85, 6, 0), row(0.93, 0.90, 8, 1),
                          row(0.97, 0.82, 9, 2)]).splitlines()[2]
    assert "| 0.963 [0.930, 0.983] (0.930) |" in line and "| 1/3 [0.00, 1.00] |" in line


@pytest.mark.parametrize("k", ["rooms", "online"])
def test_offline_methods_can_be_given_the_rooms_or_the_online_place_count(tmp_path, k):
    matrix = replace(TINY, algos=("kmeans",), conditions=("day",), latency_sizes=(),
                     params=(("n_clusters", k),))
    (row,) = run_bench(matrix, tmp_path, workers=1, progress=False)
    if k == "rooms":
        assert row["n_places"] == row["n_rooms"]
    else:
        (online,) = run_bench(replace(matrix, algos=("online",), params=()),
                              tmp_path / "online", workers=1, progress=False)
        assert row["n_places"] == online["n_places"]
    assert f"n_clusters={k}" in (tmp_path / "results.md").read_text()


def test_nested_localizes_across_conditions(tmp_path) -> None:
    matrix = replace(TINY, algos=("nested",), features=("sift",), conditions=("day>night",),
                     latency_sizes=())
    (row,) = run_bench(matrix, tmp_path, workers=1, progress=False)
    assert row["condition"] == "day>night" and 0.0 <= row["precision"] <= 1.0
    assert row["map_precision"] > 0.0


@pytest.fixture(scope="module")
def datasets(tmp_path_factory):
    """A labelled image folder and a VPR-Bench folder of the same two synthetic places."""
    from placeclust.datasets import write_image_folder
    from placeclust.synthetic import places
    from placeclust.vprbench import write_vpr_bench

    root = tmp_path_factory.mktemp("data")
    frames, truth = places(2)
    write_image_folder(root / "folder", frames, [f"r{t}" for t in truth])
    write_vpr_bench(root / "vpr", frames, frames, [np.flatnonzero(truth == t) for t in truth])
    return str(root / "folder"), str(root / "vpr")


def test_real_data_sets_join_the_matrix_beside_the_tours(datasets, tmp_path) -> None:
    folder, vpr = datasets
    matrix = replace(TINY, datasets=(folder, vpr))
    runs = matrix.runs()
    real = [(r.algo, r.condition, r.dataset) for r in runs if r.dataset]
    assert real == [("online", "images", folder), ("kmeans", "images", folder),
                    ("online", "ref>query", vpr)]
    assert "kmeans on ref>query" in matrix.skipped()
    # simulated runs keep the keys they had before data sets existed
    assert [r.key for r in runs if not r.dataset] == [r.key for r in TINY.runs()]
    with pytest.raises(ValueError, match="holds no image"):
        replace(TINY, datasets=(str(tmp_path),))


def test_doors_are_a_world_option_of_the_matrix() -> None:
    doored = replace(TINY, doors=1.0).runs()
    assert {r.doors for r in doored} == {1.0}
    assert not {r.key for r in doored} & {r.key for r in TINY.runs()}  # other buildings
    assert doored[0].tour != TINY.runs()[0].tour
    with pytest.raises(ValueError, match="doors must be a fraction"):
        replace(TINY, doors=2.0)


def test_windows_and_lamps_are_a_world_option_of_the_matrix() -> None:
    from envs.commands.cli import bench_plan, build_parser

    lit = replace(TINY, local_light=True).runs()
    assert {r.local_light for r in lit} == {True}
    assert not {r.key for r in lit} & {r.key for r in TINY.runs()}  # other buildings
    assert lit[0].tour != TINY.runs()[0].tour
    args = build_parser().parse_args(["bench", "--quick", "--local-light", "--scenes", "0"])
    assert bench_plan(args)[0].local_light


def test_the_bench_runs_data_sets_and_compares_their_ranking(datasets, tmp_path) -> None:
    folder, vpr = datasets
    matrix = replace(TINY, algos=("online", "nested", "kmeans"), datasets=(folder, vpr),
                     conditions=("day",), latency_sizes=(), params=())
    rows = run_bench(matrix, tmp_path, workers=1, progress=False)
    by = {(r["algo"], r["condition"]): r for r in rows if r.get("dataset")}
    assert by[("online", "images")]["precision"] == 1.0
    assert by[("online", "ref>query")]["query_top1"] == 1.0
    report = (tmp_path / "results.md").read_text()
    assert "Real data sets" in report and "| online (orb) | vpr |" in report
    assert "Spearman's rank correlation over 3 methods" in report  # the folder: 3 recognizers
    assert "2 methods: too few to rank" in report  # VPR-Bench: kmeans cannot localize
    kept = run_bench(matrix, tmp_path, workers=1, progress=False)  # resumes: nothing redone
    assert _stable(kept) == _stable(rows)
