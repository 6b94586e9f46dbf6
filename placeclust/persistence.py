"""The map-file format of :mod:`placeclust.mapfile`, and :class:`MapPersistence`: the mixin that
gives :class:`~placeclust.online.OnlinePlaceClustering` its ``get_params``, ``save``, ``load``
and ``restore``.

This module knows a recognizer only through the mixin's attributes and the class it is given,
so it imports none: :mod:`placeclust.online` builds on it, and :mod:`placeclust.mapfile`'s
``save_map`` and ``load_map`` call it with the recognizer.
"""

from __future__ import annotations

import inspect
import json
import os
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import networkx as nx
import numpy as np

from placeclust.atomic import write_atomic
from placeclust.features import FeatureExtractor
from placeclust.index import PlaceIndex
from placeclust.kernel import UnionKernel

FORMAT = "placeclust-map"
#: The format version written. :meth:`MapPersistence.load` reads older ones with the parameters
#: their maps were made with:
#: 2: the parameters include ``normalize``; version-1 maps were made from raw frames
#: 3: the parameters include ``scale``; older maps were made from full-size frames
#: 4: the parameters include ``view``; older maps hold features of the whole frame
#: 5: the parameters include ``scene_change``; older maps opened places without a gate
#: 6: ``merged`` lists the ids consolidation merged away; older maps merged none
VERSION = 6

_UNKNOWN = -1  # placeclust.online.UNKNOWN, which imports this module

#: A kernel's saved state: ``(descriptors, weights, last_seen, n_images)``.
KernelState = tuple[np.ndarray, np.ndarray, np.ndarray, int]

_Model = TypeVar("_Model", bound="MapPersistence")


def write_map(model: MapPersistence, path: str | os.PathLike, world: str = "") -> Path:
    """Write ``model``'s map to ``path`` atomically.

    Args:
        model: the recognizer whose map (kernels, graph, current place) is saved.
        path: target file; its folder must exist. An existing file is replaced only once the
            new one is complete.
        world: a fingerprint of the world the map was made in (e.g.
            ``PlaceNavEnv.world_id``); :func:`read_map` can insist on it.

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
        "merged": {str(d): int(k) for d, k in model.merged.items()},
    }
    arrays = {"meta": np.array(json.dumps(meta))}
    for p, k in model.kernels.items():
        arrays[f"k{p}_desc"], arrays[f"k{p}_w"], arrays[f"k{p}_seen"] = (
            k.descriptors, k.weights, k.last_seen)
    # numpy's stub gives savez a bool ``allow_pickle`` keyword, which mypy lets **arrays fill
    # (no array is named so); passing it would store an array of that name on numpy < 2.1
    return write_atomic(path, lambda f: np.savez(f, **arrays))  # type: ignore[arg-type]


def read_meta(path: str | os.PathLike) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
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


def read_map(cls: type[_Model], path: str | os.PathLike, world: str | None = None) -> _Model:
    """A recognizer of class ``cls`` restored from a map file written by :func:`write_map`.

    Args:
        cls: the recognizer's class; the file must hold a map of a class of that name.
        path: the map file.
        world: if given, the map must have been made in this world, else ``ValueError``.

    Returns:
        A new ``cls`` with the saved parameters, kernels, graph and current place. Maps of older
        format versions get the parameters they were made with (see :data:`VERSION`).

    Raises:
        FileNotFoundError: there is no file at ``path``.
        ValueError: the file is not a readable, consistent map of this class (and of
            ``world``, if given).
    """
    meta, arrays = read_meta(path)
    if world is not None and meta.get("world") != world:
        raise ValueError(f"{path} is a map of world {meta.get('world')!r}, not of {world!r}")
    if meta.get("class") != cls.__name__:
        raise ValueError(f"{path} holds a {meta.get('class')!r} map, not an "
                         f"{cls.__name__} one")
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
        model = cls(**params)
        model.restore(
            kernels={p: (arrays[f"k{p}_desc"], arrays[f"k{p}_w"], arrays[f"k{p}_seen"],
                         meta["kernel_images"][str(p)]) for p in meta["places"]},
            place_images={int(p): n for p, n in meta["place_images"].items()},
            edges=meta["edges"], current=meta["current"], frame_shape=meta["frame_shape"],
            merged={int(d): k for d, k in meta.get("merged", {}).items()})
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{path} is an inconsistent placeclust map: {type(e).__name__}: {e}"
                         ) from e
    return model


class MapPersistence:
    """Parameters, saving and loading of :class:`~placeclust.online.OnlinePlaceClustering`'s
    map (a mixin: it reads the recognizer's ``kernels``, ``graph``, ``current``, ``merged`` and
    ``frame_shape``, and rebuilds them and the relocalization index on loading)."""

    # the recognizer's state that a map file holds, or that restoring it needs
    kernels: dict[int, UnionKernel]
    graph: nx.Graph
    current: int
    merged: dict[int, int]
    frame_shape: tuple[int, int] | None
    kernel_capacity: int
    ratio: float
    _extractor: FeatureExtractor
    _index: PlaceIndex
    _index_sample: Callable[[int], np.ndarray]

    def get_params(self) -> dict[str, object]:
        """The constructor arguments (scikit-learn style), enough to rebuild an empty model.

        Returns:
            Parameter name -> value, for every argument of ``__init__``.
        """
        names = inspect.signature(type(self).__init__).parameters
        return {n: getattr(self, n) for n in names if n != "self"}

    def save(self, path: str | os.PathLike, world: str = "") -> None:
        """Write the map atomically (see :func:`placeclust.mapfile.save_map`).

        Args:
            path: the map file; its folder must exist.
            world: a fingerprint of the world the map was made in, checked by :meth:`load`.
        """
        write_map(self, path, world)

    @classmethod
    def load(cls: type[_Model], path: str | os.PathLike, world: str | None = None) -> _Model:
        """A recognizer from a map file (see :func:`placeclust.mapfile.load_map`).

        Args:
            path: a map file written by :meth:`save`.
            world: if given, the world the map must have been made in.

        Returns:
            A recognizer with the saved parameters, map and current place.

        Raises:
            FileNotFoundError: there is no file at ``path``.
            ValueError: the file is not a readable, consistent map (of ``world``, if given).
        """
        return read_map(cls, path, world)

    def restore(self, kernels: dict[int, KernelState], place_images: dict[int, int],
                edges: list, current: int, frame_shape: list | None,
                merged: dict[int, int] | None = None) -> None:
        """Replace the map with saved state (used by :meth:`load`).

        Args:
            kernels: place -> ``(descriptors, weights, last_seen, n_images)`` of its kernel.
            place_images: place -> frames assigned to it.
            edges: the topological graph's edges, pairs of places.
            current: the robot's place, or ``UNKNOWN`` (-1).
            frame_shape: ``(H, W)`` of the map's frames, or ``None``.
            merged: ids merged away by consolidation -> the place holding them (:attr:`merged`).

        Raises:
            ValueError: the places and the merged ids together are not ``0..n-1``, a merged id
                points to no place, or ``current`` or an edge names a place that is not in the
                map.
        """
        places = sorted(int(p) for p in kernels)
        merged = {int(d): int(k) for d, k in (merged or {}).items()}
        if sorted([*places, *merged]) != list(range(len(places) + len(merged))):
            raise ValueError(f"place ids and merged ids must be 0..n-1, got places "
                             f"{places[:10]} and merged {sorted(merged)[:10]}")
        if any(k not in kernels for k in merged.values()):
            raise ValueError("a merged id points to a place that is not in the map")
        if current != _UNKNOWN and current not in kernels:
            raise ValueError(f"current place {current} is not in the map")
        self.kernels = {p: UnionKernel.from_state(*kernels[p], binary=self._extractor.binary,
                                                  capacity=self.kernel_capacity, ratio=self.ratio)
                        for p in places}
        self.graph = nx.Graph()
        for p in places:
            self.graph.add_node(p, n_images=int(place_images[p]))
        for a, b in edges:
            if a not in self.kernels or b not in self.kernels:
                raise ValueError(f"edge ({a}, {b}) names a place that is not in the map")
            self.graph.add_edge(int(a), int(b))
        self.current = int(current)
        self.merged = merged
        self.frame_shape = tuple(frame_shape) if frame_shape else None
        self._index = PlaceIndex(self._extractor.binary, self._index_sample)
        for p in places:
            self._index.add(p)
