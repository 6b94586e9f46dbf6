"""Benchmark runs below the command line: one building's guided tour and errands
(:mod:`~envs.runs.tour_errands`), jobs of them with their stamps (:mod:`~envs.runs.jobs`), the
pool that runs jobs (:mod:`~envs.runs.pool`) and the store that keeps them
(:mod:`~envs.runs.store`), closed-loop results files (:mod:`~envs.runs.results`), and the
frozen suites with the fingerprints that make results comparable (:mod:`~envs.runs.suite`).

The commands (:mod:`envs.commands`) parse options and print; training (``train/``) runs the
same jobs without them.
"""
