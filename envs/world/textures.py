"""Deterministic procedural textures: walls, floors, posters and furniture.

Every generator takes an explicit ``np.random.Generator`` and returns an ``(H, W, 3)`` uint8 RGB
array; nothing is downloaded. Walls carry small random marks on top of their pattern so that local
feature detectors (SIFT, ORB, ...) find keypoints on every wall: a bare flat wall would give a
place recognizer nothing to match. Posters are the most distinctive element of a room.
"""

from __future__ import annotations

import json
import string
from collections.abc import Callable, Iterable
from functools import cache
from pathlib import Path

import cv2
import mujoco
import numpy as np

# In a clone (and an editable install) the assets are the repository's top-level folder; a wheel
# installs them as this package's data (pyproject.toml maps assets/ to placeclust_envs/assets/).
_PACKAGE = Path(__file__).resolve().parent.parent
ASSETS = _PACKAGE / "assets" if (_PACKAGE / "assets").is_dir() else _PACKAGE.parent / "assets"
TEX = 256  # side of wall/floor textures, pixels

Color = tuple[int, int, int]


@cache
def room_styles() -> dict[str, dict]:
    """Room kind -> style (wall/floor colour and pattern), from ``assets/room_styles.json``."""
    with open(ASSETS / "room_styles.json") as f:
        styles = json.load(f)
    styles.pop("_comment", None)
    return styles


def _color(values: Iterable[float]) -> Color:
    """Three channel values as a :data:`Color` of ints."""
    r, g, b = (int(v) for v in values)
    return r, g, b


def _jitter(color: Color, rng: np.random.Generator, amount: float) -> Color:
    c = np.asarray(color, float) + rng.normal(0.0, amount, 3)
    return _color(np.clip(c, 0, 255))


def _noise(rng: np.random.Generator, size: int, scale: int, amp: float) -> np.ndarray:
    """Smooth value noise of the given feature scale (pixels), zero mean, shape (size, size, 1)."""
    coarse = rng.normal(0.0, 1.0, (max(2, size // scale),) * 2).astype(np.float32)
    return cv2.resize(coarse, (size, size), interpolation=cv2.INTER_CUBIC)[..., None] * amp


def _finish(img: np.ndarray, rng: np.random.Generator, grain: float = 6.0) -> np.ndarray:
    img = img.astype(np.float32) + _noise(rng, img.shape[0], 32, 10.0)
    img += rng.normal(0.0, grain, img.shape[:2])[..., None]
    return np.clip(img, 0, 255).astype(np.uint8)


def _marks(img: np.ndarray, rng: np.random.Generator, n: int, base: Color) -> None:
    """Scatter small dark or light shapes (scuffs, sockets, pins): keypoints on plain walls."""
    h, w = img.shape[:2]
    for _ in range(n):
        dark = rng.random() < 0.6
        shade = np.asarray(base, float) * (0.35 if dark else 1.4)
        col = tuple(int(v) for v in np.clip(shade + rng.normal(0, 25, 3), 0, 255))
        x, y = int(rng.integers(w)), int(rng.integers(h))
        s = int(rng.integers(3, 10))
        kind = rng.integers(4)
        if kind == 0:
            cv2.circle(img, (x, y), s, col, -1, cv2.LINE_AA)
        elif kind == 1:
            cv2.rectangle(img, (x, y), (x + s, y + int(rng.integers(3, 12))), col, -1)
        elif kind == 2:
            cv2.line(img, (x, y), (x + int(rng.integers(-15, 15)), y + int(rng.integers(-15, 15))),
                     col, int(rng.integers(1, 3)), cv2.LINE_AA)
        else:
            pts = np.stack([rng.integers(-s, s, 3) + x, rng.integers(-s, s, 3) + y], 1)
            cv2.fillPoly(img, [pts.astype(np.int32)], col, cv2.LINE_AA)


def _plaster(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.empty((TEX, TEX, 3), np.float32)
    img[:] = base
    img += _noise(rng, TEX, 8, 14.0)
    return img.clip(0, 255).astype(np.uint8)


def _bricks(base: Color, rng: np.random.Generator) -> np.ndarray:
    mortar = tuple(int(c * 0.7) for c in base)
    img = np.full((TEX, TEX, 3), mortar, np.uint8)
    bh, bw = 16, 48
    for row in range(TEX // bh):
        off = (row % 2) * bw // 2
        for col in range(-1, TEX // bw + 1):
            x0, y0 = col * bw + off + 2, row * bh + 2
            cv2.rectangle(img, (x0, y0), (x0 + bw - 4, y0 + bh - 4), _jitter(base, rng, 18), -1)
    return img


def _tiles(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.full((TEX, TEX, 3), tuple(int(c * 0.6) for c in base), np.uint8)
    t = 32
    for y in range(0, TEX, t):
        for x in range(0, TEX, t):
            cv2.rectangle(img, (x + 1, y + 1), (x + t - 2, y + t - 2), _jitter(base, rng, 12), -1)
    return img


def _stripes(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.empty((TEX, TEX, 3), np.uint8)
    x = 0
    other = _jitter(_color(255 - c // 2 for c in base), rng, 20)
    while x < TEX:
        w = int(rng.integers(6, 28))
        img[:, x:x + w] = base if rng.random() < 0.6 else other
        x += w
    return img


def _wallpaper(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.full((TEX, TEX, 3), base, np.uint8)
    motif = _jitter(_color(c * 0.55 for c in base), rng, 20)
    step = 32
    for j, y in enumerate(range(step // 2, TEX, step)):
        for x in range(step // 2 + (j % 2) * step // 2, TEX, step):
            s = 6
            pts = np.array([[x, y - s], [x + s, y], [x, y + s], [x - s, y]], np.int32)
            cv2.fillPoly(img, [pts], motif, cv2.LINE_AA)
    return img


def _panels(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.full((TEX, TEX, 3), base, np.uint8)
    frame = tuple(int(c * 0.7) for c in base)
    for x in range(0, TEX, 64):
        cv2.rectangle(img, (x + 6, 10), (x + 58, TEX - 10), frame, 2, cv2.LINE_AA)
    cv2.line(img, (0, TEX - 30), (TEX, TEX - 30), frame, 3)
    return img


def _checker(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.empty((TEX, TEX, 3), np.uint8)
    t = 32
    light = tuple(min(255, int(c * 1.3) + 40) for c in base)
    for y in range(0, TEX, t):
        for x in range(0, TEX, t):
            img[y:y + t, x:x + t] = base if ((x + y) // t) % 2 else light
    return img


def _planks(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.empty((TEX, TEX, 3), np.float32)
    for y in range(0, TEX, 24):
        img[y:y + 24] = _jitter(base, rng, 14)
        img[y:y + 1] *= 0.5
    grain = np.sin(np.linspace(0, 60, TEX))[None, :, None] * 8.0
    return (img + grain).clip(0, 255).astype(np.uint8)


def _carpet(base: Color, rng: np.random.Generator) -> np.ndarray:
    img = np.empty((TEX, TEX, 3), np.float32)
    img[:] = base
    img += _noise(rng, TEX, 4, 12.0) + rng.normal(0, 14, (TEX, TEX))[..., None]
    return img.clip(0, 255).astype(np.uint8)


PATTERNS: dict[str, Callable[[Color, np.random.Generator], np.ndarray]] = {
    "plaster": _plaster, "bricks": _bricks, "tiles": _tiles, "stripes": _stripes,
    "wallpaper": _wallpaper, "panels": _panels, "checker": _checker, "planks": _planks,
    "carpet": _carpet,
}


def wall_texture(kind: str, rng: np.random.Generator, marks: int = 60) -> np.ndarray:
    """The wall texture of a room of ``kind``: its style's pattern plus ``marks`` small shapes."""
    style = room_styles()[kind]
    base = _jitter(tuple(style["wall"]), rng, 6)
    img = PATTERNS[style["wall_pattern"]](base, rng)
    _marks(img, rng, marks, base)
    return _finish(img, rng)


def floor_texture(kind: str, rng: np.random.Generator) -> np.ndarray:
    """The floor texture of a room of ``kind``."""
    style = room_styles()[kind]
    base = _jitter(tuple(style["floor"]), rng, 6)
    img = PATTERNS[style["floor_pattern"]](base, rng)
    _marks(img, rng, 25, base)
    return _finish(img, rng)


def poster_texture(rng: np.random.Generator, width: int = 128, height: int = 160) -> np.ndarray:
    """A random poster: coloured shapes and lines of random letters in a frame."""
    bg = tuple(int(v) for v in rng.integers(20, 235, 3))
    img = np.full((height, width, 3), bg, np.uint8)
    for _ in range(int(rng.integers(4, 9))):
        col = tuple(int(v) for v in rng.integers(0, 256, 3))
        x, y = int(rng.integers(width)), int(rng.integers(height))
        s = int(rng.integers(8, 40))
        shape = rng.integers(3)
        if shape == 0:
            cv2.rectangle(img, (x - s, y - s // 2), (x + s, y + s // 2), col, -1)
        elif shape == 1:
            cv2.circle(img, (x, y), s // 2 + 3, col, -1, cv2.LINE_AA)
        else:
            pts = np.stack([rng.integers(0, width, 3), rng.integers(0, height, 3)], 1)
            cv2.fillPoly(img, [pts.astype(np.int32)], col, cv2.LINE_AA)
    ink = tuple(255 - c for c in bg)
    for line in range(int(rng.integers(1, 4))):
        text = "".join(rng.choice(list(string.ascii_uppercase + string.digits), 6))
        cv2.putText(img, text, (6, height - 12 - 22 * line), cv2.FONT_HERSHEY_SIMPLEX, 0.6,
                    ink, 2, cv2.LINE_AA)
    cv2.rectangle(img, (0, 0), (width - 1, height - 1), (30, 30, 30), 4)
    return img


def furniture_texture(rng: np.random.Generator) -> np.ndarray:
    """Wood, metal or painted surface with a few marks, for furniture boxes."""
    base = _color(rng.integers(40, 220, 3))
    img = _planks(base, rng) if rng.random() < 0.5 else _plaster(base, rng)
    _marks(img, rng, 30, base)
    return _finish(img, rng, grain=4.0)


def add_texture(spec: mujoco.MjSpec, name: str, img: np.ndarray) -> str:
    """Add ``img`` (H, W, 3 uint8, row 0 at the top) to ``spec`` as a 2D texture named ``name``."""
    tex = spec.add_texture(name=name, type=mujoco.mjtTexture.mjTEXTURE_2D,
                           width=img.shape[1], height=img.shape[0], nchannel=3)
    # MuJoCo stores 2D textures bottom row first relative to image convention: flip to upright.
    tex.data = np.ascontiguousarray(img[::-1]).tobytes()
    return name
