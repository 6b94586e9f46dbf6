"""Where and when a place recognizer errs: the shapes its errors take along a drive.

Precision counts wrong frames; a robot cares where they fall. Two shapes dominate real
recognizers' errors, and the closed loop's calibration oracles model each
(``envs.tasks.oracles``: ``oracle-door:D``, ``oracle-revisit:P``), so their sizes should be
read off a real recognizer's own maps:

- **the doorway lag**: after the robot enters a room, the place of the room it left goes on
  being reported for a while. ``lag_m`` is the median over room entries of the metres driven
  from the entry to the first frame whose place is the room's own (a place is a room's own
  where most of its frames were taken, :func:`placeclust.metrics.place_to_room`); an entry
  whose visit never reaches it counts its visit's length. ``near_door_share`` is the share of
  the wrong frames that fall within ``near`` metres after an entry.
- **the revisit that opens a place**: ``revisit_new`` is the share of a room's later visits
  whose most frequent place is none of the places its first visit reported most.

Examples:
    A corridor (room 0) entered twice from an office (room 1); the recognizer lags one frame
    behind at each door and opens a new place (2) on the second visit of the office:

    >>> import numpy as np
    >>> truth = np.array([0, 0, 0, 1, 1, 1, 0, 0, 1, 1, 1])
    >>> pred = np.array([0, 0, 0, 0, 1, 1, 1, 0, 0, 2, 2])
    >>> xy = np.stack([np.arange(11.0), np.zeros(11)], axis=1)
    >>> shapes = error_shapes(pred, truth, xy)
    >>> shapes["lag_m"], shapes["near_door_share"], shapes["revisit_new"]
    (1.0, 1.0, 0.5)
"""

from __future__ import annotations

import numpy as np

from placeclust.metrics import place_to_room


def _visits(truth: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """Each visit to a room: ``(room, frame indices)``, frames in no room (-1) skipped."""
    inside = np.flatnonzero(truth >= 0)
    if inside.size == 0:
        return []
    cuts = np.flatnonzero(np.diff(truth[inside]) != 0) + 1
    return [(int(truth[run[0]]), run) for run in np.split(inside, cuts)]


def _majority(pred: np.ndarray) -> int:
    known = pred[pred >= 0]
    if known.size == 0:
        return -1
    values, counts = np.unique(known, return_counts=True)
    return int(values[np.argmax(counts)])


def error_shapes(pred: np.ndarray, truth: np.ndarray, positions: np.ndarray,
                 near: float = 1.0) -> dict[str, float]:
    """The doorway lag and the revisits that open a place (the module's definitions).

    Args:
        pred: (N,) place ids, -1 unknown.
        truth: (N,) true rooms, -1 in no room (a doorway).
        positions: (N, 2) where each frame was taken (m).
        near: metres after an entry within which a wrong frame counts as near a door.

    Returns:
        ``lag_m``, ``near_door_share``, ``revisit_new`` (``nan`` where there is nothing to
        measure: no entry, no wrong frame, no revisit), ``entries`` and ``revisits``.
    """
    pred, truth = np.asarray(pred), np.asarray(truth)
    positions = np.asarray(positions, float)
    if not (len(pred) == len(truth) == len(positions)):
        raise ValueError(f"pred, truth and positions must be as long, got {len(pred)}, "
                         f"{len(truth)} and {len(positions)}")
    owner = place_to_room(pred, truth)
    right = np.array([p >= 0 and owner.get(int(p)) == t for p, t in zip(pred, truth)])
    visits = _visits(truth)
    lags, near_wrong = [], 0
    first: dict[int, int] = {}
    reopened: list[bool] = []
    for k, (room, frames) in enumerate(visits):
        driven = np.concatenate([[0.0], np.cumsum(np.linalg.norm(
            np.diff(positions[frames], axis=0), axis=1))])
        if k > 0:  # an entry through a doorway
            hit = np.flatnonzero(right[frames])
            lags.append(float(driven[hit[0]] if hit.size else driven[-1]))
            near_wrong += int(np.sum(~right[frames] & (truth[frames] >= 0)
                                     & (driven <= near)))
        place = _majority(pred[frames])
        if room in first:
            reopened.append(place != first[room])
        else:
            first[room] = place
    wrong = int(np.sum(~right & (truth >= 0)))
    return {"lag_m": float(np.median(lags)) if lags else float("nan"),
            "near_door_share": near_wrong / wrong if wrong else float("nan"),
            "revisit_new": float(np.mean(reopened)) if reopened else float("nan"),
            "entries": len(lags), "revisits": len(reopened)}
