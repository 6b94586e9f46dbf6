"""The global Haar wavelet signature of seed 001 (Elgayar et al., Sec. 3.2 and 4.4)."""

from __future__ import annotations

import numpy as np
import pywt


def haar_signature(gray: np.ndarray, level: int = 4) -> np.ndarray:
    """Horizontal, vertical and diagonal detail coefficients of the ``level``-th 2-D Haar level.

    Args:
        gray: 2-D image, any real dtype.
        level: decomposition level; the paper chooses 4 (Sec. 5.4).

    Returns:
        1-D float32 vector: the concatenated (H, V, D) details of the coarsest level.

    Examples:
        A 128x512 image at level 4 gives three 8x32 detail bands:

        >>> import numpy as np
        >>> from placeclust.wavelet import haar_signature
        >>> haar_signature(np.zeros((128, 512), np.uint8)).shape
        (768,)
    """
    img = np.asarray(gray, np.float32) / 255.0
    coeffs = pywt.wavedec2(img, "haar", level=level)
    h, v, d = coeffs[1]  # coeffs[0] is the approximation; [1] the details of the coarsest level
    return np.concatenate([h.ravel(), v.ravel(), d.ravel()]).astype(np.float32)


def signature_similarity(a: np.ndarray, b: np.ndarray) -> float:
    """Similarity in [0, 1] of two signatures: ``1 - |a - b|_1 / (|a|_1 + |b|_1)``.

    The paper gives a percentage (96% threshold) without a formula; this normalised L1 form is
    1 for identical signatures, 0 for opposite ones, and insensitive to the signature's length.

    Examples:
        >>> import numpy as np
        >>> from placeclust.frames import to_gray
        >>> from placeclust.synthetic import jitter, textured
        >>> from placeclust.wavelet import haar_signature, signature_similarity
        >>> place = haar_signature(to_gray(textured(0)))
        >>> again = haar_signature(to_gray(jitter(textured(0), np.random.default_rng(0))))
        >>> other = haar_signature(to_gray(textured(1)))
        >>> signature_similarity(place, place), signature_similarity(place, -place)
        (1.0, 0.0)
        >>> signature_similarity(place, again) > signature_similarity(place, other)
        True
    """
    den = float(np.abs(a).sum() + np.abs(b).sum())
    if den == 0.0:
        return 1.0
    return 1.0 - float(np.abs(a - b).sum()) / den
