"""Input checks shared by every recognizer: frames in, greyscale uint8 out, or a clear error."""

from __future__ import annotations

import cv2
import numpy as np


def to_gray(frame: np.ndarray) -> np.ndarray:
    """Validate one image and return it as a 2-D uint8 greyscale array.

    Args:
        frame: ``(H, W)`` or ``(H, W, 1|3|4)`` array, uint8 (0-255) or float (0-1). Colour
            frames are taken as RGB.

    Returns:
        ``(H, W)`` uint8.

    Raises:
        ValueError: wrong type, shape, channel count or dtype, NaN/inf values, float values
            outside [0, 1], or an image smaller than 16x16.

    Examples:
        >>> import numpy as np
        >>> from placeclust.frames import to_gray
        >>> gray = to_gray(np.ones((32, 48, 3), np.float32))
        >>> gray.shape, gray.dtype, int(gray.max())
        ((32, 48), dtype('uint8'), 255)
        >>> to_gray(np.zeros((8, 8), np.uint8))
        Traceback (most recent call last):
            ...
        ValueError: frame of shape (8, 8) is too small; need at least 16x16
    """
    if not isinstance(frame, np.ndarray):
        raise ValueError(f"frame must be a numpy array, got {type(frame).__name__}")
    if frame.ndim == 3 and frame.shape[2] == 1:
        frame = frame[..., 0]
    if frame.ndim not in (2, 3) or (frame.ndim == 3 and frame.shape[2] not in (3, 4)):
        raise ValueError(f"frame must be (H, W) or (H, W, 1|3|4), got shape {frame.shape}")
    if frame.shape[0] < 16 or frame.shape[1] < 16:
        raise ValueError(f"frame of shape {frame.shape} is too small; need at least 16x16")
    if frame.dtype == np.uint8:
        img = frame
    elif np.issubdtype(frame.dtype, np.floating):
        if not np.all(np.isfinite(frame)):
            raise ValueError("frame contains NaN or inf")
        if frame.min() < 0.0 or frame.max() > 1.0:
            raise ValueError(f"float frames must be in [0, 1], got [{frame.min()}, {frame.max()}]")
        img = (frame * 255.0 + 0.5).astype(np.uint8)
    else:
        raise ValueError(f"frame dtype must be uint8 or float, got {frame.dtype}")
    if img.ndim == 3:
        code = cv2.COLOR_RGB2GRAY if img.shape[2] == 3 else cv2.COLOR_RGBA2GRAY
        img = cv2.cvtColor(np.ascontiguousarray(img), code)
    return np.ascontiguousarray(img)


def check_size(gray: np.ndarray, expected: tuple[int, int] | None) -> tuple[int, int]:
    """The size a map is built from: ``expected``, or ``gray``'s for the first frame.

    Args:
        gray: a 2-D image from :func:`to_gray`.
        expected: the map's frame size, or ``None`` before its first frame.

    Returns:
        ``(H, W)``, the size every later frame must have.

    Raises:
        ValueError: ``gray`` has another size than the frames the map was built from.
    """
    if expected is not None and gray.shape != expected:
        raise ValueError(f"frame of size {gray.shape} differs from the {expected} "
                         "frames this map was built from")
    return gray.shape


def check_sequence(frames: np.ndarray) -> np.ndarray:
    """Validate a sequence ``(T, H, W[, C])`` of frames for the offline methods.

    Returns:
        ``frames`` itself.

    Raises:
        ValueError: ``frames`` is not a 3-D or 4-D array, or is empty.
    """
    if not isinstance(frames, np.ndarray) or frames.ndim not in (3, 4):
        shape = getattr(frames, "shape", None)
        raise ValueError(f"frames must be an array (T, H, W[, C]), got shape {shape}")
    if len(frames) == 0:
        raise ValueError("frames is empty")
    return frames
