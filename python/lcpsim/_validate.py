"""Input checks shared by the solver wrappers (:mod:`lcpsim.lcp`), the
exact check (:mod:`lcpsim.certification`) and the world's constructors
(:mod:`lcpsim.world`, :mod:`lcpsim._shapes`): every mistake is a
:class:`ValueError` naming the argument and its value."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

# dtype kinds that convert to float64 without loss of meaning:
# bool, signed and unsigned integers, floats.
REAL_KINDS = frozenset("biuf")


def as_real_array(x: ArrayLike, name: str, ndim: int) -> NDArray[np.float64]:
    """``x`` as a float64 array with ``ndim`` dimensions, or a ValueError naming ``name``."""
    if isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == ndim:
        return x  # fast path: the compiled module copies what it needs
    try:
        a = np.asarray(x)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name} must be a {ndim}-D array of real numbers, got {short_repr(x)}: {e}") from None
    if a.dtype.kind not in REAL_KINDS:
        raise ValueError(
            f"{name} must hold real numbers, got dtype {a.dtype} ({short_repr(x)})"
        )
    if a.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {a.shape} ({short_repr(x)})")
    return a.astype(np.float64, copy=False)


def as_basis(b: ArrayLike, name: str = "basis") -> NDArray[np.bool_]:
    """``b`` as a contiguous boolean array (``z_j`` basic), or a ValueError naming ``name``."""
    a = np.asarray(b)
    if a.dtype != np.bool_:
        raise ValueError(f"{name} must be a boolean array (z_j basic), got dtype {a.dtype}")
    return np.ascontiguousarray(a)


def short_repr(x: Any, limit: int = 60) -> str:
    """``x`` on one line, cut to ``limit`` characters."""
    r = np.array2string(x, threshold=6) if isinstance(x, np.ndarray) else repr(x)
    r = " ".join(r.split())
    return r if len(r) <= limit else r[: limit - 3] + "..."


def vec(x: Any, name: str, n: int = 3) -> tuple[float, ...]:
    """``n`` finite reals from any sequence, else a ValueError naming ``name``."""
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a sequence of {n} real numbers, got {x!r}") from None
    if a.shape != (n,):
        raise ValueError(f"{name} must be a sequence of {n} real numbers, got {x!r}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {x!r}")
    return tuple(float(v) for v in a)


def real(x: Any, name: str) -> float:
    """A real number (bool refused), else a ValueError naming ``name``."""
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a real number, got {x!r}")
    return float(x)


def velocities(velocity: Any, angular_velocity: Any) -> tuple[Any, Any]:
    """``velocity`` with 6 values is ``[v; ω]``."""
    if velocity is not None and np.ndim(velocity) == 1 and np.size(velocity) == 6:
        v6 = vec(velocity, "velocity", 6)
        if angular_velocity is not None and np.any(np.asarray(angular_velocity, dtype=float) != 0):
            raise ValueError("give the angular velocity either in a 6-value velocity or as angular_velocity, not both")
        return v6[:3], v6[3:]
    return velocity, angular_velocity
