"""Named splits of scene seeds: tune and train on ``train``, choose on ``val``, report on ``test``.

A building is its scene seed, so a split is a set of scene seeds. Settings chosen on the
scenes they are reported on say nothing about buildings never seen; every figure says the
split it comes from, and nothing is chosen on ``test``. The project's settings were tuned on
scenes 0–3, which lie in ``train``.

Examples:
    >>> from envs.splits import SPLITS, split_of, scenes
    >>> split_of(3), split_of(1500), split_of(2001), split_of(5000)
    ('train', 'val', 'test', None)
    >>> scenes("test")
    (2000, 2001, 2002, 2003)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from types import MappingProxyType

#: scene seeds of each split: ``train`` may be used for anything, ``val`` to choose among
#: candidates, ``test`` only to report
SPLITS: Mapping[str, range] = MappingProxyType({
    "train": range(0, 1000),
    "val": range(1000, 2000),
    "test": range(2000, 3000),
})

#: how many scenes a command takes from a split when no scene seeds are given
N_SCENES = 4


def split_of(scene_seed: int) -> str | None:
    """The name of the split that holds ``scene_seed``, or ``None`` for a seed in none of them
    (any seed may still be used, but its figures belong to no split)."""
    for name, seeds in SPLITS.items():
        if scene_seed in seeds:
            return name
    return None


def scenes(split: str, n: int = N_SCENES) -> tuple[int, ...]:
    """The first ``n`` scene seeds of ``split``: the buildings a command uses by default."""
    if split not in SPLITS:
        raise ValueError(f"unknown split {split!r}; choose one of {list(SPLITS)}")
    return tuple(SPLITS[split][:n])


def check_split(split: str, scene_seeds: Iterable[int]) -> None:
    """``ValueError`` naming the scene seeds that are not in ``split``."""
    if split not in SPLITS:
        raise ValueError(f"unknown split {split!r}; choose one of {list(SPLITS)}")
    outside = [s for s in scene_seeds if s not in SPLITS[split]]
    if outside:
        raise ValueError(f"scene seeds {outside} are not in the {split!r} split "
                         f"({SPLITS[split].start}-{SPLITS[split].stop - 1})")
