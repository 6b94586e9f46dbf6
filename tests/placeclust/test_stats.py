"""Intervals over buildings: what a user reads off a benchmark table must hold."""

import math

import numpy as np
import pytest

from placeclust.stats import (
    Estimate,
    buildings_for,
    interval,
    paired_difference,
    probability_of_improvement,
    suite_score,
)


def _buildings(rng, n, p_low, p_high, errands=5):
    return [rng.binomial(1, p, errands) for p in rng.uniform(p_low, p_high, n)]


def test_the_mean_weighs_every_errand_and_the_interval_holds_it():
    groups = [[1, 1, 0], [1], [0, 0, 1, 1]]  # 5 of 8 errands
    est = interval(groups)
    assert est.mean == pytest.approx(5 / 8) and est.n_buildings == 3
    assert est.low <= est.mean <= est.high


def test_the_interval_shrinks_with_more_buildings_and_covers_the_truth():
    rng = np.random.default_rng(0)
    small = interval(_buildings(rng, 10, 0.5, 1.0))
    large = interval(_buildings(rng, 160, 0.5, 1.0))
    assert large.half_width < small.half_width / 2.5  # about 1/sqrt(16)
    assert large.low < 0.75 < large.high


def test_buildings_that_fail_together_widen_the_interval():
    """The same 200 errands, spread evenly or clumped by building: the clumped sample has
    the wider interval, which a bootstrap over errands would miss."""
    even = [[1, 1, 1, 1, 0]] * 40
    clumped = [[1] * 5] * 32 + [[0] * 5] * 8
    assert interval(even).mean == interval(clumped).mean == 0.8
    assert interval(clumped).half_width > 3 * interval(even).half_width


def test_identical_buildings_give_a_point_and_one_building_no_interval():
    assert interval([[1, 1]] * 6) == Estimate(1.0, 1.0, 1.0, 6)
    lone = interval([[1, 0, 1]])
    assert lone.mean == pytest.approx(2 / 3) and math.isnan(lone.low) and math.isnan(lone.high)


def test_a_paired_difference_is_tighter_than_the_difference_of_two_intervals():
    rng = np.random.default_rng(1)
    p = rng.uniform(0.2, 1.0, 30)  # the building decides most of the outcome
    a = [rng.binomial(1, min(q + 0.1, 1.0), 6) for q in p]
    b = [rng.binomial(1, q, 6) for q in p]
    diff = paired_difference(a, b)
    assert diff.mean == pytest.approx(interval(a).mean - interval(b).mean)
    assert diff.half_width < interval(a).half_width + interval(b).half_width
    assert paired_difference(a, a) == Estimate(0.0, 0.0, 0.0, 30)


def test_probability_of_improvement_is_a_half_for_equals_and_one_for_a_sweep():
    a, b = [[1, 1, 1]] * 5, [[0, 0, 0]] * 5
    assert probability_of_improvement(a, b).mean == 1.0
    assert probability_of_improvement(b, a).mean == 0.0
    assert probability_of_improvement(a, a).mean == 0.5


def test_bad_samples_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="no buildings"):
        interval([])
    with pytest.raises(ValueError, match="building 1 has no values"):
        interval([[1], []])
    with pytest.raises(ValueError, match="not finite"):
        interval([[1], [math.nan]])
    with pytest.raises(ValueError, match="same buildings"):
        paired_difference([[1], [1]], [[1]])
    with pytest.raises(ValueError, match="at least 2 buildings"):
        buildings_for([[1, 0]], 0.05)


def test_the_buildings_needed_follow_the_pilots_spread():
    rng = np.random.default_rng(2)
    pilot = _buildings(rng, 20, 0.3, 1.0)
    n = buildings_for(pilot, 0.05)
    assert buildings_for(pilot, 0.10) == pytest.approx(n / 4, rel=0.1)
    assert buildings_for([[1, 1]] * 5, 0.05) == 2  # no spread: the fewest that resample


def _track(rng, p, n=20, errands=5):
    return [rng.binomial(1, p, errands) for _ in range(n)]


def test_the_suite_score_normalizes_each_track_between_its_floor_and_ceiling():
    tracks = {"a": [[1, 0], [1, 1]], "b": [[0, 0], [0, 1]]}  # means 0.75 and 0.25
    est = suite_score(tracks, floors={"a": 0.5, "b": 0.0}, ceilings={"a": 1.0, "b": 0.5},
                      n_resamples=200)
    assert est.mean == pytest.approx((0.5 + 0.5) / 2)
    same = {"a": [[1, 1]] * 3, "b": [[1, 1]] * 3}
    assert suite_score(same, {"a": 0, "b": 0}, {"a": 1, "b": 1}, n_resamples=100).mean == 1.0
    with pytest.raises(ValueError, match="floor and a ceiling that differ"):
        suite_score(tracks, {"a": 0.5, "b": 0.5}, {"a": 1.0, "b": 0.5})
    with pytest.raises(ValueError, match="aggregate"):
        suite_score(tracks, {"a": 0, "b": 0}, {"a": 1, "b": 1}, aggregate="median")


def test_the_iqm_trims_the_outlying_tracks():
    ones, zeros = [[1, 1]] * 4, [[0, 0]] * 4
    tracks = {"a": zeros, "b": ones, "c": ones, "d": ones}
    f, c = dict.fromkeys(tracks, 0.0), dict.fromkeys(tracks, 1.0)
    assert suite_score(tracks, f, c, n_resamples=100).mean == 0.75
    assert suite_score(tracks, f, c, aggregate="iqm", n_resamples=100).mean == 1.0


def test_the_stratified_interval_covers_the_truth_at_its_rate():
    # three tracks of 30 buildings whose true success is known: the 95% interval of the
    # normalized mean must hold the truth in about 95 of 100 draws (not just once)
    rng = np.random.default_rng(0)
    truth = {"a": 0.8, "b": 0.6, "c": 0.4}
    f, c = dict.fromkeys(truth, 0.0), dict.fromkeys(truth, 1.0)
    held = 0
    for seed in range(100):
        est = suite_score({t: _track(rng, p, n=30) for t, p in truth.items()}, f, c,
                          n_resamples=1000, seed=seed)
        held += est.low <= np.mean(list(truth.values())) <= est.high
    assert 88 <= held <= 99


def test_a_paired_suite_score_needs_the_pairing():
    # two recognizers whose buildings vary together: paired, the difference is decided;
    # with the buildings of one shuffled, the same means give a wider interval
    rng = np.random.default_rng(1)
    base = {t: rng.uniform(0.15, 0.95, 30) for t in "abc"}
    a = {t: [rng.binomial(1, p, 20) for p in base[t]] for t in "abc"}
    b = {t: [rng.binomial(1, max(p - 0.1, 0), 20) for p in base[t]] for t in "abc"}
    f, c = dict.fromkeys("abc", 0.0), dict.fromkeys("abc", 1.0)
    paired = suite_score(a, f, c, against=b, n_resamples=2000)
    shuffled = suite_score(a, f, c, against={t: list(rng.permutation(np.array(b[t])))
                                             for t in "abc"}, n_resamples=2000)
    assert paired.mean == pytest.approx(shuffled.mean)
    assert paired.half_width < 0.8 * shuffled.half_width
    assert paired.low > 0
    with pytest.raises(ValueError, match="paired tracks differ"):
        suite_score(a, f, c, against={"a": b["a"]})


def test_one_building_says_it_has_no_interval_instead_of_nan():
    assert interval([[1, 0, 1, 1]]).text() == "0.75 [1 building: no interval]"
    assert "nan" not in interval([[1, 0]]).text(3)


def test_over_seeds_with_one_seed_is_the_paired_bootstrap_over_buildings():
    from placeclust.stats import over_seeds, paired_difference

    rng = np.random.default_rng(3)
    a = [rng.integers(0, 2, 5) for _ in range(20)]
    b = [rng.integers(0, 2, 5) for _ in range(20)]
    one, paired = over_seeds([a], [b]), paired_difference(a, b)
    assert one.mean == pytest.approx(paired.mean)
    assert one.low == pytest.approx(paired.low, abs=0.05)
    assert one.high == pytest.approx(paired.high, abs=0.05)


def test_over_seeds_holds_the_seeds_spread_and_pairs_the_buildings():
    from placeclust.stats import over_seeds

    rng = np.random.default_rng(4)
    hard = rng.uniform(0, 1, 30)  # buildings differ a lot; a and b alike on each
    a = [[rng.random(4) < h + 0.1 for h in hard] for _ in range(3)]
    b = [[rng.random(4) < h for h in hard]]
    paired = over_seeds(a, b)
    unpaired_a, unpaired_b = over_seeds(a), over_seeds(b)
    assert paired.half_width < unpaired_a.half_width + unpaired_b.half_width
    # one seed that fails everywhere beside two that succeed: a wide interval
    seeds = [[np.ones(4)] * 10, [np.ones(4)] * 10, [np.zeros(4)] * 10]
    est = over_seeds(seeds)
    assert est.mean == pytest.approx(2 / 3) and est.low <= 1 / 3 and est.high == 1.0
    with pytest.raises(ValueError, match="same buildings"):
        over_seeds([[np.ones(2)] * 3, [np.ones(2)] * 4])


def _coverage(rng, n, draws=150, paired=False):
    """How many of ``draws`` synthetic samples of ``n`` buildings have a 95% interval that holds
    the true mean: buildings' success drawn from U(0.3, 1.0) (mean 0.65), 5 errands each;
    paired, b is a with 0.1 less success in every building (true difference 0.1)."""
    held = 0
    for seed in range(draws):
        p = rng.uniform(0.3, 1.0, n)
        a = [rng.binomial(1, q, 5) for q in p]
        if paired:
            b = [rng.binomial(1, q - 0.1, 5) for q in p]
            est = paired_difference(a, b, n_resamples=1000, seed=seed)
            held += est.low <= 0.1 <= est.high
        else:
            est = interval(a, n_resamples=1000, seed=seed)
            held += est.low <= 0.65 <= est.high
    return held / draws


@pytest.mark.parametrize("n, low, high", [(10, 0.85, 0.99), (60, 0.89, 1.0)])
def test_intervals_hold_the_truth_at_about_their_rate(n, low, high):
    """Coverage at the docs' sample sizes (a 10-building pilot, the 60-building suite): small
    samples run narrow (docs/design.md says so and `compare` warns below 10 buildings)."""
    rng = np.random.default_rng(n)
    assert low <= _coverage(rng, n) <= high
    assert low <= _coverage(rng, n, paired=True) <= high


def test_the_pairing_is_what_narrows_a_paired_difference():
    """The same buildings in another order break the pairing: the interval must widen, not just
    stay under the sum of two intervals (which it does either way)."""
    rng = np.random.default_rng(5)
    p = rng.uniform(0.1, 1.0, 40)
    a = [rng.binomial(1, min(q + 0.1, 1.0), 6) for q in p]
    b = [rng.binomial(1, q, 6) for q in p]
    shuffled = [b[i] for i in rng.permutation(len(b))]
    assert paired_difference(a, b).half_width < 0.6 * paired_difference(a, shuffled).half_width


def test_the_buildings_needed_reach_the_half_width_promised():
    """Sized from a 10-building pilot, a sample's half-width lands near the target on average
    over pilots; one pilot's spread is itself noisy (41 to 133 buildings here for the same
    population), which is why the docs size the suite from the pilot's, not one draw's."""
    rng = np.random.default_rng(0)
    widths = []
    for _ in range(6):
        n = buildings_for(_buildings(rng, 10, 0.2, 1.0), 0.06)
        widths += [interval(_buildings(rng, n, 0.2, 1.0), n_resamples=1000, seed=s).half_width
                   for s in range(10)]
    assert 0.048 <= float(np.mean(widths)) <= 0.072  # within a fifth of the target
