import cv2
import numpy as np
import pytest


def textured(seed: int, shape=(128, 512)) -> np.ndarray:
    """A feature-rich synthetic RGB 'panorama': random shapes on smooth noise, distinct per seed."""
    rng = np.random.default_rng(seed)
    coarse = rng.integers(0, 256, (shape[0] // 8, shape[1] // 8, 3)).astype(np.uint8)
    img = cv2.resize(coarse, (shape[1], shape[0]), interpolation=cv2.INTER_CUBIC)
    for _ in range(120):
        col = tuple(int(c) for c in rng.integers(0, 256, 3))
        x, y = int(rng.integers(shape[1])), int(rng.integers(shape[0]))
        if rng.random() < 0.5:
            cv2.circle(img, (x, y), int(rng.integers(3, 10)), col, -1)
        else:
            cv2.rectangle(img, (x, y), (x + int(rng.integers(4, 16)), y + int(rng.integers(4, 16))),
                          col, -1)
    return img


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
