"""How many buildings, and how many errands a building, a paired comparison needs.

A pilot of two recognizers on the same buildings gives a difference and two sources of its
noise: the buildings differ in what the difference truly is (``between``, a variance over
buildings), and a building's few errands estimate its own difference with noise that shrinks
as errands are added (``within``, the variance of one building's difference at one errand a
side). With ``n`` buildings of ``m`` errands each the difference's standard error is

    se(n, m) = sqrt((between + within / m) / n),

the two-stage (buildings, then errands in them) sampling variance of a cluster mean (Cochran
1977, ch. 10). More errands shrink only the second term, so where the buildings themselves
differ, only more buildings decide; :func:`plan` says which lever a comparison needs.

The interval :mod:`placeclust.stats` reports is a bootstrap over buildings; this module sizes
it with the normal approximation, from the pilot's own spread (a pilot on ``val``, never the
sample that reports). It assumes a building's errands are independent draws; chained errands
(each from where the last ended) that succeed or fail together make the within part larger
than it looks, and the ``between`` part holds what they share.

Examples:
    Two recognizers on four buildings, four errands each; the first is better by a quarter in
    every building, so the buildings agree (``between`` is 0) and only errands add noise:

    >>> from placeclust.sizing import plan
    >>> p = plan([[1, 1, 1, 0], [1, 1, 0, 1], [0, 1, 1, 1], [1, 0, 1, 1]],
    ...          [[1, 1, 0, 0], [0, 1, 0, 1], [0, 1, 0, 1], [1, 0, 0, 1]])
    >>> round(p.difference, 2), p.between
    (0.25, 0.0)
    >>> round(p.half_width(buildings=4, errands=4), 2)
    0.37
    >>> p.buildings_for(errands=4), p.buildings_for(errands=16)
    (19, 5)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from placeclust.stats import CONFIDENCE, Groups, _paired

#: the chance of excluding 0 a sample is sized for, when the difference is the pilot's
POWER = 0.8


@dataclass(frozen=True)
class Plan:
    """A pilot's difference and its two variance components (see the module).

    Attributes:
        difference: the pilot's mean of A − B (errand-weighted per side, as
            :func:`placeclust.stats.paired_difference`).
        between: the variance over buildings of their true differences (0 where the pilot's
            buildings differ no more than their errands explain).
        within: the variance of one building's difference at one errand a side.
        buildings: the pilot's buildings.
        errands: the pilot's errands a building a side (the mean).
    """

    difference: float
    between: float
    within: float
    buildings: int
    errands: float

    def standard_error(self, buildings: int, errands: float) -> float:
        """The difference's standard error at ``buildings`` buildings of ``errands`` each."""
        if buildings < 1:
            raise ValueError(f"need at least 1 building, got {buildings}")
        return math.sqrt(self._building_variance(errands) / buildings)

    def _building_variance(self, errands: float) -> float:
        """The variance of one building's difference at ``errands`` a side."""
        if not errands > 0:
            raise ValueError(f"need errands > 0, got {errands}")
        return self.between + self.within / errands

    def half_width(self, buildings: int, errands: float, confidence: float = CONFIDENCE
                   ) -> float:
        """The interval's expected half-width at that size."""
        return _z(confidence) * self.standard_error(buildings, errands)

    def power(self, buildings: int, errands: float, confidence: float = CONFIDENCE) -> float:
        """The chance the interval excludes 0 at that size, if the difference is the pilot's."""
        se = self.standard_error(buildings, errands)
        if se == 0:
            return float(self.difference != 0)
        return float(stats.norm.cdf(abs(self.difference) / se - _z(confidence)))

    def buildings_for(self, errands: float, power: float = POWER,
                      confidence: float = CONFIDENCE) -> int | None:
        """The fewest buildings of ``errands`` each whose interval excludes 0 with chance
        ``power``, if the difference is the pilot's; None for a difference of 0 (no sample
        decides it)."""
        if self.difference == 0:
            return None
        z = _z(confidence) + stats.norm.ppf(power)
        return max(2, math.ceil(self._building_variance(errands) * (z / self.difference) ** 2))


def _z(confidence: float) -> float:
    return float(stats.norm.ppf(0.5 + confidence / 2))


def plan(a: Groups, b: Groups) -> Plan:
    """The :class:`Plan` of a paired pilot: ``a[i]`` and ``b[i]`` are building ``i``'s errand
    outcomes (0/1 successes, or SPLs) of the two recognizers.

    Raises:
        ValueError: different numbers of buildings, fewer than 2, a building with values that
            are not finite, or with fewer than 2 errands on a side (its errands' spread is
            unknown).
    """
    xa, xb = _paired(a, b)
    if len(xa) < 2:
        raise ValueError(f"a pilot needs at least 2 buildings, got {len(xa)}")
    if min(x.size for x in xa + xb) < 2:
        raise ValueError("every building needs at least 2 errands a side")
    means = np.array([x.mean() - y.mean() for x, y in zip(xa, xb)])
    counts = np.array([(x.size + y.size) / 2 for x, y in zip(xa, xb)])
    # each building's own sampling variance of its difference, rescaled to one errand a side
    own = np.array([x.var(ddof=1) / x.size + y.var(ddof=1) / y.size for x, y in zip(xa, xb)])
    within = float(np.mean(own * counts))
    between = max(0.0, float(means.var(ddof=1) - own.mean()))
    # errand-weighted on each side, as placeclust.stats.paired_difference's point
    difference = float(np.concatenate(xa).mean() - np.concatenate(xb).mean())
    return Plan(difference, between, within, len(xa), float(counts.mean()))
