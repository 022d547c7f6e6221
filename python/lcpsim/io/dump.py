"""Failure dumps: a failed solve written to a file, and read back.

``solve_lcp(M, q, dump=DIR)`` writes, when the result is not ``solved``, one
HDF5 file into ``DIR`` (named ``lcpsim-dump-<status>-n<n>-<digest>.h5``, the
digest of ``M``, ``q``, method and options) and names it in
``LcpResult.dump_path``. The file holds

==========================  ================================================
``/M``, ``/q``              the LCP as given (so :func:`lcpsim.io.load_lcp`
                            reads a dump like any LCP file)
``/z``, ``/w``              the failed answer (last iterate)
``/basis``                  its basis (Lemke), if any
``/trace/<field>``          the pivot trace of a traced re-solve (Lemke): one
                            entry per pivot over every rung of the repair
                            ladder — ``rung``, ``entering``, ``leaving``
                            (variables: ``w_i`` → i, ``z_j`` → n + j,
                            ``z0`` → 2n), ``theta`` (step length), ``pivot``
                            and ``column_max`` (the pivot and the largest
                            entry of its column)
attributes                  ``format`` (``"lcpsim-failure-dump"``),
                            ``format_version``, ``lcpsim_version``,
                            ``created``, ``method``, ``options`` (JSON),
                            ``status``, ``pivots``, ``residual``, ``min_z``,
                            ``min_w``, ``max_complementarity``,
                            ``trace_status`` (the traced re-solve's status)
==========================  ================================================

``lcpsim solve DUMP`` (or :func:`lcpsim.io.forensics.replay`) re-solves it with the dumped method
and options (unless overridden) and says whether the status and ``z`` are
reproduced.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .hdf5 import HDF5_READ_ERRORS, hdf5_dataset, open_hdf5
from .lcp_file import LcpFileError, file_format, validate_lcp

if TYPE_CHECKING:
    from ..result import LcpResult

__all__ = ["DUMP_FORMAT", "TRACE_FIELDS", "Dump", "write_dump", "load_dump", "is_dump", "variable_name"]

#: The ``format`` attribute of a dump file.
DUMP_FORMAT = "lcpsim-failure-dump"
DUMP_VERSION = 1

TRACE_FIELDS: tuple[str, ...] = ("rung", "entering", "leaving", "theta", "pivot", "column_max")
_RESIDUAL_FIELDS: tuple[str, ...] = ("residual", "min_z", "min_w", "max_complementarity")


def _json_default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    return str(o)


def _options_json(options: Mapping[str, Any]) -> str:
    return json.dumps(dict(options), sort_keys=True, default=_json_default)


def variable_name(index: int, n: int) -> str:
    """The name of Lemke variable ``index`` in a pivot trace: ``w[i]``, ``z[j]``
    (0-based) or ``z0`` (the artificial variable)."""
    if index < n:
        return f"w[{index}]"
    if index < 2 * n:
        return f"z[{index - n}]"
    return "z0"


def write_dump(
    directory: str | os.PathLike[str],
    M: NDArray[np.float64],
    q: NDArray[np.float64],
    method: str,
    options: Mapping[str, Any],
    result: LcpResult,
) -> Path:
    """Writes the dump of a failed solve into ``directory`` (created if needed)
    and returns its path. Lemke problems are re-solved with a pivot trace."""
    import h5py  # type: ignore[import-untyped]

    from .. import __version__

    d = Path(directory)
    if d.exists() and not d.is_dir():
        raise ValueError(f"dump: {directory} is not a directory")
    d.mkdir(parents=True, exist_ok=True)
    M = np.ascontiguousarray(M, dtype=np.float64)
    q = np.ascontiguousarray(q, dtype=np.float64)
    opts_json = _options_json(options)
    h = hashlib.sha256()
    h.update(M.tobytes())
    h.update(q.tobytes())
    h.update(method.encode())
    h.update(opts_json.encode())
    path = d / f"lcpsim-dump-{result.status}-n{q.shape[0]}-{h.hexdigest()[:12]}.h5"

    trace: Mapping[str, object] | None = None
    trace_status = ""
    if method == "lemke":
        sol, trace = _core.solve_lcp_traced(M, q, method, None, **dict(options))
        trace_status = str(sol["status"])

    tmp = path.with_name(path.name + ".tmp")
    with h5py.File(tmp, "w") as f:
        f.attrs["format"] = DUMP_FORMAT
        f.attrs["format_version"] = DUMP_VERSION
        f.attrs["lcpsim_version"] = __version__
        f.attrs["created"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
        f.attrs["method"] = method
        f.attrs["options"] = opts_json
        f.attrs["status"] = result.status
        f.attrs["pivots"] = int(result.pivots)
        for k in _RESIDUAL_FIELDS:
            f.attrs[k] = float(getattr(result, k))
        f.attrs["trace_status"] = trace_status
        f.attrs["variables"] = "trace entering/leaving: w_i -> i, z_j -> n + j, z0 -> 2n"
        f.create_dataset("M", data=M)
        f.create_dataset("q", data=q)
        f.create_dataset("z", data=np.asarray(result.z, dtype=np.float64))
        f.create_dataset("w", data=np.asarray(result.w, dtype=np.float64))
        if result.basis is not None:
            f.create_dataset("basis", data=np.asarray(result.basis, dtype=bool))
        if trace is not None:
            g = f.create_group("trace")
            for k in TRACE_FIELDS:
                g.create_dataset(k, data=np.asarray(trace[k]))
    os.replace(tmp, path)
    return path


def is_dump(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is a failure dump (this module): an HDF5
    file whose ``format`` attribute is ``"lcpsim-failure-dump"``. A dump also
    holds ``/M`` and ``/q``, so :func:`load_lcp` reads it like any LCP file."""
    p = Path(path)
    if not p.is_file():
        return False
    try:
        if file_format(p) != "hdf5":
            return False
    except LcpFileError:
        return False
    try:
        with open_hdf5(p) as f:
            fmt = f.attrs.get("format")
    except HDF5_READ_ERRORS:
        return False
    if isinstance(fmt, bytes):
        fmt = fmt.decode(errors="replace")
    return bool(fmt == DUMP_FORMAT)


@dataclass(frozen=True)
class Dump:
    """A failure dump read back (see the module docs)."""

    path: str
    M: NDArray[np.float64]
    q: NDArray[np.float64]
    method: str
    options: dict[str, Any]
    status: str
    z: NDArray[np.float64]
    w: NDArray[np.float64]
    basis: NDArray[np.bool_] | None
    pivots: int
    residuals: dict[str, float]
    trace: dict[str, NDArray[Any]] | None
    trace_status: str | None
    lcpsim_version: str
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def n(self) -> int:
        return int(self.q.shape[0])

    def trace_summary(self) -> str:
        """One line: pivots, rungs and the last pivot of the trace."""
        if self.trace is None:
            return "no pivot trace (not a Lemke solve)"
        t = self.trace
        k = len(t["rung"])
        if k == 0:
            return "pivot trace: 0 pivots"
        rungs = len(np.unique(t["rung"]))
        i = k - 1
        return (
            f"pivot trace: {k} pivots over {rungs} rung(s); last: {variable_name(int(t['entering'][i]), self.n)} in, "
            f"{variable_name(int(t['leaving'][i]), self.n)} out, θ = {float(t['theta'][i]):.3e}, "
            f"pivot {float(t['pivot'][i]):.3e} (column max {float(t['column_max'][i]):.3e})"
        )


def _attr(f: Any, key: str, default: Any = None) -> Any:
    v = f.attrs.get(key, default)
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.generic):
        return v.item()
    return v


def _vector(path: Path, f: Any, key: str, n: int, dtype: Any) -> NDArray[Any] | None:
    """Dataset ``/key`` as a length-``n`` vector (None when absent)."""
    if key not in f:
        return None
    v = np.asarray(hdf5_dataset(path, f, key, LcpFileError)[()])
    if v.shape != (n,):
        raise LcpFileError(f"{path}: '/{key}' has shape {v.shape}, expected ({n},)")
    return v.astype(dtype)


def _trace(path: Path, f: Any) -> dict[str, NDArray[Any]] | None:
    """The pivot trace: 1-D numeric datasets of one length, or an error naming what is wrong."""
    if "trace" not in f:
        return None
    group = f["trace"]
    if not hasattr(group, "keys"):
        raise LcpFileError(f"{path}: '/trace' must be a group of datasets ({', '.join(TRACE_FIELDS)})")
    trace = {k: np.asarray(hdf5_dataset(path, group, k, LcpFileError)[()]) for k in TRACE_FIELDS if k in group}
    missing = [k for k in TRACE_FIELDS if k not in trace]
    lengths = {v.shape for v in trace.values()}
    if missing or len(lengths) > 1 or any(len(s) != 1 for s in lengths):
        raise LcpFileError(
            f"{path}: damaged pivot trace (missing: {', '.join(missing) or 'none'}; shapes: "
            f"{', '.join(f'{k} {v.shape}' for k, v in trace.items())}; 1-D of one length expected)"
        )
    return trace


def load_dump(path: str | os.PathLike[str]) -> Dump:
    """Reads a failure dump; :class:`lcpsim.io.LcpFileError` if ``path`` is not one
    (or is damaged: every field is checked before it is used)."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{path}: no such file")
    if not is_dump(p):
        raise LcpFileError(f"{path}: not an lcpsim failure dump")
    try:
        with open_hdf5(p, LcpFileError) as f:
            M, q = validate_lcp(p, hdf5_dataset(p, f, "M", LcpFileError)[()], hdf5_dataset(p, f, "q", LcpFileError)[()])
            n = q.shape[0]
            try:
                options = json.loads(str(_attr(f, "options", "{}")))
            except json.JSONDecodeError as e:
                raise LcpFileError(f"{path}: the options attribute is not JSON ({e})") from None
            if not isinstance(options, dict) or not all(isinstance(k, str) for k in options):
                raise LcpFileError(f"{path}: the options attribute must be a JSON object of name: value, got {options!r}")
            z, w = _vector(p, f, "z", n, np.float64), _vector(p, f, "w", n, np.float64)
            ts = _attr(f, "trace_status", "")
            return Dump(
                path=str(p),
                M=M,
                q=q,
                method=str(_attr(f, "method", "lemke")),
                options=options,
                status=str(_attr(f, "status", "")),
                z=np.zeros(n) if z is None else z,
                w=np.zeros(n) if w is None else w,
                basis=_vector(p, f, "basis", n, bool),
                pivots=int(_attr(f, "pivots", 0)),
                residuals={k: float(_attr(f, k, float("nan"))) for k in _RESIDUAL_FIELDS},
                trace=_trace(p, f),
                trace_status=str(ts) if ts else None,
                lcpsim_version=str(_attr(f, "lcpsim_version", "")),
                attrs={k: _attr(f, k) for k in f.attrs},
            )
    except (TypeError, OSError, KeyError, RuntimeError) as e:
        raise LcpFileError(f"{path}: unreadable failure dump ({e})") from None
    except ValueError as e:
        if isinstance(e, LcpFileError):
            raise
        raise LcpFileError(f"{path}: damaged failure dump ({e})") from None
