import pytest

from envs.world.splits import SPLITS, check_split, scenes, split_of


def test_splits_are_disjoint_and_hold_the_tuning_scenes_in_train():
    seen = [set(r) for r in SPLITS.values()]
    assert not set.intersection(*seen)
    assert all(split_of(s) == "train" for s in range(4))  # the scenes the settings were tuned on


def test_every_split_gives_its_first_scenes_and_refuses_others():
    for name in SPLITS:
        assert all(split_of(s) == name for s in scenes(name))
    with pytest.raises(ValueError, match=r"\[5\] are not in the 'test' split"):
        check_split("test", [2000, 5])
    with pytest.raises(ValueError, match="unknown split 'dev'"):
        scenes("dev")
    assert split_of(10**6) is None  # usable, but in no split
