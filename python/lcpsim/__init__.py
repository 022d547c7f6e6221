"""lcpsim — rigid-body contact simulation with a Lemke LCP solver that does not
lie, and the tools to study its LCPs.

Public API (the compiled module ``lcpsim._core`` is private)::

    from lcpsim import solve_lcp, solve_lcp_batch, lcp_residual
    res = solve_lcp(M, q)                 # Lemke, lexicographic pivoting
    res.ok, res.status, res.z, res.residual
    solve_lcp(M, q, certify=True).certified   # exact rational check of the final basis
    solve_lcp(M, q, dump="dumps/").dump_path  # failure dump (None when solved)

    from lcpsim import World, scenes, open_capture
    s = scenes.cube_on_slope(30.0, 0.5)   # a ready World plus metadata
    traj = s.world.run(1000, capture="lcps.h5")
    with open_capture("lcps.h5") as c: ...   # every LCP the run solved

Sub-packages: :mod:`lcpsim.io` (LCP files, captures, failure dumps, FCLib files),
:mod:`lcpsim.faceting` (FCLib problems as faceted LCPs, the exact-cone residual),
:mod:`lcpsim.experiments` (the source note's experiments, their registry, the
report), :mod:`lcpsim.cli` (the ``lcpsim`` command).
"""

from __future__ import annotations

from ._core import ContactLayout, __version__
from .lcp import (
    METHODS,
    PIVOTINGS,
    STATUSES,
    lcp_residual,
    lcp_residuals,
    solve_lcp,
    solve_lcp_batch,
)
from .certification import certify
from .result import Certificate, LcpBatchResult, LcpResult
from . import world
from .world import *  # noqa: F403 (its __all__: World, StepRecord, Trajectory, … joins ours below)
from . import scenes
from .scenes import Scene
from .io.capture import Capture, CaptureRecord, CaptureWriter, open_capture
from . import faceting

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
    "scenes",
    "Scene",
    "Capture",
    "CaptureRecord",
    "CaptureWriter",
    "open_capture",
    "faceting",
]
__all__ += world.__all__
