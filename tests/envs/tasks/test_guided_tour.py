import gymnasium as gym
import numpy as np
import pytest

from envs.tasks.guided_tour import GuidedTourEnv

SMALL = {"n_rooms": 3, "n_errands": 2, "tour_steps_per_room": 40, "errand_steps": 60}


@pytest.fixture
def make_tour(made):
    def _make(**kwargs):
        made.append(gym.make("PlaceNav-GuidedTour-v1", **{**SMALL, **kwargs}))
        return made[-1]

    return _make


def test_the_guide_names_every_room_once_and_the_map_is_scored(make_tour):
    env = make_tour(recognizer="oracle")
    obs, info = env.reset(seed=0)
    rooms = sorted(r.name for r in env.unwrapped.plan.rooms)
    assert sorted(info["tour"].heard_names()) == rooms == sorted(info["named"])
    tour = info["tour"]
    assert len(tour.place_id) == len(tour.heard) == len(tour.odometry) >= 3 * 40
    assert info["map"]["precision"] == 1.0 and info["map"]["nmi"] == pytest.approx(1.0)
    assert obs["goal"] in rooms and obs in env.observation_space
    assert "panorama" not in obs  # no ground truth and no image unless asked for


def test_errands_end_the_episode_with_their_outcomes(make_tour):
    env = make_tour(recognizer="oracle")
    obs, info = env.reset(seed=1)
    done, ends, steps = False, [], 0
    while not done:
        obs, reward, done, truncated, info = env.step(np.zeros(2, np.float32))
        steps += 1
        assert not truncated and np.isfinite(reward)
        if "errand_result" in info:
            ends.append(info["errand_result"])
    assert len(ends) == 2 and info["errands"] == ends and steps <= 2 * 60
    assert obs in env.observation_space  # the last observation too
    assert all(e["steps"] <= 60 and 0.0 <= e["spl"] <= 1.0 for e in ends)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(2, np.float32))


def test_the_same_seed_gives_the_same_tour_and_goals(make_tour):
    a, b = make_tour(recognizer="random", panorama_width=64, panorama_height=16), \
        make_tour(recognizer="random", panorama_width=64, panorama_height=16)
    (oa, ia), (ob, ib) = a.reset(seed=5), b.reset(seed=5)
    assert np.array_equal(ia["tour"].place_id, ib["tour"].place_id)
    assert oa["goal"] == ob["goal"] and ia["map"] == ib["map"]


def test_goals_must_be_rooms_the_guide_named(make_tour):
    env = make_tour(recognizer="oracle")
    names = [r.name for r in env.unwrapped.plan.rooms]
    obs, _ = env.reset(seed=0, options={"goals": [names[1], names[2]]})
    assert obs["goal"] == names[1]
    with pytest.raises(KeyError, match="unknown room"):
        env.reset(seed=0, options={"goals": ["ballroom"]})
    short = make_tour(recognizer="oracle", tour_steps_per_room=1, name_after=10)
    with pytest.raises(ValueError, match="never named on the tour"):
        short.reset(seed=0, options={"goals": names})


def test_a_recognizer_that_knows_nothing_gives_unknown_ids(make_tour):
    env = make_tour(recognizer="none", panorama_width=64, panorama_height=16)
    obs, info = env.reset(seed=0)
    unknown = env.unwrapped.max_places
    assert (info["tour"].place_id == -1).all() and obs["place_id"] == unknown
    assert info["map"]["n_places"] == 0


def test_seed_001_gets_its_forward_camera_and_bad_names_are_refused():
    env = GuidedTourEnv(recognizer="nested", **SMALL)
    try:
        assert env.nav.camera == "forward"
    finally:
        env.close()
    with pytest.raises(ValueError, match="unknown recognizer"):
        GuidedTourEnv(recognizer="psychic", **SMALL)
    with pytest.raises(ValueError, match="positive"):
        GuidedTourEnv(recognizer="oracle", n_errands=0)


def test_an_errand_starts_a_metre_or_more_of_walking_from_its_goal():
    from envs.runs.tour_errands import run_scene

    def errands(**kw):
        return run_scene(0, n_rooms=3, recognizer="oracle", n_errands=6, seed=0,
                         tour_steps_per_room=40, **kw)["errands"]

    near = errands(min_errand_distance=0.0)  # v0: the room behind the door just reached
    assert min(e["shortest"] for e in near) < 0.5 and not any(e["redrawn"] for e in near)
    far = errands()
    assert min(e["shortest"] for e in far) >= 1.0 and any(e["redrawn"] for e in far)
    with pytest.raises(ValueError, match="min_errand_distance"):
        GuidedTourEnv(recognizer="oracle", min_errand_distance=float("nan"))


def test_a_recognizer_that_reads_no_images_gets_none_rendered_and_the_same_ids(make_tour):
    from placeclust.null import RandomPlaces

    class Seeing(RandomPlaces):
        reads_images = True

    def episode(recognizer):
        env = make_tour(recognizer=recognizer)
        obs, info = env.reset(seed=3)
        done = False
        while not done:
            obs, _, done, _, step = env.step(np.array([0.6, 0.2], np.float32))
        return env, info["tour"].place_id, step["errands"]

    blind, ids, errands = episode(RandomPlaces(n_ids=6))
    seeing, seen_ids, seen_errands = episode(Seeing(n_ids=6))
    image = blind.unwrapped.nav.image_key
    assert image not in blind.unwrapped.nav.observation_space.spaces
    assert image in seeing.unwrapped.nav.observation_space.spaces
    assert np.array_equal(ids, seen_ids) and errands == seen_errands


def test_a_carried_robot_starts_each_errand_away_from_its_goal(make_tour):
    env = make_tour(recognizer="panorama-orb", errand_start="carried", n_errands=3,
                    errand_steps=5, panorama_width=128, panorama_height=32)
    obs, info = env.reset(seed=4)
    plan = env.unwrapped.plan
    starts, done = [(info["pose"], info["goal"])], False
    while not done:
        obs, _, done, _, info = env.step(np.zeros(2, np.float32))
        if "errand_result" in info and not done:
            starts.append((info["pose"], info["goal"]))
            assert obs in env.observation_space
    assert len(starts) == 3
    for pose, goal in starts:
        assert plan.room_at(pose[0], pose[1]) != plan.room_by_name(goal).id
    assert all(e["shortest"] >= 1.0 for e in info["errands"])
    assert len({tuple(np.round(p[:2], 3)) for p, _ in starts}) == 3  # put down, not driven


def test_carrying_needs_two_rooms_and_a_known_start():
    with pytest.raises(ValueError, match="errand_start must be one of"):
        GuidedTourEnv(recognizer="oracle", n_rooms=3, errand_start="teleport")
    with pytest.raises(ValueError, match="at least 2 rooms"):
        GuidedTourEnv(recognizer="oracle", n_rooms=1, errand_start="carried")


def test_errands_under_another_condition_see_it_from_their_first_frame(make_tour):
    small = {"panorama_width": 64, "panorama_height": 16, "observe_image": True}
    day = make_tour(recognizer="oracle", **small)
    night = make_tour(recognizer="oracle", errand_condition="night", **small)
    (o_day, i_day), (o_night, i_night) = day.reset(seed=2), night.reset(seed=2)
    # the same tour, the same map and goals: only the errands' world differs
    assert np.array_equal(i_day["tour"].place_id, i_night["tour"].place_id)
    assert o_day["goal"] == o_night["goal"]
    assert np.allclose(i_day["pose"], i_night["pose"], atol=1e-6)
    task = night.unwrapped
    assert task.nav is task.errand_nav and task.nav.scene.lighting == "night"
    assert o_night["panorama"].mean() < 0.8 * o_day["panorama"].mean()
    night.step(np.zeros(2, np.float32))
    night.reset(seed=3)  # the next tour is under the tour's light again
    assert task.tour_nav.scene.lighting == "day"


def test_moved_furniture_moves_the_obstacles_and_clears_the_robot(make_tour):
    env = make_tour(recognizer="oracle", errand_condition="moved")
    env.reset(seed=0)
    task = env.unwrapped
    tour, errands = task.tour_nav.plan.furniture, task.errand_nav.plan.furniture
    assert len(errands) < len(tour) or errands != tour  # moved and removed
    x, y, _ = task.nav.robot.pose(task.nav.data)
    assert all(abs(x - f.x) > f.hx or abs(y - f.y) > f.hy for f in errands)


def test_a_map_that_only_localizes_keeps_its_places(make_tour):
    env = make_tour(recognizer="placeclust.online:OnlinePlaceClustering",
                    recognizer_params={"features": "orb"}, errand_learn=False,
                    errand_condition="cloudy", panorama_width=128, panorama_height=32)
    _, info = env.reset(seed=0)
    n = env.unwrapped.recognizer.n_places
    done = False
    while not done:
        _, _, done, _, info = env.step(np.array([0.6, 0.3], np.float32))
    assert env.unwrapped.recognizer.n_places == n
    assert not env.unwrapped.places.wrapper.learn


def test_conditions_and_learning_are_checked_before_the_tour():
    with pytest.raises(ValueError, match="unknown errand_condition 'dusk'"):
        GuidedTourEnv(recognizer="oracle", n_rooms=3, errand_condition="dusk")
    with pytest.raises(ValueError, match="localize_one"):
        GuidedTourEnv(recognizer="examples.tiny_recognizer:HaarPlaces", n_rooms=3,
                      errand_learn=False)
    GuidedTourEnv(recognizer="random", n_rooms=3, errand_learn=False).close()  # no map to fix


def _trajectory(env, reset, steps=70):
    """Every step's place, pose, goal, reward and errand outcome under fixed actions."""
    obs, info = reset()
    seen = [(int(obs["place_id"]), obs["goal"], info["pose"].round(9).tolist())]
    rng = np.random.default_rng(0)
    for _ in range(steps):
        obs, reward, done, _, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        seen.append((int(obs["place_id"]), obs["goal"], info["pose"].round(9).tolist(), reward,
                     obs["odometry"].tolist(), info.get("errand_result")))
        if done:
            break
    return seen


@pytest.mark.parametrize("recognizer", ["panorama-orb", "oracle-noise:0.2"])
def test_one_tour_serves_the_errands_of_another_track(make_tour, recognizer):
    small = {"panorama_width": 128, "panorama_height": 32, "errand_steps": 20, "n_errands": 3}
    toured = make_tour(recognizer=recognizer, **small)
    _, info = toured.reset(seed=6)
    state = toured.unwrapped.tour_state()
    places = state.recognizer.n_places if state.recognizer else None
    # the same building's carried errands, from that tour, and from a tour of their own:
    # the same errands step for step (carries, goals, odometry, the noisy oracle's draws)
    resumed = make_tour(recognizer=recognizer, errand_start="carried", **small)
    fresh = make_tour(recognizer=recognizer, errand_start="carried", **small)
    from_state = _trajectory(resumed, lambda: resumed.reset(seed=6, options={"tour": state}))
    assert from_state == _trajectory(fresh, lambda: fresh.reset(seed=6))
    assert sum(1 for s in from_state[1:] if s[-1]) == 3  # three errands, two carries between
    # and the toured env's own continued errands, from the state again in another env
    again = make_tour(recognizer=recognizer, **small)
    assert (_trajectory(again, lambda: again.reset(seed=6, options={"tour": state}))
            == _trajectory(toured, lambda: toured.reset(seed=6)))
    if places is not None:  # the state is a copy, left as it was by every errand above
        assert resumed.unwrapped.recognizer is not state.recognizer
        assert state.recognizer.n_places == places


def test_a_tour_state_goes_on_only_in_its_own_building(make_tour):
    toured = make_tour(recognizer="oracle")
    toured.reset(seed=6)
    state = toured.unwrapped.tour_state()
    with pytest.raises(ValueError, match="another kind of recognizer"):
        make_tour(recognizer="random").reset(seed=6, options={"tour": state})
    with pytest.raises(ValueError, match="cannot go on in"):
        make_tour(recognizer="oracle", scene_seed=7).reset(seed=6, options={"tour": state})
    with pytest.raises(RuntimeError, match="no tour yet"):
        make_tour(recognizer="oracle").unwrapped.tour_state()
