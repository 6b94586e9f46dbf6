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
