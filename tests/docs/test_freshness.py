"""The check that tells which generated tables of the docs the code has moved under."""

import importlib.util
import json
import shlex
import subprocess
from importlib.metadata import entry_points
from pathlib import Path

import pytest

from docs.freshness import check as freshness
from docs.freshness import probes, syntax
from placeclust.docs_section import write_section

MODULE = "placeclust/stats.py"
#: the tiny runs call the installed `placeclust` command (make test-oldest runs from the tree)
needs_cli = pytest.mark.skipif(
    not entry_points(group="console_scripts", name="placeclust")
    or importlib.util.find_spec("placeclust_envs") is None,
    reason="the placeclust command is not installed")


def test_docstrings_comments_and_layout_do_not_count_code_and_constants_do():
    code = "X = 1\n\ndef f(a):\n    '''Say.'''\n    return a + X  # why\n\ndef g():\n    pass\n"
    reworded = code.replace("Say.", "Say otherwise.").replace("# why", "# because")
    assert syntax.source_digest(code, ["f"]) == syntax.source_digest(reworded, ["f"])
    for changed in (code.replace("a + X", "a - X"), code.replace("X = 1", "X = 2"),
                    code.replace("def f(a)", "def f(a=3)")):
        assert syntax.source_digest(code, ["f"]) != syntax.source_digest(changed, ["f"])
    # a function the command never ran may change freely; one that disappears is a change
    assert syntax.source_digest(code, ["f"]) == syntax.source_digest(
        code.replace("pass", "return 1"), ["f"])
    assert syntax.source_digest(code, ["f"]) != syntax.source_digest(
        code.replace("def f(a)", "def h(a)"), ["f"])
    assert syntax.source_digest(None, ["f"]) != syntax.source_digest(code, ["f"])
    assert syntax.source_digest(None, []) == syntax.source_digest("import os\nX = 1\n", [])


def test_a_fingerprint_follows_the_sources_it_reads_through_its_caches():
    """Fault caught: a memo keyed by path or by commit name alone (a file changed between two
    commits, or a branch that moved, read as its first version)."""
    code = "X = 1\n\ndef f(a):\n    return a + X\n"
    trace = {"functions": {"m.py": ["f"]}, "files": []}
    first = syntax.fingerprint(trace, {"m.py": code.encode()}.get)
    changed = syntax.fingerprint(trace, {"m.py": code.replace("X = 1", "X = 2").encode()}.get)
    assert changed != first
    assert syntax.fingerprint(trace, {"m.py": code.encode()}.get) == first
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=probes.ROOT, capture_output=True,
                          text=True).stdout.strip()
    if not head:
        pytest.skip("needs the repository's history")
    assert syntax.at_commit("HEAD").args == (head,)  # a ref is read as the commit it named
    assert syntax.at_commit("HEAD")("pyproject.toml") == syntax.at_commit(head)("pyproject.toml")


def test_the_tracer_sees_the_repository_functions_that_ran_and_the_files_read():
    from placeclust import stats

    with probes.traced() as trace:
        stats.interval([[0.1, 0.5], [0.9]], n_resamples=50)
        with open(probes.ROOT / "pyproject.toml") as f:
            f.read(1)
    assert "interval" in trace["functions"][MODULE]
    assert "pyproject.toml" in trace["files"]
    assert not any(p.startswith("docs/freshness/") for p in trace["functions"])


@pytest.fixture
def repo_docs(tmp_path):
    """A docs file with one section and a manifest that recorded it against stats.py."""
    docs, manifest = tmp_path / "benchmarks.md", tmp_path / "generated.json"
    write_section(docs, "table", "| a |\n|---|\n| 1 |", "placeclust demo --out runs/demo")
    trace = {"functions": {MODULE: ["interval"]}, "files": ["pyproject.toml"]}
    (stamp, command), = freshness.sections(docs).values()
    freshness.save({"sections": {"table": {"stamp": stamp, "command": command, "trace": trace,
                                           "fingerprint": syntax.fingerprint(trace)}},
                    "differs": {}}, manifest)
    return docs, manifest


def _older(manifest):
    """The manifest as if recorded when interval() read otherwise: the code moved since."""
    data = json.loads(manifest.read_text())
    data["sections"]["table"]["fingerprint"] = syntax.fingerprint(
        data["sections"]["table"]["trace"], lambda p: (
            syntax.working_tree(p).replace(b"def interval(", b"def interval(*_unused, ")
            if p == MODULE else syntax.working_tree(p)))
    freshness.save(data, manifest)


def test_a_moved_dated_record_passes_and_a_moved_cited_table_fails(repo_docs, monkeypatch):
    docs, manifest = repo_docs
    assert freshness.status(docs, manifest)["current"] == ["table"]
    _older(manifest)
    assert freshness.status(docs, manifest)["moved"] == ["table"]
    check = ["check", "--docs", str(docs), "--manifest", str(manifest)]
    assert freshness.main(check) == 0  # a dated record: the code moving is no verdict
    monkeypatch.setattr(freshness, "CITED", {"table": "README.md, a figure"})
    assert freshness.main(check) == 1  # a claim cites it: it must be current


@pytest.mark.parametrize("same", [True, False])
def test_verify_makes_a_moved_table_current_or_lists_it_as_differing(repo_docs, monkeypatch,
                                                                     same):
    """Fault caught: a probe that differs leaving the table unlisted (or current), or one
    that does not leaving it moved."""
    docs, manifest = repo_docs
    _older(manifest)
    monkeypatch.setattr(freshness.verify, "verdict",
                        lambda name, entry, commands, scratch: (same, "'0.97' → '0.95'"))
    monkeypatch.setattr(freshness, "measured_commit", lambda name, entry, docs: "c0ffee")
    freshness.run_verify(["table"], docs, manifest, docs.parent / "scratch", log=lambda _: None)
    state = freshness.status(docs, manifest)
    listed = "| table | '0.97' → '0.95' | `placeclust demo --out runs/demo` |" in docs.read_text()
    if same:
        assert state["current"] == ["table"] and not listed
    else:
        assert state["differs"] == ["table"] and listed and not state["unlisted"]
    # the code moving again puts a differing table back among the unverified
    data = json.loads(manifest.read_text())
    if not same:
        data["differs"]["table"] = "older"
        freshness.save(data, manifest)
        assert freshness.status(docs, manifest)["moved"] == ["table"]


def test_a_difference_in_words_only_is_accepted_with_its_reason_and_listed(repo_docs,
                                                                          monkeypatch):
    """Fault caught: accepting a table no probe found different, or without a reason, or
    leaving an accepted one unlisted in the docs or listed after it is measured again."""
    docs, manifest = repo_docs
    monkeypatch.setattr(freshness, "CITED", {"table": "README.md, a figure"})
    check = ["check", "--docs", str(docs), "--manifest", str(manifest)]
    with pytest.raises(ValueError, match="do not differ"):
        freshness.accept(["table"], "a renamed key", docs, manifest)
    _older(manifest)
    monkeypatch.setattr(freshness.verify, "verdict", lambda name, entry, commands, scratch: (
        False, "'goals: 1' → 'n_errands: 1'"))
    monkeypatch.setattr(freshness, "measured_commit", lambda name, entry, docs: "c0ffee")
    freshness.run_verify(["table"], docs, manifest, docs.parent / "scratch", log=lambda _: None)
    assert freshness.main(check) == 1  # cited and differing
    assert freshness.main(["accept", "table", "--because", " ", *check[1:]]) == 2
    assert freshness.main(["accept", "table", "--because", "the errand count's key renamed",
                           *check[1:]]) == 0
    assert freshness.main(check) == 0 and freshness.status(docs, manifest)["current"] == [
        "table"]
    text = docs.read_text()
    assert "- `table`: 'goals: 1' → 'n_errands: 1' (the errand count's key renamed)" in text
    freshness.record(["table"], docs, manifest, docs.parent / "scratch", log=lambda _: None,
                     now=True)  # measured again: its words are today's
    freshness.write_stale_list(docs, manifest)
    assert "errand count's key renamed" not in docs.read_text()


def test_a_verdict_saved_by_another_verify_during_a_probe_is_kept(repo_docs, monkeypatch):
    """Fault caught: writing back the manifest as it was read before the probe, which drops
    what a verify process beside this one saved meanwhile."""
    docs, manifest = repo_docs
    _older(manifest)

    def probe_while_another_saves(name, entry, commands, scratch):
        data = freshness.load(manifest)
        data["sections"]["other"] = {"verified": "by the process beside"}
        freshness.save(data, manifest)
        return True, ""

    monkeypatch.setattr(freshness.verify, "verdict", probe_while_another_saves)
    monkeypatch.setattr(freshness, "measured_commit", lambda name, entry, docs: "c0ffee")
    freshness.run_verify(["table"], docs, manifest, docs.parent / "scratch", log=lambda _: None)
    sections = json.loads(manifest.read_text())["sections"]
    assert sections["other"] == {"verified": "by the process beside"}
    assert "verified" in sections["table"]


def test_a_moved_section_is_probed_against_the_newest_commit_that_still_measured_it():
    """Fault caught: probing the old side at the commit that first wrote the section (every
    section a checkout of its own, each probe run again) or at today's code (the change
    unseen); a fingerprint no commit has falls back to that first commit."""
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=probes.ROOT, capture_output=True,
                          text=True).stdout.strip()
    trace = {"functions": {MODULE: ["interval"]}, "files": []}
    first = freshness.section_commit("demo")
    if not head or first in (None, head):
        pytest.skip("needs the repository's history, with the demo section older than HEAD")
    at_head = {"trace": trace, "fingerprint": syntax.fingerprint(trace, syntax.at_commit(head))}
    assert freshness.measured_commit("demo", at_head) == head
    nowhere = {"trace": trace, "fingerprint": "0" * 16}
    assert freshness.measured_commit("demo", nowhere) == first


def test_a_checkouts_stand_ins_share_their_jobs_and_keep_their_own(tmp_path):
    """Fault caught: a stand-in's own job overwritten by another's (a run's rows must be the
    ones its store holds), or only closed-loop runs that write no store given one."""
    from docs.freshness import verify

    pool, runs = tmp_path / "jobs", tmp_path / "stand-in" / "runs"
    pool.mkdir()
    (pool / "panorama-a.json").write_text("pool")
    (pool / "oracle-a.json").write_text("pool")
    runs.mkdir(parents=True)
    (runs / "oracle-a.json").write_text("own")
    verify._share_jobs(pool, runs)
    assert (runs / "panorama-a.json").read_text() == "pool"
    assert (runs / "oracle-a.json").read_text() == "own"
    assert verify._out_runs(["placeclust", "leaderboard", "--out", "x"]) == Path("x/runs")
    assert verify._out_runs(["placeclust", "score", "x/results.json"]) is None


def test_timings_are_masked_and_figures_are_not():
    from docs.freshness.verify import comparable_text

    a = "| recognizer | success | core-seconds per building |\n|---|---|---|\n| x | 0.90 | 41 |"
    assert comparable_text(a) == comparable_text(a.replace("41", "57"))
    assert comparable_text(a) != comparable_text(a.replace("0.90", "0.93"))
    prose = "6 buildings; 16 minutes of one core in all. Success 0.58."
    assert comparable_text(prose) == comparable_text(prose.replace("16 minutes", "1 minute"))
    assert comparable_text(prose) != comparable_text(prose.replace("0.58", "0.68"))


def test_a_section_written_again_is_unrecorded_until_traced(repo_docs):
    docs, manifest = repo_docs
    write_section(docs, "table", "| a |\n|---|\n| 2 |", "placeclust demo --rooms 6")
    assert freshness.status(docs, manifest)["unrecorded"] == ["table"]
    assert freshness.main(["check", "--docs", str(docs), "--manifest", str(manifest)]) == 1


def test_every_cited_table_is_current_and_the_docs_list_what_differs():
    """The gate: change a function a cited table's command runs and this fails until the
    table is measured again (then ``python -m docs.freshness record --now NAME``) or its probe
    shows the same tables (``python -m docs.freshness verify NAME``); a dated record fails it
    only once a probe has shown it differs and the docs do not list it."""
    if not freshness.comparable():
        pytest.skip(f"fingerprints recorded with Python {freshness.load()['python']}")
    failed = {k: v for k, v in freshness.failing(freshness.status()).items() if v}
    assert not failed, failed


def test_every_cited_section_is_a_section_of_the_docs():
    assert set(freshness.CITED) <= set(freshness.sections())


def _probe(command, out="/tmp/x"):
    return shlex.join(probes.probe_argv(shlex.split(command), out))


def test_a_probe_is_the_sections_own_command_at_a_tiny_size():
    assert _probe("placeclust bench --quick --algos kmeans --conditions day --latency-sizes 10 "
                  "50 --param n_clusters=rooms --out runs/m --docs docs/benchmarks.md") == (
        "placeclust bench --quick --algos kmeans --conditions day --param n_clusters=rooms "
        "--scenes 0 --rooms 2 --tour-seeds 0 --steps-per-room 15 --latency-sizes --workers 1 "
        "--quiet --out /tmp/x")
    # a suite's buildings and size give way to one small val building; its agent stays
    assert _probe("placeclust leaderboard --suite placenav-v1 --size quick --agent ppo "
                  "--out runs/quick --docs docs/benchmarks.md") == (
        "placeclust leaderboard --agent ppo --split val --n-scenes 2 --rooms 2 "
        "--goals-per-scene 1 --tour-steps-per-room 25 --workers 1 --out /tmp/x")
    # what a suite fixes beyond its size is kept: placenav-v2's agent and tracks
    v2 = _probe("placeclust leaderboard --suite placenav-v2 --recognizers oracle none "
                "--out runs/v2 --docs docs/benchmarks.md")
    assert v2.startswith("placeclust leaderboard --agent relocalizer --track continued "
                         "changed-night changed-cloudy changed-moved carried corridor "
                         "corridor-carried --recognizers oracle none --split val")
    # a command that keeps its runs writes into the probe's folder, never reuses the default's
    assert _probe("placeclust like ../shared/data/rtabmap-loop --scenes 1000 1001 "
                  "--steps-per-room 50 --out runs/like --workers 1 --docs docs/benchmarks.md") == (
        "placeclust like ../shared/data/rtabmap-loop --scenes 1000 --rooms 2 "
        "--steps-per-room 10 --out /tmp/x")


def test_a_probe_writes_its_figure_beside_its_own_run_never_over_the_docs():
    # a traced score --calibration once drew a stand-in's curves over docs/images/
    command = ("placeclust score runs/v2-cal/continued/results.json --calibration "
               "docs/images/calibration_test.png --docs docs/benchmarks.md --section c")
    assert _probe(command, "/tmp/fr/c") == ("placeclust score runs/v2-cal/continued/results.json "
                                            "--calibration /tmp/fr/c-calibration_test.png")
    assert "docs/" not in " ".join(probes.probe_argv(shlex.split(command), None))


def test_a_command_that_reads_results_runs_what_wrote_them_or_a_stand_in(tmp_path):
    produced = {"runs/quick": "leaderboard-quick"}
    argv = shlex.split("placeclust compare runs/quick/results.json runs/other/changed-night/"
                       "results.json --a x --b y --docs docs/benchmarks.md")
    assert probes.inputs(argv, produced) == [("runs/quick/results.json", "runs/quick"),
                                             ("runs/other/changed-night/results.json", None)]
    assert probes.stand_in("runs/other/changed-night/results.json", tmp_path) == str(
        tmp_path / "stand-in" / "changed-night" / "results.json")
    runs = probes.stand_in_commands(["runs/v2/long/results.json", "runs/v2/carried/results.json"],
                                    tmp_path)  # long's own tours would take minutes traced
    assert [r[-1] for r in runs] == [str(tmp_path / "stand-in" / "long"),
                                     str(tmp_path / "stand-in" / "carried")]
    assert "--track" not in runs[0] and runs[1][runs[1].index("--track") + 1:][:1] == ["carried"]
    assert probes.stand_in("runs/suite/place/results.json", tmp_path) == str(
        tmp_path / "stand-in-plain" / "results.json")
    # a lone track: the leaderboard writes its results into --out itself, not a track folder
    lone = "runs/agents/corridor/place.json"
    (run,) = probes.stand_in_commands([lone], tmp_path)
    assert run[run.index("--track") + 1:][:1] == ["corridor"]
    assert str(Path(run[-1]) / "results.json") == probes.stand_in(lone, tmp_path)
    report = probes.substitute(["python", "-m", "train.report", "a=runs/x/a.json,runs/x/b.json",
                                "b=runs/quick/results.json@none"],
                               {"runs/x/a.json": "S/results.json", "runs/x/b.json": "S/r.json",
                                "runs/quick": "Q"})
    assert report[3:] == ["a=S/results.json@oracle,S/r.json", "b=Q/results.json@none"]


def test_a_command_that_reads_a_whole_run_folder_runs_what_wrote_it(tmp_path):
    """``like --against OUT`` reads another like run's folder, not a file in it. Fault
    caught: the folder taken for an unknown input (a stand-in's results.json, which the
    tiny run cannot read)."""
    commands = {"base": shlex.split("placeclust like data --out runs/base --docs d.md"),
                "lever": shlex.split("placeclust like data --textures photo --against runs/base "
                                     "--out runs/lever --docs d.md")}
    assert probes.inputs(commands["lever"], {"runs/base": "base"}) == [("runs/base",
                                                                        "runs/base")]
    base, lever = probes.probe_runs("lever", commands, tmp_path)
    assert base[-1] == str(tmp_path / "base")
    assert lever[lever.index("--against") + 1] == str(tmp_path / "base")


def test_a_suites_long_track_read_from_its_run_gets_a_stand_in(tmp_path):
    # the suite's tiny run leaves long out, so placeclust score over all eight tracks of a
    # suite run reads long's file from a stand-in and every other track's from that tiny run
    suite = "placeclust leaderboard --suite placenav-v2 --out runs/v2 --docs docs/benchmarks.md"
    files = " ".join(f"runs/v2/{t}/results.json" for t in probes.TRACK_NAMES)
    commands = {"leaderboard-v2": shlex.split(suite),
                "score-v2": shlex.split(f"placeclust score {files} --docs docs/benchmarks.md")}
    runs = probes.probe_runs("score-v2", commands, tmp_path)
    assert [r[-1] for r in runs[:2]] == [str(tmp_path / "leaderboard-v2"),
                                         str(tmp_path / "stand-in" / "long")]
    score = runs[-1]
    assert str(tmp_path / "stand-in" / "long" / "results.json") in score
    assert str(tmp_path / "leaderboard-v2" / "carried" / "results.json") in score


def test_a_stand_in_also_runs_the_recognizers_the_reader_names(tmp_path):
    # score --pair over a user's recognizer, from files no section writes: the stand-in must
    # run that recognizer too, or the tiny score has nothing to pair (and traces none of it)
    mine = "placeclust.online:OnlinePlaceClustering"
    files = " ".join(f"runs/x/{t}/results.json" for t in ("carried", "long"))
    commands = {"score-x": shlex.split(f"placeclust score {files} --pair {mine} panorama "
                                       "--docs docs/benchmarks.md")}
    runs = probes.probe_runs("score-x", commands, tmp_path)
    long, tracked = (r[r.index("--recognizers") + 1:r.index("--agent")] for r in runs[:2])
    assert long == ["oracle", "none", "panorama", "panorama-orb", mine]
    assert tracked == ["oracle", "none", "panorama", "panorama-orb", "oracle-noise:0.05", mine]
    folders = {Path(r[-1]).name for r in runs[:2]}
    assert folders == {"long", "carried"}  # the lone track runs into its own folder
    assert str(Path(runs[1][-1]) / "results.json") in runs[-1]
    assert Path(runs[1][-1]).parent.name != "stand-in"  # not where the plain stand-ins are kept
    plain = probes.probe_runs("s", {"s": shlex.split(f"placeclust score {files} --pair panorama "
                                                     "panorama-orb")}, tmp_path)
    assert mine not in plain[0] and Path(plain[1][-1]).parent.name == "stand-in"


def test_a_constant_counts_where_the_code_that_ran_can_reach_it_across_modules():
    from docs.freshness.syntax import _digests, _parse

    def digests(presets, other="UNUSED = 1\n"):
        trees = {"pkg/presets.py": _parse(presets + other),
                 "pkg/run.py": _parse("from .presets import FAST\n"
                                      "def run():\n    return FAST['k']\n")}
        return _digests(trees, {"pkg/run.py": ["run"], "pkg/presets.py": []})

    base = digests("FAST = {'k': 1}\n")
    assert digests("FAST = {'k': 2}\n") != base  # what run() reads, through the import
    assert digests("FAST = {'k': 1}\n", other="UNUSED = 2\nNEW = 3\n") == base


def test_a_section_measured_again_leaves_the_stale_list_until_it_is_written_anew(repo_docs):
    docs, manifest = repo_docs
    data = json.loads(manifest.read_text())
    data["sections"]["table"]["fingerprint"] = "older"
    data["differs"]["table"] = syntax.fingerprint(data["sections"]["table"]["trace"])
    data["sections"]["table"]["difference"] = "'1' → '2'"
    freshness.save(data, manifest)
    freshness.main(["check", "--write", "--docs", str(docs), "--manifest", str(manifest)])
    assert "| table | '1' → '2' |" in docs.read_text()
    data = json.loads(manifest.read_text())
    data["sections"]["table"]["fingerprint"] = syntax.fingerprint(
        data["sections"]["table"]["trace"])  # as `record` does once it is measured again
    del data["differs"]["table"]
    freshness.save(data, manifest)
    assert freshness.status(docs, manifest)["unlisted"] == ["table"]  # the docs still list it
    freshness.main(["check", "--write", "--docs", str(docs), "--manifest", str(manifest)])
    assert freshness.status(docs, manifest)["current"] == ["table"]
    assert "No table is known to differ" in docs.read_text()


@needs_cli
def test_record_traces_a_sections_command_and_check_then_finds_it_current(tmp_path):
    """End to end: a section written by `placeclust latency` is traced at its tiny size (in a
    process of its own), and what it ran includes the latency code and not the simulator's
    tours, which that command never runs."""
    docs, manifest = tmp_path / "benchmarks.md", tmp_path / "generated.json"
    write_section(docs, "latency", "| a |\n|---|\n| 1 |", "placeclust latency --docs x.md")
    freshness.record(["latency"], docs, manifest, tmp_path / "scratch", log=lambda _: None)
    entry = freshness.load(manifest)["sections"]["latency"]
    assert entry["probes"] == ["placeclust latency --sizes 4 8 --repeats 1"]
    assert entry["commit"] is None  # not committed: fingerprinted as the tree stands
    functions = entry["trace"]["functions"]
    assert "main" in functions["placeclust/latency.py"]
    assert "envs/tasks/tour.py" not in functions or "guided_tour" not in functions[
        "envs/tasks/tour.py"]
    assert freshness.status(docs, manifest)["current"] == ["latency"]
    # measured again with the same text: `--now` records it as the tree stands (trace kept)
    freshness.record(["latency"], docs, manifest, tmp_path / "scratch", log=lambda _: None,
                     now=True)
    assert freshness.load(manifest)["sections"]["latency"]["commit"] is None


def test_sections_of_one_command_share_the_trace_of_their_own_run(tmp_path, monkeypatch):
    ran = []

    def fake_run(cmd, **_):  # the traced process: writes an empty trace where it is told
        ran.append(cmd)
        Path(cmd[4]).write_text('{"functions": {}, "files": []}')
        return subprocess.CompletedProcess(cmd, 0, "", "")

    monkeypatch.setattr(probes.subprocess, "run", fake_run)
    board = "placeclust leaderboard --suite placenav-v2 --workers 1 --out".split()
    for name in ("leaderboard-v2-continued", "leaderboard-v2-carried"):
        probes.trace_command([*board, str(tmp_path / name)], tmp_path, read_by_none=True)
    assert len(ran) == 1  # their own runs differ only in where they write, which none reads
    probes.trace_command([*board, str(tmp_path / "read")], tmp_path)  # another reads it: run
    assert len(ran) == 2


@needs_cli
def test_a_tiny_run_that_fails_says_why_in_one_line(tmp_path):
    with pytest.raises(RuntimeError, match=r"failed: error: .*missing\.json: cannot read"):
        probes.trace_command(["placeclust", "compare", str(tmp_path / "missing.json"),
                              str(tmp_path / "missing.json"), "--a", "x", "--b", "y"], tmp_path)


def test_a_probes_own_scratch_folder_is_no_difference(tmp_path):
    """Fault caught: a figure's path under each checkout's scratch folder (``score
    --calibration``) made two identical tables differ."""
    from docs.freshness.verify import _in_place

    line = "Curves: `{}/calibration.png`. Resolution: noise 0.05."
    then, now = tmp_path / "then" / "c0ffee", tmp_path / "now"
    assert _in_place(line.format(then), then) == _in_place(line.format(now), now)
    assert _in_place(line.format(now), now) != _in_place(
        line.format(now).replace("0.05", "0.10"), now)
