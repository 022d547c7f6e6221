"""What every experiment's figure shares: matplotlib with the Agg backend,
saving to PNG, solver labels and outcome colours."""

from __future__ import annotations

import os
from typing import Any, Iterator, Mapping, Sequence

__all__ = ["OUTCOME_COLORS", "pyplot", "save", "solver_label", "label_axes", "traced"]

OUTCOME_COLORS = {"slide": "tab:green", "rest": "tab:blue", "tip": "tab:red"}


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def two_panels(width: float, height: float) -> tuple[Any, Any, Any]:
    """A figure of two axes side by side: ``(fig, left, right)``."""
    fig, (ax1, ax2) = pyplot().subplots(1, 2, figsize=(width, height))
    return fig, ax1, ax2


def save(fig: Any, path: str | os.PathLike[str]) -> str:
    """Writes ``fig`` as PNG to ``path`` (creating its directory) and closes it."""
    p = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(p)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    pyplot().close(fig)
    return p


def label_axes(
    ax: Any, xlabel: str, ylabel: str | None = None, *, title: str | None = None, legend: int | None = None
) -> None:
    """The figures' axis conventions: labels, an optional title, a light grid,
    and a legend in font size ``legend`` when given."""
    ax.set_xlabel(xlabel)
    if ylabel is not None:
        ax.set_ylabel(ylabel)
    if title is not None:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    if legend is not None:
        ax.legend(fontsize=legend)


def solver_label(r: Mapping[str, Any]) -> str:
    s = r.get("solver") or {}
    return str(s.get("name", "?")) if isinstance(s, Mapping) else str(s)


def traced(results: Sequence[Mapping[str, Any]]) -> Iterator[tuple[int, Mapping[str, Any], Mapping[str, Any]]]:
    """``(i, result, trace)`` for each result that carries a trace (``i`` its
    place among all results, which picks its colour)."""
    for i, r in enumerate(results):
        if r.get("trace"):
            yield i, r, r["trace"]
