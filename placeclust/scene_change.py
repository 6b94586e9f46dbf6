"""Online scene-change detection, the gate on new places of the online recognizer.

Seed 000 (Tang et al.) finds scene changes offline, as local minima of the similarity between
neighbouring images (Sec. III.C, step 1; :func:`placeclust.baselines.scene_changes`). Online,
a minimum can only be seen once it has passed, so :class:`SceneChangeGate` asks a question it
can answer at once: how much of what the robot sees now could it see ``lag`` frames ago? The
similarity of frame ``t`` is the share of its view's features with a correspondence (Eq. 3,
ratio test) among the *whole* frame's features ``lag`` frames earlier. Comparing a view with a
whole 360° panorama makes turning on the spot free (what the sides see after a turn was seen
before, elsewhere in the panorama), while a doorway is not: the walls beside the robot after a
door were out of sight before it.

The default threshold, 0.25 with ``lag=10`` (40 cm of driving), lies between the similarity at
door crossings and elsewhere on the simulator's tours.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from placeclust.matching import ratio_matches


class SceneChangeGate:
    """Says whether a scene change happened within the last ``window`` frames.

    Feed every described frame to :meth:`update`; :attr:`is_open` is then true for ``window``
    frames after a frame whose similarity (see the module docstring) fell below
    ``threshold``. Until ``lag`` frames have been seen no similarity can be computed and the
    gate stays closed.

    Args:
        threshold: similarity below which a frame is a scene change, in (0, 1).
        lag: how many frames back the whole frame is compared with.
        window: frames the gate stays open after a scene change.
        binary: Hamming (True) or Euclidean (False) descriptors.
        ratio: Lowe's ratio for correspondences (Eq. 3).

    Raises:
        ValueError: ``threshold`` is outside (0, 1), ``lag`` below 1 or ``window`` negative.

    Examples:
        Three frames of one room, then a room whose features were never seen:

        >>> import numpy as np
        >>> from placeclust.matching import normalize
        >>> from placeclust.scene_change import SceneChangeGate
        >>> rng = np.random.default_rng(0)
        >>> room = normalize(rng.normal(size=(40, 16)).astype(np.float32), binary=False)
        >>> other = normalize(rng.normal(size=(40, 16)).astype(np.float32), binary=False)
        >>> gate = SceneChangeGate(threshold=0.25, lag=2, window=1)
        >>> [gate.update(room, room) for _ in range(3)], gate.is_open
        ([nan, nan, 1.0], False)
        >>> [(gate.update(other, other), gate.is_open) for _ in range(4)]
        [(0.0, True), (0.0, True), (1.0, True), (1.0, False)]
    """

    def __init__(self, threshold: float = 0.25, lag: int = 10, window: int = 10,
                 binary: bool = False, ratio: float = 0.8) -> None:
        if not 0.0 < threshold < 1.0:
            raise ValueError(f"scene-change threshold must be in (0, 1), got {threshold}")
        if lag < 1 or window < 0:
            raise ValueError(f"need lag >= 1 and window >= 0, got lag={lag}, window={window}")
        self.threshold = threshold
        self.lag = lag
        self.window = window
        self.binary = binary
        self.ratio = ratio
        self._history: deque[np.ndarray] = deque(maxlen=lag)
        self._since = window + 1  # frames since the last scene change: closed at the start

    def update(self, view: np.ndarray, whole: np.ndarray) -> float:
        """Take one frame's features and return its similarity (``nan`` before ``lag`` frames).

        Args:
            view: the features the recognizer uses (N, D), e.g. the side views.
            whole: all features of the same frame (M, D), kept for ``lag`` frames.

        Returns:
            The share of ``view``'s features matched in the whole frame ``lag`` frames back;
            ``nan`` before ``lag`` frames or for an empty ``view``.
        """
        self._since += 1
        similarity = float("nan")
        if len(self._history) == self.lag and len(view):
            matched, _ = ratio_matches(view, self._history[0], self.binary, self.ratio)
            similarity = len(matched) / len(view)
            if similarity < self.threshold:
                self._since = 0
        self._history.append(whole)
        return similarity

    @property
    def is_open(self) -> bool:
        """Whether a scene change happened in the last ``window`` frames."""
        return self._since <= self.window

    def reset(self) -> None:
        """Forget past frames (the robot was carried elsewhere) and close the gate."""
        self._history.clear()
        self._since = self.window + 1
