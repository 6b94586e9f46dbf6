"""placeclust.sizing: a pilot's two noise sources, and which lever (buildings or errands)
decides a comparison."""

import numpy as np
import pytest

from placeclust.sizing import plan


def _two_stage(rng, n_buildings, errands, mean, spread, base=0.4):
    """Buildings whose true difference is drawn around ``mean`` with ``spread``; each errand a
    coin with its building's success chance."""
    a, b = [], []
    for _ in range(n_buildings):
        d = float(np.clip(rng.normal(mean, spread), -base, 1 - base))
        a.append(rng.random(errands) < base + d)
        b.append(rng.random(errands) < base)
    return a, b


def test_recovers_the_two_variance_components_of_a_known_two_stage_sample():
    a, b = _two_stage(np.random.default_rng(0), 2000, 6, mean=0.2, spread=0.15)
    p = plan(a, b)
    assert p.difference == pytest.approx(0.2, abs=0.02)
    assert p.between == pytest.approx(0.15 ** 2, rel=0.25)
    # one errand a side: var(A) + var(B) of two coins near 0.6 and 0.4, plus the spread of A's
    assert p.within == pytest.approx(0.6 * 0.4 + 0.4 * 0.6, rel=0.1)


def test_predicted_half_width_matches_the_spread_of_repeated_samples():
    rng = np.random.default_rng(1)
    pilot = plan(*_two_stage(rng, 3000, 5, mean=0.1, spread=0.1))
    draws = []
    for _ in range(400):
        a, b = _two_stage(rng, 12, 15, mean=0.1, spread=0.1)
        draws.append(np.mean([x.mean() - y.mean() for x, y in zip(a, b)]))
    assert pilot.standard_error(12, 15) == pytest.approx(np.std(draws), rel=0.15)


def test_errands_help_where_buildings_agree_and_not_where_they_differ():
    rng = np.random.default_rng(2)
    agree = plan(*_two_stage(rng, 400, 5, mean=0.15, spread=0.0))
    differ = plan(*_two_stage(rng, 400, 5, mean=0.15, spread=0.3))
    def saved(p):  # the share of buildings that four times the errands leaves needed
        return p.buildings_for(errands=20) / p.buildings_for(errands=5)

    assert saved(agree) < 0.35
    assert saved(differ) > 1.8 * saved(agree)
    assert agree.power(12, 20) > agree.power(12, 5)


def test_no_sample_decides_a_difference_of_zero():
    same = [[1, 0, 1, 0], [0, 1, 0, 1]]
    p = plan(same, same)
    assert p.difference == 0 and p.buildings_for(errands=10) is None


@pytest.mark.parametrize("a, b, message", [
    ([[1, 0], [1, 1]], [[1, 0]], "same buildings"),
    ([[1, 0]], [[0, 1]], "at least 2 buildings"),
    ([[1], [1, 0]], [[0, 1], [1, 0]], "at least 2 errands"),
    ([[1, float("nan")], [1, 0]], [[0, 1], [1, 0]], "not finite"),
])
def test_bad_pilots_are_refused_with_what_is_wrong(a, b, message):
    with pytest.raises(ValueError, match=message):
        plan(a, b)


def test_sizes_must_be_positive():
    p = plan([[1, 0], [1, 1]], [[0, 0], [1, 0]])
    with pytest.raises(ValueError, match="at least 1 building"):
        p.half_width(0, 5)
