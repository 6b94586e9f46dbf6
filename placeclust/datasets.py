"""Real image sequences: an ordered folder of images, read one frame at a time.

The folder layout (what ``placeclust cluster --images DIR`` reads and ``placeclust tour
--export-images DIR`` writes)::

    DIR/000000.png, 000001.png, ...   png or jpg, in natural order (img2 before img10)
    DIR/labels.csv                    optional: frame,label[,x,y,heading,condition]

``frame`` is an image's file name (or its index in that order), ``label`` the place it shows
(any text: a room name, a segment number; empty for a frame without one). With labels every
metric of :func:`placeclust.metrics.score` can be computed; without them a run gives places,
graph and latency only. A folder is never loaded whole: :class:`ImageFolder` is a sequence
that decodes frame ``t`` when asked, so a recognizer's memory, not the sequence's length,
bounds a run.

Every problem with a folder raises :class:`DatasetError` (a ``ValueError``) naming the file:
a missing folder, no images, an image OpenCV cannot read, a labels file whose rows do not
match the images.

Examples:
    >>> import tempfile
    >>> import numpy as np
    >>> from placeclust.datasets import ImageFolder, write_image_folder
    >>> folder = tempfile.mkdtemp()
    >>> frames = np.random.default_rng(0).integers(0, 255, (3, 32, 48, 3), np.uint8)
    >>> paths = write_image_folder(folder, frames, labels=["hall", "hall", "lab"])
    >>> images = ImageFolder(folder)
    >>> len(images), images[2].shape, images.labels.tolist(), images.label_names
    (3, (32, 48, 3), [0, 0, 1], ['hall', 'lab'])
"""

from __future__ import annotations

import csv
import re
from collections.abc import Iterator, Sequence
from pathlib import Path

import cv2
import numpy as np

#: image file suffixes an image folder is made of (case-insensitive)
SUFFIXES = (".png", ".jpg", ".jpeg")
LABELS = "labels.csv"
#: the columns of ``labels.csv``: the first two are required, the pose and condition optional
COLUMNS = ("frame", "label", "x", "y", "heading", "condition")


class DatasetError(ValueError):
    """A folder that cannot be read as a sequence; the message names the file and the
    problem."""


def natural_key(name: str) -> list[object]:
    """Sort key that puts ``img2`` before ``img10`` (digit runs compared as numbers)."""
    return [int(part) if part.isdigit() else part.lower() for part in re.split(r"(\d+)", name)]


def image_files(folder: str | Path) -> list[Path]:
    """The images of ``folder`` (:data:`SUFFIXES`) in natural order.

    Raises:
        DatasetError: the folder is missing or holds no image.
    """
    path = Path(folder)
    if path.is_file():
        raise DatasetError(f"{path} is a file; give the folder that holds the images"
                           + (f" ({path.parent})" if path.suffix.lower() in SUFFIXES else ""))
    if not path.is_dir():
        raise DatasetError(f"image folder {path} does not exist")
    files = sorted((f for f in path.iterdir() if f.suffix.lower() in SUFFIXES and f.is_file()),
                   key=lambda f: natural_key(f.name))
    if not files:
        raise DatasetError(f"{path} holds no image ({', '.join(SUFFIXES)})")
    return files


def read_image(path: Path) -> np.ndarray:
    """One image as ``(H, W, 3)`` uint8 RGB (what the recognizers and the simulator use).

    Raises:
        DatasetError: OpenCV cannot decode it (damaged, empty, not an image).
    """
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        raise DatasetError(f"cannot read image {path}: damaged or not an image")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


class ImageFolder(Sequence[np.ndarray]):
    """An ordered folder of images as a lazy sequence of ``(H, W, 3)`` RGB frames.

    Args:
        folder: the folder (see the module docstring for its layout).
        labels: read ``labels.csv`` when present (False: ignore it).

    Attributes:
        files: the images, in natural order.
        labels: ``(T,)`` int64 place per frame (-1 where the label is empty), or ``None``
            without ``labels.csv``; ids number :attr:`label_names` in order of first
            appearance.
        label_names: the label text of each id.
        poses: ``(T, 3)`` float ``x, y, heading`` per frame, or ``None`` if not given.
        conditions: the ``condition`` column per frame, or ``None`` if not given.

    Raises:
        DatasetError: see :func:`image_files` and :func:`read_labels`. Every image's header is
            checked here (``cv2.haveImageReader``), so a folder with a file that is not an image
            fails before any frame is used; a file damaged past its header fails when read.
    """

    def __init__(self, folder: str | Path, labels: bool = True) -> None:
        self.path = Path(folder)
        self.files = image_files(self.path)
        for f in self.files:
            if not cv2.haveImageReader(str(f)):
                raise DatasetError(f"cannot read image {f}: not a png or jpg OpenCV can decode")
        self.labels: np.ndarray | None = None
        self.label_names: list[str] = []
        self.poses: np.ndarray | None = None
        self.conditions: list[str] | None = None
        table = self.path / LABELS
        if labels and table.exists():
            self.labels, self.label_names, self.poses, self.conditions = read_labels(
                table, [f.name for f in self.files])

    def __len__(self) -> int:
        return len(self.files)

    def __getitem__(self, t: int) -> np.ndarray:  # type: ignore[override]
        # a sequence of frames, not of slices: a recognizer reads frame by frame
        return read_image(self.files[t])

    def __iter__(self) -> Iterator[np.ndarray]:
        for f in self.files:
            yield read_image(f)

    def __repr__(self) -> str:
        labelled = f", {len(self.label_names)} labels" if self.labels is not None else ""
        return f"ImageFolder({str(self.path)!r}, {len(self)} frames{labelled})"


def read_labels(path: Path, names: list[str]
                ) -> tuple[np.ndarray, list[str], np.ndarray | None, list[str] | None]:
    """``labels.csv`` for the images ``names`` (in order): ``(labels, label_names, poses,
    conditions)`` as :class:`ImageFolder` keeps them.

    Raises:
        DatasetError: no ``frame`` and ``label`` columns, a row naming no image of the folder,
            an image without a row or with two, or a pose that is not a number; the message
            names the file, and the row where one is at fault.
    """
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        fields = reader.fieldnames or []
        if "frame" not in fields or "label" not in fields:
            raise DatasetError(f"{path} must have the columns frame,label (it has {fields})")
        rows = list(reader)
    index = {name: t for t, name in enumerate(names)}
    order: list[dict[str, str] | None] = [None] * len(names)
    for line, row in enumerate(rows, start=2):
        t = _frame_index(row["frame"] or "", index, len(names))
        if t is None:
            raise DatasetError(f"{path} line {line}: frame {row['frame']!r} is not an image "
                               f"of {path.parent}")
        if order[t] is not None:
            raise DatasetError(f"{path} line {line}: frame {row['frame']!r} is labelled twice")
        order[t] = row
    missing = [names[t] for t, row in enumerate(order) if row is None]
    if missing:
        raise DatasetError(f"{path} has no row for {len(missing)} of the {len(names)} images "
                           f"(first: {missing[0]})")
    table: list[dict[str, str]] = [row for row in order if row is not None]
    label_names = list(dict.fromkeys(r["label"] for r in table if r["label"]))
    ids = {name: i for i, name in enumerate(label_names)}
    labels = np.array([ids.get(r["label"], -1) for r in table], np.int64)
    poses = _poses(path, table) if {"x", "y", "heading"} <= set(fields) else None
    conditions = [r["condition"] or "" for r in table] if "condition" in fields else None
    return labels, label_names, poses, conditions


def _frame_index(text: str, index: dict[str, int], n: int) -> int | None:
    """The image a ``frame`` cell names: a file name of the folder, or an index into it."""
    if text in index:
        return index[text]
    if text.strip().isdigit() and int(text) < n:
        return int(text)
    return None


def _poses(path: Path, table: list[dict[str, str]]) -> np.ndarray:
    try:
        return np.array([[float(r["x"]), float(r["y"]), float(r["heading"])] for r in table])
    except (TypeError, ValueError) as exc:
        raise DatasetError(f"{path}: x, y and heading must be numbers ({exc})") from exc


def write_image_folder(folder: str | Path, frames: Sequence[np.ndarray] | np.ndarray,
                       labels: Sequence[object] | np.ndarray | None = None,
                       poses: np.ndarray | None = None, condition: str | None = None,
                       suffix: str = ".png") -> list[Path]:
    """Write ``frames`` (RGB or greyscale uint8) as an image folder, with ``labels.csv`` when
    ``labels`` are given (``poses``: ``(T, 3)`` x, y, heading; ``condition``: one for all).

    The inverse of :class:`ImageFolder`: reading the folder back gives the same frames (png is
    lossless) and labels. Returns the image paths.
    """
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    digits = max(6, len(str(len(frames) - 1)))
    paths = []
    for t, frame in enumerate(frames):
        image = np.asarray(frame)
        if image.ndim == 3:
            image = cv2.cvtColor(np.ascontiguousarray(image[..., :3]), cv2.COLOR_RGB2BGR)
        paths.append(out / f"{t:0{digits}d}{suffix}")
        if not cv2.imwrite(str(paths[-1]), image):
            raise DatasetError(f"cannot write image {paths[-1]}")
    if labels is not None:
        columns = ["frame", "label"] + (["x", "y", "heading"] if poses is not None else []) \
            + (["condition"] if condition is not None else [])
        with open(out / LABELS, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(columns)
            for t, (path, label) in enumerate(zip(paths, labels)):
                pose = [f"{v:.4f}" for v in poses[t]] if poses is not None else []
                writer.writerow([path.name, label, *pose,
                                 *([condition] if condition is not None else [])])
    return paths
