"""``python -m docs.renderers``: the same figures drawn by two renderers, paired."""

import csv
import json

from docs import renderers
from envs.runs.results import write_results

PROVENANCE = {"suite": "placenav-v4", "size": "full", "buildings": "suite", "definition": {},
              "versions": {"placeclust": "0.19.0", "mujoco": "4.0.0"},
              "render_fingerprint": "abc", "physics_fingerprint": "fed"}


def _row(recognizer, scene, successes):
    errands = [{"goal": "a", "success": bool(s), "steps": 100 if s else 500, "path": 5.0,
                "shortest": 4.0, "spl": 0.8 * s, "redrawn": False, "final_distance": 1.0}
               for s in successes]
    return {"scene_seed": scene, "recognizer": recognizer, "agent": "spot",
            "success_rate": sum(successes) / len(successes), "errands": errands,
            "precision": 0.9, "nmi": 0.8, "n_places": 8, "places_per_room": 1.3, "seconds": 1.0}


def _track(folder, track, rows, names):
    settings = {"split": "test", "scene_seeds": [0, 1, 2, 3], "rooms": 6, "n_errands": 4,
                "seed": 0, "agent": "spot", "task": {}, "track": track}
    (folder / track).mkdir(parents=True)
    write_results(folder / track / "results.json", rows, names, settings, PROVENANCE)


def _bench(path, shift):
    rows = [{"algo": "online", "features": "sift", "params": "", "scene_seed": s,
             "world_rooms": rooms, "tour_seed": 0, "precision": 0.9 + shift * (1 + s % 2),
             "nmi": 0.8, "n_places": 8, "n_rooms": rooms}
            for s in range(4) for rooms in (4, 8)]
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _demo(folder, places):
    metrics = {row: {"precision": 0.9, "nmi": 0.8, "n_places": places}
               for row in renderers.DEMO_ROWS}
    (folder / "demo").mkdir(parents=True)
    (folder / "demo" / "metrics.json").write_text(json.dumps(metrics))


def test_the_section_pairs_each_figure_and_names_those_that_move(tmp_path, capsys):
    store, out = tmp_path / "placenav-v4", tmp_path / "renderers"
    for track in ("continued", "carried"):
        rows = [_row(name, s, ok) for s in range(4) for name, ok in (
            ("none", [0, 0, 0, 0]), ("oracle-pose", [1, 1, 1, 1]),
            ("panorama-orb", [1, 0, 1, 0]))]
        _track(store, track, rows, ["none", "oracle-pose", "panorama-orb"])
        _track(out / "sse41" / "placenav-v4", track,
               [_row("panorama-orb", s, [1, 1, 1, 0]) for s in range(4)], ["panorama-orb"])
    _demo(out / "native", 6)
    _demo(out / "sse41", 5)
    _bench(out / "native" / "bench" / "results.csv", 0.0)
    _bench(out / "sse41" / "bench" / "results.csv", 0.05)
    docs = tmp_path / "benchmarks.md"
    assert renderers.main([str(out), "--store", str(store), "--docs", str(docs)]) == 0
    text = capsys.readouterr().out
    assert "| `PANORAMA` | 0.900 / 0.800 / 6 | 0.900 / 0.800 / 5 | no |" in text
    # precision moved by 0.05 on half the buildings, 0.10 on the others: outside the native
    # interval; no parameters are the paper's preset
    assert ("| online, sift, paper | precision | 0.900 [0.900, 0.900] | 0.975 | "
            "0.075 [0.050, 0.100] | no |") in text
    assert ("| online, sift, paper | nmi | 0.800 [0.800, 0.800] | 0.800 | 0.000 [0.000, 0.000] "
            "| yes |") in text
    # success 0.50 natively, 0.75 by the second renderer: 0.25 over a ceiling-floor of 1
    assert "panorama-orb (sse4.1) − panorama-orb on the suite score: 0.250 [0.250, 0.250]" in text
    assert ("outside the native figure's 95% interval: online, sift, paper precision (0.900 "
            "against 0.975); panorama-orb's suite score (0.50 against 0.75)") in text
    assert "python -m docs.renderers" in docs.read_text()


def test_a_folder_without_the_runs_is_one_line(tmp_path, capsys):
    assert renderers.main([str(tmp_path)]) == 2
    assert capsys.readouterr().err.count("\n") == 1
