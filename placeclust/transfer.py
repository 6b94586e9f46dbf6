"""Does a simulator rank methods as real images do? Rank correlation and pairwise agreement,
each with an interval from both sides' own sampling.

A simulated benchmark is worth running if what wins there wins on a robot. Given the same
methods' scores on both sides, :func:`rank_transfer` reports Spearman's rank correlation of
their means and, for every pair of methods, whether the simulator orders them as the data
does. Its interval resamples what each side drew:

- **simulated side**: buildings (a method's score is its mean over the same buildings);
- **real side**: blocks of consecutive frames or queries (a moving-block bootstrap, blocks of
  :data:`BLOCK` units), since neighbouring frames of one drive succeed or fail together.

Both sides are resampled independently in each of ``n_resamples`` draws; the correlation's
interval is the percentile interval of its draws, and each pair's ``p_agree`` is the share of
draws in which the two sides order it alike.

Examples:
    >>> from placeclust.transfer import rank_transfer
    >>> sim = {"a": [0.9, 0.8, 0.85], "b": [0.6, 0.5, 0.55], "c": [0.3, 0.2, 0.25]}
    >>> real = {"a": [1, 1, 1, 0] * 5, "b": [1, 0, 1, 0] * 5, "c": [0, 0, 0, 1] * 5}
    >>> t = rank_transfer(sim, real, block=2)
    >>> round(t.rho.mean, 2), t.concordant, t.discordant, t.ties, t.agreement.mean
    (1.0, 3, 0, 0, 1.0)
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from placeclust.stats import CONFIDENCE, Estimate

#: consecutive real frames or queries resampled together: about a place's worth of a drive
BLOCK = 10


@dataclass(frozen=True)
class PairOrder:
    """How the two sides order methods ``a`` and ``b``: each side's ``a - b`` and how often the
    resamples order them alike (:func:`rank_transfer`'s ``agreement``, pair by pair)."""

    a: str
    b: str
    sim: float
    real: float
    p_agree: float

    @property
    def verdict(self) -> str:
        """``"agree"``, ``"disagree"``, or ``"tie"`` where either side cannot order them."""
        if self.sim == 0 or self.real == 0:
            return "tie"
        return "agree" if (self.sim > 0) == (self.real > 0) else "disagree"


@dataclass(frozen=True)
class Transfer:
    """:func:`rank_transfer`'s answer."""

    methods: tuple[str, ...]
    sim_means: tuple[float, ...]
    real_means: tuple[float, ...]
    rho: Estimate
    pairs: tuple[PairOrder, ...]
    agreement: Estimate
    #: each method's real score as an interval from the same draws (the simulated side's is
    #: :func:`placeclust.stats.interval` over buildings)
    real: tuple[Estimate, ...] = ()

    @property
    def concordant(self) -> int:
        return sum(p.verdict == "agree" for p in self.pairs)

    @property
    def discordant(self) -> int:
        return sum(p.verdict == "disagree" for p in self.pairs)

    @property
    def ties(self) -> int:
        return sum(p.verdict == "tie" for p in self.pairs)


def block_resample(n: int, block: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of one moving-block bootstrap draw of ``n`` units: blocks of ``block``
    consecutive units from uniform starts, concatenated and cut to ``n``."""
    block = max(1, min(block, n))
    starts = rng.integers(0, n - block + 1, math.ceil(n / block))
    return (starts[:, None] + np.arange(block)[None, :]).ravel()[:n]


def _spearman(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Spearman's rho of each row of ``x`` with the same row of ``y`` (the Pearson
    correlation of their ranks, ties at their mean rank); NaN where a row is constant."""
    rx, ry = (stats.rankdata(v, axis=-1) for v in (x, y))
    rx, ry = (r - r.mean(axis=-1, keepdims=True) for r in (rx, ry))
    with np.errstate(invalid="ignore", divide="ignore"):
        return (rx * ry).sum(axis=-1) / np.sqrt((rx**2).sum(axis=-1) * (ry**2).sum(axis=-1))


def _agreement(sim: np.ndarray, real: np.ndarray, pairs: list[tuple[int, int]]) -> np.ndarray:
    """Per pair: 1 where both sides order it alike (tied on both counts alike), 0 where they
    order it oppositely, 0.5 where one side ties and the other does not."""
    i, j = np.array(pairs).T
    a, b = np.sign(sim[..., i] - sim[..., j]), np.sign(real[..., i] - real[..., j])
    return np.where(a == b, 1.0, np.where((a == 0) | (b == 0), 0.5, 0.0))


def rank_transfer(sim: Mapping[str, Sequence[float]],
                  real: Mapping[str, Sequence[float]] | RealScore,
                  block: int = BLOCK, confidence: float = CONFIDENCE,
                  n_resamples: int = 2000, seed: int = 0) -> Transfer:
    """How far the simulator's ranking of methods holds on real data.

    Args:
        sim: per method, its score on each simulated building (every method on the same
            buildings, in the same order).
        real: per method, its score on each real unit (a query's hit), every method on the
            same units in the same order, a method's real score being their mean; or a
            :class:`RealScore` for a score that is not a mean of units (NMI of a clustering).
        block: real units resampled together (:func:`block_resample`).
        confidence, n_resamples, seed: the bootstrap.

    Returns:
        A :class:`Transfer`: the means, Spearman's rho with its interval (NaN with fewer than
        3 methods), every pair's order on both sides, and ``agreement``, the share of pairs
        the two sides order alike (a pair one side ties and the other orders counts half),
        with its interval.

    Raises:
        ValueError: the two sides name other methods, or a side's methods differ in length.
    """
    if not isinstance(real, RealScore):
        real = RealScore.of_means(real)
    if set(sim) != set(real.methods):
        raise ValueError(f"the two sides must score the same methods: simulated "
                         f"{sorted(sim)}, real {sorted(real.methods)}")
    methods = tuple(sim)
    s = np.array([np.asarray(sim[m], float) for m in methods]).T  # (buildings, methods)
    if s.ndim != 2 or not len(s) or not real.n_units:
        raise ValueError("every method needs scores on the same buildings and the same units")
    rng = np.random.default_rng(seed)
    sim_draws = s[rng.integers(0, len(s), (n_resamples, len(s)))].mean(axis=1)
    real_draws = np.array([real.score(methods, block_resample(real.n_units, block, rng))
                           for _ in range(n_resamples)])
    return _compare(methods, s.mean(axis=0), sim_draws,
                    real.score(methods, np.arange(real.n_units)), real_draws, confidence)


@dataclass(frozen=True)
class RealScore:
    """The real side of :func:`rank_transfer` as a score of any subset of its units.

    Attributes:
        methods: the methods it scores.
        n_units: frames or queries of the real sequence, in order.
        score_of: ``(method, unit indices) -> score`` over those units (indices may repeat,
            as a bootstrap draws them).
    """

    methods: tuple[str, ...]
    n_units: int
    score_of: Callable[[str, np.ndarray], float]

    @classmethod
    def of_means(cls, per_unit: Mapping[str, Sequence[float]]) -> RealScore:
        """Each method's score the mean of its units' scores (a query's hit: top-1)."""
        arrays = {m: np.asarray(v, float) for m, v in per_unit.items()}
        lengths = {len(v) for v in arrays.values()}
        if len(lengths) != 1:
            raise ValueError("every method needs scores on the same real units, got "
                             f"{sorted(lengths)} of them")
        return cls(tuple(arrays), lengths.pop(),
                   lambda m, idx: float(arrays[m][idx].mean()) if len(idx) else math.nan)

    def score(self, methods: Sequence[str], idx: np.ndarray) -> np.ndarray:
        """Every method's score on units ``idx``, in ``methods``' order."""
        return np.array([self.score_of(m, idx) for m in methods])


def _estimate(point: float, draws: np.ndarray, n: int, confidence: float) -> Estimate:
    """``point`` with the percentile interval of its finite bootstrap ``draws``."""
    tail = (1 - confidence) / 2 * 100
    draws = draws[np.isfinite(draws)]
    if not draws.size or not math.isfinite(point):
        return Estimate(point, math.nan, math.nan, n, confidence)
    low, high = np.percentile(draws, [tail, 100 - tail])
    return Estimate(point, float(min(low, point)), float(max(high, point)), n, confidence)


def _compare(methods: tuple[str, ...], sim_means: np.ndarray, sim_draws: np.ndarray,
             real_means: np.ndarray, real_draws: np.ndarray, confidence: float) -> Transfer:
    """The :class:`Transfer` of both sides' points and ``(resamples, methods)`` draws."""

    def estimate(point: float, draws: np.ndarray, n: int) -> Estimate:
        return _estimate(point, draws, n, confidence)

    pairs = list(itertools.combinations(range(len(methods)), 2))
    rho = math.nan if len(methods) < 3 else float(_spearman(sim_means, real_means))
    rho_draws = _spearman(sim_draws, real_draws) if len(methods) >= 3 else np.array([])
    orders: list[PairOrder] = []
    agree_share = math.nan
    agree_draws = np.array([])
    if pairs:
        agree = _agreement(sim_draws, real_draws, pairs)  # (resamples, pairs)
        orders = [PairOrder(methods[i], methods[j], float(sim_means[i] - sim_means[j]),
                            float(real_means[i] - real_means[j]), float(agree[:, k].mean()))
                  for k, (i, j) in enumerate(pairs)]
        agree_share = float(_agreement(sim_means, real_means, pairs).mean())
        agree_draws = agree.mean(axis=1)
    return Transfer(methods, tuple(float(x) for x in sim_means),
                    tuple(float(x) for x in real_means),
                    estimate(rho, rho_draws, len(methods)), tuple(orders),
                    estimate(agree_share, agree_draws, len(pairs)),
                    tuple(estimate(float(real_means[k]), real_draws[:, k], 1)
                          for k in range(len(methods))))


def transfer_difference(sim_a: Mapping[str, Sequence[float]],
                        sim_b: Mapping[str, Sequence[float]],
                        real: Mapping[str, Sequence[float]] | RealScore,
                        block: int = BLOCK, confidence: float = CONFIDENCE,
                        n_resamples: int = 2000, seed: int = 0) -> tuple[Estimate, Estimate]:
    """How much better simulator ``a`` ranks the methods than simulator ``b`` (a lever on
    against off), paired: each draw resamples the same buildings for both (a building is
    the unit drawn, the same building with and without the lever) and one real draw.

    Args:
        sim_a, sim_b: per method, its score on each simulated building, both on the same
            buildings in the same order (as :func:`rank_transfer`'s ``sim``).
        real: the real side, as :func:`rank_transfer`'s.
        block, confidence, n_resamples, seed: the bootstrap.

    Returns:
        Spearman's rho of ``a`` minus that of ``b``, and the share of pairs ordered alike of
        ``a`` minus ``b``'s, each with its paired interval (one excluding 0 decides).

    Raises:
        ValueError: the sides name other methods or other numbers of buildings.

    Examples:
        >>> from placeclust.transfer import transfer_difference
        >>> real = {"a": [1, 1, 1, 0] * 5, "b": [1, 0, 1, 0] * 5, "c": [0, 0, 0, 1] * 5}
        >>> right = {"a": [0.9, 0.8], "b": [0.6, 0.5], "c": [0.3, 0.2]}
        >>> wrong = {"a": [0.3, 0.2], "b": [0.6, 0.5], "c": [0.9, 0.8]}
        >>> rho, pairs = transfer_difference(right, wrong, real, block=2)
        >>> round(rho.mean, 2), round(pairs.mean, 2)
        (2.0, 1.0)
    """
    if not isinstance(real, RealScore):
        real = RealScore.of_means(real)
    methods = tuple(sim_a)
    if not (set(methods) == set(sim_b) == set(real.methods)):
        raise ValueError(f"both simulators and the data must score the same methods: "
                         f"{sorted(sim_a)}, {sorted(sim_b)}, {sorted(real.methods)}")
    a, b = (np.array([np.asarray(sim[m], float) for m in methods]).T for sim in (sim_a, sim_b))
    if a.shape != b.shape or a.ndim != 2 or not len(a):
        raise ValueError(f"both simulators need every method on the same buildings, got "
                         f"{a.shape} and {b.shape} (buildings, methods)")
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, len(a), (n_resamples, len(a)))
    real_draws = np.array([real.score(methods, block_resample(real.n_units, block, rng))
                           for _ in range(n_resamples)])
    real_means = real.score(methods, np.arange(real.n_units))
    pairs = list(itertools.combinations(range(len(methods)), 2))

    def rho(sim: np.ndarray, on_real: np.ndarray) -> np.ndarray:
        return _spearman(sim, on_real)

    def alike(sim: np.ndarray, on_real: np.ndarray) -> np.ndarray:
        return _agreement(sim, on_real, pairs).mean(axis=-1)

    out = []
    for stat in (rho, alike):
        point = float(stat(a.mean(axis=0), real_means) - stat(b.mean(axis=0), real_means))
        draws = stat(a[idx].mean(axis=1), real_draws) - stat(b[idx].mean(axis=1), real_draws)
        out.append(_estimate(point, draws, len(a), confidence))
    return out[0], out[1]
