"""Array checks of the shapes with data (:meth:`lcpsim.World.add_convex`,
:meth:`lcpsim.World.add_mesh`): shapes and size limits here, the rest
(finite values, index ranges, degenerate faces) in Rust (``sim::geometry``)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

#: The most points :meth:`World.add_convex` takes, and the most vertices and
#: triangles of :meth:`World.add_mesh` (``sim::geometry::MAX_*``).
MAX_HULL_POINTS = 100_000
MAX_MESH_VERTICES = 1_000_000
MAX_MESH_FACES = 2_000_000


def points_array(x: Any, name: str, limit: int) -> NDArray[np.float64]:
    """An (N, 3) float array, N ≤ ``limit``, else a ValueError naming ``name``."""
    try:
        a = np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an (N, 3) array of real numbers, got {x!r}") from None
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be an (N, 3) array of real numbers, got shape {a.shape}")
    if a.shape[0] > limit:
        raise ValueError(f"{name} has {a.shape[0]} points, more than the limit of {limit}")
    return a


def faces_array(faces: Any, limit: int) -> NDArray[np.int64]:
    """An (M, 3) int64 array, M ≤ ``limit``, else a ValueError naming ``faces``."""
    try:
        f = np.asarray(faces)
    except (TypeError, ValueError):
        raise ValueError(f"faces must be an (M, 3) array of integers, got {faces!r}") from None
    if f.ndim != 2 or f.shape[1] != 3 or not (f.size == 0 or np.issubdtype(f.dtype, np.integer)):
        raise ValueError(f"faces must be an (M, 3) array of integers, got shape {f.shape}, dtype {f.dtype}")
    if f.shape[0] > limit:
        raise ValueError(f"faces has {f.shape[0]} triangles, more than the limit of {limit}")
    return np.ascontiguousarray(f, dtype=np.int64)
