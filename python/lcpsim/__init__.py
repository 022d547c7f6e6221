"""lcpsim — rigid-body contact simulation with a Lemke LCP solver that does not
lie, and the tools to study its LCPs.

Public API (the compiled module ``lcpsim._core`` is private)::

    from lcpsim import solve_lcp, solve_lcp_batch, lcp_residual
    res = solve_lcp(M, q)                 # Lemke, lexicographic pivoting
    res.ok, res.status, res.z, res.residual
    solve_lcp(M, q, certify=True).certified   # exact rational check of the final basis
    solve_lcp(M, q, dump="dumps/").dump_path  # failure dump (None when solved)

    from lcpsim import World, scenes, open_corpus
    s = scenes.cube_on_slope(30.0, 0.5)   # a ready World plus metadata
    traj = s.world.run(1000, capture="lcps.h5")
"""

from __future__ import annotations

from ._core import ContactLayout, __version__
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
from .certification import Certificate, certify
from .world import NO_CONTACT, BodyState, LcpStats, Stabilization, StepRecord, Trajectory, World
from . import scenes
from .scenes import Scene
from .corpus import Corpus, CorpusRecord, CorpusWriter, open_corpus

__all__ = [
    "__version__",
    "ContactLayout",
    "solve_lcp",
    "solve_lcp_batch",
    "lcp_residual",
    "lcp_residuals",
    "LcpResult",
    "LcpBatchResult",
    "METHODS",
    "PIVOTINGS",
    "STATUSES",
    "certify",
    "Certificate",
    "World",
    "StepRecord",
    "Trajectory",
    "BodyState",
    "Stabilization",
    "LcpStats",
    "NO_CONTACT",
    "scenes",
    "Scene",
    "Corpus",
    "CorpusRecord",
    "CorpusWriter",
    "open_corpus",
]
