"""Map files of :class:`~placeclust.online.OnlinePlaceClustering`: safe to write, checked to read.

A map file is a NumPy ``.npz`` archive read with ``allow_pickle=False`` (loading a file runs no
code): one JSON record (format name and version, constructor parameters, the world the map
was made in, the topological graph) and three arrays per place kernel. Saving writes a
temporary file beside the target and renames it over the target, so a process killed
mid-save leaves the old map or the new one, never a broken file.

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
    ('placeclust-map', 5, [0, 1], [[0, 1]])
    >>> loaded.n_places, loaded.current, loaded.features
    (2, 1, 'orb')
"""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from placeclust.atomic import write_atomic

if TYPE_CHECKING:
    from placeclust.online import OnlinePlaceClustering

FORMAT = "placeclust-map"
#: The format version written. :func:`load_map` reads older ones with the parameters their maps
#: were made with:
#: 2: the parameters include ``normalize``; version-1 maps were made from raw frames
#: 3: the parameters include ``scale``; older maps were made from full-size frames
#: 4: the parameters include ``view``; older maps hold features of the whole frame
#: 5: the parameters include ``scene_change``; older maps opened places without a gate
VERSION = 5


def save_map(model: OnlinePlaceClustering, path: str | os.PathLike, world: str = "") -> Path:
    """Write ``model``'s map to ``path`` atomically.

    Args:
        model: the recognizer whose map (kernels, graph, current place) is saved.
        path: target file; its folder must exist. An existing file is replaced only once the
            new one is complete.
        world: a fingerprint of the world the map was made in (e.g.
            ``PlaceNavEnv.world_id``); :func:`load_map` can insist on it.

    Returns:
        The path written.

    Raises:
        FileNotFoundError: the folder of ``path`` does not exist.
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"folder {path.parent} does not exist; cannot save the map there")
    meta = {
        "format": FORMAT,
        "version": VERSION,
        "class": type(model).__name__,
        "params": model.get_params(),
        "world": world,
        "current": int(model.current),
        "frame_shape": list(model.frame_shape) if model.frame_shape else None,
        "places": sorted(model.kernels),
        "kernel_images": {str(p): k.n_images for p, k in model.kernels.items()},
        "place_images": {str(p): int(d["n_images"]) for p, d in model.graph.nodes(data=True)},
        "edges": [[int(a), int(b)] for a, b in model.graph.edges()],
    }
    arrays = {"meta": np.array(json.dumps(meta))}
    for p, k in model.kernels.items():
        arrays[f"k{p}_desc"], arrays[f"k{p}_w"], arrays[f"k{p}_seen"] = (
            k.descriptors, k.weights, k.last_seen)
    return write_atomic(path, lambda f: np.savez(f, **arrays))


def read_meta(path: str | os.PathLike) -> tuple[dict, dict[str, np.ndarray]]:
    """The JSON record and arrays of a map file, or a ``ValueError`` saying what is wrong.

    Args:
        path: the map file.

    Returns:
        ``(meta, arrays)``: the JSON record and the kernel arrays by name.

    Raises:
        FileNotFoundError: there is no file at ``path``.
        ValueError: the file is not a readable placeclust map, or of a newer format version
            than :data:`VERSION`.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no map file at {path}")
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        meta = json.loads(str(arrays.pop("meta")))
    except (zipfile.BadZipFile, OSError, EOFError, KeyError, ValueError) as e:
        raise ValueError(f"{path} is not a readable placeclust map (corrupt or truncated?): "
                         f"{type(e).__name__}: {e}") from e
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"{path} is not a placeclust map (format {meta.get('format')!r})"
                         if isinstance(meta, dict) else f"{path} is not a placeclust map")
    if not isinstance(meta.get("version"), int) or meta["version"] > VERSION:
        raise ValueError(f"{path} has map format version {meta.get('version')!r}; this "
                         f"placeclust reads up to version {VERSION}: upgrade placeclust")
    return meta, arrays


def load_map(path: str | os.PathLike, world: str | None = None) -> OnlinePlaceClustering:
    """A recognizer restored from a map file written by :func:`save_map`.

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
    from placeclust.online import OnlinePlaceClustering

    meta, arrays = read_meta(path)
    if world is not None and meta.get("world") != world:
        raise ValueError(f"{path} is a map of world {meta.get('world')!r}, not of {world!r}")
    if meta.get("class") != OnlinePlaceClustering.__name__:
        raise ValueError(f"{path} holds a {meta.get('class')!r} map, not an "
                         f"{OnlinePlaceClustering.__name__} one")
    try:
        params = dict(meta["params"])
        if meta["version"] < 2:
            params.setdefault("normalize", None)  # the kernels hold features of raw frames
        if meta["version"] < 3:
            params.setdefault("scale", 1.0)  # ... and of full-size frames
        if meta["version"] < 4:
            params.setdefault("view", "full")  # ... and of the whole frame
        if meta["version"] < 5:
            params.setdefault("scene_change", None)  # ... and opened places without a gate
        model = OnlinePlaceClustering(**params)
        model.restore(
            kernels={p: (arrays[f"k{p}_desc"], arrays[f"k{p}_w"], arrays[f"k{p}_seen"],
                         meta["kernel_images"][str(p)]) for p in meta["places"]},
            place_images={int(p): n for p, n in meta["place_images"].items()},
            edges=meta["edges"], current=meta["current"], frame_shape=meta["frame_shape"])
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{path} is an inconsistent placeclust map: {type(e).__name__}: {e}"
                         ) from e
    return model
