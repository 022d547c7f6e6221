"""Writing a file so that nothing is ever lost (captures, sweep results).

A writer of ``PATH``:

1. takes an exclusive lock on ``PATH.lock`` before touching anything (a
   second writer of the same path fails at once with :class:`FileLockedError`,
   and the first writer's file and the original stay as they are);
2. refuses an existing ``PATH`` (:class:`FileExistsError`) unless asked to
   overwrite — and even then the original is replaced only at the end;
3. writes ``PATH.partial`` beside it, and on success renames it onto ``PATH``
   in one atomic step (``os.replace``): ``PATH`` is always either the old
   complete file or the new complete one. A run that is killed or fails
   leaves its data in ``PATH.partial``, which a later writer refuses to
   replace unless asked to overwrite.

The lock is advisory (``flock``), taken on a separate small file so that the
target itself is never opened for writing before the lock is held.
"""

from __future__ import annotations

import errno
import os
from pathlib import Path
from typing import Any

__all__ = ["PARTIAL_SUFFIX", "LOCK_SUFFIX", "FileLockedError", "SafeTarget", "partial_path"]

#: Suffix of the file being written (and of what an interrupted run leaves).
PARTIAL_SUFFIX = ".partial"
#: Suffix of the lock file held while writing.
LOCK_SUFFIX = ".lock"

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows: an exclusively created lock file instead
    fcntl = None  # type: ignore[assignment]


class FileLockedError(BlockingIOError):
    """Another process is writing the same path."""


def partial_path(path: str | os.PathLike[str]) -> Path:
    """Where a writer of ``path`` writes (and an interrupted run leaves its data)."""
    p = Path(path)
    return p.with_name(p.name + PARTIAL_SUFFIX)


def _lock(lock_path: Path, target: Path) -> int:
    """An open descriptor holding the exclusive lock on ``lock_path``."""
    for _ in range(8):
        flags = os.O_RDWR | os.O_CREAT | (0 if fcntl is not None else os.O_EXCL)
        try:
            fd = os.open(lock_path, flags, 0o644)
        except FileExistsError:
            raise FileLockedError(errno.EWOULDBLOCK, f"{target}: another process is writing it (lock file {lock_path})") from None
        if fcntl is None:  # pragma: no cover
            return fd
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.read(fd, 64).decode(errors="replace").strip()
            os.close(fd)
            who = f" (process {holder})" if holder else ""
            raise FileLockedError(
                errno.EWOULDBLOCK, f"{target}: another process{who} is writing it; wait for it or choose another path"
            ) from None
        # The holder before us may have removed the lock file after we opened it: retry on the new one.
        try:
            same = os.stat(lock_path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            os.ftruncate(fd, 0)
            os.write(fd, str(os.getpid()).encode())
            return fd
        os.close(fd)
    raise FileLockedError(errno.EWOULDBLOCK, f"{target}: could not lock {lock_path}")  # pragma: no cover


class SafeTarget:
    """The lock, the checks and the final rename of one write of ``path``.

    Write to :attr:`partial`; then :meth:`commit` (rename onto ``path``) or
    :meth:`abandon` (keep ``PATH.partial``, e.g. after an error). Either
    releases the lock."""

    def __init__(self, path: str | os.PathLike[str], *, overwrite: bool = False, what: str = "file") -> None:
        self._fd: int | None = None
        self.path = Path(path)
        self.partial = partial_path(self.path)
        self.lock_path = self.path.with_name(self.path.name + LOCK_SUFFIX)
        if self.path.is_dir():
            raise IsADirectoryError(errno.EISDIR, f"{self.path}: is a directory")
        if not self.path.parent.is_dir():
            raise FileNotFoundError(errno.ENOENT, f"{self.path.parent}: no such directory (for {self.path})")
        self._fd = _lock(self.lock_path, self.path)
        try:
            if self.path.exists() and not overwrite:
                raise FileExistsError(
                    errno.EEXIST, f"{self.path}: already exists; pass overwrite=True (command line: --overwrite) to replace it"
                )
            if self.partial.exists():
                if not overwrite:
                    raise FileExistsError(
                        errno.EEXIST,
                        f"{self.partial}: an interrupted {what} is there (it is readable); move it away "
                        "or pass overwrite=True (command line: --overwrite) to replace it",
                    )
                self.partial.unlink()
        except BaseException:
            self._release()
            raise

    @property
    def locked(self) -> bool:
        return self._fd is not None

    def commit(self) -> Path:
        """Renames the complete ``PATH.partial`` onto ``PATH`` (atomic) and releases the lock."""
        if self._fd is None:
            raise ValueError(f"{self.path}: already committed or abandoned")
        try:
            _fsync_file(self.partial)
            os.replace(self.partial, self.path)
            _fsync_dir(self.path.parent)
        finally:
            self._release()
        return self.path

    def abandon(self) -> None:
        """Releases the lock, leaving whatever was written in ``PATH.partial``."""
        self._release()

    def _release(self) -> None:
        fd, self._fd = self._fd, None
        if fd is None:
            return
        try:
            os.unlink(self.lock_path)  # while still holding it: see _lock's retry
        except OSError:
            pass
        os.close(fd)

    def __del__(self) -> None:
        self._release()

    def __enter__(self) -> "SafeTarget":
        return self

    def __exit__(self, exc_type: Any, *exc: Any) -> None:
        if self._fd is not None:
            self.abandon() if exc_type is not None else self.commit()


def _fsync_file(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - e.g. Windows
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)
