"""VPR-Bench's dataset layout, read safely, and its score for place recognizers.

VPR-Bench (Zaffar et al., IJCV 2021) ships a dozen public place-recognition datasets as::

    DIR/ref/       reference images (a traversal)
    DIR/query/     query images (another traversal of the same places)
    DIR/ground_truth_new.npy   for each query, the reference images that show its place

``ground_truth_new.npy`` is a NumPy *object* array (rows ``[query_index, [ref_indices]]``),
which ``np.load`` opens only by unpickling, and a pickle can run code. :func:`read_ground_truth`
never does that: it reads the pickle with an unpickler that builds NumPy arrays, lists and
integers and refuses any other object, naming it.

A recognizer maps ``ref/`` (``learn_predict_one``), then localizes each query on that fixed map
(``localize_one``). :func:`score_queries` calls a query right, as VPR-Bench calls its top-1
match right, when the place it was given holds one of its ground-truth references; its recall at
N when one of the N places the recognizer ranks first does (``rank_places``).

Examples:
    >>> import tempfile
    >>> import numpy as np
    >>> from placeclust.vprbench import VPRBench, write_vpr_bench
    >>> rng = np.random.default_rng(0)
    >>> folder = tempfile.mkdtemp()
    >>> ref, query = rng.integers(0, 255, (2, 4, 32, 32, 3), np.uint8)
    >>> write_vpr_bench(folder, ref, query, [[0, 1], [1], [2, 3], [3]])
    >>> data = VPRBench(folder)
    >>> len(data.ref), len(data.query), [g.tolist() for g in data.ground_truth]
    (4, 4, [[0, 1], [1], [2, 3], [3]])
"""

from __future__ import annotations

import io
import pickle
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from placeclust.datasets import DatasetError, ImageFolder, write_image_folder

GROUND_TRUTH = "ground_truth_new.npy"

#: the only globals a VPR-Bench ground truth's pickle may name: NumPy's array rebuilders
_SAFE = {("numpy.core.multiarray", "_reconstruct"), ("numpy._core.multiarray", "_reconstruct"),
         ("numpy.core.multiarray", "scalar"), ("numpy._core.multiarray", "scalar"),
         ("numpy", "ndarray"), ("numpy", "dtype")}


class _ArraysOnly(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> object:
        if (module, name) not in _SAFE:
            raise pickle.UnpicklingError(f"it names {module}.{name}, which is not a NumPy array")
        return super().find_class(module, name)


def is_vpr_bench(folder: str | Path) -> bool:
    """Whether ``folder`` has VPR-Bench's layout (``ref/``, ``query/`` and the ground truth)."""
    path = Path(folder)
    return (path / "ref").is_dir() and (path / "query").is_dir() and (path / GROUND_TRUTH).is_file()


def read_ground_truth(path: str | Path, n_query: int, n_ref: int) -> list[np.ndarray]:
    """For each of ``n_query`` queries, the indices of the references that show its place.

    Reads VPR-Bench's object array without running its pickle (see the module docstring); a
    plain integer array ``(n_query, k)`` is read too.

    Raises:
        DatasetError: not a ``.npy`` file, a pickle naming anything but NumPy arrays, rows that
            do not number the queries ``0..n_query-1`` once each, or a reference index outside
            ``0..n_ref-1``.
    """
    path = Path(path)
    try:
        with open(path, "rb") as f:
            version = np.lib.format.read_magic(f)
            header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                      else np.lib.format.read_array_header_2_0)
            _, _, dtype = header(f)
            if dtype.hasobject:
                table = np.asarray(_ArraysOnly(io.BytesIO(f.read())).load(), dtype=object)
            else:
                f.seek(0)
                table = np.load(f, allow_pickle=False)
    except (OSError, ValueError, EOFError, pickle.UnpicklingError, AttributeError,
            TypeError) as exc:
        raise DatasetError(f"cannot read {path} as VPR-Bench ground truth: {exc}") from exc
    if table.ndim != 2 or len(table) != n_query:
        raise DatasetError(f"{path} has shape {table.shape}; expected one row per query "
                           f"({n_query})")
    return _rows(path, table, n_query, n_ref)


def _rows(path: Path, table: np.ndarray, n_query: int, n_ref: int) -> list[np.ndarray]:
    if table.dtype != object:  # (Q, k) integers: row q lists query q's references
        rows = [(q, row) for q, row in enumerate(table)]
    else:
        rows = [(row[0], row[1]) for row in table]
    truth: list[np.ndarray | None] = [None] * n_query
    for q, refs in rows:
        try:
            q, refs = int(q), np.asarray(refs, np.int64).ravel()
        except (TypeError, ValueError) as exc:
            raise DatasetError(f"{path}: a row is not [query, [references]] ({exc})") from exc
        if not 0 <= q < n_query or truth[q] is not None:
            raise DatasetError(f"{path}: query {q} is out of range or listed twice")
        if len(refs) and (refs.min() < 0 or refs.max() >= n_ref):
            raise DatasetError(f"{path}: query {q} names reference {refs.max()}, but there are "
                               f"{n_ref}")
        truth[q] = refs
    return [np.zeros(0, np.int64) if t is None else t for t in truth]


class VPRBench:
    """A VPR-Bench dataset folder: ``ref`` and ``query`` as :class:`ImageFolder`, and for each
    query the reference indices that show its place (``ground_truth``).

    Raises:
        DatasetError: a part of the layout is missing or unreadable (the message names it).
    """

    def __init__(self, folder: str | Path) -> None:
        self.path = Path(folder)
        if not is_vpr_bench(self.path):
            raise DatasetError(f"{self.path} is not a VPR-Bench dataset: it needs ref/, query/ "
                               f"and {GROUND_TRUTH}")
        self.ref = ImageFolder(self.path / "ref", labels=False)
        self.query = ImageFolder(self.path / "query", labels=False)
        self.ground_truth = read_ground_truth(self.path / GROUND_TRUTH, len(self.query),
                                              len(self.ref))

    def __repr__(self) -> str:
        return f"VPRBench({str(self.path)!r}, {len(self.ref)} ref, {len(self.query)} query)"


def write_vpr_bench(folder: str | Path, ref: Sequence[np.ndarray] | np.ndarray,
                    query: Sequence[np.ndarray] | np.ndarray,
                    ground_truth: Sequence[Sequence[int]]) -> None:
    """Write a dataset in VPR-Bench's layout: the frames as ``ref/`` and ``query/`` png
    folders, ``ground_truth`` (for each query, its references) as VPR-Bench's object array."""
    out = Path(folder)
    write_image_folder(out / "ref", ref)
    write_image_folder(out / "query", query)
    table = np.empty((len(ground_truth), 2), dtype=object)
    for q, refs in enumerate(ground_truth):
        table[q, 0], table[q, 1] = q, [int(r) for r in refs]
    np.save(out / GROUND_TRUTH, table, allow_pickle=True)


def same_place_truth(ref_labels: np.ndarray, query_labels: np.ndarray) -> list[list[int]]:
    """Ground truth from labels: each query's references are those with its label (none for a
    query labelled -1)."""
    return [[] if q < 0 else np.flatnonzero(ref_labels == q).tolist() for q in query_labels]


def nearby_truth(ref_xy: np.ndarray, query_xy: np.ndarray, radius: float,
                 ref_labels: np.ndarray | None = None,
                 query_labels: np.ndarray | None = None) -> list[list[int]]:
    """Ground truth from positions, as VPR-Bench's data sets give it: each query's references
    are those within ``radius`` (the units of the positions), in its place when labels are
    given (a wall between two positions parts them).

    Examples:
        >>> import numpy as np
        >>> from placeclust.vprbench import nearby_truth
        >>> nearby_truth(np.array([[0.0, 0], [1, 0], [5, 0]]), np.array([[0.2, 0]]), 1.0)
        [[0, 1]]
    """
    from scipy.spatial import cKDTree

    near = cKDTree(np.asarray(ref_xy)[:, :2]).query_ball_point(np.asarray(query_xy)[:, :2],
                                                                radius)
    out = [sorted(int(r) for r in refs) for refs in near]
    if ref_labels is not None and query_labels is not None:
        out = [[r for r in refs if ref_labels[r] == q] for refs, q in zip(out, query_labels)]
    return out


def score_queries(ref_places: np.ndarray, query_places: np.ndarray,
                  ground_truth: Sequence[np.ndarray],
                  ranked: Sequence[Sequence[int]] | None = None,
                  recall_at: Sequence[int] = (1, 5, 10)) -> dict[str, float]:
    """VPR-Bench's top-1 score at the level of places.

    Args:
        ref_places: the place of each reference frame on the map the references built.
        query_places: the place each query was localized in (-1: none).
        ground_truth: for each query, the indices of its correct references.
        ranked: for each query, places best first (``rank_places``), for recall at N.
        recall_at: the N of recall at N.

    Returns:
        ``top1`` (share of queries whose place holds a correct reference), ``unknown_rate``,
        ``chance`` (the share a uniformly drawn place would get right), ``n_places``,
        ``refs_per_place``, and ``recall@N`` for each N when ``ranked`` is given. Queries
        without ground truth are left out.

    Examples:
        >>> import numpy as np
        >>> from placeclust.vprbench import score_queries
        >>> truth = [np.array([0]), np.array([2, 3]), np.array([3])]
        >>> s = score_queries(np.array([0, 0, 1, 1]), np.array([0, 0, -1]), truth)
        >>> round(s["top1"], 3), round(s["unknown_rate"], 3), s["chance"], s["n_places"]
        (0.333, 0.333, 0.5, 2)
    """
    ref_places = np.asarray(ref_places, np.int64)
    places = np.unique(ref_places[ref_places >= 0])
    keep = [q for q, refs in enumerate(ground_truth) if len(refs)]
    right = [set(ref_places[ground_truth[q]].tolist()) for q in keep]
    out = {"top1": float(np.mean([int(query_places[q]) in r for q, r in zip(keep, right)])),
           "unknown_rate": float(np.mean([query_places[q] < 0 for q in keep])),
           "chance": float(np.mean(query_chances(ref_places, ground_truth))),
           "n_places": int(len(places)), "n_queries": len(keep),
           "refs_per_place": float(np.sum(ref_places >= 0) / max(1, len(places)))}
    if ranked is not None:
        for n in recall_at:
            out[f"recall@{n}"] = float(np.mean([bool(set(list(ranked[q])[:n]) & r)
                                                for q, r in zip(keep, right)]))
    return out


def query_chances(ref_places: np.ndarray, ground_truth: Sequence[np.ndarray]) -> np.ndarray:
    """Per query with ground truth, the top-1 a uniformly drawn place of the map would score:
    the share of the map's places that hold one of its references (1 on a map of one place).

    Examples:
        >>> import numpy as np
        >>> from placeclust.vprbench import query_chances
        >>> query_chances(np.array([0, 0, 1, 2]), [np.array([0, 1]), np.array([]), [3]])
        array([0.33333333, 0.33333333])
    """
    ref_places = np.asarray(ref_places, np.int64)
    n_places = max(1, len(np.unique(ref_places[ref_places >= 0])))
    return np.array([len(set(ref_places[np.asarray(refs, np.int64)].tolist()) - {-1})
                     / n_places for refs in ground_truth if len(refs)], float)


def above_chance(hits: Sequence[float], chances: Sequence[float]) -> float:
    """Top-1 corrected for chance, in Cohen's kappa's form: ``(top1 - c) / (1 - c)`` with
    ``top1`` the mean hit and ``c`` the mean of :func:`query_chances`. 1 is every query right,
    0 what a map that guesses among its places scores; a map of one place (``c = 1``) scores 0,
    since it says nothing of where a query is, though its raw top-1 is 1. Maps that cut a
    route into few places and many score on one scale, so ranking by it does not reward the
    coarse one. NaN without queries.

    Examples:
        >>> from placeclust.vprbench import above_chance
        >>> above_chance([1, 1, 0, 1], [0.5, 0.5, 0.5, 0.5]), above_chance([1, 1], [1, 1])
        (0.5, 0.0)
    """
    if not len(hits):
        return float("nan")
    top1, c = float(np.mean(hits)), float(np.mean(chances))
    return 0.0 if c >= 1 else (top1 - c) / (1 - c)
