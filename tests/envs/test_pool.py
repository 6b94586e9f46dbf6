import pytest

from envs.pool import run_all


def test_every_job_comes_back_with_its_result_in_process_and_pooled():
    jobs = [-3, 1, -2, 5]
    for workers in (1, 2):
        assert sorted(run_all(abs, jobs, workers=workers)) == sorted(
            (j, abs(j)) for j in jobs)


def test_an_unknown_executor_is_named():
    with pytest.raises(ValueError, match="unknown executor 'dask'"):
        list(run_all(abs, [1], executor="dask"))
