"""Sizes read from a file, checked before anything is allocated.

An ``.npz`` header or an HDF5 dataset shape is only a claim: a damaged or
hostile file can claim a 10⁶ × 10⁶ matrix in a few hundred bytes. Before an
array is read its size is checked against the machine's physical memory (a
request larger than that can never succeed) and, where the file must hold
the data itself, against what the file holds. The compiled core checks its
own sizes the same way (Rust ``lcp::limits``).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

__all__ = ["physical_memory", "human_bytes", "check_bytes", "array_bytes", "SizeLimitError"]


class SizeLimitError(ValueError):
    """A request whose size cannot fit in memory (or that its file cannot hold)."""


def physical_memory() -> int | None:
    """The machine's physical memory in bytes (None where it cannot be read)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, OSError, ValueError):  # pragma: no cover - not POSIX
        return None


def human_bytes(n: int | float) -> str:
    """``800 B``, ``1.5 GiB``, ``7.28 TiB``."""
    units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB", "ZiB", "YiB"]
    v = float(n)
    u = 0
    while v >= 1024 and u + 1 < len(units):
        v /= 1024
        u += 1
    return f"{int(n)} B" if u == 0 else f"{v:.3g} {units[u]}"


def array_bytes(shape: tuple[int, ...], dtype: Any) -> int:
    """Bytes of an array of ``shape`` and ``dtype`` (exact, Python ints)."""
    count = 1
    for d in shape:
        count *= int(d)
    return count * int(np.dtype(dtype).itemsize)


def check_bytes(what: str, nbytes: int) -> None:
    """Raises :class:`SizeLimitError` if ``nbytes`` exceeds the physical memory."""
    limit = physical_memory()
    if limit is not None and nbytes > limit:
        raise SizeLimitError(f"{what} needs {human_bytes(nbytes)}, more than this machine's {human_bytes(limit)} of memory")
