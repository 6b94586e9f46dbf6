"""Synthetic, feature-rich 'panoramas' for tests and benchmarks that need no simulator."""

from __future__ import annotations

import cv2
import numpy as np


def textured(seed: int, shape: tuple[int, int] = (128, 512)) -> np.ndarray:
    """An RGB image of random shapes on smooth noise, different for every ``seed``.

    Args:
        seed: the only source of randomness.
        shape: (height, width).

    Returns:
        A ``(height, width, 3)`` uint8 image with hundreds of SIFT/ORB keypoints.
    """
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


def jitter(img: np.ndarray, rng: np.random.Generator, shift: int = 3, noise: int = 6
           ) -> np.ndarray:
    """``img`` rolled by up to ``shift`` columns (a small turn) with uniform pixel noise."""
    rolled = np.roll(img, int(rng.integers(-shift, shift + 1)), axis=1).astype(np.int16)
    return np.clip(rolled + rng.integers(-noise, noise + 1, img.shape), 0, 255).astype(np.uint8)
