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

    Examples:
        >>> import numpy as np
        >>> from placeclust.synthetic import textured
        >>> img = textured(0)
        >>> img.shape, img.dtype, bool(np.array_equal(img, textured(0)))
        ((128, 512, 3), dtype('uint8'), True)
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
    """``img`` rolled by up to ``shift`` columns (a small turn) with uniform pixel noise.

    Args:
        img: a uint8 image.
        rng: draws the shift and the noise.
        shift: the largest roll, in columns, either way.
        noise: the largest change of a pixel value, either way.

    Returns:
        A new uint8 image of ``img``'s shape: another view of the same place.
    """
    rolled = np.roll(img, int(rng.integers(-shift, shift + 1)), axis=1).astype(np.int16)
    return np.clip(rolled + rng.integers(-noise, noise + 1, img.shape), 0, 255).astype(np.uint8)


def places(views: int, n_places: int = 2, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``views`` jittered views of each of ``n_places`` synthetic places, one place after another.

    Args:
        views: frames per place.
        n_places: places, made by :func:`textured` with seeds ``1 .. n_places``.
        seed: draws the jitter.

    Returns:
        ``(frames, truth)``: ``(views * n_places, 128, 512, 3)`` uint8 frames and the place of
        each frame, ``(views * n_places,)`` int.

    Examples:
        >>> frames, truth = places(3)
        >>> frames.shape, truth.tolist()
        ((6, 128, 512, 3), [0, 0, 0, 1, 1, 1])
    """
    rng = np.random.default_rng(seed)
    truth = np.repeat(np.arange(n_places), views)
    bases = [textured(k + 1) for k in range(n_places)]
    return np.stack([jitter(bases[p], rng) for p in truth]), truth
