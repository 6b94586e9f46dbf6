"""Sim-to-real rank agreement: it sees agreement, disagreement and ties, with intervals that
shrink as either side draws more."""

import numpy as np
import pytest

from placeclust.transfer import block_resample, rank_transfer


def _sides(real_order, n_buildings=6, n_queries=100, seed=0):
    """Four methods whose simulated scores fall a > b > c > d, and real hit rates given."""
    rng = np.random.default_rng(seed)
    sim = {m: list(0.9 - 0.2 * i + rng.normal(0, 0.02, n_buildings))
           for i, m in enumerate("abcd")}
    real = {m: list((rng.random(n_queries) < p).astype(float)) for m, p in
            zip("abcd", real_order)}
    return sim, real


def test_the_same_order_agrees_and_the_reversed_one_disagrees():
    same = rank_transfer(*_sides([0.8, 0.6, 0.4, 0.2]))
    assert same.rho.mean == pytest.approx(1.0) and same.rho.low > 0.3
    assert same.concordant == 6 and same.agreement.mean == 1.0
    reversed_ = rank_transfer(*_sides([0.2, 0.4, 0.6, 0.8]))
    assert reversed_.rho.mean == pytest.approx(-1.0) and reversed_.rho.high < 0
    assert reversed_.discordant == 6 and reversed_.agreement.mean == 0.0
    assert all(p.p_agree < 0.2 for p in reversed_.pairs)


def test_close_real_scores_leave_the_interval_wide():
    near = rank_transfer(*_sides([0.52, 0.5, 0.48, 0.46], n_queries=60))
    far = rank_transfer(*_sides([0.9, 0.6, 0.3, 0.05], n_queries=60))
    assert near.rho.high - near.rho.low > far.rho.high - far.rho.low


def test_a_tie_on_one_side_counts_half():
    sim = {"a": [0.9, 0.9], "b": [0.5, 0.5], "c": [0.1, 0.1]}
    real = {"a": [1.0] * 10, "b": [0.0] * 10, "c": [0.0] * 10}  # b and c tie on real data
    t = rank_transfer(sim, real, block=2)
    assert (t.concordant, t.discordant, t.ties) == (2, 0, 1)
    assert t.agreement.mean == pytest.approx((1 + 1 + 0.5) / 3)


def test_other_methods_on_each_side_are_refused():
    with pytest.raises(ValueError, match="same methods"):
        rank_transfer({"a": [1.0], "b": [0.0]}, {"a": [1.0], "c": [0.0]})


def test_block_resample_keeps_blocks_of_neighbours():
    picks = block_resample(25, 5, np.random.default_rng(0))
    assert len(picks) == 25 and picks.max() < 25
    steps = np.diff(picks.reshape(5, 5), axis=1)
    assert (steps == 1).all()
    assert len(block_resample(3, 10, np.random.default_rng(0))) == 3
