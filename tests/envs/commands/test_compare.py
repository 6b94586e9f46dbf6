"""``placeclust compare``: two recognizers paired on the same buildings, or refused."""

import copy
import json

import pytest

from envs.commands import compare
from envs.runs.results import load_results, write_results

PROVENANCE = {"suite": "placenav-v1", "size": "quick", "buildings": "suite", "definition": {},
              "versions": {"placeclust": "0.13.0", "mujoco": "4.0.0"},
              "render_fingerprint": "abc", "physics_fingerprint": "fed"}
SETTINGS = {"split": "test", "scene_seeds": [0, 1, 2, 3], "rooms": 6, "n_errands": 4, "seed": 0,
            "agent": "planner", "task": {}}


def _row(recognizer, scene, successes, precision):
    errands = [{"goal": "a", "success": bool(s), "steps": 100 if s else 500, "path": 5.0,
                "shortest": 4.0, "spl": 0.8 * s, "redrawn": False} for s in successes]
    return {"scene_seed": scene, "recognizer": recognizer, "agent": "planner",
            "success_rate": sum(successes) / len(successes), "errands": errands,
            "precision": precision, "nmi": precision - 0.1, "n_places": 8,
            "places_per_room": 1.3, "seconds": 1.0}


@pytest.fixture
def results(tmp_path):
    """One file with a good and a poor recognizer on four buildings."""
    rows = [_row("good", s, [1, 1, 1, 1], 0.99) for s in range(4)]
    rows += [_row("poor", s, [1, 0, 0, 0], 0.80 + 0.01 * s) for s in range(4)]
    path = tmp_path / "results.json"
    write_results(path, rows, ["good", "poor"], SETTINGS, PROVENANCE)
    return path


def test_compare_prints_the_paired_table_and_the_verdict(results, capsys):
    assert compare.main([str(results), str(results), "--a", "good", "--b", "poor"]) == 0
    out = capsys.readouterr().out
    assert ("| success_rate | 1.000 [1.000, 1.000] | 0.250 [0.250, 0.250] | 0.750 [0.750, 0.750] "
            "| 0.88 [0.88, 0.88] |") in out
    assert "good succeeds more often than poor" in out and "FLAG" not in out
    assert "read it as a pilot" in out  # 4 buildings: too few to decide on
    docs = results.parent / "benchmarks.md"
    compare.main([str(results), str(results), "--a", "good", "--b", "poor", "--docs", str(docs)])
    assert "BEGIN GENERATED compare-good-poor" in docs.read_text()
    assert "Paired on 4 buildings (scene seeds 0–3)" in docs.read_text()
    compare.main([str(results), str(results), "--a", "good", "--b", "poor", "--docs", str(docs),
                  "--section", "compare-full"])
    assert docs.read_text().count("| success_rate | 1.000 [1.000, 1.000] | 0.250") == 2


def test_compare_says_when_the_sample_cannot_decide(results, capsys):
    doc = load_results(results)
    for row in doc["buildings"]:  # in building 0 poor now wins outright: no decision
        if row["scene_seed"] == 0:
            for e in row["errands"]:
                e["success"] = row["recognizer"] == "poor"
    results.write_text(json.dumps(doc))
    compare.main([str(results), str(results), "--a", "good", "--b", "poor"])
    assert "cannot decide" in capsys.readouterr().out


@pytest.mark.parametrize(("field", "value", "message"), [
    (("provenance", "suite"), "placenav-v2", "suite: placenav-v1 against placenav-v2"),
    (("provenance", "render_fingerprint"), "def", "render_fingerprint: abc against def"),
    (("provenance", "physics_fingerprint"), "cba", "physics_fingerprint: fed against cba"),
    (("settings", "n_errands"), 5, "settings n_errands: 4 against 5"),
    (("provenance", "buildings"), "named", "buildings: suite against named"),
])
def test_results_from_another_suite_or_render_are_refused_or_flagged(
        results, tmp_path, capsys, field, value, message):
    other = copy.deepcopy(load_results(results))
    other[field[0]][field[1]] = value
    path = tmp_path / "other.json"
    path.write_text(json.dumps(other))
    argv = [str(results), str(path), "--a", "good", "--b", "poor"]
    assert compare.main(argv) == 2
    err = capsys.readouterr().err
    assert "not comparable" in err and message in err
    assert compare.main([*argv, "--force"]) == 0
    assert f"FLAG {message}" in capsys.readouterr().out


def test_compare_names_what_it_needs(results, tmp_path, capsys):
    assert compare.main([str(results), str(results)]) == 2
    assert "name one with --a" in capsys.readouterr().err
    assert compare.main([str(results), str(results), "--a", "good", "--b", "psychic"]) == 2
    assert "no recognizer 'psychic'" in capsys.readouterr().err
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    assert compare.main([str(bad), str(results), "--b", "poor"]) == 2
    assert "not a placeclust-results/2 results file" in capsys.readouterr().err


def test_one_recognizer_under_two_agents_is_compared_by_agent(results, tmp_path, capsys):
    other = copy.deepcopy(load_results(results))
    other["settings"]["agent"] = "ppo"
    path = tmp_path / "ppo.json"
    path.write_text(json.dumps(other))
    assert compare.main([str(results), str(path), "--a", "good", "--b", "good"]) == 0
    out = capsys.readouterr().out
    assert "A: good (planner)" in out and "B: good (ppo)" in out and "FLAG" not in out


def test_two_policies_of_one_agent_are_compared_by_their_run_folders(results, tmp_path,
                                                                       capsys):
    a, b = copy.deepcopy(load_results(results)), copy.deepcopy(load_results(results))
    for doc, run in ((a, "carried_place"), (b, "carried_oracle")):
        doc["settings"].update(agent="ppo", policy=f"runs/train/{run}/policy.zip")
    paths = [tmp_path / "a.json", tmp_path / "b.json"]
    for doc, path in zip((a, b), paths, strict=True):
        path.write_text(json.dumps(doc))
    assert compare.main([*map(str, paths), "--a", "good", "--b", "good"]) == 0
    out = capsys.readouterr().out
    assert "A: good (carried_place)" in out and "B: good (carried_oracle)" in out
    assert "FLAG" not in out


def test_one_recognizer_after_short_and_long_tours_is_compared_by_size(results, tmp_path,
                                                                        capsys):
    other = copy.deepcopy(load_results(results))
    other["provenance"]["size"] = "long"
    other["settings"]["task"] = {"tour_steps_per_room": 500}
    path = tmp_path / "long.json"
    path.write_text(json.dumps(other))
    docs = tmp_path / "benchmarks.md"
    argv = [str(path), str(results), "--a", "good", "--b", "good", "--force",
            "--docs", str(docs)]
    assert compare.main(argv) == 0
    out = capsys.readouterr().out
    assert "A: good (long)" in out and "B: good (quick)" in out
    assert "suite placenav-v1 (long and quick)" in out
    # what --force let through is said in the docs too, not only on the terminal
    assert "compared anyway (--force): size: long against quick" in docs.read_text()


def test_one_recognizer_with_its_map_fixed_is_compared_by_whether_it_learns(results, tmp_path,
                                                                            capsys):
    """A suite run against a run of no suite with ``--localize-only``: the sides are named by
    what differs in the map, not by a size one of them does not have."""
    other = copy.deepcopy(load_results(results))
    other["provenance"].update(suite=None, size=None)
    other["settings"]["task"] = {"errand_learn": False}
    path = tmp_path / "fixed.json"
    path.write_text(json.dumps(other))
    assert compare.main([str(results), str(path), "--a", "good", "--b", "good", "--force"]) == 0
    out = capsys.readouterr().out
    assert "A: good (learning)" in out and "B: good (map fixed)" in out
    assert "(None)" not in out and "FLAG" in out


def test_buildings_pair_by_seed_whatever_their_order_and_only_where_shared(tmp_path, capsys):
    # A on buildings 0-5 in one order, B on 2-7 in another: pairs are 2-5, building by building
    rows_a = [_row("a", s, [1, 1, 0, 0] if s % 2 else [1, 1, 1, 1], 0.9) for s in (5, 0, 3, 1,
                                                                                   4, 2)]
    rows_b = [_row("b", s, [1, 0, 0, 0] if s % 2 else [1, 1, 1, 0], 0.9) for s in (7, 2, 6, 5,
                                                                                   3, 4)]
    paths = []
    for name, rows, seeds in (("a", rows_a, [5, 0, 3, 1, 4, 2]), ("b", rows_b, [7, 2, 6, 5, 3,
                                                                                   4])):
        paths.append(tmp_path / f"{name}.json")
        write_results(paths[-1], rows, [name], {**SETTINGS, "scene_seeds": seeds}, PROVENANCE)
    ra, rb = compare.paired_rows(load_results(paths[0]), load_results(paths[1]), "a", "b")
    assert [r["scene_seed"] for r in ra] == [r["scene_seed"] for r in rb] == [2, 3, 4, 5]
    assert compare.main([*map(str, paths), "--force"]) == 0
    out = capsys.readouterr().out
    # per shared building a − b: +0.25 (even) and +0.25 (odd): 0.250 with no spread
    assert "Paired on 4 buildings (scene seeds 2–5)" in out
    assert "| success_rate | 0.750 [0.500, 1.000] | 0.500 [0.250, 0.750] | 0.250 [0.250, 0.250]" \
        in out


def test_a_difference_whose_interval_straddles_zero_is_undecided(tmp_path, capsys):
    # twelve buildings where a and b take turns to win: their difference's interval holds 0
    rows = []
    for s in range(12):
        wins = s % 2 == 0
        rows.append(_row("a", s, [1, 1, 1, 0] if wins else [1, 0, 0, 0], 0.9))
        rows.append(_row("b", s, [1, 0, 0, 0] if wins else [1, 1, 1, 0], 0.9))
    path = tmp_path / "r.json"
    write_results(path, rows, ["a", "b"], {**SETTINGS, "scene_seeds": list(range(12))},
                  PROVENANCE)
    assert compare.main([str(path), str(path), "--a", "a", "--b", "b"]) == 0
    out = capsys.readouterr().out
    line = next(li for li in out.splitlines() if li.startswith("| success_rate"))
    low, high = (float(x) for x in line.split("|")[4].split("[")[1].rstrip("] ").split(","))
    assert low < 0 < high
    assert "cannot decide between a and b" in out and "read it as a pilot" not in out


def test_a_file_without_a_physics_fingerprint_is_refused_and_versions_are_noted(
        results, tmp_path, capsys):
    older = copy.deepcopy(load_results(results))
    del older["provenance"]["physics_fingerprint"]  # as files written before it was recorded
    older["provenance"]["versions"].update(placeclust="0.14.0", mujoco="3.17.0")
    path = tmp_path / "older.json"
    path.write_text(json.dumps(older))
    argv = [str(results), str(path), "--a", "good", "--b", "poor"]
    assert compare.main(argv) == 2
    assert "physics_fingerprint: fed against not recorded" in capsys.readouterr().err
    assert compare.main([*argv, "--force"]) == 0
    out = capsys.readouterr().out
    assert "note: mujoco 4.0.0 against 3.17.0" in out
    assert "note: placeclust 0.13.0 against 0.14.0" in out


def test_plan_sizes_the_success_difference_from_the_sample(results, capsys):
    doc = load_results(results)
    for row in doc["buildings"]:  # buildings now disagree on how much better good is
        if row["recognizer"] == "poor" and row["scene_seed"] % 2:
            for e in row["errands"]:
                e["success"] = True
    results.write_text(json.dumps(doc))
    argv = [str(results), str(results), "--a", "good", "--b", "poor", "--plan", "4", "40",
            "--plan-buildings", "12"]
    assert compare.main(argv) == 0
    out = capsys.readouterr().out
    # half the buildings differ by 0 and half by 0.75 (variance 0.156 between them, 0.031
    # from 4 errands): ten times the errands saves 2 of 11 buildings, by hand from the formula
    assert "if it is +0.375, buildings needed at 4, 40 errands a building: 11 at 4, 9 at 40" in out
    assert "At 12 buildings the half-width would be" in out
    assert compare.main([str(results), str(results), "--a", "good", "--b", "poor"]) == 0
    assert "Sizing" not in capsys.readouterr().out


@pytest.mark.parametrize(("value", "message"), [("0", "must be a positive count, got 0"),
                                                ("abc", "not a count: 'abc'")])
def test_plan_needs_positive_counts(results, capsys, value, message):
    with pytest.raises(SystemExit) as stop:
        compare.main([str(results), str(results), "--a", "good", "--b", "poor", "--plan", value])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert f"argument --plan: {message}" in err and len(err.strip().splitlines()) == 1


def test_an_old_results_file_is_read_with_todays_names(results, tmp_path, capsys):
    """Before 0.19.0 the errand count was ``goals`` (a summary's ``errands``): such a file
    still pairs with today's, nothing flagged."""
    old = json.loads(results.read_text())
    old["format"] = "placeclust-results/1"
    old["settings"]["goals"] = old["settings"].pop("n_errands")
    for summary in old["summaries"]:
        summary["errands"] = summary.pop("n_errands")
    del old["provenance"]["buildings"]
    old["settings"]["task"] = {"tour_steps_per_room": 150, "success_radius": 1.0}  # defaults
    path = tmp_path / "old.json"
    path.write_text(json.dumps(old))
    doc = load_results(path)
    assert doc["settings"]["n_errands"] == 4 and doc["provenance"]["buildings"] == "suite"
    assert doc["settings"]["task"] == {}  # written as today's: the defaults left out
    assert [s["n_errands"] for s in doc["summaries"]] == [16, 16]
    assert compare.main([str(results), str(path), "--a", "good", "--b", "poor"]) == 0
    assert "FLAG" not in capsys.readouterr().out
