"""Fixtures shared by the library and the command tests."""

import numpy as np
import pytest

from placeclust.synthetic import textured


@pytest.fixture
def two_places():
    """20 jittered views of place A then 20 of place B, with truth labels."""
    a, b = textured(1), textured(2)
    rng = np.random.default_rng(0)
    frames, truth = [], []
    for label, base in ((0, a), (1, b)):
        for _ in range(20):
            shift = int(rng.integers(-3, 4))
            noisy = np.roll(base, shift, axis=1).astype(int) + rng.integers(-6, 7, base.shape)
            frames.append(np.clip(noisy, 0, 255).astype(np.uint8))
            truth.append(label)
    return np.stack(frames), np.array(truth)
