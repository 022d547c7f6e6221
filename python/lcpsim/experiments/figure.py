"""What every experiment's figure shares: matplotlib with the Agg backend,
saving to PNG, solver labels and outcome colours."""

from __future__ import annotations

import os
from typing import Any, Mapping

__all__ = ["OUTCOME_COLORS", "pyplot", "save", "solver_label"]

OUTCOME_COLORS = {"slide": "tab:green", "rest": "tab:blue", "tip": "tab:red"}


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save(fig: Any, path: str | os.PathLike[str]) -> str:
    """Writes ``fig`` as PNG to ``path`` (creating its directory) and closes it."""
    p = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(p)), exist_ok=True)
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    pyplot().close(fig)
    return p


def solver_label(r: Mapping[str, Any]) -> str:
    s = r.get("solver") or {}
    return str(s.get("name", "?")) if isinstance(s, Mapping) else str(s)
