"""Which generated tables of ``docs/benchmarks.md`` the current code would change.

``python -m placeclust.freshness check`` (:mod:`placeclust.freshness.check`); the commands'
tiny traced runs are :mod:`placeclust.freshness.probes`, their fingerprints
:mod:`placeclust.freshness.syntax`. A package of its own, outside the
library's top level, so that editing this tool changes no benchmark's code fingerprint
(``envs.commands.suite.code_fingerprint`` hashes the library's top-level modules): no kept
run is redone, and no run in progress is spoiled, for an edit here.
"""

from placeclust.freshness.check import (
    comparable,
    load,
    main,
    record,
    sections,
    status,
    write_stale_list,
)
from placeclust.freshness.syntax import fingerprint, source_digest

__all__ = ["comparable", "fingerprint", "load", "main", "record", "sections", "source_digest",
           "status", "write_stale_list"]
