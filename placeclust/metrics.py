"""Scores of a place clustering against ground-truth rooms.

Definitions (``pred`` are place ids, ``-1`` unknown; ``truth`` room ids; N frames):

- **precision** (purity, the "clustering precision" of seed 000, Fig. 2): each place is mapped to
  the room most of its frames were taken in; precision is the fraction of frames whose place
  maps to their own room. Unknown frames count as wrong.
- **recall** (inverse purity): each room is mapped to the place holding most of its frames; the
  fraction of frames in their room's place. One place per room gives 1; splitting a room lowers it.
- **f_measure**: harmonic mean of precision and recall.
- **nmi**, **ari**: scikit-learn's normalised mutual information and adjusted Rand index, with
  unknown frames as one extra cluster.
- **matching_rate**: seed 001's Table 2 "correct match" rate, the precision over the frames
  the method actually localised (key frames for the nested mapper).
- **confusion**: seed 001's Table 3 per room, one room against the rest after mapping each
  place to its majority room: ``a`` true negatives, ``b`` false positives, ``c`` false
  negatives, ``d`` true positives, ``AC = (a+d)/N``, ``TP = d/(c+d)``, ``P = d/(b+d)``.

Examples:
    Six frames of two rooms; place 0 holds two frames of room 0, place 1 one of room 0 and two
    of room 1, and the last frame is unknown:

    >>> import numpy as np
    >>> from placeclust.metrics import precision, recall, score
    >>> pred = np.array([0, 0, 1, 1, 1, -1])
    >>> truth = np.array([0, 0, 0, 1, 1, 1])
    >>> round(precision(pred, truth), 3), round(recall(pred, truth), 3)
    (0.667, 0.667)
    >>> scores = score(pred, truth)
    >>> round(scores["nmi"], 3), scores["n_places"], round(scores["unknown_rate"], 3)
    (0.44, 2, 0.167)
"""

from __future__ import annotations

import numpy as np
from sklearn.metrics import adjusted_rand_score, normalized_mutual_info_score


def _check(pred: np.ndarray, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pred, truth = np.asarray(pred).ravel(), np.asarray(truth).ravel()
    if pred.shape != truth.shape:
        raise ValueError(f"pred has {pred.size} frames but truth has {truth.size}")
    if pred.size == 0:
        raise ValueError("no frames to score")
    return pred.astype(np.int64), truth.astype(np.int64)


def contingency(pred: np.ndarray, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The contingency table of places against rooms.

    Args:
        pred: place id per frame, -1 for unknown.
        truth: room id per frame.

    Returns:
        ``(table, places, rooms)``: ``table[i, j]`` frames of place ``places[i]`` in
        ``rooms[j]``; ``places`` and ``rooms`` are sorted.

    Raises:
        ValueError: ``pred`` and ``truth`` differ in length, or are empty.

    Examples:
        >>> from placeclust.metrics import contingency
        >>> table, places, rooms = contingency([0, 0, 1, 1, 1, -1], [0, 0, 0, 1, 1, 1])
        >>> table.tolist(), places.tolist(), rooms.tolist()
        ([[0, 1], [2, 0], [1, 2]], [-1, 0, 1], [0, 1])
    """
    pred, truth = _check(pred, truth)
    places, pi = np.unique(pred, return_inverse=True)
    rooms, ri = np.unique(truth, return_inverse=True)
    table = np.zeros((len(places), len(rooms)), np.int64)
    np.add.at(table, (pi, ri), 1)
    return table, places, rooms


def nmi(pred: np.ndarray, truth: np.ndarray) -> float:
    """Normalized mutual information of places and rooms, as scikit-learn's
    ``normalized_mutual_info_score`` (arithmetic-mean normalization; -1, unknown, is a place
    of its own), from :func:`contingency`: fast enough for a bootstrap's thousands of calls.

    Examples:
        >>> from placeclust.metrics import nmi
        >>> nmi([1, 1, 0, 0], [0, 0, 1, 1]), nmi([0, 0, 0, 0], [0, 0, 1, 1])
        (1.0, 0.0)
    """
    table = contingency(pred, truth)[0].astype(float)
    n = table.sum()
    p_place, p_room = table.sum(axis=1) / n, table.sum(axis=0) / n
    h_place = -float(np.sum(p_place * np.log(p_place)))
    h_room = -float(np.sum(p_room * np.log(p_room)))
    if h_place == 0 or h_room == 0:  # one cluster or one class: scikit-learn's convention
        return 1.0 if h_place == h_room else 0.0
    joint = table[table > 0] / n
    outer = np.outer(p_place, p_room)[table > 0]
    mi = float(np.sum(joint * np.log(joint / outer)))
    return max(0.0, min(1.0, mi / ((h_place + h_room) / 2)))


def place_to_room(pred: np.ndarray, truth: np.ndarray) -> dict[int, int]:
    """Majority room of every place (unknown -1 maps to -1).

    Examples:
        >>> from placeclust.metrics import place_to_room
        >>> place_to_room([0, 0, 1, 1, 1, -1], [0, 0, 0, 1, 1, 1])
        {-1: -1, 0: 0, 1: 1}
    """
    table, places, rooms = contingency(pred, truth)
    return {int(p): (int(rooms[table[i].argmax()]) if p >= 0 else -1)
            for i, p in enumerate(places)}


def precision(pred: np.ndarray, truth: np.ndarray) -> float:
    """Clustering precision (purity) of seed 000, Fig. 2; unknown frames count as wrong.

    Args:
        pred: place id per frame, -1 for unknown.
        truth: room id per frame.

    Returns:
        The share of frames whose place's majority room is their own room.

    Examples:
        >>> from placeclust.metrics import precision
        >>> precision([0, 0, 1, 1], [5, 5, 6, 6]), precision([0, 0, 0, -1], [5, 5, 6, 6])
        (1.0, 0.5)
    """
    table, places, _ = contingency(pred, truth)
    known = places >= 0
    return float(table[known].max(axis=1).sum() / table.sum()) if known.any() else 0.0


def recall(pred: np.ndarray, truth: np.ndarray) -> float:
    """Inverse purity: fraction of frames in the place holding most of their room.

    Examples:
        Splitting a room in two lowers recall, not precision:

        >>> from placeclust.metrics import precision, recall
        >>> precision([0, 0, 1, 1], [5, 5, 5, 5]), recall([0, 0, 1, 1], [5, 5, 5, 5])
        (1.0, 0.5)
    """
    table, places, _ = contingency(pred, truth)
    return float(table[places >= 0].max(axis=0, initial=0).sum() / table.sum())


def confusion_table(pred: np.ndarray, truth: np.ndarray) -> dict[int, dict[str, float]]:
    """Seed 001 Table 3 figures per room: a, b, c, d, AC, TP (recall), P (precision).

    Args:
        pred: place id per frame, -1 for unknown.
        truth: room id per frame.

    Returns:
        Room -> its figures, one room against the rest (see the module docstring).

    Examples:
        >>> from placeclust.metrics import confusion_table
        >>> room0 = confusion_table([0, 0, 1, 1, 1, -1], [0, 0, 0, 1, 1, 1])[0]
        >>> [room0[k] for k in "abcd"], round(room0["AC"], 3), room0["P"]
        ([3, 0, 1, 2], 0.833, 1.0)
    """
    pred, truth = _check(pred, truth)
    mapping = place_to_room(pred, truth)
    room_pred = np.array([mapping[int(p)] for p in pred])
    out = {}
    for room in np.unique(truth).tolist():
        t, p = truth == room, room_pred == room
        d, b, c = int((t & p).sum()), int((~t & p).sum()), int((t & ~p).sum())
        a = int(len(truth) - b - c - d)
        out[int(room)] = {"a": a, "b": b, "c": c, "d": d, "AC": (a + d) / len(truth),
                          "TP": d / (c + d) if c + d else 0.0, "P": d / (b + d) if b + d else 0.0}
    return out


def score(pred: np.ndarray, truth: np.ndarray, localized: np.ndarray | None = None
          ) -> dict[str, float]:
    """All scalar metrics of the module docstring.

    Args:
        pred: place id per frame, -1 for unknown.
        truth: room id per frame.
        localized: boolean mask of the frames the method localised itself (default: all).

    Returns:
        ``precision``, ``recall``, ``f_measure``, ``nmi``, ``ari``, ``n_places``, ``n_rooms``,
        ``unknown_rate``, ``matching_rate`` and the means over rooms of seed 001's ``AC``,
        ``TP`` and ``P`` (``mean_AC``, ``mean_TP``, ``mean_P``).

    Raises:
        ValueError: ``pred`` and ``truth`` differ in length, or are empty.

    Examples:
        Places numbered differently from the rooms still score 1:

        >>> from placeclust.metrics import score
        >>> scores = score([1, 1, 0, 0], [0, 0, 1, 1])
        >>> scores["precision"], scores["recall"], round(scores["nmi"], 3)
        (1.0, 1.0, 1.0)
    """
    pred, truth = _check(pred, truth)
    p, r = precision(pred, truth), recall(pred, truth)
    mask = np.ones(len(pred), bool) if localized is None else np.asarray(localized, bool)
    conf = confusion_table(pred, truth)
    return {
        "precision": p,
        "recall": r,
        "f_measure": 2 * p * r / (p + r) if p + r else 0.0,
        "nmi": float(normalized_mutual_info_score(truth, pred)),
        "ari": float(adjusted_rand_score(truth, pred)),
        "n_places": int(len(np.unique(pred[pred >= 0]))),
        "n_rooms": int(len(np.unique(truth))),
        "unknown_rate": float((pred < 0).mean()),
        "matching_rate": precision(pred[mask], truth[mask]) if mask.any() else 0.0,
        "mean_AC": float(np.mean([c["AC"] for c in conf.values()])),
        "mean_TP": float(np.mean([c["TP"] for c in conf.values()])),
        "mean_P": float(np.mean([c["P"] for c in conf.values()])),
    }


def latency_summary(seconds: np.ndarray) -> dict[str, float]:
    """Median, 95th percentile and mean per-frame latency in milliseconds.

    Args:
        seconds: per-frame latencies in seconds.

    Returns:
        ``ms_per_frame`` (the median), ``ms_p95`` and ``ms_mean``; all 0 for no frames.

    Examples:
        >>> from placeclust.metrics import latency_summary
        >>> latency_summary([0.01, 0.02, 0.03])
        {'ms_per_frame': 20.0, 'ms_p95': 29.0, 'ms_mean': 20.0}
    """
    ms = np.asarray(seconds, float) * 1000.0
    if ms.size == 0:
        return {"ms_per_frame": 0.0, "ms_p95": 0.0, "ms_mean": 0.0}
    return {"ms_per_frame": float(np.median(ms)), "ms_p95": float(np.percentile(ms, 95)),
            "ms_mean": float(ms.mean())}
