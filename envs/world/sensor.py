"""What a real camera adds to a rendered frame: motion blur, a soft lens, vignetting,
exposure, noise, grey sensors and JPEG.

The renderer draws a perfect pinhole picture. Real frames are smeared while the robot turns,
darker at the corners, over- or under-exposed, noisy (photon noise grows with the light, read
noise does not), often grey, and compressed. Recognition lives in exactly those details (how
many keypoints a frame yields, how many survive to the next frame), so a simulator that is to
rank recognizers as real images do needs them. :class:`Sensor` applies them in the order light
meets a camera: optics (motion blur, lens blur, vignetting), the sensor (exposure gain, photon
and read noise, quantization to 8 bits), then the encoder (JPEG).

Every effect is off by default, and a :class:`Sensor` with none leaves a frame untouched (the
same array, not a copy). The Gymnasium wrapper :class:`envs.tasks.camera_sensor.CameraSensor`
puts one on any env's camera; ``placeclust tour --sensor NAME=VALUE`` and ``placeclust like
DATASET`` use it, the latter with the effects a data set's camera file states
(:meth:`Sensor.of`; ``assets/cameras/`` holds those measured here). Each effect's
cost against a bare render is measured in ``docs/benchmarks.md`` ("A camera like a data
set's").

Examples:
    >>> import numpy as np
    >>> from envs.world.sensor import Sensor
    >>> frame = np.full((4, 6, 3), 200, np.uint8)
    >>> Sensor(grey=True, exposure=-1.0).apply(frame, np.random.default_rng(0))[0, 0].tolist()
    [100, 100, 100]
    >>> Sensor().apply(frame, np.random.default_rng(0)) is frame
    True
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

import cv2
import numpy as np

#: luminance weights of a grey sensor's response (ITU-R BT.601, what OpenCV's grey uses)
LUMA = np.array([0.299, 0.587, 0.114], np.float32)


@dataclass(frozen=True)
class Sensor:
    """A camera's effects on a rendered (H, W, 3) uint8 frame; each 0 (or False) is off.

    Args:
        grey: a monochrome sensor: the frame's luminance in all three channels.
        exposure: gain in stops (EV): the frame times ``2**exposure``, clipped at 255 (a
            positive value burns out bright walls, a negative one sinks dark corners).
        shot_noise: photon noise: a pixel of ``I`` grey levels gets Gaussian noise of variance
            ``shot_noise * I`` (grey levels squared), so bright pixels are noisier.
        read_noise: the sensor's signal-independent noise, standard deviation in grey levels.
        motion_blur: exposure time in seconds: while the robot turns at ``w`` rad/s the frame
            is smeared horizontally over ``w * motion_blur * focal`` pixels.
        blur: a soft lens or slight defocus: a Gaussian blur of this standard deviation in
            pixels (a rendered frame is sharper than any real lens makes it).
        vignetting: relative fall-off of light at the image's corners (0.3: corners get 70%),
            quadratic in the distance from the centre.
        jpeg: JPEG quality, 1-100 (0: no compression).
    """

    grey: bool = False
    exposure: float = 0.0
    shot_noise: float = 0.0
    read_noise: float = 0.0
    motion_blur: float = 0.0
    blur: float = 0.0
    vignetting: float = 0.0
    jpeg: int = 0

    def __post_init__(self) -> None:
        for name in ("exposure", "shot_noise", "read_noise", "motion_blur", "blur",
                     "vignetting"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise ValueError(f"sensor {name} must be a finite number, got {value!r}")
            if name != "exposure" and value < 0:
                raise ValueError(f"sensor {name} must be non-negative, got {value}")
        if abs(self.exposure) > 8:
            raise ValueError(f"sensor exposure must be within ±8 stops, got {self.exposure}")
        if self.vignetting > 1:
            raise ValueError(f"sensor vignetting is a fall-off in [0, 1], got {self.vignetting}")
        if isinstance(self.jpeg, bool) or not isinstance(self.jpeg, int) \
                or not 0 <= self.jpeg <= 100:
            raise ValueError(f"sensor jpeg is a quality in 1-100 (0: off), got {self.jpeg!r}")

    @classmethod
    def parse(cls, items: list[str] | None, base: Sensor | None = None) -> Sensor:
        """A sensor from ``NAME=VALUE`` strings, as ``--sensor grey=1 jpeg=75`` gives them,
        each replacing ``base``'s setting (default: every effect off).

        Raises:
            ValueError: an unknown name or a value of the wrong kind, named.
        """
        values: dict[str, Any] = {}
        for item in items or []:
            name, sep, text = item.partition("=")
            if not sep or name not in _KINDS:
                raise ValueError(f"sensor setting {item!r}: expected NAME=VALUE with NAME one of "
                                 f"{', '.join(_KINDS)}")
            try:
                if name == "grey":
                    if text.lower() not in ("0", "1", "true", "false"):
                        raise ValueError
                    values[name] = text.lower() in ("1", "true")
                else:
                    values[name] = _KINDS[name](text)
            except ValueError:
                raise ValueError(f"sensor setting {item!r}: {text!r} is not a "
                                 f"{'true/false' if name == 'grey' else 'number'}") from None
        return replace(base or cls(), **values)

    @classmethod
    def of(cls, settings: Mapping[str, Any], where: str = "sensor") -> Sensor:
        """A sensor from a mapping of settings, as a data set's ``camera.json`` states them
        (``{"blur": 1.5, "grey": true}``; :func:`placeclust.camera.sensor_of`).

        Raises:
            ValueError: an unknown name or a value of the wrong kind, named with ``where``.
        """
        for name, value in settings.items():
            if name not in _KINDS:
                raise ValueError(f"{where}: unknown sensor setting {name!r}; one of "
                                 f"{', '.join(_KINDS)}")
            kind = _KINDS[name]
            ok = isinstance(value, bool) if kind is bool else not isinstance(value, bool) \
                and isinstance(value, (int, float) if kind is float else int)
            if not ok:
                raise ValueError(f"{where}: sensor setting {name} must be "
                                 f"{_KIND_NAMES[kind]}, got {value!r}")
        try:
            values: dict[str, Any] = {name: float(v) if _KINDS[name] is float else v
                                      for name, v in settings.items()}
            return cls(**values)
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from None

    @property
    def active(self) -> bool:
        """True when it changes a frame at all."""
        return any(bool(v) for v in asdict(self).values())

    def as_dict(self) -> dict[str, Any]:
        """Its settings that are on, for a results file and a table's caption."""
        return {k: v for k, v in asdict(self).items() if v}

    def apply(self, frame: np.ndarray, rng: np.random.Generator, blur_px: float = 0.0
              ) -> np.ndarray:
        """``frame`` as this camera would have taken it.

        Args:
            frame: (H, W, 3) uint8, as rendered.
            rng: draws the noise.
            blur_px: the horizontal motion-blur length in pixels (the wrapper computes it
                from the robot's turn rate and :attr:`motion_blur`).

        Returns:
            A new (H, W, 3) uint8 frame, or ``frame`` itself when no effect is on.
        """
        if not self.active:
            return frame
        out = frame.astype(np.float32)
        if self.grey:  # a mono sensor sees luminance; keep three channels for the obs space
            out = np.repeat((out @ LUMA)[..., None], 3, axis=2)
        if blur_px >= 1.0:
            out = _smear(out, blur_px)
        if self.blur:
            out = np.asarray(cv2.GaussianBlur(out, (0, 0), self.blur,
                                              borderType=cv2.BORDER_REFLECT), np.float32)
        if self.vignetting:
            out *= _falloff(out.shape[0], out.shape[1], self.vignetting)[..., None]
        if self.exposure:
            out *= 2.0 ** self.exposure
        out = np.clip(out, 0, 255)
        if self.shot_noise or self.read_noise:
            sigma = np.sqrt(self.shot_noise * out + self.read_noise ** 2)
            noise = rng.standard_normal(out.shape[:2] if self.grey else out.shape,
                                        dtype=np.float32)
            out += sigma * (noise[..., None] if self.grey else noise)
        result = np.clip(np.rint(out), 0, 255).astype(np.uint8)
        if self.jpeg:
            result = _jpeg(result, self.jpeg)
        return result


#: each setting's type, in the order the fields are declared (the order effects are listed in)
_KINDS: dict[str, type] = {f.name: {"bool": bool, "int": int}.get(str(f.type), float)
                           for f in fields(Sensor)}
_KIND_NAMES = {bool: "true or false", int: "a whole number", float: "a number"}


def _smear(image: np.ndarray, length: float) -> np.ndarray:
    """A horizontal box blur of ``length`` pixels: a yaw during the exposure."""
    n = max(1, int(round(length)))
    kernel = np.full((1, n), 1.0 / n, np.float32)
    return cv2.filter2D(image, -1, kernel, borderType=cv2.BORDER_REFLECT)


@functools.lru_cache(maxsize=8)  # one camera size and setting per env: computed once
def _falloff(height: int, width: int, strength: float) -> np.ndarray:
    """(H, W) gain, 1 at the centre and ``1 - strength`` at the corner pixels, quadratic in
    the distance from the centre."""
    y = np.linspace(-1.0, 1.0, height, dtype=np.float32)
    x = np.linspace(-1.0, 1.0, width, dtype=np.float32)
    r2 = (x[None, :] ** 2 + y[:, None] ** 2) / 2.0  # 1 at the corners
    gain = 1.0 - strength * r2
    gain.flags.writeable = False  # shared by every call of this size
    return gain


def _jpeg(image: np.ndarray, quality: int) -> np.ndarray:
    """``image`` encoded as JPEG at ``quality`` and decoded again."""
    ok, data = cv2.imencode(".jpg", image[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:  # OpenCV encodes any uint8 BGR image; this is a broken build
        raise RuntimeError("OpenCV could not encode a JPEG")
    decoded = cv2.imdecode(data, cv2.IMREAD_COLOR)
    if decoded is None:  # cannot happen for what imencode just wrote
        raise RuntimeError("OpenCV could not decode its own JPEG")
    return decoded[..., ::-1].copy()
