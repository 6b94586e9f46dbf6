"""The camera a data set was taken with: image size, colour and field of view.

A simulator can only be asked a real data set's question if it looks through the same camera:
a recognizer that wins on 512×128 colour panoramas may lose on 160×120 grey forward frames.
:func:`camera_of` reads what a folder's images say of their camera, and its ``camera.json``
for what they cannot say::

    DIR/camera.json    optional: {"horizontal_fov": 60.0, "colour": false, "note": "...",
                                  "sensor": {"blur": 1.5, "read_noise": 2}}

- **size**: read from the first image (every image of a data set is taken to share it; the
  recognizers do not need that, a matched simulator does);
- **colour**: ``camera.json``'s ``colour``, else from the pixels: a frame is grey when its
  three channels differ by at most :data:`GREY_TOLERANCE` grey levels at the 99th percentile
  (JPEG's chroma rounding leaves a few levels in a grey picture);
- **horizontal field of view**: ``camera.json``'s ``horizontal_fov`` (degrees), else
  :data:`DEFAULT_FOV`, and :attr:`CameraSpec.fov_source` says which;
- **sensor effects** (:func:`sensor_of`): ``camera.json``'s ``sensor``, the effects a
  simulator should add to its clean renders to look like this camera (blur, noise, exposure:
  the names of ``envs.world.sensor.Sensor``, which checks them). A data set cannot measure
  them; they are chosen on image statistics (``placeclust stats``) and written down, so every
  later comparison renders through the same camera.

For a VPR-Bench folder the images of ``ref/`` are read and ``camera.json`` is looked for at
its top. A data set you cannot write to is described by a camera file elsewhere
(``described_by``; the command lines' ``--camera-file``), read instead of its own.

Examples:
    >>> import tempfile
    >>> import numpy as np
    >>> from placeclust.camera import camera_of
    >>> from placeclust.datasets import write_image_folder
    >>> folder = tempfile.mkdtemp()
    >>> grey = np.repeat(np.random.default_rng(0).integers(0, 255, (2, 30, 40, 1), np.uint8),
    ...                  3, axis=3)
    >>> _ = write_image_folder(folder, grey)
    >>> camera = camera_of(folder)
    >>> camera.width, camera.height, camera.colour, camera.fov, camera.fov_source
    (40, 30, False, 60.0, 'default')
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.datasets import DatasetError, image_files, read_image
from placeclust.vprbench import is_vpr_bench

#: the metadata file a data set may describe its camera in
CAMERA_FILE = "camera.json"
#: the horizontal field of view, degrees, of a data set that does not state one: a common
#: webcam's (Logitech C270: 60°; the corridor's own paper gives none)
DEFAULT_FOV = 60.0
#: the most two channels of a grey frame differ by, at the 99th percentile (JPEG rounding)
GREY_TOLERANCE = 4
#: frames read to decide colour: spread over the sequence, a few are enough
_COLOUR_SAMPLES = 5


@dataclass(frozen=True)
class CameraSpec:
    """A camera as a simulator needs it to render like a data set.

    Attributes:
        width, height: image size in pixels.
        colour: False for a grey (monochrome) camera.
        fov: horizontal field of view in degrees.
        fov_source: ``"camera.json"`` where a camera file states it (the data set's or one
            named for it), ``"default"`` where it is :data:`DEFAULT_FOV`.
    """

    width: int
    height: int
    colour: bool
    fov: float
    fov_source: str = "default"

    def __post_init__(self) -> None:
        if self.width < 16 or self.height < 16:
            raise ValueError(f"a camera of {self.width}x{self.height} is too small; need at "
                             "least 16 pixels a side")
        if not (math.isfinite(self.fov) and 10 <= self.fov < 170):
            raise ValueError(f"horizontal field of view {self.fov}° is out of [10, 170)")

    @property
    def fovy(self) -> float:
        """The vertical field of view, degrees, of square pixels."""
        half = math.atan(math.tan(math.radians(self.fov) / 2) * self.height / self.width)
        return math.degrees(2 * half)

    def as_dict(self) -> dict[str, Any]:
        """Its fields, for a results file."""
        return asdict(self)

    def describe(self) -> str:
        """One line: ``160×120 grey, 60° wide (default)``."""
        source = "stated" if self.fov_source == CAMERA_FILE else self.fov_source
        return (f"{self.width}×{self.height} {'colour' if self.colour else 'grey'}, "
                f"{self.fov:g}° wide ({source})")


def is_grey(frame: np.ndarray, tolerance: int = GREY_TOLERANCE) -> bool:
    """True when an (H, W, 3) frame's channels agree within ``tolerance`` grey levels at the
    99th percentile (a single-channel frame is grey)."""
    if frame.ndim == 2 or frame.shape[2] == 1:
        return True
    f = frame.astype(np.int16)
    spread = np.maximum(np.abs(f[..., 0] - f[..., 1]), np.abs(f[..., 1] - f[..., 2]))
    return float(np.percentile(spread, 99)) <= tolerance


def _metadata(folder: Path, described_by: str | Path | None = None) -> dict[str, Any]:
    """The camera file (``described_by``, else ``folder``'s ``camera.json``; empty without
    one), its values checked."""
    path = folder / CAMERA_FILE if described_by is None else Path(described_by)
    if described_by is not None and not path.is_file():
        raise DatasetError(f"camera file {path} does not exist")
    if not path.exists():
        return {}
    try:
        meta = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise DatasetError(f"{path} is not JSON: {err}") from None
    if not isinstance(meta, dict):
        raise DatasetError(f"{path} must hold a JSON object, got {type(meta).__name__}")
    fov = meta.get("horizontal_fov")
    if fov is not None and (isinstance(fov, bool) or not isinstance(fov, (int, float))):
        raise DatasetError(f"{path}: horizontal_fov must be a number of degrees, got {fov!r}")
    if "colour" in meta and not isinstance(meta["colour"], bool):
        raise DatasetError(f"{path}: colour must be true or false, got {meta['colour']!r}")
    sensor = meta.get("sensor", {})
    if not isinstance(sensor, dict) or not all(
            isinstance(v, (bool, int, float)) for v in sensor.values()):
        raise DatasetError(f"{path}: sensor must be an object of settings to numbers or "
                           f"true/false, e.g. {{\"blur\": 1.5}}, got {sensor!r}")
    return meta


def camera_of(folder: str | Path, described_by: str | Path | None = None) -> CameraSpec:
    """The camera of a data set: an image folder or a VPR-Bench folder (its ``ref/``);
    ``described_by``, a camera file read instead of the folder's ``camera.json``.

    Returns:
        Its :class:`CameraSpec`: size from the first image, colour from ``camera.json`` or the
        pixels of a few frames, field of view from ``camera.json`` or :data:`DEFAULT_FOV`.

    Raises:
        DatasetError: no images, an unreadable image or camera file, or a stated field of
            view out of range (the message names the file).
    """
    root = Path(folder)
    files = image_files(root / "ref" if is_vpr_bench(root) else root)
    meta = _metadata(root, described_by)
    first = read_image(files[0])
    if "colour" in meta:
        colour = bool(meta["colour"])
    else:
        picks = np.linspace(0, len(files) - 1, min(_COLOUR_SAMPLES, len(files))).astype(int)
        colour = not all(is_grey(read_image(files[i])) for i in picks)
    fov = meta.get("horizontal_fov")
    try:
        return CameraSpec(int(first.shape[1]), int(first.shape[0]), colour,
                          float(fov if fov is not None else DEFAULT_FOV),
                          CAMERA_FILE if fov is not None else "default")
    except ValueError as err:
        raise DatasetError(f"{root}: {err}") from None


def sensor_of(folder: str | Path, described_by: str | Path | None = None
              ) -> dict[str, bool | int | float]:
    """The sensor effects a data set's camera file states (its ``"sensor"`` object; empty
    without one), as written: names and ranges are the simulator's to check.

    Example:
        >>> import json, tempfile
        >>> from pathlib import Path
        >>> folder = Path(tempfile.mkdtemp())
        >>> _ = (folder / "camera.json").write_text(json.dumps({"sensor": {"blur": 1.5}}))
        >>> sensor_of(folder)
        {'blur': 1.5}

    Raises:
        DatasetError: the camera file is not JSON, or its ``sensor`` not an object of numbers.
    """
    return dict(_metadata(Path(folder), described_by).get("sensor", {}))
