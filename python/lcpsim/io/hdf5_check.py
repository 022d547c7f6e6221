"""A guard against a damaged HDF5 file that hangs the HDF5 library itself.

HDF5 (up to 2.0 at least) reads a *global heap collection* — where
variable-length strings such as lcpsim's JSON attributes live — by walking its
objects: each object header says how far to step; the free-space object
(index 0) steps by its own size. A damaged collection whose free-space object
has size 0 makes that walk stand still: reading any string attribute then
spins forever in C, out of reach of Python (found by ``scripts/fuzz_readers.py``).
:func:`check_global_heaps` walks every collection the same way first and
refuses such a file with a clear error.

Other damage can crash or stall HDF5 where no check of ours reaches (a
segmentation fault reading a damaged attribute was found too): :func:`probe`
reads a file in a child process first, as ``lcpsim solve``, ``lcpsim view``
and ``Trajectory.load`` do.

Collections are found by their ``GCOL`` signature (version 1, reserved bytes
zero, size at least 4096 and within the file) in the first
:data:`SCAN_BYTES` of the file, where files written by lcpsim keep their
attributes.
"""

from __future__ import annotations

import mmap
import os
import struct
from pathlib import Path

__all__ = ["SCAN_BYTES", "PROBE_SECONDS", "PROBE_KINDS", "DamagedHdf5Error", "check_global_heaps", "probe"]

#: How much of a file is searched for global heap collections.
SCAN_BYTES = 64 << 20

_HEADER = 16  # signature 4, version 1, reserved 3, collection size 8
_OBJECT = 16  # index 2, references 2, reserved 4, size 8


class DamagedHdf5Error(ValueError):
    """An HDF5 file whose structure would hang the HDF5 library."""


def _walk(buf: mmap.mmap | bytes, start: int, size: int) -> str | None:
    """What stalls HDF5's walk of the collection at ``start`` (None: nothing)."""
    end, p = start + size, start + _HEADER
    for _ in range(size // 8 + 1):  # every step advances at least 8 bytes, or stalls
        if p >= end:
            return None
        if p + _OBJECT > end:  # a tail too small for a header: free space
            return None
        index = struct.unpack_from("<H", buf, p)[0]
        length = struct.unpack_from("<Q", buf, p + 8)[0]
        step = length if index == 0 else (_OBJECT + ((length + 7) // 8) * 8) % (1 << 64)
        if step == 0:
            return f"free-space object of size 0 at offset {p}"
        p += step
    return None  # pragma: no cover - the bound above is never reached


def check_global_heaps(path: str | os.PathLike[str]) -> None:
    """Raises :class:`DamagedHdf5Error` if a global heap collection of ``path``
    would stall HDF5's reader; returns quietly otherwise (or if ``path`` is
    not a regular file)."""
    p = Path(path)
    try:
        fh = open(p, "rb")
    except OSError:
        return
    with fh:
        length = os.fstat(fh.fileno()).st_size
        if length < _HEADER:
            return
        with mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as buf:
            scan_end = min(length, SCAN_BYTES)
            at = buf.find(b"GCOL", 0, scan_end)
            while at >= 0:
                if at + _HEADER <= length and buf[at + 4] == 1 and buf[at + 5 : at + 8] == b"\0\0\0":
                    size = struct.unpack_from("<Q", buf, at + 8)[0]
                    if 4096 <= size <= length - at:
                        why = _walk(buf, at, size)
                        if why is not None:
                            raise DamagedHdf5Error(f"{p}: damaged HDF5 global heap ({why}); the HDF5 library would hang on it")
                at = buf.find(b"GCOL", at + 4, scan_end)


#: How long :func:`probe` lets the child read before calling the file damaged.
PROBE_SECONDS = 30.0

_PROBE = """
import sys
path, index = sys.argv[1], (None if sys.argv[2] == "-" else int(sys.argv[2]))
try:
    if sys.argv[3] == "trajectory":
        from lcpsim.io.trajectory_file import read_trajectory
        read_trajectory(path, probe=False)
    elif sys.argv[3] == "capture":
        from lcpsim.io.capture import open_capture
        with open_capture(path) as c:
            if len(c):
                c[0 if index is None else index]
    else:
        from lcpsim.io import load_dump, load_lcp
        from lcpsim.io.dump import is_dump
        load_dump(path) if is_dump(path) else load_lcp(path, index)
except (ValueError, OSError):
    pass
"""

#: What :func:`probe` reads: an LCP or dump (as ``lcpsim solve``), a
#: trajectory, or a capture (its attributes, index and one record).
PROBE_KINDS = ("lcp", "trajectory", "capture")


def probe(
    path: str | os.PathLike[str], index: int | None = None, timeout: float = PROBE_SECONDS, kind: str = "lcp"
) -> None:
    """Reads ``path`` in a child process first — with ``kind="lcp"`` as
    ``lcpsim solve`` would (a dump, or ``load_lcp(path, index)``), with
    ``kind="trajectory"`` as ``Trajectory.load``, with ``kind="capture"`` as
    ``open_capture(path, probe=True)`` (the corpus's attributes and index,
    and record ``index``, or 0) — and raises
    :class:`DamagedHdf5Error` if that child crashes or does not finish within
    ``timeout`` seconds.

    The HDF5 library itself can crash (a segmentation fault on some damaged
    attribute heaps) or loop on a damaged file, beyond the reach of any
    Python exception; a child process is the only sure guard. Clean errors
    are left to the caller's own read. ``lcpsim solve``, ``lcpsim view`` and
    ``Trajectory.load`` probe every HDF5 file they are given, ``open_capture``
    when asked (``probe=True``); a program reading untrusted files can do the
    same. A probe costs a Python start-up (about 0.3–0.5 s)."""
    import subprocess
    import sys

    if kind not in PROBE_KINDS:
        raise ValueError(f"kind must be one of {', '.join(PROBE_KINDS)}, not {kind!r}")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    args = [sys.executable, "-c", _PROBE, os.fspath(path), "-" if index is None else str(int(index)), kind]
    try:
        p = subprocess.run(args, capture_output=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        raise DamagedHdf5Error(f"{path}: reading it did not finish in {timeout:g} s (a damaged file the HDF5 library loops on)") from None
    if p.returncode < 0:
        raise DamagedHdf5Error(f"{path}: reading it crashes the HDF5 library (signal {-p.returncode}): a damaged file")
