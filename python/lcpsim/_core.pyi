"""Type stubs for the private compiled module ``lcpsim._core``.

Use the public wrappers in :mod:`lcpsim` instead; these functions return plain
dicts and are documented here for the wrappers' sake.
"""

from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str
#: ["lemke", "pgs", "newton_fb"]
METHODS: list[str]
#: ["lexicographic", "classic"]
PIVOTINGS: list[str]
#: ["solved", "ray_termination", "max_pivots", "max_iterations",
#:  "singular_basis", "cycling", "numerical", "regularized"]
STATUSES: list[str]
#: Option names accepted by each method.
METHOD_OPTIONS: dict[str, list[str]]

class SolutionDict(TypedDict):
    z: NDArray[np.float64]
    w: NDArray[np.float64]
    status: str
    iterations: int
    natural: float
    min_z: float
    min_w: float
    max_complementarity: float
    basis: NDArray[np.bool_] | None
    method: str

class BatchDict(TypedDict):
    z: NDArray[np.float64]  # (b, n)
    w: NDArray[np.float64]  # (b, n)
    status: list[str]
    iterations: NDArray[np.int64]
    natural: NDArray[np.float64]
    min_z: NDArray[np.float64]
    min_w: NDArray[np.float64]
    max_complementarity: NDArray[np.float64]
    basis: NDArray[np.bool_] | None  # (b, n) when every solve returned one
    method: str

class ResidualsDict(TypedDict):
    w: NDArray[np.float64]
    natural: float
    min_z: float
    min_w: float
    max_complementarity: float

def solve_lcp(m: ArrayLike, q: ArrayLike, method: str = "lemke", **options: Any) -> SolutionDict:
    """Solve one LCP. Raises ValueError on invalid input or options."""

def solve_lcp_batch(
    ms: ArrayLike, qs: ArrayLike, method: str = "lemke", threads: int = 1, **options: Any
) -> BatchDict:
    """Solve a (b, n, n) / (b, n) batch with the GIL released."""

def lcp_residual(m: ArrayLike, q: ArrayLike, z: ArrayLike) -> float:
    """‖min(z, M z + q)‖∞."""

def lcp_residuals(m: ArrayLike, q: ArrayLike, z: ArrayLike) -> ResidualsDict:
    """w = M z + q and every residual of z."""
