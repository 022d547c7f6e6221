"""Failure forensics: a failure dump (:mod:`lcpsim.io.dump`) re-solved with
its method and options, or others, and whether the status and ``z`` are
reproduced (``lcpsim solve DUMP``)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..lcp import solve_lcp
from ..result import LcpResult
from .dump import Dump, load_dump

__all__ = ["Replay", "replay"]


@dataclass(frozen=True)
class Replay:
    """The outcome of :func:`replay`: the new ``result`` beside the ``dump``."""

    dump: Dump
    result: LcpResult
    method: str
    options: dict[str, Any]

    @property
    def overridden(self) -> bool:
        """Whether the method or options differ from the dumped ones."""
        return self.method != self.dump.method or self.options != self.dump.options

    @property
    def same_status(self) -> bool:
        return self.result.status == self.dump.status

    @property
    def max_abs_dz(self) -> float:
        return float(np.max(np.abs(self.result.z - self.dump.z), initial=0.0))

    @property
    def same_z(self) -> bool:
        """``z`` reproduced bit for bit."""
        return bool(np.array_equal(self.result.z, self.dump.z))

    @property
    def reproduced(self) -> bool:
        """Same status and the same ``z``."""
        return self.same_status and self.same_z

    def to_dict(self) -> dict[str, Any]:
        return {
            "dump": self.dump.path,
            "dump_status": self.dump.status,
            "dump_lcpsim_version": self.dump.lcpsim_version,
            "method": self.method,
            "options": self.options,
            "overridden": self.overridden,
            "reproduced": self.reproduced,
            "same_status": self.same_status,
            "same_z": self.same_z,
            "max_abs_dz": self.max_abs_dz,
            "trace_pivots": None if self.dump.trace is None else int(len(self.dump.trace["rung"])),
        }


def replay(
    path: str | os.PathLike[str] | Dump,
    *,
    method: str | None = None,
    certify: bool = False,
    dump: str | os.PathLike[str] | None = None,
    **overrides: Any,
) -> Replay:
    """Re-solves a dump with its method and options; ``method`` and keyword
    ``overrides`` (solver options) replace the dumped ones. With another method
    the dumped options are dropped (they belong to the dumped method).
    ``certify`` and ``dump`` are passed to :func:`lcpsim.solve_lcp`."""
    d = path if isinstance(path, Dump) else load_dump(path)
    m = d.method if method is None else method
    opts = dict(d.options) if m == d.method else {}
    opts.update(overrides)
    res = solve_lcp(d.M, d.q, method=m, certify=certify, dump=dump, **opts)
    return Replay(dump=d, result=res, method=m, options=opts)
