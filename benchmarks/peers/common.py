"""Where the peers' run reads and writes, and its console: the peers print
from C to fds 1 and 2, so those go to a log while progress goes to the real
stderr (:func:`say`)."""

from __future__ import annotations

import contextlib
import os
import sys
from pathlib import Path
from typing import Any, Iterator

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
RESULTS_MD = ROOT / "benchmarks" / "RESULTS.md"
RESULTS_JSON = HERE / "results.json.gz"  # gzip-compressed JSON


_REAL_ERR: int | None = None


def say(*parts: Any) -> None:
    msg = (" ".join(str(p) for p in parts) + "\n").encode()
    os.write(_REAL_ERR if _REAL_ERR is not None else 2, msg)


@contextlib.contextmanager
def peers_chatter_to(path: Path) -> Iterator[None]:
    """Redirects fds 1 and 2 (C-level printf of Siconos, Drake logging) to ``path``."""
    global _REAL_ERR
    sys.stdout.flush()
    sys.stderr.flush()
    saved_out, saved_err = os.dup(1), os.dup(2)
    log = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    _REAL_ERR = saved_err
    os.dup2(log, 1)
    os.dup2(log, 2)
    try:
        yield
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(saved_out, 1)
        os.dup2(saved_err, 2)
        os.close(log)
        os.close(saved_out)
        os.close(saved_err)
        _REAL_ERR = None
