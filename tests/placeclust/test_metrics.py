"""Metrics a figure rests on agree with the references users know."""

import numpy as np
import pytest


def test_nmi_is_scikit_learns_on_any_labelling():
    from sklearn.metrics import normalized_mutual_info_score

    from placeclust.metrics import nmi

    rng = np.random.default_rng(0)
    for _ in range(100):
        n = int(rng.integers(2, 50))
        pred = rng.integers(-1, int(rng.integers(1, 6)), n)
        truth = rng.integers(0, int(rng.integers(1, 5)), n)
        assert nmi(pred, truth) == pytest.approx(normalized_mutual_info_score(truth, pred))
