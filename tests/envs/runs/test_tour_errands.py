from envs.runs.tour_errands import run_scene

TINY = {"n_rooms": 3, "n_errands": 3, "recognizer": "oracle", "agent": "relocalizer",
        "tour_steps_per_room": 40, "errand_steps": 120, "panorama_width": 64,
        "panorama_height": 16}


def _errands(row):
    return [(e["goal"], e["steps"], e["success"]) for e in row["errands"]]


def test_a_track_gives_the_same_errands_alone_and_beside_other_tracks():
    # one tour serving several tracks must not change any track's errands: the suite runs
    # tracks together, a user checks one alone
    tracks = {"continued": {}, "carried": {"errand_start": "carried"}}
    shared = run_scene(4, tracks=tracks, **TINY)["tracks"]
    assert _errands(shared["carried"]) == _errands(run_scene(4, errand_start="carried", **TINY))
    assert _errands(shared["continued"]) == _errands(run_scene(4, **TINY))
    assert shared["carried"]["errands"] != shared["continued"]["errands"]
