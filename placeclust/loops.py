"""Loop-closure data sets: one drive that comes back to its places, and a matrix that says
which frames revisit which.

The layout RTAB-Map's samples and the loop-closure sets before them (Angeli et al. 2008's
Lip6 indoor and outdoor) ship::

    DIR/1.jpg, 2.jpg, ...        the frames, in natural order
    DIR/same_place.bmp           (T, T) image: pixel (i, j), 0-based, is non-zero where frame
                                 i revisits the place of the earlier frame j (below the
                                 diagonal; a bitmap, so that no image reader takes it for
                                 a frame)

:class:`LoopClosures` asks it VPR-Bench's question: the frames before the first revisit are
the map (``ref``), the rest the queries, and a query's references are the map frames it
revisits. A revisit of a query frame by a later query is left out (the map is fixed).
:func:`placeclust.realdata.run_dataset` and ``placeclust like`` then score it as they score a
VPR-Bench folder.

Examples:
    >>> import tempfile
    >>> import cv2
    >>> import numpy as np
    >>> from placeclust.datasets import write_image_folder
    >>> from placeclust.loops import LoopClosures
    >>> folder = tempfile.mkdtemp()
    >>> _ = write_image_folder(folder, np.zeros((5, 16, 16, 3), np.uint8))
    >>> same = np.zeros((5, 5), np.uint8)
    >>> same[3, 0] = same[4, 1] = same[4, 3] = 255   # frames 3 and 4 come back
    >>> _ = cv2.imwrite(f"{folder}/same_place.bmp", same)
    >>> data = LoopClosures(folder)
    >>> len(data.ref), len(data.query), [g.tolist() for g in data.ground_truth]
    (3, 2, [[0], [1]])
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path

import cv2
import numpy as np

from placeclust.datasets import DatasetError, ImageFolder

#: the ground-truth matrix's file name
TRUTH_FILE = "same_place.bmp"


def is_loop_closures(folder: str | Path) -> bool:
    """Whether ``folder`` holds a loop-closure matrix (:data:`TRUTH_FILE`)."""
    return (Path(folder) / TRUTH_FILE).is_file()


def read_same_place(path: str | Path, n_frames: int) -> np.ndarray:
    """The (T, T) bool matrix of revisits, below the diagonal.

    Raises:
        DatasetError: unreadable, not square, or not one row a frame (named).
    """
    image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise DatasetError(f"cannot read {path}: damaged or not an image")
    if image.shape != (n_frames, n_frames):
        raise DatasetError(f"{path} is {image.shape[0]}x{image.shape[1]}; the folder has "
                           f"{n_frames} frames, so it must be {n_frames}x{n_frames}")
    return np.tril(image > 0, k=-1)


class LoopClosures:
    """A loop-closure folder as VPR-Bench's question: ``ref``, ``query``, ``ground_truth``.

    Attributes:
        frames: every frame, in order (an :class:`ImageFolder`).
        same_place: the matrix (:func:`read_same_place`).
        ref, query: the frames before the first revisit, and the rest (lazy sequences).
        ground_truth: per query, the indices of the map frames it revisits.

    Raises:
        DatasetError: no matrix, an unreadable one, or one without a revisit.
    """

    def __init__(self, folder: str | Path) -> None:
        self.path = Path(folder)
        truth = self.path / TRUTH_FILE
        if not truth.is_file():
            raise DatasetError(f"{self.path} holds no loop-closure matrix ({TRUTH_FILE})")
        self.frames = ImageFolder(self.path, labels=False)
        self.same_place = read_same_place(truth, len(self.frames))
        revisits = np.flatnonzero(self.same_place.any(axis=1))
        if not len(revisits):
            raise DatasetError(f"{truth} marks no revisit: there is nothing to localize")
        first = int(revisits[0])
        self.ref = _Slice(self.frames, 0, first)
        self.query = _Slice(self.frames, first, len(self.frames))
        self.ground_truth = [np.flatnonzero(self.same_place[i, :first])
                             for i in range(first, len(self.frames))]

    def __repr__(self) -> str:
        return f"LoopClosures({str(self.path)!r}, {len(self.ref)} ref, {len(self.query)} query)"


class _Slice(Sequence[np.ndarray]):
    """Frames ``start`` to ``stop`` of an :class:`ImageFolder`, read when asked."""

    def __init__(self, frames: ImageFolder, start: int, stop: int) -> None:
        self.frames, self.start, self.stop = frames, start, stop

    def __len__(self) -> int:
        return self.stop - self.start

    def __getitem__(self, t: int) -> np.ndarray:  # type: ignore[override]
        # a sequence of frames, not of slices: a recognizer reads frame by frame
        if not 0 <= t < len(self):
            raise IndexError(t)
        return self.frames[self.start + t]

    def __iter__(self) -> Iterator[np.ndarray]:
        return (self.frames[t] for t in range(self.start, self.stop))
