"""Captures: every LCP a simulation solves, streamed to an HDF5 file
(``World.run(capture=...)``; the format is still called ``lcpsim-corpus``).

::

    from lcpsim import scenes, open_capture
    s = scenes.cube_on_slope(45.2, 1.0, cone_scale="dt")
    s.world.run(2000, capture="slope.h5")         # streams every LCP to slope.h5
    with open_capture("slope.h5") as c:
        print(len(c), c.metadata["scene"])
        for rec in c:                              # constant memory
            rec.M, rec.q, rec.z, rec.w, rec.status, rec.scale, rec.step
    M, q = load_captured_lcp("slope.h5", 3)               # or: lcpsim solve slope.h5 --index 3

The layout (documented in ``docs/capture.md``) is a handful of growing 1-D
datasets — the problems concatenated, plus an index with one row per LCP —
written in HDF5's single-writer/multiple-reader (SWMR) mode and flushed after
every chunk, so that a run killed at any moment leaves a file that opens and
holds every LCP up to the last flush. ``M``, ``q``, ``z``, ``w`` are exactly
what the solver saw and returned: the *scaled* LCP (``D M D``, ``D q`` with
``D = diag(I, I, s·I)``); :meth:`CaptureRecord.unscaled` undoes it.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._json import jsonable
from .limits import human_bytes
from .hdf5 import HDF5_ERRORS, HDF5_READ_ERRORS, is_hdf5_file
from .hdf5_check import DamagedHdf5Error, check_global_heaps
from .safe_file import SafeTarget, partial_path

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "CaptureError",
    "CaptureWriter",
    "CaptureRecord",
    "Capture",
    "open_capture",
    "load_captured_lcp",
    "load_record",
    "is_capture",
]

#: Value of the root attribute ``format``.
FORMAT = "lcpsim-corpus"
#: Value of the root attribute ``format_version`` (2: ``/index/island``; version 1 files read with island 0).
FORMAT_VERSION = 2
#: Solver names, indexed by ``/index/method``.
METHOD_NAMES: tuple[str, ...] = (*_core.METHODS, "custom")

# name → dtype of the per-LCP index datasets (chunks of _INDEX_CHUNK rows);
# `n` is written last and its length is the number of complete records.
_INDEX: dict[str, str] = {
    "m_offset": "i8", "v_offset": "i8", "step": "i8", "island": "i4", "time": "f8", "contacts": "i4",
    "friction_dirs": "i4", "scale": "f8", "status": "i1", "pivots": "i8", "method": "i1", "run": "i4", "n": "i4",
}
_INDEX_CHUNK = 4096
# Index datasets a version-1 file lacks, and the value its records take.
_ADDED_IN_V2 = {"island": 0}
_DATA = {"M": 1 << 16, "q": 1 << 12, "z": 1 << 12, "w": 1 << 12}


class CaptureError(ValueError):
    """A file that is not a readable capture, or a bad record index."""


def _h5py() -> Any:
    import h5py  # type: ignore[import-untyped]

    return h5py


def _open_read(path: Path) -> Any:
    """Opens a capture for reading without HDF5's file locking (a reader never
    waits for a writer). A complete file opens plainly, where damaged metadata
    fails at once; only a file still marked open for writing (a live or killed
    writer's ``PATH.partial``) is opened in SWMR read mode — with HDF5's
    metadata read attempts cut from 100 (retried with exponential back-off, so
    a damaged file hangs the reader) to :data:`SWMR_READ_ATTEMPTS`."""
    h5py = _h5py()
    try:
        check_global_heaps(path)
        return h5py.File(path, "r", locking=False)
    except DamagedHdf5Error as e:
        raise CaptureError(str(e)) from None
    except HDF5_ERRORS as e:
        plain_error = e
    # Only the "open for writing" flag sends a file to the SWMR reader: SWMR
    # tolerates a file shorter than its superblock says, where a truncated file hangs it.
    if "already open for write" in str(plain_error):
        try:
            return _open_swmr(path)
        except HDF5_ERRORS:
            pass
    raise CaptureError(f"{path}: not a readable HDF5 file ({plain_error})") from None


#: Metadata read attempts of a SWMR reader (HDF5's default, 100, backs off
#: exponentially: hours on a damaged file; 16 wait about 65 ms in all).
SWMR_READ_ATTEMPTS = 16


def _open_swmr(path: Path) -> Any:
    h5py = _h5py()
    fapl = h5py.h5p.create(h5py.h5p.FILE_ACCESS)
    fapl.set_libver_bounds(h5py.h5f.LIBVER_LATEST, h5py.h5f.LIBVER_LATEST)
    fapl.set_fclose_degree(h5py.h5f.CLOSE_STRONG)
    fapl.set_file_locking(False, True)
    if not _limit_read_attempts(fapl.id, SWMR_READ_ATTEMPTS):  # pragma: no cover - HDF5 not found
        raise CaptureError(f"{path}: open for writing, and SWMR reading cannot be bounded here")
    fid = h5py.h5f.open(os.fsencode(str(path)), h5py.h5f.ACC_RDONLY | h5py.h5f.ACC_SWMR_READ, fapl=fapl)
    return h5py.File(fid)


def _limit_read_attempts(fapl_id: int, attempts: int) -> bool:
    """``H5Pset_metadata_read_attempts`` (not wrapped by h5py) on the HDF5
    library h5py uses, found among the process's mapped libraries."""
    import ctypes
    import re

    try:
        with open("/proc/self/maps") as fh:
            libs = sorted(set(re.findall(r"(/\S*libhdf5(?:[-.][^/\s]*)?\.so[^/\s]*)", fh.read())))
    except OSError:  # pragma: no cover - not Linux
        return False
    for lib in libs:
        if "_hl" in lib:
            continue
        try:
            fn = ctypes.CDLL(lib).H5Pset_metadata_read_attempts
        except (OSError, AttributeError):
            continue
        fn.argtypes, fn.restype = [ctypes.c_int64, ctypes.c_uint], ctypes.c_int
        return bool(fn(fapl_id, attempts) >= 0)
    return False


def _check_lengths(path: Path, f: Any, datasets: Mapping[str, Any]) -> None:
    """Refuses datasets longer than the file could hold (a damaged file can
    claim any shape; reading it would allocate that much). A chunk of slack
    covers a writer's last, not yet written, resize; compressed data up to
    gzip's ratio."""
    size = path.stat().st_size
    for name, ds in datasets.items():
        if ds.ndim != 1:
            raise CaptureError(f"{path}: damaged corpus, {name} has shape {ds.shape} (1-D expected)")
        ratio = 1100 if ds.compression else 1
        slack = (ds.chunks[0] if ds.chunks else 0) * ds.dtype.itemsize
        nbytes = ds.shape[0] * ds.dtype.itemsize
        if nbytes > ratio * size + slack + (1 << 20):
            raise CaptureError(
                f"{path}: damaged corpus, {name} claims {ds.shape[0]} entries ({human_bytes(nbytes)}) "
                f"in a file of {human_bytes(size)}"
            )


def _append(ds: Any, values: NDArray[Any]) -> None:
    if values.size == 0:
        return
    n0 = ds.shape[0]
    ds.resize((n0 + values.shape[0],))
    ds[n0:] = values


def _create_layout(f: Any, metadata: Mapping[str, Any] | None, compression: str | None) -> tuple[dict[str, Any], ...]:
    """Root attributes and the empty growing datasets of a new capture: ``(data, index, runs)``."""
    from .. import __version__

    f.attrs["format"] = FORMAT
    f.attrs["format_version"] = FORMAT_VERSION
    f.attrs["lcpsim_version"] = __version__
    f.attrs["created"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    f.attrs["metadata"] = json.dumps(jsonable(dict(metadata or {})))
    f.attrs["status_names"] = json.dumps(list(_core.STATUSES))
    f.attrs["method_names"] = json.dumps(list(METHOD_NAMES))
    kw: dict[str, Any] = {"compression": compression} if compression else {}
    data = f.create_group("data")
    index = f.create_group("index")
    runs = f.create_group("runs")
    return (
        {k: data.create_dataset(k, shape=(0,), maxshape=(None,), chunks=(c,), dtype="f8", **kw) for k, c in _DATA.items()},
        {k: index.create_dataset(k, shape=(0,), maxshape=(None,), chunks=(_INDEX_CHUNK,), dtype=t) for k, t in _INDEX.items()},
        {
            "json": runs.create_dataset("json", shape=(0,), maxshape=(None,), chunks=(4096,), dtype="u1"),
            "offset": runs.create_dataset("offset", shape=(0,), maxshape=(None,), chunks=(256,), dtype="i8"),
            "length": runs.create_dataset("length", shape=(0,), maxshape=(None,), chunks=(256,), dtype="i8"),
        },
    )


def _pivots(captured: Mapping[str, Any], b: int) -> Any:
    """A batch's pivots (``iterations`` in batches drained by an older lcpsim)."""
    if "pivots" in captured:
        return captured["pivots"]
    return captured.get("iterations", np.zeros(b))


class CaptureWriter:
    """Streams LCPs to an HDF5 capture (constant memory; see ``docs/capture.md``).

    ``metadata`` (JSON-ready: scene, config, seed, …) is stored once for the
    file; :meth:`begin_run` adds a run with its own metadata, and the LCPs
    appended after it carry its number. :meth:`flush` makes everything written
    so far durable: a crash after it leaves a readable file. Use as a context
    manager or call :meth:`close`.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        metadata: Mapping[str, Any] | None = None,
        *,
        compression: str | None = None,
        overwrite: bool = False,
    ) -> None:
        self.path = Path(path)
        self._closed = True
        # Lock, refuse an existing path, write beside it (see safe_file).
        self._target = SafeTarget(self.path, overwrite=overwrite, what="capture")
        #: The file being written; renamed onto ``path`` by :meth:`close`.
        self.partial_path = self._target.partial
        try:
            self._f = f = _h5py().File(self.partial_path, "w", libver="latest")
            self._data, self._index, self._runs = _create_layout(f, metadata, compression)
        except BaseException:
            if getattr(self, "_f", None) is not None:
                self._f.close()
            self._target.abandon()
            raise
        # From here on the file's structure is fixed and every write keeps it readable.
        self._f.swmr_mode = True
        self._count = 0
        self._m_end = 0
        self._v_end = 0
        self._run = -1
        self._run_bytes = 0
        self._closed = False

    def __len__(self) -> int:
        """LCPs written."""
        return self._count

    @property
    def runs(self) -> int:
        return self._run + 1

    def begin_run(self, metadata: Mapping[str, Any] | None = None) -> int:
        """Starts a new run (its metadata stored as JSON); returns its number."""
        self._check_open()
        blob = np.frombuffer(json.dumps(jsonable(dict(metadata or {}))).encode(), dtype=np.uint8)
        _append(self._runs["json"], blob)
        _append(self._runs["offset"], np.array([self._run_bytes], dtype=np.int64))
        _append(self._runs["length"], np.array([blob.size], dtype=np.int64))
        self._run_bytes += blob.size
        self._run += 1
        return self._run

    def append(self, captured: Mapping[str, Any]) -> int:
        """Appends a batch of LCPs in the compiled module's capture layout:
        flat ``M``, ``q``, ``z``, ``w`` (problems concatenated) and per-problem
        ``n``, ``step``, ``island``, ``time``, ``contacts``, ``friction_dirs``, ``scale``,
        ``status`` (index into :data:`lcpsim.STATUSES`), ``pivots``,
        ``method`` (names). Returns the number appended. A batch drained by
        an older lcpsim (``iterations`` instead of ``pivots``) is still
        accepted."""
        self._check_open()
        n = np.asarray(captured["n"], dtype=np.int64)
        b = int(n.size)
        if b == 0:
            return 0
        if self._run < 0:
            self.begin_run({})
        M = np.asarray(captured["M"], dtype=np.float64)
        q = np.asarray(captured["q"], dtype=np.float64)
        z = np.asarray(captured["z"], dtype=np.float64)
        w = np.asarray(captured["w"], dtype=np.float64)
        sq, lin = int((n * n).sum()), int(n.sum())
        if M.shape != (sq,) or q.shape != (lin,) or z.shape != (lin,) or w.shape != (lin,):
            raise CaptureError(
                f"inconsistent batch: n sums to {lin} (n² to {sq}) but M, q, z, w have "
                f"{M.shape}, {q.shape}, {z.shape}, {w.shape} values"
            )
        m_off = self._m_end + np.concatenate([[0], np.cumsum(n * n)[:-1]])
        v_off = self._v_end + np.concatenate([[0], np.cumsum(n)[:-1]])
        methods = captured.get("method")
        codes = np.array(
            [METHOD_NAMES.index(m) if m in METHOD_NAMES else len(METHOD_NAMES) - 1 for m in methods]
            if methods is not None
            else [len(METHOD_NAMES) - 1] * b,
            dtype=np.int8,
        )
        # Data first, then the index, `n` last: a reader counts only complete records.
        for key, arr in (("M", M), ("q", q), ("z", z), ("w", w)):
            _append(self._data[key], arr)
        rows: dict[str, NDArray[Any]] = {
            "m_offset": m_off,
            "v_offset": v_off,
            "step": np.asarray(captured.get("step", np.full(b, -1)), dtype=np.int64),
            "island": np.asarray(captured.get("island", np.zeros(b)), dtype=np.int32),
            "time": np.asarray(captured.get("time", np.full(b, np.nan)), dtype=np.float64),
            "contacts": np.asarray(captured.get("contacts", np.zeros(b)), dtype=np.int32),
            "friction_dirs": np.asarray(captured.get("friction_dirs", np.zeros(b)), dtype=np.int32),
            "scale": np.asarray(captured.get("scale", np.ones(b)), dtype=np.float64),
            "status": np.asarray(captured["status"], dtype=np.int8),
            "pivots": np.asarray(_pivots(captured, b), dtype=np.int64),
            "method": codes,
            "run": np.full(b, self._run, dtype=np.int32),
            "n": n.astype(np.int32),
        }
        for key in _INDEX:
            _append(self._index[key], rows[key])
        self._m_end += sq
        self._v_end += lin
        self._count += b
        return b

    def add(
        self,
        M: ArrayLike,
        q: ArrayLike,
        z: ArrayLike | None = None,
        w: ArrayLike | None = None,
        *,
        status: str = "solved",
        scale: float = 1.0,
        step: int = -1,
        island: int = 0,
        time: float = float("nan"),
        contacts: int = 0,
        friction_dirs: int = 0,
        pivots: int = 0,
        method: str = "custom",
    ) -> int:
        """Appends one LCP (z, w default to NaN when not known); returns its index."""
        M_ = np.asarray(M, dtype=np.float64)
        q_ = np.asarray(q, dtype=np.float64).ravel()
        n = q_.size
        if M_.shape != (n, n):
            raise CaptureError(f"M has shape {M_.shape} but q has length {n}")
        z_ = np.full(n, np.nan) if z is None else np.asarray(z, dtype=np.float64).ravel()
        w_ = np.full(n, np.nan) if w is None else np.asarray(w, dtype=np.float64).ravel()
        if z_.size != n or w_.size != n:
            raise CaptureError(f"z and w must have length {n}, got {z_.size} and {w_.size}")
        if status not in _core.STATUSES:
            raise CaptureError(f"unknown status {status!r} (valid: {', '.join(_core.STATUSES)})")
        self.append(
            {
                "M": M_.ravel(),
                "q": q_,
                "z": z_,
                "w": w_,
                "n": [n],
                "step": [step],
                "island": [island],
                "time": [time],
                "contacts": [contacts],
                "friction_dirs": [friction_dirs],
                "scale": [scale],
                "status": [_core.STATUSES.index(status)],
                "pivots": [pivots],
                "method": [method],
            }
        )
        return self._count - 1

    def flush(self) -> None:
        """Makes everything written so far durable and visible to readers."""
        self._check_open()
        self._f.flush()

    def close(self, *, complete: bool = True) -> None:
        """Closes the file and renames it onto ``path`` — or, with
        ``complete=False`` (an interrupted run), leaves it as ``PATH.partial``."""
        if not self._closed:
            self._closed = True
            try:
                self._f.close()
            except BaseException:
                self._target.abandon()
                raise
            if complete:
                self._target.commit()
            else:
                self._target.abandon()

    def _check_open(self) -> None:
        if self._closed:
            raise CaptureError(f"{self.path}: corpus writer is closed")

    def __enter__(self) -> "CaptureWriter":
        return self

    def __exit__(self, exc_type: Any, *exc: Any) -> None:
        self.close(complete=exc_type is None)


def _column(key: str, dtype: Any, doc: str | None = None) -> Any:
    """A :class:`Capture` property: the index column ``key`` as an array of ``dtype``."""
    return property(lambda self: np.asarray(self._idx[key], dtype=dtype), doc=doc)


def _decode(names: list[str], codes: Any) -> Any:
    """Names of stored codes (array or scalar); ``"unknown"`` for a code outside ``names``."""
    table = np.array(list(names) + ["unknown"])
    c = np.asarray(codes, dtype=np.int64)
    return table[np.where((c >= 0) & (c < len(names)), c, len(names))]


@dataclass(frozen=True)
class CaptureRecord:
    """One LCP of a capture: exactly what the solver saw (the scaled LCP) and returned."""

    index: int
    M: NDArray[np.float64]  # (n, n) as the solver saw it (scaled)
    q: NDArray[np.float64]  # (n,) scaled
    z: NDArray[np.float64]  # (n,) the solver's answer
    w: NDArray[np.float64]  # (n,) M z + q
    status: str  # the solver's status
    scale: float  # the cone scale s
    step: int
    time: float
    contacts: int
    friction_dirs: int
    pivots: int
    method: str
    run: int
    #: Island of its step (0 for the first; always 0 in version-1 files).
    island: int = 0

    @property
    def n(self) -> int:
        return int(self.q.shape[0])

    @property
    def ok(self) -> bool:
        return self.status == "solved"

    def layout(self) -> _core.ContactLayout | None:
        """Where fn, fd, λ live in ``z``; None when the LCP is not a contact LCP of this size."""
        nc, k = self.contacts, self.friction_dirs
        if nc > 0 and k > 0:
            lay = _core.ContactLayout(nc, k)
            if lay.n == self.n:
                return lay
        return None

    def unscaled(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The unscaled LCP ``(D⁻¹ M D⁻¹, D⁻¹ q)`` with ``D = diag(I, I, s·I)`` (s = ``scale``);
        ``(M, q)`` itself when s = 1 or the layout is not the contact LCP's."""
        lay = self.layout()
        if lay is None or self.scale == 1.0:
            return self.M, self.q
        return lay.scale_lcp(self.M, self.q, 1.0 / self.scale)

    def physical_z(self) -> NDArray[np.float64]:
        """``z`` with λ mapped back to physical units (``λ = s·λ_scaled``)."""
        lay = self.layout()
        return self.z.copy() if lay is None else lay.unscale_z(self.z, self.scale)


class Capture:
    """A capture opened for reading (see :func:`open_capture`).

    ``len(c)`` LCPs; ``c[i]`` is a :class:`CaptureRecord`; iterating reads the
    data in blocks (bounded memory). The per-LCP index is loaded at once as
    arrays: ``c.n``, ``c.step``, ``c.island``, ``c.time``, ``c.contacts``, ``c.scale``,
    ``c.status`` (strings), ``c.pivots``, ``c.method`` (strings), ``c.run``.
    ``c.metadata`` is the file's metadata, ``c.runs`` each run's.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        if not self.path.exists():
            partial = partial_path(self.path)
            hint = f" (an interrupted capture is at {partial})" if partial.exists() else ""
            raise FileNotFoundError(f"{path}: no such file{hint}")
        f = _open_read(self.path)
        self._f = f
        try:
            if f.attrs.get("format") != FORMAT:
                raise CaptureError(f"{path}: not an lcpsim LCP corpus (no root attribute format={FORMAT!r})")
            version = int(f.attrs.get("format_version", 0))
            if version > FORMAT_VERSION:
                raise CaptureError(f"{path}: corpus format version {version} is newer than this lcpsim reads")
            self.format_version = version
            self.lcpsim_version = str(f.attrs.get("lcpsim_version", ""))
            self.created = str(f.attrs.get("created", ""))
            self.metadata: dict[str, Any] = json.loads(f.attrs.get("metadata", "{}"))
            self.status_names: list[str] = json.loads(f.attrs["status_names"])
            self.method_names: list[str] = json.loads(f.attrs["method_names"])
            stored = f["index"]
            present = {k: stored[k] for k in _INDEX if k not in _ADDED_IN_V2 or k in stored}
            runs = f["runs"]
            _check_lengths(self.path, f, {
                **{f"/index/{k}": v for k, v in present.items()},
                **{f"/data/{k}": f["data"][k] for k in _DATA},
                **{f"/runs/{k}": runs[k] for k in ("json", "offset", "length")},
            })
            idx = {k: v[()] for k, v in present.items()}
            data_len = {k: f["data"][k].shape[0] for k in _DATA}
            # Complete records only: as many as every index dataset holds and
            # whose data lies within the data written.
            count = min(v.shape[0] for v in idx.values())
            idx = {k: v[:count] for k, v in idx.items()}
            for k, value in _ADDED_IN_V2.items():
                idx.setdefault(k, np.full(count, value, dtype=_INDEX[k]))
            n = idx["n"].astype(np.int64)
            m_off, v_off = idx["m_offset"].astype(np.int64), idx["v_offset"].astype(np.int64)
            m_end = m_off + n * n
            v_end = v_off + n
            ok = (n >= 1) & (m_off >= 0) & (v_off >= 0)
            ok &= (m_end <= data_len["M"]) & (v_end <= min(data_len["q"], data_len["z"], data_len["w"]))
            if not ok.all():
                count = int(np.argmin(ok))
                idx = {k: v[:count] for k, v in idx.items()}
            self._idx: dict[str, NDArray[Any]] = idx
            r_count = min(runs["offset"].shape[0], runs["length"].shape[0])
            blob = runs["json"][()].tobytes()
            self.runs: list[dict[str, Any]] = []
            for o, ln in zip(runs["offset"][:r_count], runs["length"][:r_count]):
                try:
                    self.runs.append(json.loads(blob[int(o) : int(o) + int(ln)].decode()))
                except ValueError:
                    break
        except KeyError as e:
            f.close()
            raise CaptureError(f"{path}: damaged corpus, missing {e}") from None
        except HDF5_READ_ERRORS as e:
            f.close()
            if isinstance(e, CaptureError):
                raise
            raise CaptureError(f"{path}: damaged corpus ({type(e).__name__}: {e})") from None
        except BaseException:
            f.close()
            raise

    def __len__(self) -> int:
        return int(self._idx["n"].shape[0])

    # Index arrays.
    n = _column("n", np.int64)
    step = _column("step", np.int64)
    island = _column("island", np.int64, "Island of its step per LCP (0 in version-1 files).")
    time = _column("time", np.float64)
    contacts = _column("contacts", np.int64)
    friction_dirs = _column("friction_dirs", np.int64)
    scale = _column("scale", np.float64)
    pivots = _column("pivots", np.int64)
    run = _column("run", np.int64)

    @property
    def status(self) -> NDArray[np.str_]:
        return _decode(self.status_names, self._idx["status"])

    @property
    def method(self) -> NDArray[np.str_]:
        return _decode(self.method_names, self._idx["method"])

    def _check(self, index: Any) -> int:
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)):
            raise CaptureError(f"index must be an integer, got {index!r}")
        i = int(index)
        count = len(self)
        if i < 0:
            i += count
        if not 0 <= i < count:
            raise CaptureError(f"{self.path}: index {index} out of range (the corpus holds {count} LCPs)")
        return i

    def _record(self, i: int, M: NDArray[np.float64], q: Any, z: Any, w: Any) -> CaptureRecord:
        ix = self._idx
        n = int(ix["n"][i])
        return CaptureRecord(
            index=i,
            M=M.reshape(n, n),
            q=q,
            z=z,
            w=w,
            status=str(_decode(self.status_names, ix["status"][i])),
            scale=float(ix["scale"][i]),
            step=int(ix["step"][i]),
            time=float(ix["time"][i]),
            contacts=int(ix["contacts"][i]),
            friction_dirs=int(ix["friction_dirs"][i]),
            pivots=int(ix["pivots"][i]),
            method=str(_decode(self.method_names, ix["method"][i])),
            run=int(ix["run"][i]),
            island=int(ix["island"][i]),
        )

    def _data(self, key: str, lo: int, hi: int) -> NDArray[np.float64]:
        """``/data/key[lo:hi]``; a damaged dataset is a :class:`CaptureError` (an I/O error stays an OSError)."""
        try:
            return np.asarray(self._f["data"][key][lo:hi], dtype=np.float64)
        except (KeyError, TypeError, RuntimeError, ValueError) as e:
            raise CaptureError(f"{self.path}: damaged corpus, cannot read /data/{key} ({e})") from None

    def __getitem__(self, index: int) -> CaptureRecord:
        i = self._check(index)
        n = int(self._idx["n"][i])
        mo, vo = int(self._idx["m_offset"][i]), int(self._idx["v_offset"][i])
        return self._record(
            i, self._data("M", mo, mo + n * n), *(self._data(k, vo, vo + n) for k in ("q", "z", "w"))
        )

    def records(self, start: int = 0, stop: int | None = None, *, block_bytes: int = 8 << 20) -> Iterator[CaptureRecord]:
        """Records ``start … stop-1``, read in blocks of about ``block_bytes``."""
        stop = len(self) if stop is None else min(stop, len(self))
        ix = self._idx
        i = max(start, 0)
        while i < stop:
            # One block: consecutive records up to block_bytes of M.
            j = i
            m0, v0 = int(ix["m_offset"][i]), int(ix["v_offset"][i])
            m1, v1 = m0, v0
            while j < stop and (j == i or 8 * (m1 - m0) < block_bytes):
                n = int(ix["n"][j])
                m1 = int(ix["m_offset"][j]) + n * n
                v1 = int(ix["v_offset"][j]) + n
                j += 1
            M, q, z, w = self._data("M", m0, m1), *(self._data(k, v0, v1) for k in ("q", "z", "w"))
            for r in range(i, j):
                n = int(ix["n"][r])
                mo, vo = int(ix["m_offset"][r]) - m0, int(ix["v_offset"][r]) - v0
                yield self._record(
                    r, M[mo : mo + n * n], q[vo : vo + n], z[vo : vo + n], w[vo : vo + n]
                )
            i = j

    def __iter__(self) -> Iterator[CaptureRecord]:
        return self.records()

    def close(self) -> None:
        self._f.close()

    def __enter__(self) -> "Capture":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Capture({str(self.path)!r}, {len(self)} LCPs, scene={self.metadata.get('scene')!r})"


def open_capture(path: str | os.PathLike[str], probe: bool = False) -> Capture:
    """Opens a capture for reading (also one whose writer was interrupted).

    With ``probe``, the file is first opened in a child process
    (:func:`lcpsim.io.hdf5_check.probe`, ``kind="capture"``: attributes,
    index and the first record): the HDF5 library itself can crash (a
    segmentation fault on some damaged attributes) or loop on a damaged file,
    which no Python exception can catch; the probe turns that into a
    :class:`~lcpsim.io.hdf5_check.DamagedHdf5Error` (a ``ValueError``) at the
    cost of a Python start-up (about 0.3–0.5 s). Off by default: captures
    are usually one's own; use it for files from elsewhere. Records read
    later are not probed (their data are datasets, which the readers check;
    the crashes found were in attributes)."""
    if probe:
        from .hdf5_check import probe as probe_file

        probe_file(path, kind="capture")
    return Capture(path)


def load_captured_lcp(path: str | os.PathLike[str], index: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(M, q)`` of LCP ``index`` of a capture (negative counts from the end)."""
    with Capture(path) as c:
        r = c[index]
        return r.M, r.q


def load_record(path: str | os.PathLike[str], index: int) -> CaptureRecord:
    """LCP ``index`` of a capture with everything recorded about it."""
    with Capture(path) as c:
        return c[index]


def is_capture(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an HDF5 file with the capture format attribute."""
    p = Path(path)
    if not is_hdf5_file(p):
        return False
    try:
        f = _open_read(p)
    except CaptureError:
        return False
    with f:
        try:
            return bool(f.attrs.get("format") == FORMAT)
        except HDF5_READ_ERRORS:  # a damaged attribute: not a capture we can read
            return False
