"""Geometry of the unwrapped 360° cylindrical panorama, built from a ring of pinhole cameras.

Pure numpy: no OpenGL here. :class:`PanoramaGeometry` says how large each camera image must be
and precomputes the ``cv2.remap`` maps that turn the strip of camera images, as read back from
OpenGL (bottom row first), into the panorama.

Conventions: column ``u`` of a ``W``-wide panorama looks at azimuth
``phi(u) = pi - 2*pi*(u + 0.5)/W`` relative to the robot heading (counter-clockwise positive), so
the heading is at the centre column, the robot's left at ``W/4`` and its right at ``3W/4``.
Turning the robot counter-clockwise by 90° therefore rolls the panorama right by ``W/4``
(``np.roll(pano, W // 4, axis=1)``). Rows are uniform in ``tan(elevation)`` (a cylinder), with
square pixels at the horizon unless ``vertical_fov`` is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

MIN_WIDTH, MIN_HEIGHT = 32, 8


def camera_yaw(k: ArrayLike, n_cameras: int) -> np.ndarray:
    """Yaw (radians, CCW from the heading) of camera ``k`` of a ring of ``n_cameras``: the one
    convention for the scene that mounts the cameras and the panorama that unwraps them.

    Examples:
        >>> camera_yaw([0, 1, 2, 3], 4).round(4).tolist()
        [0.0, 1.5708, 3.1416, 4.7124]
    """
    return 2 * math.pi * np.asarray(k) / n_cameras


@dataclass(frozen=True)
class PanoramaGeometry:
    """Camera ring and remap tables for a ``width`` x ``height`` panorama.

    Args:
        width: panorama width in pixels (360° of azimuth).
        height: panorama height in pixels.
        n_cameras: cameras in the ring, evenly spaced in yaw, camera ``k`` at ``2*pi*k/n``.
        vertical_fov: total vertical field of view in degrees; ``None`` gives square pixels at
            the horizon (``2*atan(pi*height/width)``, 76° for 512x128).
    """

    width: int
    height: int
    n_cameras: int = 4
    vertical_fov: float | None = None
    cam_width: int = field(init=False)
    cam_height: int = field(init=False)
    fovy: float = field(init=False)

    def __post_init__(self) -> None:
        if self.width < MIN_WIDTH or self.height < MIN_HEIGHT:
            raise ValueError(
                f"panorama size {self.width}x{self.height} is too small; "
                f"need at least {MIN_WIDTH}x{MIN_HEIGHT}"
            )
        if not 3 <= self.n_cameras <= 12:
            raise ValueError(f"n_cameras must be in [3, 12], got {self.n_cameras}")
        if self.vertical_fov is not None and not 1.0 <= self.vertical_fov <= 150.0:
            raise ValueError(f"vertical_fov must be in [1, 150] degrees, got {self.vertical_fov}")
        f = self.focal
        margin = 2.0 / f  # two pixels of overlap so bilinear lookups never leave a camera
        half_h = math.pi / self.n_cameras + margin
        cam_w = 2 * math.ceil(f * math.tan(half_h))
        cam_h = 2 * math.ceil(f * self.tan_top / math.cos(half_h))
        object.__setattr__(self, "cam_width", cam_w)
        object.__setattr__(self, "cam_height", cam_h)
        object.__setattr__(self, "fovy", math.degrees(2 * math.atan(cam_h / (2 * f))))

    @property
    def focal(self) -> float:
        """Focal length of every camera in pixels: one panorama column per pixel at the centre."""
        return self.width / (2 * math.pi)

    @property
    def tan_top(self) -> float:
        """tan of the elevation of the panorama's top edge."""
        if self.vertical_fov is None:
            return math.pi * self.height / self.width
        return math.tan(math.radians(self.vertical_fov) / 2)

    @property
    def strip_shape(self) -> tuple[int, int]:
        """(height, width) of the strip the cameras are rendered side by side into."""
        return (self.cam_height, self.cam_width * self.n_cameras)

    def azimuth(self) -> np.ndarray:
        """Azimuth in radians of each panorama column, relative to the heading (CCW positive)."""
        u = np.arange(self.width) + 0.5
        return math.pi - 2 * math.pi * u / self.width

    def remap_tables(self) -> tuple[np.ndarray, np.ndarray]:
        """``(map_x, map_y)`` float32 arrays of shape (height, width) for ``cv2.remap``.

        They sample the strip as OpenGL reads it back, bottom row first, so no separate flip is
        needed.
        """
        phi = self.azimuth()[None, :]
        v = np.arange(self.height)[:, None] + 0.5
        t = self.tan_top * (1 - 2 * v / self.height)  # tan(elevation) of each row
        step = 2 * math.pi / self.n_cameras
        k = np.round(phi / step).astype(int) % self.n_cameras  # nearest camera per column
        alpha = phi - camera_yaw(k, self.n_cameras)
        alpha = (alpha + math.pi) % (2 * math.pi) - math.pi
        f = self.focal
        col = self.cam_width / 2 + f * (-np.tan(alpha)) - 0.5
        row = self.cam_height / 2 - f * t / np.cos(alpha) - 0.5  # image row, top = 0
        map_x = np.broadcast_to(k * self.cam_width + col, (self.height, self.width))
        map_y = self.cam_height - 1 - row  # read-back rows are bottom first
        return map_x.astype(np.float32), map_y.astype(np.float32)
