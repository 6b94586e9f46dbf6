"""``PlaceNav`` envs stepped side by side in worker processes, one core each.

One env already keeps two cores busy on a 2-core machine: Mesa's llvmpipe rasterizes on a
thread per core and OpenCV remaps on a pool of its own. Workers that each do the same
oversubscribe the cores and run slower together than one process alone (``python -m
envs.commands.speed``). :func:`single_threaded_workers` makes the processes spawned inside it
rasterize in their own thread (``LP_NUM_THREADS=0``) with one OpenCV, OpenMP and OpenBLAS
thread each; the pictures are the same. :func:`make_vector_env` builds Gymnasium's
``AsyncVectorEnv`` that way; stable-baselines3's ``SubprocVecEnv`` can be made inside the
context manager (``train/train.py`` does).

Workers are spawned, never forked: a forked worker inherits the parent's GL state and
deadlocks inside Mesa.
"""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Iterator
from typing import Any

import gymnasium as gym

#: what each worker is told, unless the user set it already
WORKER_THREADS = {
    "LP_NUM_THREADS": "0",  # llvmpipe: rasterize in the rendering thread, no helper threads
    "OPENCV_FOR_THREADS_NUM": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
}


@contextlib.contextmanager
def single_threaded_workers() -> Iterator[None]:
    """Processes spawned inside use one thread each for rendering and numerics.

    The variables of :data:`WORKER_THREADS` are set for the duration (a value the user set
    wins) and restored afterwards; this process's own threads are not changed, since each
    library reads them when it starts.
    """
    saved = {name: os.environ.get(name) for name in WORKER_THREADS}
    for name, value in WORKER_THREADS.items():
        os.environ.setdefault(name, value)
    try:
        yield
    finally:
        for name, before in saved.items():
            if before is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = before


def make_vector_env(num_envs: int, env_id: str = "PlaceNav-v0", **kwargs: Any
                    ) -> gym.vector.AsyncVectorEnv:
    """``num_envs`` copies of ``env_id`` (made with ``kwargs``) in spawned, single-threaded
    worker processes.

    Example:
        >>> from envs.runs.vector import make_vector_env
        >>> vec = make_vector_env(2, panorama_width=64, panorama_height=16, n_rooms=2)
        >>> obs, info = vec.reset(seed=0)
        >>> obs["panorama"].shape
        (2, 16, 64, 3)
        >>> vec.close()
    """
    if num_envs < 1:
        raise ValueError(f"num_envs must be at least 1, got {num_envs}")
    # the package's own name: "envs" in a clone, "placeclust_envs" when installed
    make = functools.partial(gym.make, f"{__package__}:{env_id}", **kwargs)
    with single_threaded_workers():
        return gym.vector.AsyncVectorEnv([make] * num_envs, context="spawn")
