"""Consolidation: a young place that keeps matching an older one is merged into it.

Seed 000's online recognizer decides each frame once. When the robot comes back to a room
through another door, or sees it from a new side, the first frames may match no place within
``T_New_Cluster`` and a new place opens for a room the map already holds; from then on the new
place tracks the robot and the old one is never compared again. The paper's offline method
repairs such splits by reassigning images among neighbouring clusters until nothing changes
(Sec. III.C); online systems do it by merging: RTAB-Map's *rehearsal* merges a new node into
the previous one when they match, iBoW-LCD counts a match to any image of an *island*.

:class:`Rehearsal` is that step for :class:`~placeclust.online.OnlinePlaceClustering`, with
bounded work per frame. While a place is on *probation* (its kernel has taken in at most
``probation`` images), each frame it takes is also compared (Eq. 4) with the older place the
relocalization index votes for most. When ``streak`` frames in a row
match the same older place within ``threshold``, the two places are one: the young place is
merged into the older one, its kernel taken in by :meth:`~placeclust.kernel.UnionKernel.merge`,
its edges moved, and its id kept as an alias (:attr:`OnlinePlaceClustering.merged`). A
settled place costs nothing.

Ids a caller was already given for the merged place stay meaningful through
:meth:`OnlinePlaceClustering.resolve`, which maps any id ever returned to the place that holds
it now; :func:`placeclust.runner.run` scores the final map that way.

Examples:
    Two frames in a row matching place 0 within the threshold merge the young place 3:

    >>> from placeclust.consolidation import Rehearsal
    >>> rehearsal = Rehearsal(threshold=0.8, probation=30, streak=2)
    >>> rehearsal.observe(place=3, other=0, distance=0.7)
    False
    >>> rehearsal.observe(place=3, other=0, distance=0.75)
    True

    A frame that matches no other place breaks the streak:

    >>> rehearsal.observe(place=3, other=0, distance=0.7)
    False
    >>> rehearsal.observe(place=3, other=0, distance=0.9)
    False
    >>> rehearsal.observe(place=3, other=0, distance=0.7)
    False
"""

from __future__ import annotations


class Rehearsal:
    """When to merge a young place into another: ``streak`` matching frames in a row.

    Args:
        threshold: the most ``1 - Eq. 4`` distance between a frame of the young place and the
            other place that counts as a match; at most ``T_New_Cluster``, so that the frame
            would have joined the other place had it been searched.
        probation: a place whose kernel has taken in more images than this is settled and
            never merged.
        streak: matching frames in a row, with the same other place, needed to merge.

    Raises:
        ValueError: ``threshold`` is not in ``[0, 1)``, or ``probation`` or ``streak`` is
            below 1.
    """

    def __init__(self, threshold: float, probation: int = 60, streak: int = 2) -> None:
        if not 0.0 <= threshold < 1.0:
            raise ValueError(f"consolidation threshold must be in [0, 1), got {threshold}")
        if probation < 1 or streak < 1:
            raise ValueError(f"probation and streak must be at least 1, got {probation} and "
                             f"{streak}")
        self.threshold = threshold
        self.probation = probation
        self.streak = streak
        self._pair: tuple[int, int] | None = None
        self._count = 0

    def on_probation(self, n_images: int) -> bool:
        """Whether a place whose kernel has taken in ``n_images`` images may still be merged."""
        return n_images <= self.probation

    def observe(self, place: int, other: int, distance: float) -> bool:
        """Count one frame of ``place`` that is ``distance`` from ``other``.

        Returns:
            Whether the two places should be merged now (the streak is then reset).
        """
        if distance > self.threshold:
            self.reset()
            return False
        self._count = self._count + 1 if self._pair == (place, other) else 1
        self._pair = (place, other)
        if self._count < self.streak:
            return False
        self.reset()
        return True

    def reset(self) -> None:
        """Forget the streak (a frame that matched nothing else, or a frame elsewhere)."""
        self._pair, self._count = None, 0
