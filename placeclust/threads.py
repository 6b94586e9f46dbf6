"""How placeclust uses the machine's cores: one search split over OpenCV's thread count.

A frame's work runs in phases (detection, then matching, then the index), so splitting each
phase over the cores uses them without oversubscribing them. The thread count is OpenCV's
(``cv2.getNumThreads()``, what its SIFT and ORB already use): ``cv2.setNumThreads(1)`` keeps
all of placeclust on one core.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import TypeVar

import cv2
import numpy as np

T = TypeVar("T")

_pool: tuple[int, ThreadPoolExecutor] | None = None  # (pid, pool): a forked child makes its own
_pool_lock = threading.Lock()
_in_worker = threading.local()  # set in the pool's threads, whose work must not wait on the pool


def _workers() -> ThreadPoolExecutor:
    global _pool
    with _pool_lock:
        if _pool is None or _pool[0] != os.getpid():
            _pool = (os.getpid(), ThreadPoolExecutor(
                max(1, (os.cpu_count() or 2) - 1), thread_name_prefix="placeclust",
                initializer=setattr, initargs=(_in_worker, "active", True)))
        return _pool[1]


def split_rows(fn: Callable[[np.ndarray], T], rows: np.ndarray, min_rows: int) -> list[T]:
    """``fn`` on consecutive chunks of ``rows``, run side by side.

    Args:
        fn: work on a chunk of rows; it must release the GIL to gain anything (numpy's matrix
            products and OpenCV's calls do).
        rows: the array to split along its first axis.
        min_rows: the fewest rows per chunk (below that a thread costs more than it saves).

    Returns:
        ``fn``'s results in chunk order (one result, ``fn(rows)``, when no split pays off, or
        when called from a chunk's own work: a worker waiting on the pool it belongs to could
        wait forever). The calling thread takes the first chunk.

    Examples:
        However many chunks the machine's threads make, their results come in order:

        >>> import numpy as np
        >>> from placeclust.threads import split_rows
        >>> parts = split_rows(lambda rows: rows * 2, np.arange(10), min_rows=2)
        >>> np.concatenate(parts).tolist()
        [0, 2, 4, 6, 8, 10, 12, 14, 16, 18]
    """
    parts = min(cv2.getNumThreads(), len(rows) // max(1, min_rows))
    if parts <= 1 or getattr(_in_worker, "active", False):
        return [fn(rows)]
    chunks = np.array_split(rows, parts)
    later = [_workers().submit(fn, chunk) for chunk in chunks[1:]]
    return [fn(chunks[0]), *(f.result() for f in later)]
