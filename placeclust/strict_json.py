"""JSON that other tools can read: no bare ``NaN`` or ``Infinity`` (they are not JSON).

An interval drawn from one building, an NMI of no places, is undefined: Python's ``json``
writes it as ``NaN``, which ``jq``, JavaScript and pandas' strict readers refuse. The results
files write ``null`` there instead (:func:`dumps`), and readers that want the float back call
:func:`nan_for_none` on the fields that may hold one.

Examples:
    >>> from placeclust.strict_json import dumps, nan_for_none
    >>> dumps({"interval": [float("nan"), 1.0]})
    '{"interval": [null, 1.0]}'
    >>> nan_for_none([None, 1.0])
    [nan, 1.0]
"""

from __future__ import annotations

import json
import math
from typing import Any


def finite(obj: Any) -> Any:
    """``obj`` with every non-finite float (NaN, ±inf, numpy's too) as None, recursively
    through dicts, lists and tuples."""
    if isinstance(obj, dict):
        return {k: finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs: Any) -> str:
    """``json.dumps`` of :func:`finite` ``(obj)``, refusing any non-finite float left."""
    return json.dumps(finite(obj), allow_nan=False, **kwargs)


def nan_for_none(values: list[float | None]) -> list[float]:
    """A list read back from :func:`dumps`: None (an undefined figure) as NaN again."""
    return [math.nan if v is None else float(v) for v in values]
