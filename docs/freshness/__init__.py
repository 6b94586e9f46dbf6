"""Which generated tables of ``docs/benchmarks.md`` the current code would change.

``python -m docs.freshness check|verify|record`` (:mod:`docs.freshness.check`); the commands'
tiny traced runs are :mod:`docs.freshness.probes`, their fingerprints
:mod:`docs.freshness.syntax`, the verdict of a probe run with the code then and now
:mod:`docs.freshness.verify`, the tables claims cite :mod:`docs.freshness.cited`. Tooling of
this repository, not of the library: ``pip install .`` does not install it, and editing it
changes no benchmark's code fingerprint.
"""

from docs.freshness.check import (
    comparable,
    failing,
    load,
    main,
    record,
    run_verify,
    sections,
    status,
    write_stale_list,
)
from docs.freshness.syntax import fingerprint, source_digest

__all__ = ["comparable", "failing", "fingerprint", "load", "main", "record", "run_verify",
           "sections", "source_digest", "status", "write_stale_list"]
