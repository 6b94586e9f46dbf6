"""Closed-loop jobs: the order the pool gets them in."""

from envs.runs import jobs
from envs.runs.jobs import make_jobs
from envs.runs.task_spec import ErrandTask


def test_the_slow_recognizers_run_first_and_the_oracles_last(monkeypatch):
    """Fault caught: a calibration oracle (it renders nothing: a short job) sorted among the
    detectors, so that a run's last job is a long one and one core idles."""
    given = []

    def run_all(fn, todo, workers, executor):
        for job in todo:
            given.append(job["recognizer"])
            yield job, {}

    monkeypatch.setattr(jobs, "run_all", run_all)
    names = ["oracle-cells:2", "none", "oracle", "examples.tiny_recognizer:HaarPlaces",
             "panorama-orb", "oracle-pose", "panorama"]
    jobs.run_jobs(make_jobs([0], names, ErrandTask(n_errands=1), n_rooms=3, agent="spot",
                            seed=0),
                  progress=False)
    assert given[:3] == ["examples.tiny_recognizer:HaarPlaces", "panorama", "panorama-orb"]
    assert given[3] == "none" and set(given[4:]) == {"oracle-cells:2", "oracle", "oracle-pose"}
