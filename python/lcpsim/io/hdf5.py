"""Reading HDF5 files that may be damaged or hostile: the file's magic bytes,
the errors h5py raises on a damaged file, an HDF5 file opened once it is safe
to, and a dataset read once it is safe to. The LCP files, captures, dumps and
FCLib files all read through these."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .limits import SizeLimitError, array_bytes, check_bytes

__all__ = ["HDF5_MAGIC", "HDF5_ERRORS", "HDF5_READ_ERRORS", "is_hdf5_file", "open_hdf5", "hdf5_dataset"]

#: The first 8 bytes of every HDF5 file.
HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"

def is_hdf5_file(path: Path) -> bool:
    """Whether ``path`` is a file that begins with the HDF5 magic bytes."""
    if not path.is_file():
        return False
    with open(path, "rb") as fh:
        return fh.read(8) == HDF5_MAGIC


#: What h5py raises on a damaged file (RuntimeError: e.g. a bad superblock
#: version; KeyError: an object whose header fails its checksum).
HDF5_ERRORS: tuple[type[Exception], ...] = (OSError, ValueError, RuntimeError, KeyError)
#: What reading a damaged dataset or attribute raises: :data:`HDF5_ERRORS` and TypeError.
HDF5_READ_ERRORS: tuple[type[Exception], ...] = (TypeError, *HDF5_ERRORS)


def open_hdf5(path: Path, error: type[ValueError] = ValueError) -> Any:
    """An HDF5 file opened for reading without HDF5's file locking (a reader
    never waits for, or is refused by, a writer's lock), once
    :func:`~lcpsim.io.hdf5_check.check_global_heaps` has found nothing that
    would hang HDF5; ``error`` for a file that is not readable HDF5."""
    import h5py  # type: ignore[import-untyped]

    from .hdf5_check import check_global_heaps

    try:
        check_global_heaps(path)
        return h5py.File(path, "r", locking=False)
    except HDF5_ERRORS as e:
        raise error(f"{path}: not a readable HDF5 file ({e})") from None


def hdf5_dataset(path: Path, f: Any, key: str, error: type[ValueError] = ValueError) -> Any:
    """Dataset ``/key`` of ``f`` once it is safe to read: a dataset in this
    file (external links, external storage and virtual datasets are refused),
    whose shape fits in memory."""
    import h5py

    try:
        link = f.get(key, getlink=True)
    except HDF5_ERRORS as e:
        raise error(f"{path}: cannot read the link '/{key}' ({e})") from None
    if link is None:
        try:
            # (a damaged name comes back as bytes)
            found = ", ".join("/" + (k.decode(errors="replace") if isinstance(k, bytes) else k) for k in f.keys()) or "none"
        except HDF5_ERRORS:
            found = "an unreadable group"
        raise error(f"{path}: no dataset '/{key}' (found: {found})")
    if isinstance(link, h5py.ExternalLink):
        raise error(f"{path}: '/{key}' is an external link (to {link.filename}:{link.path}); lcpsim reads only data in the file itself")
    try:
        ds = f[key]
    except HDF5_ERRORS as e:  # (KeyError among them)
        raise error(f"{path}: cannot open '/{key}' ({e})") from None
    if not isinstance(ds, h5py.Dataset):
        raise error(f"{path}: '/{key}' is a group, not a dataset")
    if ds.external or ds.is_virtual:
        raise error(f"{path}: '/{key}' keeps its data outside the file (external or virtual dataset); refused")
    if ds.dtype.kind not in "biuf" or ds.shape is None:
        raise error(f"{path}: '/{key}' must hold real numbers, got dtype {ds.dtype}")
    try:
        check_bytes(f"{path}: dataset '/{key}' of shape {ds.shape}", array_bytes(ds.shape, ds.dtype))
    except SizeLimitError as e:
        raise error(str(e)) from None
    return ds
