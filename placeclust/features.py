"""Local features, pluggable behind one small interface: ``extract(gray) -> Features``.

| name   | descriptor      | paper / note |
|--------|-----------------|--------------|
| sift   | 128-d float     | seed 001 (Elgayar et al.), Sec. 3.1 |
| kaze   | 64-d float      | closest free stand-in for the 64-d SURF of seed 000 (Tang et al.) |
| surf   | 64-d float      | real SURF-64 from mahotas (MIT); SURF itself is patented and not in |
|        |                 | the opencv-contrib wheels, so OpenCV's SURF is unavailable |
| orb    | 256-bit binary  | fast; matched with the Hamming distance |
| akaze  | 486-bit binary  | fast, scale-space like KAZE |

Each extractor keeps at most ``max_features`` keypoints (strongest response first), so a kernel's
size and the matching cost stay bounded.

Frames can be resized by ``scale`` before detection (keypoint coordinates are given back in
the frame's pixels). OpenCV's SIFT doubles its input for its first octave, so a 0.75 copy of a
simulator panorama still yields nearly all its features, faster; :data:`placeclust.PANORAMA`
uses it.

On 360° panoramas ``view="sides"`` keeps only the keypoints seen at the robot's left and right
(see :data:`VIEWS`): a sideways view changes room as the robot passes the door.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np

FEATURES = ("sift", "kaze", "surf", "orb", "akaze")
#: the feature types with binary descriptors (Hamming distance); the others are float (L2)
BINARY = ("orb", "akaze")
NORMALIZE = (None, "equalize", "clahe")
#: ``"full"``: the whole frame (any camera). ``"sides"``: for 360° panoramas whose centre column
#: looks along the robot's heading (the convention of ``envs.world.panorama``), the keypoints
#: within 45° of the robot's left and right (columns ``W/4 ± W/8`` and ``3W/4 ± W/8``), about
#: half of them. A panorama sees the next room through a doorway before the robot reaches it
#: and the last room after, so place boundaries fall anywhere near a door; a view to the side
#: swaps rooms as the robot passes it. Kept after the ``max_features`` strongest of the whole
#: frame are chosen.
VIEWS = ("full", "sides")


@dataclass(frozen=True)
class Features:
    """Keypoints of one image: ``xy`` (N, 2) float32 and ``descriptors`` (N, D)."""

    xy: np.ndarray
    descriptors: np.ndarray
    binary: bool

    def __len__(self) -> int:
        return len(self.descriptors)


def _sides(feats: Features, width: int) -> Features:
    """The keypoints within 45° of the robot's left and right on a ``width``-wide panorama."""
    x = feats.xy[:, 0]
    keep = ((np.abs(x - width / 4) < width / 8) | (np.abs(x - 3 * width / 4) < width / 8))
    return Features(feats.xy[keep], np.ascontiguousarray(feats.descriptors[keep]),
                    feats.binary)


def _cv2_factory(name: str) -> Callable[..., cv2.Feature2D]:
    contrib = getattr(cv2, "xfeatures2d", None)
    for module in (cv2, contrib):
        fn = getattr(module, f"{name}_create", None) if module is not None else None
        if fn is not None:
            return fn
    raise ValueError(f"this OpenCV build has no {name}; install opencv-contrib-python-headless")


class FeatureExtractor:
    """Detects keypoints and computes descriptors with one of :data:`FEATURES`.

    The one interface behind which every recognizer gets its local features: seed 000 uses
    SURF-64, seed 001 SIFT (Sec. 3.1).

    Args:
        name: feature type.
        max_features: keep the strongest ``max_features`` keypoints.
        normalize: contrast normalization before detection: ``None``, ``"equalize"``
            (global histogram equalization) or ``"clahe"`` (contrast-limited adaptive
            histogram equalization, 8x2 tiles on a 4:1 panorama). It makes detection less
            dependent on the light: at night a contrast threshold keeps other keypoints.
        scale: resize factor in (0, 1] applied before detection (``cv2.INTER_AREA``); smaller
            is faster and finds fewer, coarser keypoints.
        view: which keypoints to keep, one of :data:`VIEWS`.

    Raises:
        ValueError: an unknown ``name``, ``normalize`` or ``view``, ``max_features`` below 1,
            ``scale`` outside (0, 1], or a feature type this OpenCV build lacks.

    Examples:
        >>> from placeclust.features import FeatureExtractor
        >>> from placeclust.frames import to_gray
        >>> from placeclust.synthetic import textured
        >>> gray = to_gray(textured(0))
        >>> feats = FeatureExtractor("sift", max_features=50).extract(gray)
        >>> len(feats), feats.xy.shape, feats.descriptors.shape, feats.binary
        (50, (50, 2), (50, 128), False)
        >>> orb = FeatureExtractor("orb", max_features=50).extract(gray)
        >>> orb.descriptors.dtype, orb.descriptors.shape[1], orb.binary
        (dtype('uint8'), 32, True)

        ``view="sides"`` keeps a subset of the whole frame's keypoints, at the cost of one
        detection:

        >>> view, whole = FeatureExtractor("orb", 50, view="sides").extract_pair(gray)
        >>> len(view) < len(whole)
        True
    """

    def __init__(self, name: str = "sift", max_features: int = 500,
                 normalize: str | None = "clahe", scale: float = 1.0, view: str = "full") -> None:
        if name not in FEATURES:
            raise ValueError(f"unknown feature type {name!r}; choose one of {FEATURES}")
        if normalize not in NORMALIZE:
            raise ValueError(f"unknown normalize {normalize!r}; choose one of {NORMALIZE}")
        if view not in VIEWS:
            raise ValueError(f"unknown view {view!r}; choose one of {VIEWS}")
        self.view = view
        self.normalize = normalize
        self._clahe = cv2.createCLAHE(clipLimit=2.0, tileGridSize=(8, 2))
        if max_features < 1:
            raise ValueError(f"max_features must be positive, got {max_features}")
        scale = float(scale)
        if not 0.0 < scale <= 1.0:
            raise ValueError(f"scale must be in (0, 1], got {scale}")
        self.name = name
        self.max_features = max_features
        self.scale = scale
        self.binary = name in BINARY
        self._cv: cv2.Feature2D | None = None  # None for mahotas' SURF
        if name == "sift":
            self._cv = cv2.SIFT.create(nfeatures=max_features)
        elif name == "orb":
            self._cv = cv2.ORB.create(nfeatures=max_features)
        elif name == "kaze":
            self._cv = _cv2_factory("KAZE")(extended=False)
        elif name == "akaze":
            self._cv = _cv2_factory("AKAZE")()

    def __getstate__(self) -> dict:  # cv2 objects do not pickle; rebuild them on load
        return {"name": self.name, "max_features": self.max_features,
                "normalize": self.normalize, "scale": self.scale, "view": self.view}

    def __setstate__(self, state: dict) -> None:
        type(self).__init__(self, **state)

    def extract(self, gray: np.ndarray) -> Features:
        """Features of one image in this extractor's ``view``.

        Args:
            gray: 2-D uint8 image (see :func:`placeclust.frames.to_gray`).

        Returns:
            The strongest ``max_features`` features at most; keypoint coordinates are in
            ``gray``'s pixels whatever ``scale``.
        """
        return self.extract_pair(gray)[0]

    def extract_pair(self, gray: np.ndarray) -> tuple[Features, Features]:
        """The features of :meth:`extract` and those of the whole frame, from one detection.

        Args:
            gray: 2-D uint8 image.

        Returns:
            ``(view, whole)``: the features in ``view`` and the whole frame's features they
            were selected from (the same object when ``view="full"``).
        """
        width = gray.shape[1]
        if self.scale != 1.0:
            h, w = gray.shape
            size = (max(1, round(w * self.scale)), max(1, round(h * self.scale)))
            gray = cv2.resize(gray, size, interpolation=cv2.INTER_AREA)
        feats = self._detect(gray)
        if self.scale != 1.0 and len(feats):
            # pixel centres map as (x + 0.5) / scale - 0.5
            xy = (feats.xy + np.float32(0.5)) / np.float32(self.scale) - np.float32(0.5)
            feats = Features(xy, feats.descriptors, feats.binary)
        if self.view == "sides" and len(feats):
            return _sides(feats, width), feats
        return feats, feats

    def _detect(self, gray: np.ndarray) -> Features:
        if self.normalize == "equalize":
            gray = cv2.equalizeHist(gray)
        elif self.normalize == "clahe":
            gray = self._clahe.apply(gray)
        if self.name == "surf":
            return self._surf(gray)
        assert self._cv is not None  # every feature type but SURF has an OpenCV detector
        kps, desc = self._cv.detectAndCompute(gray, None)
        if desc is None or not kps:
            return self._empty()
        if len(kps) > self.max_features:
            order = np.argsort([-k.response for k in kps])[: self.max_features]
            kps = [kps[i] for i in order]
            desc = desc[order]
        # on the C++ side, not a Python loop (an array, which cv2's stubs call a sequence)
        xy = np.asarray(cv2.KeyPoint.convert(kps)).reshape(-1, 2)
        desc = desc if self.binary else np.asarray(desc, np.float32)
        return Features(xy, np.ascontiguousarray(desc), self.binary)

    def _surf(self, gray: np.ndarray) -> Features:
        try:
            from mahotas.features import surf
        except ImportError as exc:
            raise ImportError("features='surf' needs mahotas: pip install mahotas") from exc
        pts = surf.surf(gray.astype(np.float64), max_points=self.max_features,
                        descriptor_only=False)
        if len(pts) == 0:
            return self._empty()
        # mahotas rows: y, x, scale, score, laplacian, angle, then the 64-d descriptor
        return Features(pts[:, [1, 0]].astype(np.float32),
                        np.ascontiguousarray(pts[:, 6:], np.float32), False)

    def _empty(self) -> Features:
        dim = {"sift": 128, "kaze": 64, "surf": 64}.get(self.name, 32 if self.name == "orb" else 61)
        dtype = np.uint8 if self.binary else np.float32
        return Features(np.zeros((0, 2), np.float32), np.zeros((0, dim), dtype), self.binary)
