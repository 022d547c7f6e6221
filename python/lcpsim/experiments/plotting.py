"""Plots of the experiments' results (matplotlib, Agg backend, PNG).

Each experiment draws its own figures (``plot_*`` in its module, shared
set-up in :mod:`.figure`); this module gathers them and draws the natural
plot of any result.
"""

from __future__ import annotations

import os
from typing import Any, Mapping

from .critical_scale import plot_critical_scale
from .failure_rate import plot_failure_rate
from .figure import OUTCOME_COLORS
from .invariance import plot_invariance
from .patterns import plot_patterns
from .push import plot_push, plot_push_sweep
from .slope import plot_slope

__all__ = [
    "OUTCOME_COLORS",
    "plot_failure_rate",
    "plot_slope",
    "plot_critical_scale",
    "plot_invariance",
    "plot_patterns",
    "plot_push",
    "plot_push_sweep",
    "plot_result",
]


def plot_result(result: Mapping[str, Any], path: str | os.PathLike[str]) -> str:
    """The natural plot of one result, by its ``experiment``."""
    from .registry import REGISTRY

    kind = result.get("experiment")
    if kind not in REGISTRY:
        raise ValueError(f"no plot for experiment {kind!r}")
    return REGISTRY[str(kind)].plot([result], path)
