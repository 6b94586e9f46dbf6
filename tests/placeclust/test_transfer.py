"""Sim-to-real rank agreement: it sees agreement, disagreement and ties, with intervals that
shrink as either side draws more."""

import numpy as np
import pytest

from placeclust.transfer import block_resample, rank_transfer, transfer_difference


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


def test_a_lever_that_changes_nothing_differs_by_exactly_zero():
    """Paired draws: the same buildings and real draws for both, so no noise is left."""
    sim = {"a": [0.9, 0.5, 0.7], "b": [0.6, 0.7, 0.4], "c": [0.3, 0.2, 0.6]}
    real = {"a": [1, 1, 0, 1] * 5, "b": [1, 0, 1, 0] * 5, "c": [0, 0, 1, 0] * 5}
    rho, alike = transfer_difference(sim, dict(sim), real, block=2)
    assert (rho.mean, rho.low, rho.high) == (0.0, 0.0, 0.0)
    assert (alike.mean, alike.low, alike.high) == (0.0, 0.0, 0.0)


def test_the_simulator_that_ranks_as_the_data_does_is_better_and_decided():
    """Fault caught: the sides subtracted the wrong way round, or unpaired draws (the
    interval would then reach past zero on buildings this noisy)."""
    rng = np.random.default_rng(0)
    real = {"a": [1, 1, 1, 0] * 10, "b": [1, 0, 1, 0] * 10, "c": [0, 0, 0, 1] * 10}
    noise = rng.normal(0, 0.3, (8, 3))
    right = {m: (base + noise[:, k]).tolist() for k, (m, base) in
             enumerate({"a": 0.9, "b": 0.6, "c": 0.3}.items())}
    wrong = {m: (base + noise[:, k]).tolist() for k, (m, base) in
             enumerate({"a": 0.3, "b": 0.6, "c": 0.9}.items())}
    rho, alike = transfer_difference(right, wrong, real)
    assert rho.mean == 2.0 and rho.low > 0 and alike.low > 0
    flipped, _ = transfer_difference(wrong, right, real)
    assert flipped.mean == -2.0 and flipped.high < 0


def test_other_buildings_on_the_two_sides_are_refused():
    real = {"a": [1, 0], "b": [0, 1], "c": [1, 1]}
    with pytest.raises(ValueError, match="same buildings"):
        transfer_difference({"a": [1, 2], "b": [1, 2], "c": [1, 2]},
                            {"a": [1], "b": [1], "c": [1]}, real)
