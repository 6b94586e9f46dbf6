"""Run independent jobs in parallel: in-process, on a local ``spawn`` pool, or on Ray.

The benchmark matrix (:mod:`envs.commands.bench`) and the closed-loop leaderboard
(:mod:`envs.commands.leaderboard`) both hand their jobs to :func:`run_all` and record what comes
back.

Examples:
    >>> from envs.runs.pool import run_all
    >>> sorted(result for _, result in run_all(abs, [-2, 1, -3], workers=1))
    [1, 2, 3]
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Generator, Iterator
from typing import Any, TypeVar

Job = TypeVar("Job")
EXECUTORS = ("process", "ray")


def run_all(fn: Callable[[Job], Any], jobs: list[Job], workers: int = 1,
            executor: str = "process", address: str | None = None
            ) -> Generator[tuple[Job, Any], None, None]:
    """``(job, fn(job))`` for every job, in the order they finish; closing the generator
    early (``close()``, or dropping it) stops the jobs still running.

    Args:
        fn: a picklable callable (a module-level function, or a ``functools.partial`` of one).
        jobs: its arguments, one per call.
        workers: processes (or Ray CPUs of a local Ray instance); 1 runs in this process,
            which is easier to debug and profile.
        executor: ``"process"`` (a local pool of spawned processes) or ``"ray"``.
        address: with ``"ray"``, the cluster to join; None joins the one in the environment
            variable ``RAY_ADDRESS`` (Ray's convention) if set, else starts a local instance.

    Raises:
        ValueError: an unknown executor, or ``"ray"`` without Ray installed.
    """
    if executor not in EXECUTORS:
        raise ValueError(f"unknown executor {executor!r}; choose one of {EXECUTORS}")
    if executor == "ray":
        yield from _ray(fn, jobs, workers, address)
    elif workers <= 1:
        for job in jobs:
            yield job, fn(job)
    else:
        yield from _local(fn, jobs, workers)


def _local(fn: Callable, jobs: list, workers: int) -> Iterator[tuple[Any, Any]]:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # spawn, never fork: a forked child of a process that has rendered deadlocks in Mesa's EGL
    pool = ProcessPoolExecutor(workers, mp_context=mp.get_context("spawn"),
                               initializer=_die_with_parent, initargs=(os.getpid(),))
    futures = {pool.submit(fn, job): job for job in jobs}
    try:
        for fut in as_completed(futures):
            yield futures[fut], fut.result()
    except BaseException:
        # Ctrl-C or a failed job: stop the running jobs now rather than wait minutes for them
        # (their results would be dropped anyway); finished ones were yielded and kept
        workers_now = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in workers_now:
            process.terminate()
        raise
    pool.shutdown()


def _die_with_parent(parent: int) -> None:
    """Have the kernel stop this worker when the process that started it dies (Linux), and
    leave Ctrl-C to the parent.

    A killed benchmark (``kill``, a job scheduler's time limit) would otherwise leave its
    workers running their jobs, minutes each, on cores the next run needs.
    """
    import signal

    # Ctrl-C reaches the whole process group: the parent alone answers it (one line, kept
    # jobs said) and stops the workers, which would each print a traceback of their own
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    pr_set_pdeathsig = 1
    ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, int(signal.SIGTERM))
    if os.getppid() != parent:  # it died before the call: nobody is left to signal
        os._exit(1)


def _call(fn: Callable, job: Any) -> Any:
    return fn(job)


def _ray(fn: Callable, jobs: list, workers: int, address: str | None
         ) -> Iterator[tuple[Any, Any]]:
    try:
        import ray
    except ImportError as exc:
        raise ValueError("executor 'ray' needs Ray: pip install 'placeclust[ray]'") from exc
    if not ray.is_initialized():
        # a cluster's CPUs are its own: num_cpus is only for the instance started here
        address = address or os.environ.get("RAY_ADDRESS")
        kwargs = {"address": address} if address else {"num_cpus": max(workers, 1)}
        ray.init(include_dashboard=False, log_to_driver=False, **kwargs)
    task = ray.remote(num_cpus=1)(_call)  # a function: Ray cannot make a partial remote
    pending = {task.remote(fn, job): job for job in jobs}
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        yield pending.pop(ready[0]), ray.get(ready[0])
