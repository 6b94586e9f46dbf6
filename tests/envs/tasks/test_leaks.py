"""Nothing leaks: creating, stepping and closing ``PlaceNav-v0`` again and again holds the
process's memory and open file descriptors flat (EGL contexts are the usual culprit)."""

import os
from pathlib import Path

import gymnasium as gym
import numpy as np

import envs  # noqa: F401 - registers PlaceNav-v0


def _rss_mib() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def _open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


def _cycle() -> None:
    env = gym.make("PlaceNav-v0", panorama_width=64, panorama_height=16, n_rooms=2)
    env.reset(seed=0)
    env.step(np.zeros(2, np.float32))
    env.close()


def test_create_step_close_cycles_hold_memory_and_descriptors_flat():
    for _ in range(10):  # the first cycles fill caches and pools that are kept on purpose
        _cycle()
    rss, fds = _rss_mib(), _open_fds()
    for _ in range(40):
        _cycle()
    # one leaked env (model, data, textures, a GL context) is several MiB: 40 leaked, well
    # over 100 MiB
    assert _rss_mib() - rss < 40, f"RSS grew from {rss:.0f} to {_rss_mib():.0f} MiB"
    assert _open_fds() - fds <= 2, f"open file descriptors grew from {fds} to {_open_fds()}"
