"""Reading and writing LCPs: ``.npz`` (arrays ``M``, ``q``) or HDF5 (datasets
``/M``, ``/q``), and single problems out of a capture (HDF5 written by
:mod:`lcpsim.io.capture`; choose the problem with ``index``); a failure dump
(:mod:`lcpsim.io.dump`) also reads as an LCP. Every problem with a file is a :class:`LcpFileError` (a
``ValueError``) whose message names the file and what is wrong; a missing file
is a :class:`FileNotFoundError`."""

from __future__ import annotations

import os
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .hdf5 import HDF5_MAGIC, HDF5_READ_ERRORS, hdf5_dataset, open_hdf5
from .limits import SizeLimitError, array_bytes, check_bytes, human_bytes

__all__ = ["LcpFileError", "load_lcp", "save_lcp", "file_format", "validate_lcp"]

_NPZ_SUFFIXES = {".npz"}
_HDF5_SUFFIXES = {".h5", ".hdf5", ".hdf", ".he5"}
_ZIP_MAGIC = b"PK"


class LcpFileError(ValueError):
    """A file that does not hold a valid LCP."""


def file_format(path: str | os.PathLike[str]) -> str:
    """``"npz"`` or ``"hdf5"``, from the suffix, else from the file's first bytes."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in _NPZ_SUFFIXES:
        return "npz"
    if suffix in _HDF5_SUFFIXES:
        return "hdf5"
    if p.is_file():
        with open(p, "rb") as f:
            head = f.read(8)
        if head.startswith(HDF5_MAGIC):
            return "hdf5"
        if head.startswith(_ZIP_MAGIC):
            return "npz"
    raise LcpFileError(
        f"{path}: unknown LCP file format (expected .npz with arrays M, q or HDF5 .h5 with datasets /M, /q)"
    )


def _npz_header(path: Path, zf: zipfile.ZipFile, name: str) -> None:
    """Checks array ``name``'s ``.npy`` header before numpy allocates it: the
    shape it claims must fit in memory and in the bytes the archive holds."""
    info = zf.getinfo(name + ".npy")
    with zf.open(info) as fh:
        version = np.lib.format.read_magic(fh)
        if version == (1, 0):
            shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
        else:
            shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
        header = fh.tell()
    nbytes = array_bytes(shape, dtype)
    if dtype.hasobject:
        return  # numpy refuses it without allocating (allow_pickle=False)
    if nbytes > info.file_size - header:
        raise LcpFileError(
            f"{path}: array {name!r} claims shape {shape} ({human_bytes(nbytes)}) but the file holds "
            f"{human_bytes(max(info.file_size - header, 0))} of it: damaged or truncated"
        )
    check_bytes(f"{path}: array {name!r} of shape {shape}", nbytes)


def _read_npz(path: Path) -> tuple[Any, Any]:
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError, NotImplementedError, zipfile.BadZipFile) as e:
        raise LcpFileError(f"{path}: not a readable .npz file ({e})") from None
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise LcpFileError(f"{path}: not an .npz archive (a single .npy array?)")
    with data:
        names = list(data.files)
        missing = [k for k in ("M", "q") if k not in names]
        if missing:
            raise LcpFileError(
                f"{path}: no array {' or '.join(repr(k) for k in missing)} "
                f"(found: {', '.join(names) if names else 'none'})"
            )
        zf = data.zip
        assert zf is not None  # (an open NpzFile holds its archive)
        try:
            for key in ("M", "q"):
                _npz_header(path, zf, key)
            return data["M"], data["q"]
        except LcpFileError:
            raise
        except SizeLimitError as e:
            raise LcpFileError(str(e)) from None
        # (zipfile raises RuntimeError for a member flagged as encrypted.)
        except (OSError, ValueError, EOFError, KeyError, NotImplementedError, RuntimeError, zipfile.BadZipFile) as e:
            raise LcpFileError(f"{path}: cannot read arrays M, q ({e})") from None


def _read_hdf5(path: Path) -> tuple[Any, Any]:
    with open_hdf5(path, LcpFileError) as f:
        out = []
        for key in ("M", "q"):
            ds = hdf5_dataset(path, f, key, LcpFileError)
            try:
                out.append(ds[()])
            except HDF5_READ_ERRORS as e:
                raise LcpFileError(f"{path}: cannot read dataset '/{key}' ({e})") from None
        return out[0], out[1]


def validate_lcp(path: Path, M: Any, q: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(M, q)`` as float64 arrays once they make an LCP (real, square, matching,
    non-empty, finite), else a :class:`LcpFileError` naming ``path`` and what is wrong."""
    M = np.asarray(M)
    q = np.asarray(q)
    for name, a in (("M", M), ("q", q)):
        if a.dtype.kind not in "biuf":
            raise LcpFileError(f"{path}: {name} must hold real numbers, got dtype {a.dtype}")
    if M.ndim != 2 or M.shape[0] != M.shape[1]:
        raise LcpFileError(f"{path}: M must be a square 2-D array, got shape {M.shape}")
    if q.ndim != 1:
        raise LcpFileError(f"{path}: q must be a 1-D array, got shape {q.shape}")
    if q.shape[0] != M.shape[0]:
        raise LcpFileError(f"{path}: q has length {q.shape[0]} but M has shape {M.shape}")
    if q.shape[0] == 0:
        raise LcpFileError(f"{path}: the LCP is empty (M has shape {M.shape})")
    M = M.astype(np.float64, copy=False)
    q = q.astype(np.float64, copy=False)
    for name, a in (("M", M), ("q", q)):
        bad = np.argwhere(~np.isfinite(a))
        if bad.size:
            idx = tuple(int(i) for i in bad[0])
            shown = ", ".join(map(str, idx))
            raise LcpFileError(f"{path}: {name}[{shown}] = {a[idx]} is not finite")
    return M, q


def load_lcp(
    path: str | os.PathLike[str], index: int | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Loads ``(M, q)`` as float64 arrays from an ``.npz`` or HDF5 file, or
    problem ``index`` of a capture (:mod:`lcpsim.io.capture`; negative counts
    from the end). A capture needs ``index``; a single-LCP file refuses one.

    Raises :class:`FileNotFoundError` if the file does not exist and
    :class:`LcpFileError` if it is not a valid LCP file (unreadable, missing
    array, wrong shapes or dtype, non-finite entries, bad index)."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{path}: no such file")
    if p.is_dir():
        raise LcpFileError(f"{path}: is a directory, not an LCP file")
    fmt = file_format(p)
    if fmt == "hdf5":
        from . import capture

        if capture.is_capture(p):
            try:
                with capture.open_capture(p) as c:
                    if index is None:
                        raise LcpFileError(
                            f"{path}: an LCP corpus of {len(c)} problems; choose one with an index "
                            f"(lcpsim solve FILE --index K, K in 0..{len(c) - 1})"
                        )
                    rec = c[index]
            except capture.CaptureError as e:
                raise LcpFileError(str(e)) from None
            return validate_lcp(p, rec.M, rec.q)
    if index is not None:
        raise LcpFileError(f"{path}: holds a single LCP, not a corpus (no index {index} to choose)")
    M, q = _read_npz(p) if fmt == "npz" else _read_hdf5(p)
    return validate_lcp(p, M, q)


def save_lcp(
    path: str | os.PathLike[str],
    M: ArrayLike,
    q: ArrayLike,
    *,
    attrs: dict[str, Any] | None = None,
) -> Path:
    """Writes ``(M, q)`` to ``path`` (``.npz`` or ``.h5``/``.hdf5``, by suffix).

    ``attrs`` (str, int or float values, e.g. config, seed) are stored as HDF5
    attributes or as 0-d arrays ``attr_<name>`` in an ``.npz``; the lcpsim
    version is always recorded."""
    from .. import __version__

    p = Path(path)
    suffix = p.suffix.lower()
    M = np.asarray(M, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    meta = {"lcpsim_version": __version__, **(attrs or {})}
    if suffix in _NPZ_SUFFIXES:
        arrays: dict[str, Any] = {"M": M, "q": q, **{f"attr_{k}": np.asarray(v) for k, v in meta.items()}}
        np.savez(p, **arrays)
    elif suffix in _HDF5_SUFFIXES:
        import h5py  # type: ignore[import-untyped]

        with h5py.File(p, "w") as f:
            f.create_dataset("M", data=M)
            f.create_dataset("q", data=q)
            for k, v in meta.items():
                f.attrs[k] = v
    else:
        raise LcpFileError(f"{path}: unknown suffix {p.suffix!r} (use .npz, .h5 or .hdf5)")
    return p
