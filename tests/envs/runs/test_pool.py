import subprocess
import sys
import time
from pathlib import Path

import pytest

from envs.runs.pool import run_all


def test_every_job_comes_back_with_its_result_in_process_and_pooled():
    jobs = [-3, 1, -2, 5]
    for workers in (1, 2):
        assert sorted(run_all(abs, jobs, workers=workers)) == sorted(
            (j, abs(j)) for j in jobs)


def test_an_unknown_executor_is_named():
    with pytest.raises(ValueError, match="unknown executor 'dask'"):
        list(run_all(abs, [1], executor="dask"))


def test_ray_joins_the_cluster_named_in_ray_address(monkeypatch):
    ray = pytest.importorskip("ray")
    seen: dict = {}

    def init(**kwargs):
        seen.update(kwargs)
        raise RuntimeError("no cluster here")

    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    monkeypatch.setattr(ray, "init", init)
    monkeypatch.setenv("RAY_ADDRESS", "10.0.0.7:6379")
    with pytest.raises(RuntimeError, match="no cluster"):
        list(run_all(abs, [1], workers=4, executor="ray"))
    assert seen["address"] == "10.0.0.7:6379" and "num_cpus" not in seen  # its CPUs, not ours


def _stat(pid: int | str) -> list[str] | None:
    """A process's ``/proc/PID/stat`` fields after its name (state, parent, ...), or ``None``
    once it is gone or a zombie."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None  # it ended while being read
    return None if fields[0] == "Z" else fields


def _alive(pid: int) -> bool:
    return _stat(pid) is not None


def _children(pid: int) -> list[int]:
    """Live processes whose parent is ``pid`` (Linux ``/proc``)."""
    found = []
    for proc in Path("/proc").glob("[0-9]*"):
        fields = _stat(proc.name)
        if fields is not None and int(fields[1]) == pid:
            found.append(int(proc.name))
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the kernel's parent-death signal")
def test_pooled_workers_stop_when_the_benchmark_is_killed():
    script = ("import time; from envs.runs.pool import run_all; "
              "list(run_all(time.sleep, [60, 60], 2))")
    parent = subprocess.Popen([sys.executable, "-c", script],
                              cwd=Path(__file__).resolve().parents[3])
    try:
        deadline = time.monotonic() + 60
        while len(workers := _children(parent.pid)) < 3 and time.monotonic() < deadline:
            time.sleep(0.2)  # two workers and multiprocessing's resource tracker
        assert len(workers) >= 3, "the pool never started"
        time.sleep(1.0)  # the workers have taken their minute-long jobs
    finally:
        parent.kill()
        parent.wait()
    deadline = time.monotonic() + 20
    while any(map(_alive, workers)) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not any(map(_alive, workers))


def test_stopping_early_stops_the_running_jobs_at_once():
    """Fault caught: Ctrl-C (or a failed job) waited for every running job, minutes each,
    before the command could say anything; and the workers lived on."""
    import multiprocessing

    results = run_all(time.sleep, [0, 120, 120], workers=2)
    assert next(results) == (0, None)
    start = time.perf_counter()
    results.close()  # what run_jobs does when Ctrl-C or an error ends its loop
    assert time.perf_counter() - start < 30
    deadline = time.time() + 30
    while multiprocessing.active_children() and time.time() < deadline:
        time.sleep(0.2)
    assert not multiprocessing.active_children()
