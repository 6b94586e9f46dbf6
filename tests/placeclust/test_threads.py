import threading

import cv2
import numpy as np

from placeclust.threads import split_rows


def test_split_rows_covers_every_row_once_in_order():
    rows = np.arange(1000)
    before = cv2.getNumThreads()
    try:
        cv2.setNumThreads(4)
        parts = split_rows(lambda chunk: chunk.copy(), rows, min_rows=100)
        few = split_rows(lambda chunk: chunk.copy(), rows[:150], min_rows=100)
        cv2.setNumThreads(1)
        alone = split_rows(lambda chunk: chunk.copy(), rows, min_rows=100)
    finally:
        cv2.setNumThreads(before)
    assert len(parts) == 4 and np.array_equal(np.concatenate(parts), rows)
    assert len(few) == 1 and len(alone) == 1  # too few rows to split, or one thread


def test_split_rows_inside_a_chunk_runs_in_one_piece():
    """Work that splits again (a match inside a split search) must not wait on the pool: with
    one worker that waited on itself, this would never return (so it runs under a deadline)."""
    rows = np.arange(1000)
    found = {}
    before = cv2.getNumThreads()
    try:
        cv2.setNumThreads(4)
        nested = threading.Thread(target=lambda: found.setdefault("parts", split_rows(
            lambda chunk: len(split_rows(np.copy, chunk, 10)), rows, 100)), daemon=True)
        nested.start()
        nested.join(30)
    finally:
        cv2.setNumThreads(before)
    assert found.get("parts") == [4, 1, 1, 1]  # the caller's chunk splits; the workers' run whole
