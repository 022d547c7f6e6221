"""Files lcpsim reads and writes:

==================  ==========================================================
:mod:`.lcp_file`    one LCP in a file (``.npz`` / HDF5 with ``M``, ``q``):
                    :func:`load_lcp`, :func:`save_lcp`
:mod:`.capture`     the HDF5 stream of every LCP a simulation solved
                    (``World.run(capture=...)``)
:mod:`.dump`        failure dumps (``solve_lcp(..., dump=DIR)``)
:mod:`.forensics`   a failure dump re-solved (replay)
:mod:`.fclib`       FCLib local problems (as faceted LCPs: :mod:`lcpsim.faceting`)
==================  ==========================================================
"""

from __future__ import annotations

from .capture import Capture, CaptureRecord, CaptureWriter, load_captured_lcp, open_capture
from .dump import is_dump, load_dump, write_dump
from .forensics import replay
from .lcp_file import LcpFileError, file_format, load_lcp, save_lcp

__all__ = [
    "LcpFileError", "load_lcp", "save_lcp", "file_format", "is_dump",
    "Capture", "CaptureRecord", "CaptureWriter", "open_capture", "load_captured_lcp",
    "load_dump", "replay", "write_dump",
]
