"""The union-of-local-features cluster kernel of seed 000 (Tang et al., Sec. III.B)."""

from __future__ import annotations

import numpy as np

from placeclust.matching import ratio_matches


class UnionKernel:
    """A place's kernel: the weighted union of the local features of the images it holds.

    ``Union_Of_Cluster`` (Sec. III.B): the first image's features start with weight 1; each new
    image's features that match a kernel feature (Eq. 3) add 1 to that feature's weight, the
    unmatched ones join the kernel with weight 1. The paper then deletes the minimum-weight
    features; online, that would delete everything just added, so the kernel is instead pruned
    to its ``capacity`` heaviest features, which bounds its size and memory as the paper's
    pruning intends. Among equal weights the *oldest* (last matched longest ago) are kept:
    keeping the newest lets a kernel drift into the next room through a doorway.

    Args:
        descriptors: features of the first image (N, D).
        binary: Hamming (True) or Euclidean (False) descriptors.
        capacity: the most features the kernel keeps.
        ratio: Lowe's ratio for correspondences.

    Raises:
        ValueError: ``capacity`` is below 1.

    Examples:
        A second image sharing four of its six features with the first: the four gain weight,
        the two others join, and the newest of them is pruned to keep ``capacity``:

        >>> import numpy as np
        >>> from placeclust.kernel import UnionKernel
        >>> from placeclust.matching import normalize
        >>> rng = np.random.default_rng(0)
        >>> first = normalize(rng.normal(size=(6, 16)).astype(np.float32), binary=False)
        >>> new = normalize(rng.normal(size=(2, 16)).astype(np.float32), binary=False)
        >>> kernel = UnionKernel(first, binary=False, capacity=7)
        >>> kernel.update(np.concatenate([first[:4], new]))
        >>> len(kernel), kernel.n_images, kernel.weights.tolist()
        (7, 2, [2.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0])
    """

    def __init__(self, descriptors: np.ndarray, binary: bool, capacity: int = 1200,
                 ratio: float = 0.8) -> None:
        if capacity < 1:
            raise ValueError(f"capacity must be positive, got {capacity}")
        self.binary = binary
        self.capacity = capacity
        self.ratio = ratio
        self.descriptors = np.array(descriptors)
        self.weights = np.ones(len(descriptors), np.float32)
        self.last_seen = np.zeros(len(descriptors), np.int64)
        self.n_images = 1
        self._prune()

    @classmethod
    def from_state(cls, descriptors: np.ndarray, weights: np.ndarray, last_seen: np.ndarray,
                   n_images: int, binary: bool, capacity: int = 1200, ratio: float = 0.8
                   ) -> UnionKernel:
        """A kernel with saved features, weights and ages (for loading maps).

        Raises:
            ValueError: the arrays differ in length or are empty, or the descriptors' dtype
                does not fit ``binary``.
        """
        n = len(descriptors)
        if n == 0 or len(weights) != n or len(last_seen) != n:
            raise ValueError(f"kernel arrays disagree: {n} descriptors, {len(weights)} weights, "
                             f"{len(last_seen)} ages")
        if binary != (descriptors.dtype == np.uint8):
            raise ValueError(f"kernel descriptors of dtype {descriptors.dtype} do not fit "
                             f"{'binary' if binary else 'float'} features")
        kernel = cls(descriptors, binary, capacity, ratio)
        kernel.descriptors = np.array(descriptors)
        kernel.weights = np.asarray(weights, np.float32).copy()
        kernel.last_seen = np.asarray(last_seen, np.int64).copy()
        kernel.n_images = int(n_images)
        kernel._prune()
        return kernel

    def __len__(self) -> int:
        return len(self.descriptors)

    def match(self, descriptors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Correspondences (image index, kernel index) of an image's features (Eq. 3)."""
        return ratio_matches(descriptors, self.descriptors, self.binary, self.ratio)

    def update(self, descriptors: np.ndarray,
               matches: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        """Add one image (lines 6-15 of ``Union_Of_Cluster``), then prune to ``capacity``.

        Args:
            descriptors: the image's features.
            matches: its correspondences with this kernel, if already computed by :meth:`match`.
        """
        img_idx, ker_idx = matches if matches is not None else self.match(descriptors)
        self.n_images += 1
        np.add.at(self.weights, ker_idx, 1.0)
        self.last_seen[ker_idx] = self.n_images
        new = np.setdiff1d(np.arange(len(descriptors)), img_idx)
        if len(new):
            self.descriptors = np.concatenate([self.descriptors, descriptors[new]])
            self.weights = np.concatenate([self.weights, np.ones(len(new), np.float32)])
            self.last_seen = np.concatenate(
                [self.last_seen, np.full(len(new), self.n_images, np.int64)])
        self._prune()

    def merge(self, other: UnionKernel) -> None:
        """Take in another place's kernel (two places found to be one, see
        :mod:`placeclust.consolidation`), then prune to ``capacity``.

        ``Union_Of_Cluster`` over kernels instead of images: each of ``other``'s features that
        matches one of this kernel (Eq. 3) adds its weight to it, the others join with their
        weights. ``other``'s images count as having come after this kernel's.

        Args:
            other: the kernel taken in; it is left as it was.

        Examples:
            >>> import numpy as np
            >>> from placeclust.kernel import UnionKernel
            >>> from placeclust.matching import normalize
            >>> rng = np.random.default_rng(0)
            >>> feats = normalize(rng.normal(size=(6, 16)).astype(np.float32), binary=False)
            >>> a, b = UnionKernel(feats[:4], False), UnionKernel(feats[2:], False)
            >>> a.merge(b)
            >>> len(a), a.n_images, a.weights.tolist()
            (6, 2, [1.0, 1.0, 2.0, 2.0, 1.0, 1.0])
        """
        img_idx, ker_idx = self.match(other.descriptors)
        seen = other.last_seen + self.n_images
        np.add.at(self.weights, ker_idx, other.weights[img_idx])
        self.last_seen[ker_idx] = np.maximum(self.last_seen[ker_idx], seen[img_idx])
        new = np.setdiff1d(np.arange(len(other)), img_idx)
        self.descriptors = np.concatenate([self.descriptors, other.descriptors[new]])
        self.weights = np.concatenate([self.weights, other.weights[new]])
        self.last_seen = np.concatenate([self.last_seen, seen[new]])
        self.n_images += other.n_images
        self._prune()

    def top(self, n: int) -> np.ndarray:
        """The ``n`` heaviest features' descriptors (for the relocalization index)."""
        order = np.lexsort((self.last_seen, -self.weights))[:n]
        return self.descriptors[order]

    def _prune(self) -> None:
        if len(self.descriptors) <= self.capacity:
            return
        keep = np.sort(np.lexsort((self.last_seen, -self.weights))[: self.capacity])
        self.descriptors = self.descriptors[keep]
        self.weights = self.weights[keep]
        self.last_seen = self.last_seen[keep]
