"""The same seeds give the same frames, place ids and metrics, in another process too."""

import hashlib
import subprocess
import sys

import numpy as np

from envs.tasks.tour import record_tour
from placeclust.runner import evaluate, run

SCRIPT = """
import hashlib, numpy as np
from envs.tasks.tour import record_tour
from placeclust.runner import evaluate, run
tour, _ = record_tour(2, 3, 40, seed=5, width=256, height=64, progress=False)
result = run("online", tour.frames, "orb")
m = evaluate(result, tour.room)
print(hashlib.sha1(tour.frames.tobytes()).hexdigest())
print(",".join(map(str, result.assignments)))
print(m["precision"], m["nmi"])
"""


def test_same_seeds_same_frames_places_and_metrics_across_processes():
    tour, _ = record_tour(2, 3, 40, seed=5, width=256, height=64, progress=False)
    result = run("online", tour.frames, "orb")
    m = evaluate(result, tour.room)
    here = [hashlib.sha1(tour.frames.tobytes()).hexdigest(),
            ",".join(map(str, result.assignments)), f"{m['precision']} {m['nmi']}"]
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          check=True)
    assert proc.stdout.split("\n")[:3] == here


def test_another_seed_gives_another_tour():
    a, _ = record_tour(2, 3, 20, seed=5, width=256, height=64, progress=False)
    b, _ = record_tour(2, 3, 20, seed=6, width=256, height=64, progress=False)
    assert not np.array_equal(a.pose, b.pose)
