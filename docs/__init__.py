"""The repository's documentation tooling (not part of the installed library): which
generated tables of ``docs/benchmarks.md`` today's code would change, :mod:`docs.freshness`."""
