"""Intervals over buildings: a figure's mean, its 95% interval, and paired comparisons.

A building is the unit a benchmark draws, so its scores vary with the draw of buildings more
than with anything inside one: errands in one building succeed or fail together. Every figure
here is a mean over the errands (or tours) of a sample of buildings, with a bootstrap interval
that resamples *buildings* (a cluster bootstrap), each with all its errands, through
:func:`scipy.stats.bootstrap` (BCa; percentile where BCa is undefined).

Why buildings only, not errands within them as well: the spread of the buildings' means already
holds the errands' own noise; resampling at both stages counts it twice and widens the interval
(Davison & Hinkley 1997, §3.8). rliable's stratified bootstrap resamples runs *within* fixed
tasks, which suits a fixed set of Atari games, not buildings drawn from a generator.

Two recognizers run on the same buildings are compared *paired*: the difference of their means
with the buildings resampled jointly, and the probability of improvement (Agarwal et al. 2021,
rliable): per building the chance that an errand of one beats an errand of the other (the
Mann-Whitney U statistic over the two, ties counting half), averaged over buildings.

Examples:
    >>> from placeclust.stats import interval, paired_difference
    >>> a = [[1, 1, 1, 0], [1, 1, 1, 1], [0, 1, 1, 1], [1, 1, 1, 1]]
    >>> b = [[1, 0, 0, 0], [1, 1, 0, 1], [0, 0, 1, 0], [1, 1, 0, 1]]
    >>> est = interval(a)
    >>> est.mean, est.n_buildings
    (0.875, 4)
    >>> est.low <= 0.875 <= est.high
    True
    >>> round(paired_difference(a, b).mean, 3)
    0.375
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

#: the confidence of every interval the project reports
CONFIDENCE = 0.95
#: bootstrap resamples: enough that the interval's ends move by under 0.005 between seeds
N_RESAMPLES = 10_000

Groups = Sequence[Sequence[float]]


@dataclass(frozen=True)
class Estimate:
    """A mean over buildings with its ``confidence`` interval [``low``, ``high``]."""

    mean: float
    low: float
    high: float
    n_buildings: int
    confidence: float = CONFIDENCE

    @property
    def half_width(self) -> float:
        """Half the interval's width: the precision the sample gives the mean."""
        return (self.high - self.low) / 2

    def excludes(self, value: float = 0.0) -> bool:
        """Whether ``value`` lies outside the interval (a difference that decides)."""
        return not self.low <= value <= self.high

    def text(self, digits: int = 2) -> str:
        """``"0.82 [0.68, 0.91]"``; with too few buildings to resample, says so instead of
        ``[nan, nan]``: ``"0.82 [1 building: no interval]"``."""
        if not (math.isfinite(self.low) and math.isfinite(self.high)):
            many = "building" if self.n_buildings == 1 else "buildings"
            return f"{self.mean:.{digits}f} [{self.n_buildings} {many}: no interval]"
        return f"{self.mean:.{digits}f} [{self.low:.{digits}f}, {self.high:.{digits}f}]"

    def as_dict(self) -> dict[str, float]:
        return {"mean": self.mean, "low": self.low, "high": self.high,
                "n_buildings": self.n_buildings, "confidence": self.confidence}


def _arrays(groups: Groups, name: str = "groups") -> list[np.ndarray]:
    """Each building's values as a float array; a clear error for an empty or bad sample."""
    arrays = [np.asarray(g, dtype=float).ravel() for g in groups]
    if not arrays:
        raise ValueError(f"{name}: no buildings")
    for i, a in enumerate(arrays):
        if a.size == 0:
            raise ValueError(f"{name}: building {i} has no values")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name}: building {i} has values that are not finite: {a}")
    return arrays


def _ratio(sums: np.ndarray, counts: np.ndarray, axis: int = -1) -> np.ndarray:
    """The pooled mean of resampled buildings: every errand weighs the same."""
    return np.sum(sums, axis=axis) / np.sum(counts, axis=axis)


def _bootstrap(data: tuple[np.ndarray, ...], statistic, point: float, seed: int,
               confidence: float, n_resamples: int) -> Estimate:
    n = len(data[0])
    if n < 2:  # one building: nothing to resample
        return Estimate(point, math.nan, math.nan, n, confidence)
    # BCa is undefined where every building gives the same figure: percentile then
    for method in ("BCa", "percentile"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", stats.DegenerateDataWarning)
            warnings.simplefilter("ignore", RuntimeWarning)  # BCa's 0/0 on such data
            res = stats.bootstrap(data, statistic, paired=True, vectorized=True,
                                  confidence_level=confidence, n_resamples=n_resamples,
                                  method=method, rng=np.random.default_rng(seed))
        low, high = res.confidence_interval
        if np.isfinite(low) and np.isfinite(high):
            break
    return Estimate(point, float(min(low, point)), float(max(high, point)), n, confidence)


def interval(groups: Groups, confidence: float = CONFIDENCE, n_resamples: int = N_RESAMPLES,
             seed: int = 0) -> Estimate:
    """The mean of all values (every errand or tour weighs the same) with a bootstrap interval
    over buildings.

    Args:
        groups: one sequence of values per building: its errands' successes (0/1) or SPLs,
            or its one tour's precision.
        confidence: the interval's level.
        n_resamples, seed: the bootstrap's.

    Returns:
        The :class:`Estimate`; with one building its interval is ``nan`` (nothing to resample).
    """
    arrays = _arrays(groups)
    sums = np.array([a.sum() for a in arrays])
    counts = np.array([a.size for a in arrays], dtype=float)
    point = float(sums.sum() / counts.sum())
    return _bootstrap((sums, counts), _ratio, point, seed, confidence, n_resamples)


def _paired(a: Groups, b: Groups) -> tuple[list[np.ndarray], list[np.ndarray]]:
    xa, xb = _arrays(a, "a"), _arrays(b, "b")
    if len(xa) != len(xb):
        raise ValueError(f"a paired comparison needs the same buildings: a has {len(xa)}, "
                         f"b has {len(xb)}")
    return xa, xb


def paired_difference(a: Groups, b: Groups, confidence: float = CONFIDENCE,
                      n_resamples: int = N_RESAMPLES, seed: int = 0) -> Estimate:
    """Mean of ``a`` minus mean of ``b`` over the same buildings (in the same order), with the
    buildings resampled jointly: the interval of the difference, not of either mean.

    Each building's values of ``a`` and of ``b`` may differ in number (errands end where the
    agent stops, so two recognizers need not run the same count); each side is errand-weighted.
    """
    xa, xb = _paired(a, b)
    sa, na = np.array([x.sum() for x in xa]), np.array([x.size for x in xa], float)
    sb, nb = np.array([x.sum() for x in xb]), np.array([x.size for x in xb], float)

    def diff(sa, na, sb, nb, axis=-1):
        return _ratio(sa, na, axis) - _ratio(sb, nb, axis)

    point = float(diff(sa, na, sb, nb))
    return _bootstrap((sa, na, sb, nb), diff, point, seed, confidence, n_resamples)


def probability_of_improvement(a: Groups, b: Groups, confidence: float = CONFIDENCE,
                               n_resamples: int = N_RESAMPLES, seed: int = 0) -> Estimate:
    """P(an errand of ``a`` scores above one of ``b`` in the same building), ties counting
    half, averaged over buildings (rliable's probability of improvement, buildings as tasks),
    with a bootstrap interval over buildings. 0.5: neither is better."""
    xa, xb = _paired(a, b)
    per_building = np.array([stats.mannwhitneyu(x, y).statistic / (x.size * y.size)
                             if x.size and y.size else 0.5 for x, y in zip(xa, xb, strict=True)])
    ones = np.ones_like(per_building)
    point = float(per_building.mean())
    return _bootstrap((per_building, ones), _ratio, point, seed, confidence, n_resamples)


def _stratified(per_track: Sequence[Callable[[np.ndarray], np.ndarray]], sizes: Sequence[int],
                combine: Callable[[np.ndarray], np.ndarray], point: float, confidence: float,
                n_resamples: int, seed: int) -> Estimate:
    """A percentile bootstrap stratified by track: each track's buildings resampled on their
    own (``per_track[t](indices)`` gives the track's figure for each resample's indices), the
    tracks' figures then combined row by row."""
    n = min(sizes)
    if n < 2:
        return Estimate(point, math.nan, math.nan, n, confidence)
    rng = np.random.default_rng(seed)
    table = np.stack([fn(rng.integers(size, size=(n_resamples, size)))
                      for fn, size in zip(per_track, sizes, strict=True)], axis=1)
    low, high = np.quantile(combine(table), [(1 - confidence) / 2, (1 + confidence) / 2])
    return Estimate(point, float(min(low, point)), float(max(high, point)), n, confidence)


#: how :func:`suite_score` combines the tracks' normalized scores
AGGREGATES = ("mean", "iqm")


def _combine(aggregate: str) -> Callable[[np.ndarray], np.ndarray]:
    if aggregate not in AGGREGATES:
        raise ValueError(f"unknown aggregate {aggregate!r}; choose one of {AGGREGATES}")
    if aggregate == "iqm":  # rliable's interquartile mean: a quarter trimmed at each end
        return lambda table: stats.trim_mean(table, 0.25, axis=-1)
    return lambda table: np.mean(table, axis=-1)


def suite_score(tracks: Mapping[str, Groups], floors: Mapping[str, float],
                ceilings: Mapping[str, float], against: Mapping[str, Groups] | None = None,
                aggregate: str = "mean", confidence: float = CONFIDENCE,
                n_resamples: int = N_RESAMPLES, seed: int = 0) -> Estimate:
    """One score over tracks in rliable's manner (Agarwal et al. 2021): each track's mean
    normalized between its floor (0, e.g. no place ids) and its ceiling (1, the true rooms),
    then the mean or interquartile mean (``aggregate``) over tracks, with a bootstrap interval
    stratified by track that resamples each track's buildings. The floors and ceilings are
    taken as fixed, as rliable's are.

    Args:
        tracks: per track, one sequence of values per building (as :func:`interval`'s).
        floors, ceilings: per track, the scores that map to 0 and 1.
        against: another recognizer's ``tracks`` on the same buildings in the same order: the
            score is then the paired difference, this one's minus that one's.
        aggregate: one of :data:`AGGREGATES`.

    Returns:
        The :class:`Estimate`; ``n_buildings`` is the smallest track's count.

    Raises:
        ValueError: a track without a floor and a ceiling apart, or tracks that differ between
            the two recognizers.
    """
    combine = _combine(aggregate)
    names = sorted(tracks)
    if against is not None and sorted(against) != names:
        raise ValueError(f"paired tracks differ: {names} against {sorted(against)}")
    for t in names:
        if t not in floors or t not in ceilings or not ceilings[t] != floors[t]:
            raise ValueError(f"track {t!r} needs a floor and a ceiling that differ, got "
                             f"{floors.get(t)} and {ceilings.get(t)}")
    per_track, sizes, points = [], [], []
    for t in names:
        sides = [tracks[t]] if against is None else [tracks[t], against[t]]
        if against is not None:
            _paired(*sides)
        arrays = [_arrays(g, t) for g in sides]
        sums = [np.array([x.sum() for x in a]) for a in arrays]
        counts = [np.array([x.size for x in a], float) for a in arrays]
        lo, span = floors[t], ceilings[t] - floors[t]

        def figure(idx: np.ndarray | slice, sums=sums, counts=counts, lo=lo, span=span
                   ) -> np.ndarray:
            norm = [(_ratio(s[idx], c[idx]) - lo) / span for s, c in zip(sums, counts)]
            return norm[0] if len(norm) == 1 else norm[0] - norm[1]

        per_track.append(figure)
        sizes.append(len(arrays[0]))
        points.append(float(figure(slice(None))))
    point = float(combine(np.array(points)))
    return _stratified(per_track, sizes, combine, point, confidence, n_resamples, seed)


def buildings_for(groups: Groups, half_width: float, confidence: float = CONFIDENCE) -> int:
    """How many buildings bring the interval's half-width down to ``half_width``, from a pilot
    sample ``groups``: ``ceil((z * s / half_width) ** 2)`` with ``s`` the standard deviation of
    the pilot's building means and ``z`` the normal quantile (the bootstrap interval of a mean
    shrinks as ``1 / sqrt(n)``). At least the pilot's spread of one building, never below 2."""
    if not half_width > 0:
        raise ValueError(f"half_width must be positive, got {half_width}")
    means = np.array([a.mean() for a in _arrays(groups)])
    if means.size < 2:
        raise ValueError("a pilot needs at least 2 buildings to estimate their spread")
    z = stats.norm.ppf(0.5 + confidence / 2)
    return max(2, math.ceil((z * means.std(ddof=1) / half_width) ** 2))


def rank_agreement(a: Sequence[float], b: Sequence[float], confidence: float = CONFIDENCE,
                   n_resamples: int = 2000, seed: int = 0) -> Estimate:
    """Spearman's rank correlation between two scores of the same methods (say each
    recognizer's precision in the simulator, ``a``, and on a real data set, ``b``), with a
    percentile-bootstrap interval over methods (``n_buildings`` counts the methods).

    Resamples in which either score is constant have no rank correlation and are left out.
    With fewer than 3 methods there is nothing to rank: the mean is NaN.

    Examples:
        >>> from placeclust.stats import rank_agreement
        >>> est = rank_agreement([0.9, 0.8, 0.7, 0.6, 0.5], [0.8, 0.9, 0.6, 0.5, 0.4])
        >>> round(est.mean, 2), est.n_buildings, est.low <= est.mean <= est.high
        (0.9, 5, True)
    """
    x, y = np.asarray(a, float), np.asarray(b, float)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"two scores per method are needed, got shapes {x.shape}, {y.shape}")
    if len(x) < 3:
        return Estimate(math.nan, math.nan, math.nan, len(x), confidence)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # constant resamples: no correlation, left out
        rho = float(stats.spearmanr(x, y).statistic)
        picks = np.random.default_rng(seed).integers(0, len(x), (n_resamples, len(x)))
        draws = np.array([stats.spearmanr(x[i], y[i]).statistic for i in picks])
    draws = draws[np.isfinite(draws)]
    tail = (1 - confidence) / 2 * 100
    low, high = np.percentile(draws, [tail, 100 - tail]) if draws.size else (math.nan,) * 2
    return Estimate(rho, float(low), float(high), len(x), confidence)


def _seed_table(seeds: Sequence[Groups], name: str) -> tuple[np.ndarray, np.ndarray]:
    """Per-(seed, building) sums and counts, ``(S, B)`` each; every seed on the same buildings."""
    if not seeds:
        raise ValueError(f"{name}: no seeds")
    arrays = [_arrays(g, name) for g in seeds]
    if len({len(a) for a in arrays}) != 1:
        raise ValueError(f"{name}: every seed must run the same buildings, got "
                         f"{[len(a) for a in arrays]}")
    return (np.array([[x.sum() for x in a] for a in arrays]),
            np.array([[x.size for x in a] for a in arrays], float))


def over_seeds(a: Sequence[Groups], b: Sequence[Groups] | None = None,
               confidence: float = CONFIDENCE, n_resamples: int = 4000, seed: int = 0
               ) -> Estimate:
    """The mean of ``a`` (minus that of ``b``) where each is one agent trained with several
    seeds: ``a[s]`` is seed ``s``'s groups, every seed on the same buildings in the same order.

    A crossed bootstrap: each resample draws buildings (the same for ``a`` and ``b``: paired)
    and, independently, each side's training seeds, so the interval holds seed-to-seed
    variance as well as building-to-building; pooling the seeds' errands as more errands of one
    agent would leave the first out. With one seed a side it is the bootstrap over buildings
    (percentile). With few seeds their spread is itself poorly known: show the seeds' own
    figures beside it.

    Examples:
        >>> from placeclust.stats import over_seeds
        >>> steady = [[[1, 1], [0, 1], [1, 0]], [[1, 1], [0, 1], [1, 0]]]
        >>> moody = [[[1, 1], [1, 1], [1, 1]], [[0, 0], [0, 0], [0, 0]]]
        >>> s, m = over_seeds(steady), over_seeds(moody)
        >>> round(s.mean, 2), round(m.mean, 2), m.half_width > s.half_width
        (0.67, 0.5, True)
    """
    sa, na = _seed_table(a, "a")
    # no b: a side of zeros, which every resample leaves at 0
    sb, nb = _seed_table(b, "b") if b is not None else (np.zeros_like(sa[:1]), na[:1])
    if sb.shape[1] != sa.shape[1]:
        raise ValueError(f"a paired comparison needs the same buildings: a has {sa.shape[1]}, "
                         f"b has {sb.shape[1]}")
    point = float(sa.sum() / na.sum() - sb.sum() / nb.sum())
    n_buildings = sa.shape[1]
    if n_buildings < 2:
        return Estimate(point, math.nan, math.nan, n_buildings, confidence)
    rng = np.random.default_rng(seed)
    buildings = rng.integers(0, n_buildings, (n_resamples, n_buildings))

    def side(sums: np.ndarray, counts: np.ndarray) -> np.ndarray:
        picks = rng.integers(0, len(sums), (n_resamples, len(sums)))
        chosen = (picks[:, :, None], buildings[:, None, :])  # (resample, seed, building)
        return sums[chosen].sum(axis=(1, 2)) / counts[chosen].sum(axis=(1, 2))

    draws = side(sa, na) - side(sb, nb)
    tail = (1 - confidence) / 2 * 100
    low, high = np.percentile(draws, [tail, 100 - tail])
    return Estimate(point, float(min(low, point)), float(max(high, point)), n_buildings,
                    confidence)
