"""Map files of :class:`~placeclust.online.OnlinePlaceClustering`: safe to write, checked to read.

A map file is a NumPy ``.npz`` archive read with ``allow_pickle=False`` (loading a file runs no
code): one JSON record (format name and version, constructor parameters, the world the map
was made in, the topological graph) and three arrays per place kernel. Saving writes a
temporary file beside the target and renames it over the target, so a process killed
mid-save leaves the old map or the new one, never a broken file.

:func:`save_map` and :func:`load_map` are ``model.save`` and ``OnlinePlaceClustering.load`` as
functions. The format itself lives in :mod:`placeclust.persistence`, below the recognizer, so
that the recognizer's methods and these functions share it without importing each other.

Examples:
    A map of two synthetic places, saved and loaded back:

    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from placeclust import OnlinePlaceClustering
    >>> from placeclust.mapfile import load_map, read_meta, save_map
    >>> from placeclust.synthetic import jitter, textured
    >>> rng = np.random.default_rng(0)
    >>> model = OnlinePlaceClustering(features="orb")
    >>> for img in [textured(1)] * 2 + [textured(2)] * 2:
    ...     model.learn_one(jitter(img, rng))
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = save_map(model, Path(folder) / "map.npz", world="demo")
    ...     meta, arrays = read_meta(path)
    ...     loaded = load_map(path, world="demo")
    >>> meta["format"], meta["version"], meta["places"], meta["edges"]
    ('placeclust-map', 6, [0, 1], [[0, 1]])
    >>> loaded.n_places, loaded.current, loaded.features
    (2, 1, 'orb')
"""

from __future__ import annotations

import os
from pathlib import Path

from placeclust.online import OnlinePlaceClustering
from placeclust.persistence import FORMAT, VERSION, MapPersistence, read_map, read_meta, write_map

__all__ = ["FORMAT", "VERSION", "MapPersistence", "load_map", "read_meta", "save_map"]


def save_map(model: OnlinePlaceClustering, path: str | os.PathLike, world: str = "") -> Path:
    """Write ``model``'s map to ``path`` atomically (``model.save``); the path written.

    The arguments and errors are :func:`placeclust.persistence.write_map`'s.
    """
    return write_map(model, path, world)


def load_map(path: str | os.PathLike, world: str | None = None) -> OnlinePlaceClustering:
    """A recognizer restored from a map file written by :func:`save_map`
    (``OnlinePlaceClustering.load``).

    Args:
        path: the map file.
        world: if given, the map must have been made in this world, else ``ValueError``.

    Returns:
        A new :class:`~placeclust.online.OnlinePlaceClustering` with the saved parameters,
        kernels, graph and current place. Maps of older format versions get the parameters
        they were made with (see :data:`VERSION`).

    Raises:
        FileNotFoundError: there is no file at ``path``.
        ValueError: the file is not a readable, consistent map of this class (and of
            ``world``, if given).
    """
    return read_map(OnlinePlaceClustering, path, world)
