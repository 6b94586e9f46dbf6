"""Named splits of scene seeds: tune and train on ``train``, choose on ``val``, report on ``test``.

A building is its scene seed, so a split is a set of scene seeds. Settings chosen on the
scenes they are reported on say nothing about buildings never seen; every figure says the
split it comes from, and nothing is chosen on ``test``. The project's settings were tuned on
scenes 0–3, which lie in ``train``.

Examples:
    >>> from envs.world.splits import SPLITS, split_of, scenes
    >>> split_of(3), split_of(1500), split_of(2001), split_of(5000)
    ('train', 'val', 'test', None)
    >>> scenes("test")
    (2000, 2001, 2002, 2003)
"""

from __future__ import annotations

import argparse
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


def add_scope_arguments(parser: argparse.ArgumentParser, n_scenes: int = N_SCENES,
                        default_split: str | None = None) -> None:
    """Give a command ``--split NAME | --scene-seeds S ...`` and ``--n-scenes N``.

    Read them back with :func:`scope_seeds`. Without ``default_split`` one of the two is
    required.
    """
    where = parser.add_mutually_exclusive_group(required=default_split is None)
    where.add_argument("--split", choices=list(SPLITS), default=default_split,
                       help="take the first --n-scenes buildings of this split")
    where.add_argument("--scene-seeds", type=int, nargs="+", metavar="SEED",
                       help="these buildings (their figures belong to no split)")
    parser.add_argument("--n-scenes", type=int, default=n_scenes,
                        help=f"buildings taken from --split (default {n_scenes})")


def scope_seeds(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[int]:
    """The scene seeds :func:`add_scope_arguments`' arguments name.

    Sets ``args.split`` to None when ``--scene-seeds`` was given; a bad ``--n-scenes`` is a
    parser error (exit 2).

    Examples:
        >>> import argparse
        >>> from envs.world.splits import add_scope_arguments, scope_seeds
        >>> parser = argparse.ArgumentParser()
        >>> add_scope_arguments(parser, n_scenes=2)
        >>> scope_seeds(parser.parse_args(["--split", "val"]), parser)
        [1000, 1001]
        >>> args = parser.parse_args(["--scene-seeds", "7", "2001"])
        >>> scope_seeds(args, parser), args.split
        ([7, 2001], None)
    """
    if args.scene_seeds:
        args.split = None
        return list(args.scene_seeds)
    if args.n_scenes < 1:
        parser.error(f"--n-scenes must be positive, got {args.n_scenes}")
    return list(scenes(args.split, args.n_scenes))
