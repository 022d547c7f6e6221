"""lcpsim — rigid-body contact simulation with a Lemke LCP solver that does not
lie, and the tools to study its LCPs.

Public API (the compiled module ``lcpsim._core`` is private)::

    from lcpsim import solve_lcp, solve_lcp_batch, lcp_residual
    res = solve_lcp(M, q)                 # Lemke, lexicographic pivoting
    res.ok, res.status, res.z, res.residual
"""

from __future__ import annotations

from ._core import __version__
from .lcp import (
    METHODS,
    PIVOTINGS,
    STATUSES,
    LcpBatchResult,
    LcpResult,
    lcp_residual,
    lcp_residuals,
    solve_lcp,
    solve_lcp_batch,
)

__all__ = [
    "__version__",
    "solve_lcp",
    "solve_lcp_batch",
    "lcp_residual",
    "lcp_residuals",
    "LcpResult",
    "LcpBatchResult",
    "METHODS",
    "PIVOTINGS",
    "STATUSES",
]
