"""The benchmark's store of finished runs: a JSON file (and the per-frame arrays) per run.

A run's file is written atomically and last, so its presence marks the run as done; each row
carries a stamp of the code, libraries and rendering that made it, and a row whose stamp is
not the current one is not reused (:func:`envs.commands.bench.run_stamp`).

Examples:
    >>> import tempfile
    >>> from envs.commands.store import RunStore
    >>> store = RunStore(tempfile.mkdtemp(), stamp=lambda algo: {"code": "v1"})
    >>> store.put({"key": "k", "algo": "online", "precision": 1.0})
    >>> store.get("k", "online")["precision"]
    1.0
    >>> RunStore(store.folder, stamp=lambda algo: {"code": "v2"}).get("k", "online") is None
    True
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from placeclust.atomic import write_atomic

ARRAYS = ("assignments", "truth")  # per-frame arrays of a run, stored beside its JSON
LATENCY_ALGO = "online"  # the recognizer the latency sweeps time


@dataclass
class RunStore:
    """Finished runs as ``folder/<key>.json``, written atomically (temp file, then rename),
    each with its ``stamp(algo)`` (:func:`envs.commands.bench.run_stamp`; none if not given)."""

    folder: Path
    stamp: Callable[[str], dict[str, Any]] | None = None
    _cache: dict[str, dict] = field(default_factory=dict)
    #: keys of kept runs found stale by :meth:`get`
    stale: set[str] = field(default_factory=set)

    def __post_init__(self) -> None:
        self.folder = Path(self.folder)
        self.folder.mkdir(parents=True, exist_ok=True)

    def get(self, key: str, algo: str | None = None) -> dict | None:
        """The finished row of run ``key``, or None (also for a damaged file: it is redone).
        With ``algo``, a row whose stamp is not ``stamp(algo)`` now is stale: None."""
        if key not in self._cache:
            path = self.folder / f"{key}.json"
            try:
                self._cache[key] = json.loads(path.read_text())
            except (OSError, ValueError):
                return None
        row = self._cache[key]
        if algo is not None and self.stamp and row.get("stamp") != self.stamp(algo):
            self.stale.add(key)
            del self._cache[key]  # the run that replaces it is read from its file
            return None
        return row

    def put(self, row: dict) -> None:
        """Record one finished run; its arrays (``assignments``, ``truth``) go to ``<key>.npz``.

        The JSON is written last: its presence marks the run as done.
        """
        if self.stamp is not None:
            row = {**row, "stamp": self.stamp(row.get("algo", LATENCY_ALGO))}
        else:
            row = dict(row)
        # Any: numpy's stub would match the splat against savez's allow_pickle flag too
        arrays: dict[str, Any] = {k: np.asarray(row.pop(k)) for k in ARRAYS if k in row}
        if arrays:
            write_atomic(self.folder / f"{row['key']}.npz", lambda f: np.savez(f, **arrays))
        text = json.dumps(row, indent=1, sort_keys=True).encode()
        write_atomic(self.folder / f"{row['key']}.json", lambda f: f.write(text))
        self._cache[row["key"]] = row

    def arrays(self, key: str) -> dict[str, np.ndarray]:
        """``assignments`` (place per frame, -1 unknown) and ``truth`` (room per frame) of a run."""
        with np.load(self.folder / f"{key}.npz") as z:
            return {k: z[k] for k in z.files}
