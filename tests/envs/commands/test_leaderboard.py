"""The closed loop's store and ranking: the leaderboard resumes, reruns what changed, ranks;
``placeclust errands`` writes its scores."""

import json
import math

import pytest

import envs  # noqa: F401
from envs.commands import errands
from envs.commands.leaderboard import leaderboard, rank_agreement
from envs.runs import jobs as job_runs
from envs.runs import suite
from envs.runs.jobs import job_fingerprint, run_jobs
from envs.runs.results import summarize
from train import evaluate


def test_the_leaderboard_resumes_and_ranks(tmp_path):
    jobs = [{"scene_seed": s, "recognizer": r, "n_errands": 1, "seed": 0, "agent": "planner",
             "n_rooms": 3} for r in ("oracle",) for s in (0, 1)]
    rows = run_jobs(jobs, tmp_path, progress=False)
    files = sorted((tmp_path / "runs").glob("*.json"))
    assert len(rows) == 2 and len(files) == 2
    stamp = [f.stat().st_mtime_ns for f in files]
    assert run_jobs(jobs, tmp_path, progress=False) == rows  # resumed, nothing run again
    assert [f.stat().st_mtime_ns for f in files] == stamp
    summary = summarize(rows)
    assert summary["n_errands"] == 2 and summary["success_rate"] == 1.0
    assert summary["success_rate_interval"] == [1.0, 1.0]  # every building alike
    table = leaderboard([summary, {**summary, "recognizer": "random", "success_rate": 0.1,
                                   "success_rate_interval": [0.0, 0.3]}])
    assert table.index("oracle") < table.index("random")
    assert "| random | 0.10 [0.00, 0.30] |" in table
    fake = [{"success_rate": s, "nmi": n} for s, n in ((1, 1), (0.5, 0.6), (0.1, 0.2))]
    assert rank_agreement(fake) == pytest.approx(1.0)


@pytest.mark.parametrize(("what", "changed"), [
    ("job_fingerprint", lambda job: "edited planner"),
    ("library_versions", lambda: {"mujoco": "another"}),
    ("render_fingerprint", lambda: "another Mesa"),
])
def test_a_stale_result_is_run_again_and_said(tmp_path, monkeypatch, capsys, what, changed):
    jobs = [{"scene_seed": 0, "recognizer": "oracle", "n_errands": 1, "seed": 0, "agent": "planner",
             "n_rooms": 3}]
    run_jobs(jobs, tmp_path, progress=False)
    (kept,) = (tmp_path / "runs").glob("*.json")
    stamp = kept.stat().st_mtime_ns
    monkeypatch.setattr(job_runs, what, changed)
    (row,) = run_jobs(jobs, tmp_path, progress=False)
    assert kept.stat().st_mtime_ns != stamp and row["stamp"] == job_runs.stamp(jobs[0])
    assert "1 kept results" in capsys.readouterr().err


def test_the_job_fingerprint_follows_the_code_and_the_policy_file(tmp_path, monkeypatch):
    job = {"agent": "ppo", "policy": str(tmp_path / "a.zip")}
    (tmp_path / "a.zip").write_bytes(b"one policy")
    first = job_fingerprint(job)
    (tmp_path / "a.zip").write_bytes(b"the policy trained again")
    assert job_fingerprint(job) != first
    again = job_fingerprint(job)
    (tmp_path / "config.yml").write_text("env: {observe: place, repeat: 4}\n")
    assert job_fingerprint(job) != again  # what the policy observes changes what it does
    assert job_fingerprint({"agent": "planner"}) == job_fingerprint({"agent": "planner"})
    planner = job_fingerprint({"agent": "planner"})
    monkeypatch.setattr(suite, "code_fingerprint", lambda: "the recognizer edited")
    assert job_fingerprint({"agent": "planner"}) != planner


def test_errands_writes_a_results_file(tmp_path, capsys):
    out = tmp_path / "scores.json"
    code = errands.main(["--scene-seeds", "0", "1", "--rooms", "3",
                          "--recognizer", "oracle", "--errands", "2", "--seed", "1",
                          "--json", str(out), "--tour-steps-per-room", "40"])
    assert code == 0
    doc = json.loads(out.read_text())
    (scores,) = doc["summaries"]
    for key in ("success_rate", "spl", "mean_length", "precision", "nmi", "n_places"):
        assert math.isfinite(scores[key]) and len(scores[f"{key}_interval"]) == 2
    assert doc["settings"]["scene_seeds"] == [0, 1] and len(doc["buildings"]) == 2
    assert doc["provenance"]["suite"] is None and doc["provenance"]["render_fingerprint"]
    assert "success_rate=" in capsys.readouterr().out
    # a recognizer that is not one is named before any building of the split is toured
    assert errands.main(["--split", "test", "--recognizer", "psychic"]) == 2
    assert "unknown recognizer 'psychic'" in capsys.readouterr().err


def test_train_evaluate_points_its_old_unseen_task_to_placeclust_errands(tmp_path, capsys):
    assert evaluate.main(["--task", "unseen", "--split", "test", "--json",
                          str(tmp_path / "s.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "placeclust errands" in err
    assert not (tmp_path / "s.json").exists()


def test_a_recognizer_of_your_own_runs_in_the_closed_loop(tmp_path):
    from envs.runs.tour_errands import run_scene

    row = run_scene(0, n_rooms=3, recognizer="examples.tiny_recognizer:HaarPlaces", n_errands=1,
                    seed=0, recognizer_params={"threshold": 0.8}, tour_steps_per_room=40)
    assert row["recognizer_params"] == {"threshold": 0.8} and len(row["errands"]) == 1
    assert row["n_places"] >= 1 and 0.0 <= row["precision"] <= 1.0


@pytest.mark.parametrize(("argv", "message"), [
    (["--recognizer", "nosuchpackage.mod:Thing"], "cannot import 'nosuchpackage.mod'"),
    (["--recognizer", "placeclust.kunion:KAdjacentUnion"], "needs an online one"),
    (["--recognizer", "examples.tiny_recognizer:HaarPlaces", "--param", "radius=2"],
     "radius"),
    (["--recognizer", "panorama", "--param", "scale=1.0"], "are built in"),
    (["--recognizer", "examples.tiny_recognizer:HaarPlaces", "--param", "threshold=abc"],
     "HaarPlaces's threshold must be float, got 'abc'"),
    (["--recognizer", "placeclust.online:OnlinePlaceClustering", "--param",
      "t_new_cluster=abc"], "t_new_cluster must be float"),
])
def test_a_bad_recognizer_stops_the_errands_before_any_tour(argv, message, tmp_path, capsys):
    code = errands.main(["--scene-seeds", "0", "--rooms", "3", "--out", str(tmp_path),
                             *argv])
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "runs").exists() or not any((tmp_path / "runs").iterdir())


def test_a_job_file_names_what_changes_it_and_hashes_the_rest():
    plain = {"scene_seed": 2000, "n_rooms": 6, "recognizer": "panorama", "agent": "planner",
             "n_errands": 5, "seed": 0}
    assert job_runs.job_key(plain) == "panorama-planner-scene2000-rooms6-errands5-seed0"
    own = {**plain, "recognizer": "mine:Places", "recognizer_params": {"threshold": 0.8}}
    other = {**own, "recognizer_params": {"threshold": 0.9}}
    assert job_runs.job_key(own) != job_runs.job_key(other)
    assert ":" not in job_runs.job_key(own)


def test_errands_can_start_carried_in_a_corridor_and_say_so(tmp_path):
    out = tmp_path / "carried.json"
    code = errands.main(["--scene-seeds", "0", "--rooms", "3", "--recognizer", "oracle",
                             "--errands", "2", "--tour-steps-per-room", "40",
                             "--errand-start", "carried", "--layout", "corridor",
                             "--json", str(out)])
    assert code == 0
    doc = json.loads(out.read_text())
    assert doc["settings"]["task"] == {"tour_steps_per_room": 40, "errand_start": "carried",
                                       "layout": "corridor"}
    assert all(e["shortest"] >= 1.0 for e in doc["buildings"][0]["errands"])


def test_errands_run_in_buildings_with_doors_and_say_so(tmp_path, capsys):
    out = tmp_path / "doors.json"
    code = errands.main(["--scene-seeds", "1000", "--rooms", "3", "--recognizer", "oracle",
                             "--errands", "2", "--tour-steps-per-room", "40",
                             "--doors", "1.0", "--json", str(out)])
    assert code == 0
    doc = json.loads(out.read_text())
    assert doc["settings"]["task"] == {"tour_steps_per_room": 40, "doors": 1.0}
    assert doc["buildings"][0]["success_rate"] == 1.0  # the true rooms get through the doors
    assert errands.main(["--scene-seeds", "1000", "--recognizer", "oracle", "--doors", "2",
                             "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()
    assert "--doors must be a fraction" in capsys.readouterr().err


def test_two_policies_keep_two_job_files():
    job = {"scene_seed": 2000, "n_rooms": 6, "recognizer": "panorama-orb", "agent": "ppo",
           "n_errands": 5, "seed": 0}
    a = job_runs.job_key({**job, "policy": "runs/train/carried_place/policy.zip"})
    b = job_runs.job_key({**job, "policy": "runs/train/carried_oracle/policy.zip"})
    assert a != b and "carried_place" in a
    chosen = job_runs.job_key({**job, "policy": "runs/train/carried_place/best_model.zip"})
    assert "carried_place" in chosen  # train.choose's pick is named by its run too


def test_a_track_runs_its_errands_and_a_fixed_map_skips_who_cannot_localize(tmp_path, capsys):
    from envs.commands import leaderboard as board

    code = board.main(["--scene-seeds", "0", "1", "--rooms", "3", "--errands", "1",
                       "--tour-steps-per-room", "30", "--recognizers", "oracle", "oracle-split:2",
                       "examples.tiny_recognizer:HaarPlaces", "--track", "changed-night",
                       "--localize-only", "--agent", "relocalizer", "--workers", "1",
                       "--out", str(tmp_path)])
    captured = capsys.readouterr()
    assert code == 0 and "skipped on a fixed map (no localize_one)" in captured.err
    assert "Track `changed-night`" in captured.out and "HaarPlaces." in captured.out
    doc = json.loads((tmp_path / "results.json").read_text())
    assert doc["settings"]["track"] == "changed-night"
    assert doc["settings"]["task"] == {"tour_steps_per_room": 30, "local_light": True,
                                       "errand_condition": "night", "errand_learn": False}
    assert doc["settings"]["skipped"] == ["examples.tiny_recognizer:HaarPlaces"]
    assert [s["recognizer"] for s in doc["summaries"]] == ["oracle", "oracle-split:2"]


def test_a_track_refuses_an_option_that_contradicts_it(capsys):
    code = errands.main(["--scene-seeds", "0", "--rooms", "3", "--recognizer", "oracle",
                             "--track", "long", "--tour-steps-per-room", "40"])
    err = capsys.readouterr().err
    assert code == 2 and "--track long sets tour_steps_per_room=500" in err
    code = errands.main(["--scene-seeds", "0", "--rooms", "3", "--localize-only",
                             "--recognizer", "examples.tiny_recognizer:HaarPlaces"])
    err = capsys.readouterr().err
    assert code == 2 and "cannot localize" in err and len(err.strip().splitlines()) == 1


def test_tracks_of_one_tour_share_it_and_report_apart(tmp_path, capsys):
    from envs.commands import leaderboard as board

    argv = ["--scene-seeds", "0", "1", "--rooms", "3", "--errands", "1",
            "--tour-steps-per-room", "30", "--recognizers", "oracle", "none", "--track",
            "continued", "carried", "--agent", "relocalizer", "--workers", "1",
            "--out", str(tmp_path)]
    assert board.main(argv) == 0
    out = capsys.readouterr().out
    assert "| recognizer | continued | carried | suite score (mean) |" in out
    # one job, so one tour, per recognizer and building, serving both tracks
    assert len(list((tmp_path / "runs").glob("*.json"))) == 4
    docs = {t: json.loads((tmp_path / t / "results.json").read_text())
            for t in ("continued", "carried")}
    assert docs["carried"]["settings"]["task"] == {"tour_steps_per_room": 30,
                                                   "local_light": True,
                                                   "errand_start": "carried"}
    maps = [[(r["scene_seed"], r["recognizer"], r["precision"], r["n_places"])
             for r in d["buildings"]] for d in docs.values()]
    assert maps[0] == maps[1]  # the same tours' maps
    first = (tmp_path / "carried" / "results.json").read_text()
    assert board.main(argv) == 0  # resumed: every job kept, the same results
    assert json.loads((tmp_path / "carried" / "results.json").read_text())["buildings"] == \
        json.loads(first)["buildings"]


def test_a_missing_policy_is_named_before_any_folder_is_made(tmp_path, capsys):
    pytest.importorskip("stable_baselines3")  # without it, the missing extra is named first
    out = tmp_path / "out"
    code = errands.main(["--scene-seeds", "0", "--recognizer", "oracle", "--agent", "ppo",
                             "--policy", str(tmp_path / "none.zip"), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "no policy file" in err and "carried_place" in err  # the shipped ones, named
    assert not out.exists()


def test_the_ppo_agent_without_stable_baselines3_names_the_extra(tmp_path, capsys, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "stable_baselines3" else real(name, *a))
    from envs.commands import leaderboard as board

    code = board.main(["--scene-seeds", "0", "--recognizers", "oracle", "--agent", "ppo",
                       "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "pip install 'placeclust[train]'" in err
    assert not (tmp_path / "out").exists()


def test_a_run_says_at_once_what_it_will_run_and_what_it_kept(tmp_path, capsys):
    jobs = [{"scene_seed": s, "recognizer": "oracle", "n_errands": 1, "seed": 0, "agent": "planner",
             "n_rooms": 3, "tour_steps_per_room": 30} for s in (0, 1)]
    run_jobs(jobs[:1], tmp_path)  # a partial run: one job of two
    first = capsys.readouterr().err.splitlines()
    assert first[0].startswith("errands: 1 job to run (a job: one recognizer's guided tour")
    run_jobs(jobs, tmp_path)
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith(f"errands: 1 job to run, 1 kept from an earlier run in {tmp_path}")
    assert err[-1].startswith("errands: 1 job in")  # counted as jobs, not buildings


def test_the_lit_tracks_share_one_tour_and_the_corridor_tracks_another():
    from envs.runs.jobs import track_jobs
    from envs.runs.suite import TRACKS, track_task
    from envs.runs.task_spec import ErrandTask

    names = [n for n in TRACKS if n != "long"]
    tasks = {n: ErrandTask.from_kwargs({"n_errands": 1, **track_task(n)}) for n in names}
    jobs = track_jobs([0, 1], ["oracle"], tasks, n_rooms=3, agent="relocalizer", seed=0)
    assert len(jobs) == 4  # two tours a building
    lit = [j for j in jobs if j.get("local_light")]
    assert {tuple(sorted(j["tracks"])) for j in lit} == {(
        "carried", "changed-cloudy", "changed-cloudy-fixed", "changed-moved",
        "changed-moved-fixed", "changed-night", "changed-night-fixed", "continued")}
    corridor = [j for j in jobs if j.get("layout") == "corridor"]
    assert {tuple(sorted(j["tracks"])) for j in corridor} == {("corridor", "corridor-carried")}
    assert all(not j.get("local_light") for j in corridor)


def test_the_freshness_probes_know_every_track_and_suite():
    from docs.freshness.probes import SUITE_OPTIONS, TRACK_NAMES
    from envs.runs.suite import SUITES, TRACKS

    assert TRACK_NAMES == tuple(TRACKS)  # a new track's results get their stand-in
    # a suite's section is traced with the agent and tracks the suite runs (long aside)
    assert set(SUITE_OPTIONS) == set(SUITES)
    for name, frozen in SUITES.items():
        fixed = SUITE_OPTIONS[name].split()
        assert fixed[fixed.index("--agent") + 1] == frozen.agent
        tracks = fixed[fixed.index("--track") + 1:] if "--track" in fixed else []
        assert tracks == [t for t in frozen.track_names if t != "long"]


def test_ctrl_c_is_one_line_exit_130_and_keeps_the_finished_jobs(tmp_path, capsys,
                                                                  monkeypatch):
    """Fault caught: a traceback, or the first job's result lost, on Ctrl-C in the second."""
    from envs.commands import cli

    real = job_runs._run_job
    calls = []

    def second_is_interrupted(job):
        calls.append(job)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(job)

    monkeypatch.setattr(job_runs, "_run_job", second_is_interrupted)
    argv = ["leaderboard", "--scene-seeds", "0", "1", "--rooms", "3", "--recognizers",
            "oracle", "--errands", "1", "--tour-steps-per-room", "30", "--workers",
            "1", "--out", str(tmp_path)]
    with pytest.raises(SystemExit) as stop:
        cli.main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert stop.value.code == 130
    assert err[-1] == (f"interrupted: 1 finished job kept in {tmp_path / 'runs'}; the same "
                       "command resumes from them")
    assert not any("Traceback" in line for line in err)
    assert len(list((tmp_path / "runs").glob("*.json"))) == 1
    monkeypatch.setattr(job_runs, "_run_job", real)
    with pytest.raises(SystemExit) as stop:
        cli.main(argv)  # resumed: only the interrupted job runs
    assert stop.value.code == 0
    assert "errands: 1 job to run, 1 kept from an earlier run" in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    (["--rooms", "0"], "argument --rooms: a building has 1 to 32 rooms, got '0'"),
    (["--suite", "placenav-v9"], "argument --suite: invalid choice: 'placenav-v9'"),
    (["--track", "nowhere"], "argument --track: invalid choice: 'nowhere'"),
    (["--recognizers", "oracle-noise:abc"], "'oracle-noise:abc' is not an oracle name"),
])
def test_a_bad_option_is_one_line_exit_2_and_leaves_nothing(argv, message, tmp_path, capsys):
    from envs.commands import cli

    out = tmp_path / "out"
    with pytest.raises(SystemExit) as stop:
        cli.main(["leaderboard", "--scene-seeds", "0", *argv, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert stop.value.code == 2 and len(err) == 1 and message in err[0], err
    assert not out.exists()


def test_a_broken_stable_baselines3_is_one_line_and_leaves_nothing(tmp_path, capsys,
                                                                    monkeypatch):
    """Fault caught: an install that is present but fails to import (a torch that does not
    load) passed the check and failed in every job with a traceback."""
    import importlib
    import importlib.util

    real_spec, real_import = importlib.util.find_spec, importlib.import_module
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: object()
                        if name == "stable_baselines3" else real_spec(name, *a))

    def broken(name, *a):
        if name == "stable_baselines3":
            raise OSError("libtorch_cpu.so: cannot open shared object file\nmore")
        return real_import(name, *a)

    monkeypatch.setattr(importlib, "import_module", broken)
    from envs.commands import leaderboard as board

    code = board.main(["--scene-seeds", "0", "--recognizers", "oracle", "--agent", "ppo",
                       "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "installed but does not import (OSError: libtorch_cpu.so" in err[0]
    assert not (tmp_path / "out").exists()


def test_a_one_building_results_file_is_strict_json_with_null_intervals(tmp_path):
    """Fault caught: a bare NaN (not JSON: jq and JavaScript refuse the file) where an
    interval of one building is undefined."""
    from envs.runs.results import load_results, write_results

    rows = run_jobs([{"scene_seed": 0, "recognizer": "oracle", "n_errands": 1, "seed": 0,
                      "agent": "planner", "n_rooms": 3, "tour_steps_per_room": 30}],
                    progress=False)
    path = tmp_path / "results.json"
    write_results(path, rows, ["oracle"], {}, {})

    def refuse(constant):
        raise AssertionError(f"{constant} is not JSON")

    doc = json.loads(path.read_text(), parse_constant=refuse)
    assert doc["summaries"][0]["success_rate_interval"] == [None, None]
    back = load_results(path)["summaries"][0]["success_rate_interval"]
    assert all(math.isnan(v) for v in back)  # read back as the undefined float it was
