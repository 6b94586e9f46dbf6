"""``python -m placeclust.freshness check|record`` (:mod:`placeclust.freshness.check`); its
``_trace`` runs one command traced, for ``record`` (:func:`placeclust.freshness.probes.trace_main`).
"""

import sys

from placeclust.freshness.check import main
from placeclust.freshness.probes import trace_main

if __name__ == "__main__":  # importing the module (pkgutil.walk_packages does) runs nothing
    raise SystemExit(trace_main(sys.argv[2:]) if sys.argv[1:2] == ["_trace"] else main())
