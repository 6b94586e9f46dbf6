"""How alike the places of an image sequence look to local features, simulated or real.

    python -m placeclust.imagestats --images DIR [DIR ...] [--tour tour.npz ...] [--stride K]
    placeclust stats [...]    # the same, from the simulator's command line

A place recognizer tells places apart by how many local features two images share. This
module measures, for any sequence of frames: how many keypoints a frame yields, how many
features the next frame matches (Lowe's ratio test, as the recognizers match), and with
place labels, how many a frame of another place matches (what a recognizer must reject)
against how many a later view of the same place matches (what it must accept). Run on the
simulator's tours and on your own images, it shows whether the simulator is harder or easier
than real data, before any recognizer is tuned on it.

Examples:
    >>> from placeclust.imagestats import image_stats
    >>> from placeclust.synthetic import places
    >>> frames, truth = places(6, n_places=2)
    >>> stats = image_stats(frames, truth, features="orb", pairs=20)
    >>> stats["frames"], stats["across_pairs"], stats["within_pairs"]
    (12, 20, 20)
    >>> stats["within_median"] > stats["across_median"]
    True
"""

from __future__ import annotations

import argparse
import shlex
import sys
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from placeclust.argparsing import ArgumentParser
from placeclust.features import BINARY, FEATURES, FeatureExtractor
from placeclust.frames import to_gray
from placeclust.matching import normalize, ratio_matches

#: the fewest frames between two views of one place in the ``within`` reference: consecutive
#: frames are nearly the same image, a revisit is not
GAP = 5
#: ``(key prefix, column title)`` of the match columns of :func:`stats_table`
_COLUMNS = (("next", "next-frame matches"), ("across", "across places"),
            ("within", "within a place"))


def _check(n: int, labels: Sequence[int] | np.ndarray | None, features: str, pairs: int
           ) -> np.ndarray | None:
    """The labels as an int array (or None), or a ValueError naming what is wrong."""
    if n < 2:
        raise ValueError(f"need at least 2 frames, got {n}")
    if pairs < 1:
        raise ValueError(f"pairs must be at least 1, got {pairs}")
    if features not in FEATURES:
        raise ValueError(f"unknown features {features!r}; choose one of {FEATURES}")
    if labels is None:
        return None
    lab = np.asarray(labels)
    if lab.shape != (n,) or (lab.size and not np.issubdtype(lab.dtype, np.integer)):
        raise ValueError(f"labels must be {n} integers, one per frame, got shape {lab.shape} "
                         f"of {lab.dtype}")
    places = np.unique(lab[lab >= 0])
    if len(places) < 2:
        raise ValueError(f"labels name {len(places)} place(s); matches across places need at "
                         "least 2 (pass labels=None for keypoints and next-frame matches only)")
    return lab.astype(np.int64)


def _sample(labels: np.ndarray, pairs: int, rng: np.random.Generator, same: bool, gap: int
            ) -> list[tuple[int, int]]:
    """``pairs`` random ``(i, j)``, ``i < j``, of labelled frames of different places, or of
    the same place at least ``gap`` frames apart (``same``); fewer only when none exist."""
    idx = np.flatnonzero(labels >= 0)
    if same:  # frames with a partner: a frame of their place at least ``gap`` away
        lo = {p: idx[labels[idx] == p].min() for p in np.unique(labels[idx])}
        hi = {p: idx[labels[idx] == p].max() for p in lo}
        idx = np.array([i for i in idx if lo[labels[i]] <= i - gap or hi[labels[i]] >= i + gap],
                       np.int64)
    if len(idx) == 0:
        return []
    out = []
    for i in rng.choice(idx, size=pairs):
        partner = labels[idx] == labels[i] if same else labels[idx] != labels[i]
        if same:
            partner &= np.abs(idx - i) >= gap
        j = int(rng.choice(idx[partner]))
        out.append((min(int(i), j), max(int(i), j)))
    return out


def _spread(n: int, pairs: int) -> set[int]:
    """First frames of at most ``pairs`` consecutive pairs ``(t, t+1)``, evenly spread."""
    return set(np.unique(np.linspace(0, n - 2, min(pairs, n - 1)).round().astype(int)).tolist())


def _summary(prefix: str, counts: list[int]) -> dict[str, float]:
    arr = np.asarray(counts, float)
    median, p90 = (np.median(arr), np.percentile(arr, 90)) if len(arr) else (np.nan, np.nan)
    return {f"{prefix}_median": float(median), f"{prefix}_p90": float(p90),
            f"{prefix}_pairs": len(arr)}


def image_stats(frames: Sequence[np.ndarray] | np.ndarray,
                labels: Sequence[int] | np.ndarray | None = None, features: str = "sift",
                pairs: int = 200, seed: int = 0, ratio: float = 0.8, gap: int = GAP,
                max_features: int = 500) -> dict[str, float]:
    """Keypoints per frame and feature matches between frames, as a flat dict.

    Features are those the recognizers use by default (``FeatureExtractor(features)``: the
    ``max_features`` strongest, 500, after CLAHE); a match passes Lowe's ratio test
    (:func:`placeclust.matching.ratio_matches`), counted from the later frame's features.
    Every frame is read and detected once, in order (``frames`` may be a lazy
    :class:`placeclust.datasets.ImageFolder`); the pairs are drawn first, and only the
    descriptors that a pair still waits for are held.

    Args:
        frames: ``(H, W)`` or ``(H, W, 3)`` uint8 RGB frames, in order.
        labels: place per frame (-1: unlabelled), or None.
        features: one of :data:`placeclust.features.FEATURES`.
        pairs: frame pairs per kind of pair (next-frame pairs are evenly spread).
        seed: draws the across- and within-place pairs.
        ratio: Lowe's ratio.
        gap: the fewest frames between the two views of a within-place pair.
        max_features: the keypoints kept per frame, strongest first: fewer shows how alike
            frames look at a sparser detector's density (a real frame's, say).

    Returns:
        ``frames``: frames in the sequence. ``keypoints_median``, ``keypoints_p10``,
        ``keypoints_p90``: keypoints per frame over all frames. ``next_median``, ``next_p90``:
        matches between frames ``t`` and ``t+1`` over ``next_pairs`` pairs. With labels only:
        ``across_median``, ``across_p90``: matches between frames of two different places over
        ``across_pairs`` random pairs; ``within_median``, ``within_p90``: between frames of one
        place at least ``gap`` apart over ``within_pairs`` random pairs (NaN, and 0 pairs,
        when no place spans ``gap`` frames).

    Raises:
        ValueError: fewer than 2 frames, ``pairs`` or ``max_features`` below 1, unknown
            ``features``, labels not one integer per frame or naming fewer than 2 places, or a
            malformed frame.
    """
    n = len(frames)
    lab = _check(n, labels, features, pairs)
    rng = np.random.default_rng(seed)
    sampled = {} if lab is None else {kind: _sample(lab, pairs, rng, kind == "within", gap)
                                      for kind in ("across", "within")}
    waiting: dict[int, list[tuple[str, int]]] = defaultdict(list)  # later frame: (kind, earlier)
    uses: dict[int, int] = defaultdict(int)  # earlier frame: pairs still to match with it
    for kind, drawn in sampled.items():
        for i, j in drawn:
            waiting[j].append((kind, i))
            uses[i] += 1
    starts = _spread(n, pairs)
    extractor, binary = FeatureExtractor(features, max_features), features in BINARY
    keypoints: list[int] = []
    matches: dict[str, list[int]] = {"next": [], "across": [], "within": []}
    held: dict[int, np.ndarray] = {}
    previous: np.ndarray | None = None
    for t in range(n):
        desc = normalize(extractor.extract(to_gray(frames[t])).descriptors, binary)
        keypoints.append(len(desc))
        if previous is not None:
            matches["next"].append(len(ratio_matches(desc, previous, binary, ratio)[0]))
        previous = desc if t in starts else None
        for kind, i in waiting.pop(t, []):
            matches[kind].append(len(ratio_matches(desc, held[i], binary, ratio)[0]))
            uses[i] -= 1
            if uses[i] == 0:  # its last pair is matched: let it go
                del held[i]
        if uses.get(t):
            held[t] = desc
    count = np.asarray(keypoints, float)
    out: dict[str, float] = {"frames": n, "keypoints_median": float(np.median(count)),
                             "keypoints_p10": float(np.percentile(count, 10)),
                             "keypoints_p90": float(np.percentile(count, 90))}
    for kind in ("next", *sampled):
        out.update(_summary(kind, matches[kind]))
    return out


def revisit_stats(ref: Sequence[np.ndarray] | np.ndarray, query: Sequence[np.ndarray] | np.ndarray,
                  ground_truth: Sequence[Sequence[int] | np.ndarray], features: str = "sift",
                  pairs: int = 200, ratio: float = 0.8, max_features: int = 500
                  ) -> dict[str, float]:
    """Matches between a query and its own place on the other drive: for each of up to
    ``pairs`` queries with ground truth (evenly spread), the most matches it shares with one
    of its references. A localizer accepts a query where this count clears its threshold
    (seed 001's 25 matches), so it is the statistic a query's fate depends on, which keypoints
    a frame and next-frame matches only bound.

    Args:
        ref, query: the two drives' frames, ``(H, W)`` or ``(H, W, 3)`` uint8, in order.
        ground_truth: per query, the indices of its references.
        features, ratio, max_features: as :func:`image_stats`.
        pairs: queries measured at most.

    Returns:
        ``revisit_median``, ``revisit_p90`` and ``revisit_pairs`` (queries measured; NaN
        figures and 0 when no query has a reference).

    Example:
        >>> from placeclust.imagestats import revisit_stats
        >>> from placeclust.synthetic import places
        >>> frames, truth = places(6, n_places=2)
        >>> s = revisit_stats(frames[::2], frames[1::2], [[0, 1, 2], [3, 4, 5]] * 3, "orb")
        >>> s["revisit_pairs"], s["revisit_median"] > 0
        (6, True)
    """
    if features not in FEATURES:
        raise ValueError(f"unknown features {features!r}; choose one of {FEATURES}")
    if len(ground_truth) != len(query):
        raise ValueError(f"ground truth for {len(ground_truth)} queries, but {len(query)} "
                         "query frames")
    with_truth = [q for q, refs in enumerate(ground_truth) if len(refs)]
    spread = np.linspace(0, len(with_truth) - 1, min(pairs, len(with_truth)))
    picks = [with_truth[k] for k in np.unique(spread.round().astype(int))]
    extractor, binary = FeatureExtractor(features, max_features), features in BINARY

    def describe(frame: np.ndarray) -> np.ndarray:
        return normalize(extractor.extract(to_gray(frame)).descriptors, binary)

    refs: dict[int, np.ndarray] = {}
    counts = []
    for q in picks:
        desc = describe(query[q])
        best = 0
        for r in (int(r) for r in ground_truth[q]):
            if r not in refs:
                refs[r] = describe(ref[r])
            best = max(best, len(ratio_matches(desc, refs[r], binary, ratio)[0]))
        counts.append(best)
    return _summary("revisit", counts)


def revisit_table(rows: dict[str, dict]) -> str:
    """A markdown table of :func:`revisit_stats` results, one row per named data set."""
    lines = ["| sequence | queries | matches with its place on the other drive median / p90 |",
             "|---|---|---|"]
    lines += [f"| {name} | {_cell(row, 'revisit_pairs')} | {_cell(row, 'revisit_median')} / "
              f"{_cell(row, 'revisit_p90')} |" for name, row in rows.items()]
    return "\n".join(lines)


def _cell(row: dict, key: str) -> str:
    value = row.get(key)
    if value is None or not np.isfinite(value):
        return "–"
    return f"{value:.0f}" if float(value).is_integer() else f"{value:.1f}"


def stats_table(rows: dict[str, dict]) -> str:
    """A markdown table of :func:`image_stats` results, one row per named sequence ("–" where
    a figure is absent, e.g. across/within without labels)."""
    lines = ["| sequence | frames | keypoints median | "
             + " | ".join(f"{title} median / p90" for _, title in _COLUMNS) + " |",
             "|---|---|---|" + "---|" * len(_COLUMNS)]
    for name, row in rows.items():
        cells = [_cell(row, "frames"), _cell(row, "keypoints_median")]
        cells += [f"{_cell(row, f'{key}_median')} / {_cell(row, f'{key}_p90')}"
                  for key, _ in _COLUMNS]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _open_folder(folder: str) -> tuple[str, Sequence[np.ndarray], np.ndarray | None]:
    from placeclust.datasets import ImageFolder
    from placeclust.vprbench import is_vpr_bench

    # a VPR-Bench dataset's reference traversal is its sequence; query/ revisits it
    if is_vpr_bench(folder):
        images = ImageFolder(Path(folder) / "ref")
        return f"{folder} (ref/)", images, images.labels
    images = ImageFolder(folder)
    return folder, images, images.labels


def _open_tour(path: str) -> tuple[str, Sequence[np.ndarray], np.ndarray | None]:
    if not Path(path).is_file():
        raise ValueError(f"tour file {path} does not exist")
    try:
        with np.load(path, allow_pickle=False) as z:
            frames, room = z["frames"], z["room"]
    except (OSError, ValueError, KeyError, EOFError, AttributeError, TypeError) as exc:
        raise ValueError(f"{path} is not a tour: need an .npz with the arrays frames and room "
                         f"({exc})") from exc
    if frames.ndim not in (3, 4) or room.shape != (len(frames),):
        raise ValueError(f"{path}: frames must be (T, H, W[, 3]) and room (T,), got "
                         f"{frames.shape} and {room.shape}")
    return path, frames, room


def _strided(source: tuple[str, Sequence[np.ndarray], np.ndarray | None], stride: int
             ) -> tuple[str, Sequence[np.ndarray], np.ndarray | None]:
    """Every ``stride``-th frame of a tour, named so the table says it."""
    if stride == 1:
        return source
    name, frames, labels = source
    return (f"{name} (every {stride})", frames[::stride],
            None if labels is None else labels[::stride])


def main(argv: list[str] | None = None, prog: str = "python -m placeclust.imagestats") -> int:
    """The image statistics' command line (``placeclust stats``); the exit status."""
    p = ArgumentParser(prog=prog, description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--images", nargs="+", action="extend", metavar="DIR", default=[],
                   help="image folders (labels.csv used when present and naming two places "
                   "or more), or VPR-Bench datasets (their ref/ traversal)")
    p.add_argument("--tour", nargs="+", action="extend", metavar="FILE", default=[],
                   help="recorded tours (.npz with frames and room)")
    p.add_argument("--features", choices=FEATURES, default="sift")
    p.add_argument("--pairs", type=int, default=200, help="frame pairs per kind of pair")
    p.add_argument("--max-features", type=int, default=500, metavar="N",
                   help="keypoints kept per frame, strongest first (the recognizers' default)")
    p.add_argument("--seed", type=int, default=0, help="draws the across/within pairs")
    p.add_argument("--stride", type=int, default=1, metavar="K",
                   help="keep every K-th frame of each --tour: a tour steps 0.1 s, a data "
                   "set's frames are spaced as it was recorded, and next-frame matches "
                   "fall with the spacing")
    p.add_argument("--docs", metavar="FILE", help="also write the table into FILE's "
                   "'image-stats' section (docs/benchmarks.md), or --section's")
    p.add_argument("--section", default="image-stats", help="the section --docs writes")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    if not args.images and not args.tour:
        p.error("give at least one --images DIR or --tour FILE")
    if args.pairs < 1:
        p.error("--pairs must be at least 1")
    if args.max_features < 1:
        p.error("--max-features must be at least 1")
    if args.stride < 1:
        p.error(f"--stride must be at least 1, got {args.stride}")
    rows: dict[str, dict] = {}
    try:  # open every input first, so a bad one fails before minutes of detection
        sources = [_open_folder(d) for d in args.images]
        sources += [_strided(_open_tour(f), args.stride) for f in args.tour]
        for name, frames, labels in sources:
            # one labelled place has no across pairs: give keypoints and next-frame matches
            named = labels is not None and len(np.unique(labels[labels >= 0])) >= 2
            try:
                rows[name] = image_stats(frames, labels if named else None, args.features,
                                         args.pairs, args.seed, max_features=args.max_features)
            except ValueError as exc:
                raise ValueError(f"{name}: {exc}") from exc
        lines = [f"Matches ({args.features}, the {args.max_features} strongest keypoints of a "
                 f"frame, Lowe's ratio 0.8) per frame pair: at most "
                 f"{args.pairs} pairs of each kind; within a place: views {GAP}+ frames apart.",
                 "", stats_table(rows)]
        if args.docs:
            from placeclust.docs_section import write_section

            write_section(args.docs, args.section, "\n".join(lines),
                          shlex.join([*prog.split(), *argv]))
    except (ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
