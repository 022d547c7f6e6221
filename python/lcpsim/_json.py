"""One conversion to plain JSON types, used by every result file, capture
metadata and config lcpsim writes."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["jsonable", "fields_dict"]


def jsonable(x: Any) -> Any:
    """``x`` with plain JSON types only.

    Mappings become dicts with string keys; numpy arrays, lists, tuples and
    other iterables become lists; numpy scalars become Python ones; a
    non-finite float becomes the string ``"inf"``, ``"-inf"`` or ``"nan"``
    (strict JSON has no such numbers); ``None``, strings, ints and bools stay;
    anything else becomes ``str(x)``."""
    # the plain types first, by exact type: `World.run` converts its config
    # every call, and the ABC checks below cost a microsecond a value
    t = type(x)
    if t is float:
        return x if math.isfinite(x) else ("inf" if x > 0 else "-inf" if x < 0 else "nan")
    if t is str or t is int or t is bool or x is None:
        return x
    if t is dict:
        return {str(k): jsonable(v) for k, v in x.items()}
    if t is list or t is tuple:
        return [jsonable(v) for v in x]
    if isinstance(x, Mapping):
        return {str(k): jsonable(v) for k, v in x.items()}
    if x is None or isinstance(x, str):
        return x
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        f = float(x)
        return f if math.isfinite(f) else ("inf" if f > 0 else "-inf" if f < 0 else "nan")
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (list, tuple, set, frozenset)) or (hasattr(x, "__iter__") and not isinstance(x, bytes)):
        return [jsonable(v) for v in x]
    return str(x)


def fields_dict(record: Any) -> dict[str, Any]:
    """A dataclass of plain values as a dict, field by field in declaration
    order: tuples become lists and mappings are copied; everything else is
    kept as it is (unlike :func:`jsonable`, floats stay floats)."""

    def plain(v: Any) -> Any:
        return list(v) if isinstance(v, tuple) else dict(v) if isinstance(v, Mapping) else v

    return {f.name: plain(getattr(record, f.name)) for f in dataclasses.fields(record)}
