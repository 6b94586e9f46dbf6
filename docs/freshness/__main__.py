"""``python -m docs.freshness check|record`` (:mod:`docs.freshness.check`); its
``_trace`` runs one command traced, for ``record`` (:func:`docs.freshness.probes.trace_main`).
"""

import sys

from docs.freshness.check import main
from docs.freshness.probes import trace_main

if __name__ == "__main__":  # importing the module (pkgutil.walk_packages does) runs nothing
    raise SystemExit(trace_main(sys.argv[2:]) if sys.argv[1:2] == ["_trace"] else main())
