import numpy as np
import pytest

from envs.tasks.oracles import TrueRooms, is_oracle_name, parse_oracle
from envs.tasks.recognizers import check_recognizer_name, is_own, make_recognizer
from envs.world.layout import generate_floor_plan
from placeclust.metrics import score


@pytest.fixture(scope="module")
def plan():
    return generate_floor_plan(6, np.random.default_rng(3))


def _walk(plan, n=4000, seed=0):
    """Random poses inside the rooms, with their true rooms."""
    rng = np.random.default_rng(seed)
    rooms = rng.integers(len(plan.rooms), size=n)
    poses = [(rng.uniform(plan.rooms[r].x0, plan.rooms[r].x1),
              rng.uniform(plan.rooms[r].y0, plan.rooms[r].y1), 0.0) for r in rooms]
    return rooms, poses


def test_the_plain_oracle_is_the_true_room(plan):
    truth = parse_oracle("oracle").bind(plan, seed=0)
    rooms, poses = _walk(plan)
    assert [truth.place(int(r), p) for r, p in zip(rooms, poses)] == rooms.tolist()
    assert truth.place(-1, poses[0]) == -1  # a doorway is unknown


@pytest.mark.parametrize("k", [1, 2, 3, 1.5, 2.4])
def test_split_gives_k_places_per_room_and_never_mixes_rooms(plan, k):
    truth = TrueRooms(split=k).bind(plan, seed=1)
    rooms, poses = _walk(plan)
    ids = np.array([truth.place(int(r), p) for r, p in zip(rooms, poses)])
    s = score(ids, rooms)
    assert s["precision"] == 1.0
    assert truth.n_places == truth.parts.sum() == len(set(ids.tolist()))
    assert set(truth.parts.tolist()) <= {int(np.floor(k)), int(np.ceil(k))}
    if k == int(k):
        assert truth.n_places == k * len(plan.rooms)


def test_the_mean_parts_of_a_fractional_split_is_its_value():
    plan = generate_floor_plan(24, np.random.default_rng(0))
    means = [TrueRooms(split=1.5).bind(plan, seed=s).parts.mean() for s in range(20)]
    assert np.mean(means) == pytest.approx(1.5, abs=0.05)


@pytest.mark.parametrize("p", [0.05, 0.2, 0.5])
def test_noise_wrongs_that_fraction_of_frames_in_bursts(plan, p):
    truth = TrueRooms(noise=p).bind(plan, seed=2)
    rooms, poses = _walk(plan, n=20_000)
    ids = np.array([truth.place(int(r), pose) for r, pose in zip(rooms, poses)])
    wrong = ids != rooms
    assert wrong.mean() == pytest.approx(p, abs=0.03)
    assert set(ids.tolist()) <= set(range(len(plan.rooms)))
    # wrong answers come in bursts of `hold` frames: starts are a tenth of the wrong frames
    starts = np.flatnonzero(wrong[1:] & ~wrong[:-1])
    assert len(starts) < 0.2 * wrong.sum()


def test_merge_joins_neighbouring_rooms_only(plan):
    full = TrueRooms(merge=1.0).bind(plan, seed=0)
    assert full.n_places == 1  # every room is connected through doors
    half = TrueRooms(merge=0.5).bind(plan, seed=0)
    rooms, poses = _walk(plan)
    ids = np.array([half.place(int(r), p) for r, p in zip(rooms, poses)])
    assert 1 <= half.n_places < len(plan.rooms)
    graph = plan.graph()
    for place in set(ids.tolist()):  # a merged place is rooms joined through doors
        members = sorted(set(rooms[ids == place].tolist()))
        assert len(members) == 1 or all(any(graph.has_edge(a, b) for b in members if b != a)
                                         for a in members)


def test_the_same_seed_gives_the_same_answers(plan):
    rooms, poses = _walk(plan, n=500)
    runs = [[TrueRooms(noise=0.3, split=1.5, merge=0.3).bind(plan, seed=7).place(int(r), p)
             for r, p in zip(rooms, poses)] for _ in range(2)]
    assert runs[0] == runs[1]


def test_names_parse_and_name_back():
    for name in ("oracle", "oracle-noise:0.05", "oracle-split:2.4", "oracle-merge:0.3"):
        assert is_oracle_name(name) and not is_own(name)
        assert parse_oracle(name).name == name
        check_recognizer_name(name)
        assert isinstance(make_recognizer(name, 6), TrueRooms)
    assert is_own("examples.tiny_recognizer:HaarPlaces")
    assert not is_oracle_name("oracle-noise:") and not is_oracle_name("oracles")


@pytest.mark.parametrize("name, match", [("oracle-noise:1.5", "noise"),
                                         ("oracle-split:0.5", "split"),
                                         ("oracle-blur:0.1", "oracle-KIND:VALUE")])
def test_bad_calibration_names_say_what_is_wrong(name, match):
    with pytest.raises(ValueError, match=match):
        check_recognizer_name(name)


def test_a_calibration_name_says_its_kind_and_size_of_error():
    from envs.tasks.oracles import error_of

    assert error_of("oracle-noise:0.05") == ("noise", 0.05)
    assert error_of("oracle-split:2") == ("split", 2.0)
    assert error_of("oracle") is None and error_of("panorama") is None
    assert error_of("mypackage.module:Mine") is None


@pytest.mark.parametrize("k", [2, 4, 6])
def test_cells_cut_each_room_into_k_compact_places(plan, k):
    truth = TrueRooms(cells=k).bind(plan, seed=0)
    rooms, poses = _walk(plan)
    ids = np.array([truth.place(int(r), p) for r, p in zip(rooms, poses)])
    assert score(ids, rooms)["precision"] == 1.0 and truth.n_places == k * len(plan.rooms)
    for room in plan.rooms:  # compact: no cell much longer than it is wide
        for cell in set(ids[rooms == room.id].tolist()):
            xy = np.array([p[:2] for p, i in zip(poses, ids) if i == cell])
            w, h = np.ptp(xy, axis=0)
            side = min(room.x1 - room.x0, room.y1 - room.y0)
            assert max(w, h) <= max(2.2 * min(w, h), side * 1.01)


def test_door_lag_reports_the_room_left_until_the_robot_is_far_enough_in(plan):
    door = plan.doors[0]
    a, b = door.rooms
    truth = TrueRooms(door=1.0).bind(plan, seed=0)
    ca, cb = plan.rooms[a].center, plan.rooms[b].center
    assert truth.place(a, (*ca, 0.0)) == a
    near = np.add((door.x, door.y), 0.5 * np.subtract(cb, (door.x, door.y))
                  / np.linalg.norm(np.subtract(cb, (door.x, door.y))))
    assert truth.place(b, (*near, 0.0)) == a  # 0.5 m past the door: still the room left
    far = np.add((door.x, door.y), 1.5 * np.subtract(cb, (door.x, door.y))
                 / np.linalg.norm(np.subtract(cb, (door.x, door.y))))
    if plan.room_at(*far) == b:
        assert truth.place(b, (*far, 0.0)) == b
    assert truth.place(b, (*near, 0.0)) == b  # the lag ended: it does not come back
    truth.reset_position()
    assert truth.place(b, (*near, 0.0)) == b  # carried there: no room was left


def test_a_revisit_opens_a_place_of_its_own(plan):
    truth = TrueRooms(revisit=1.0).bind(plan, seed=0)
    a, b = plan.rooms[0].center, plan.rooms[1].center
    first = truth.place(0, (*a, 0.0))
    assert truth.place(1, (*b, 0.0)) == 1
    again = truth.place(0, (*a, 0.0))
    assert first == 0 and again >= truth.n_places  # a new id, beyond the rooms' own
    assert truth.place(0, (*a, 0.0)) == again  # for the whole visit
    assert truth.goal(0, (*a, 0.0)) == 0  # a goal picture gets the room's own place


def test_the_new_kinds_parse_and_name_back():
    from envs.tasks.oracles import error_of

    for name in ("oracle-cells:4", "oracle-door:0.5", "oracle-revisit:0.3", "oracle-pose"):
        assert is_oracle_name(name) and parse_oracle(name).name == name
        check_recognizer_name(name)
    assert parse_oracle("oracle-pose").pose and error_of("oracle-pose") is None
    assert error_of("oracle-cells:4") == ("cells", 4.0)
    with pytest.raises(ValueError, match="door"):
        parse_oracle("oracle-door:9")
