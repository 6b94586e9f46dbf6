"""A place recognizer in a few lines: Haar-wavelet signatures, nearest place or a new one.

Check it, then benchmark it beside the built-in ones, from the repository's root:

    python -c "from placeclust.checks import check_recognizer; \
from examples.tiny_recognizer import HaarPlaces; check_recognizer(HaarPlaces)"
    placeclust bench --quick --algos online examples.tiny_recognizer:HaarPlaces --latency-sizes \
        --features sift --conditions day --out runs/tiny
"""

import networkx as nx
import numpy as np

from placeclust import UNKNOWN
from placeclust.frames import to_gray
from placeclust.wavelet import haar_signature, signature_similarity


class HaarPlaces:
    """A frame joins the most similar place if it is at least ``threshold`` alike, else opens
    a new one; each place keeps the signature of its first frame."""

    def __init__(self, threshold: float = 0.9) -> None:
        self.threshold = threshold
        self.signatures: list[np.ndarray] = []
        self.graph = nx.Graph()
        self.n_places = 0
        self._last = UNKNOWN

    def predict_one(self, frame: np.ndarray) -> int:
        signature = haar_signature(to_gray(frame))
        if not signature.any():
            return UNKNOWN  # a blank frame: nothing to recognise
        sims = [signature_similarity(signature, s) for s in self.signatures]
        return int(np.argmax(sims)) if sims and max(sims) >= self.threshold else UNKNOWN

    def learn_predict_one(self, frame: np.ndarray) -> int:
        place = self.predict_one(frame)
        if place == UNKNOWN and np.asarray(frame).any():
            place, self.n_places = self.n_places, self.n_places + 1
            self.signatures.append(haar_signature(to_gray(frame)))
            self.graph.add_node(place)
        if place != UNKNOWN and self._last != UNKNOWN and place != self._last:
            self.graph.add_edge(self._last, place)
        self._last = place if place != UNKNOWN else self._last
        return place
