"""The benchmarks' store of finished runs: a JSON file (and the per-frame arrays) per run.

One store serves the open-loop bench (:mod:`envs.commands.bench`) and the closed-loop
errands and leaderboard (:mod:`envs.commands.errands`). A run's file is written atomically
and last, so its presence marks the run as done; each row carries the stamp of the code,
libraries and rendering that made it, ``stamp(row)``, and a kept row whose stamp is not the
one its run would get now is stale: :meth:`RunStore.get` does not return it, and counts it.

Examples:
    >>> import tempfile
    >>> from envs.runs.store import RunStore
    >>> store = RunStore(tempfile.mkdtemp(), stamp=lambda row: {"code": "v1"})
    >>> store.put({"key": "k", "algo": "online", "precision": 1.0})["stamp"]
    {'code': 'v1'}
    >>> store.get("k")["precision"]
    1.0
    >>> edited = RunStore(store.folder, stamp=lambda row: {"code": "v2"})
    >>> edited.get("k") is None, edited.stale
    (True, {'k'})
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from placeclust import strict_json
from placeclust.atomic import write_atomic

ARRAYS = ("assignments", "truth")  # per-frame arrays of a run, stored beside its JSON


@dataclass
class RunStore:
    """Finished runs as ``folder/<key>.json``, written atomically (temp file, then rename).

    Args:
        folder: where the runs are kept, made with the first run kept: a command refused
            before any run finishes leaves no empty folder behind.
        stamp: what a row must carry to be used again, computed from the row itself (its
            recognizer, agent...): :func:`envs.commands.bench.row_stamp`,
            :func:`envs.runs.jobs.stamp`. None: rows are neither stamped nor checked.
    """

    folder: Path
    stamp: Callable[[dict[str, Any]], dict[str, Any]] | None = None
    _cache: dict[str, dict] = field(default_factory=dict)
    #: keys of kept runs found stale by :meth:`get`
    stale: set[str] = field(default_factory=set)

    def __post_init__(self) -> None:
        self.folder = Path(self.folder)

    def get(self, key: str) -> dict | None:
        """The finished row of run ``key``, or None: not run, damaged (a torn write) or stale
        (its stamp is not ``stamp(row)`` now; the key goes into :attr:`stale`)."""
        if key not in self._cache:
            path = self.folder / f"{key}.json"
            try:
                self._cache[key] = json.loads(path.read_text())
            except (OSError, ValueError):
                return None
        row = self._cache[key]
        if self.stamp is not None and row.get("stamp") != self.stamp(row):
            self.stale.add(key)
            del self._cache[key]  # the run that replaces it is read from its file
            return None
        return row

    def put(self, row: dict) -> dict:
        """Record one finished run (``row["key"]`` names it) with its stamp; its arrays
        (``assignments``, ``truth``) go to ``<key>.npz``. Returns the row as kept.

        The JSON is written last: its presence marks the run as done.
        """
        row = dict(row)
        self.folder.mkdir(parents=True, exist_ok=True)
        if self.stamp is not None:
            row["stamp"] = self.stamp(row)
        # Any: numpy's stub would match the splat against savez's allow_pickle flag too
        arrays: dict[str, Any] = {k: np.asarray(row.pop(k)) for k in ARRAYS if k in row}
        if arrays:
            write_atomic(self.folder / f"{row['key']}.npz", lambda f: np.savez(f, **arrays))
        text = strict_json.dumps(row, indent=1, sort_keys=True).encode()
        write_atomic(self.folder / f"{row['key']}.json", lambda f: f.write(text))
        self._cache[row["key"]] = row
        return row

    def arrays(self, key: str) -> dict[str, np.ndarray]:
        """``assignments`` (place per frame, -1 unknown) and ``truth`` (room per frame) of a run."""
        with np.load(self.folder / f"{key}.npz") as z:
            return {k: z[k] for k in z.files}
