"""The worked example of a recognizer of your own: it passes the battery and runs through the
CLI by its module path; paths that do not lead to a recognizer are one line of error."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from examples.tiny_recognizer import HaarPlaces
from placeclust.checks import check_recognizer

ROOT = Path(__file__).resolve().parent.parent


def test_the_tiny_recognizer_passes_the_battery():
    check_recognizer(HaarPlaces)


def _cluster(tmp_path: Path, algo: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "envs.commands.cli", "cluster", "--algo", algo,
                           "--tour", str(tmp_path / "tour.npz"), "--out", str(tmp_path / algo),
                           "--quiet"], cwd=ROOT, capture_output=True, text=True)


def test_the_cli_runs_a_recognizer_by_its_module_path(tmp_path, two_places):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    proc = _cluster(tmp_path, "examples.tiny_recognizer:HaarPlaces")
    assert proc.returncode == 0, proc.stderr
    metrics = json.loads((tmp_path / "examples.tiny_recognizer:HaarPlaces" /
                          "metrics.json").read_text())
    assert metrics["n_places"] >= 2 and metrics["precision"] > 0.9


@pytest.mark.parametrize("algo, message", [
    ("no_such_module:Places", "cannot import 'no_such_module'"),
    ("placeclust.metrics:score", "has no class 'score'"),
    ("placeclust.kernel:UnionKernel", "is not a recognizer"),
])
def test_paths_that_lead_nowhere_are_one_line_of_error(tmp_path, two_places, algo, message):
    frames, truth = two_places
    np.savez(tmp_path / "tour.npz", frames=frames, room=truth)
    proc = _cluster(tmp_path, algo)
    assert proc.returncode == 2
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
