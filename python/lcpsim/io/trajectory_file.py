"""Trajectories in HDF5: :func:`save_trajectory` / :func:`read_trajectory`
(``Trajectory.save(path)`` and ``Trajectory.load(path)``, which builds the
trajectory from the fields :func:`read_trajectory` returns).

::

    traj = scenes.cube_on_slope(45.2, 1.0).world.run(2000, record_contacts=True)
    traj.save("slope.h5")
    same = Trajectory.load("slope.h5")          # or: lcpsim view slope.h5 --out slope.html

Layout (format ``lcpsim-trajectory``, version 4; ``T`` steps, ``B`` bodies,
``N`` contacts over the whole run):

- root attributes ``format``, ``format_version``, ``lcpsim_version``, ``dt``,
  ``config`` (JSON: the world's bodies, parameters and scene; ``{}`` if unknown),
  ``status_names`` (JSON list);
- per step: ``time`` (T,), ``positions`` (T, B, 3), ``orientations``
  (T, B, 4) as (w, x, y, z), ``velocities`` (T, B, 6) as ``[v; ω]``,
  ``status`` (T,) int8 indices into ``status_names``, ``pivots``,
  ``residual``, ``solver_residual``, ``lcp_size``, ``contacts``,
  ``normal_impulse``, ``friction_impulse`` (T, 3), ``max_lambda``,
  ``islands``, ``max_island_size``, ``parts`` (new in version 2: files of
  version 1 read as one part per step), ``stage_counts`` (T, 4) (new in
  version 3: older files read as zeros, not recorded); with ``J`` joints,
  ``joint_force``, ``joint_torque`` (T, J, 3), ``joint_position`` (T, J),
  ``joint_error`` (T, J, 2) (new in version 4: older files read as J = 0);
- the state before the first step: ``initial_positions`` (B, 3),
  ``initial_orientations`` (B, 4), ``initial_velocities`` (B, 6);
- optional group ``contact_log`` (when the run recorded contacts):
  ``offsets`` (T + 1,) — step t owns rows ``offsets[t]:offsets[t+1]`` —
  ``points`` (N, 3), ``normals`` (N, 3), ``fn`` (N,), ``friction`` (N, 3),
  ``lam`` (N,), ``body_a``, ``body_b`` (N,).

A file that is missing raises ``FileNotFoundError``; one that is not HDF5, is
truncated, or is some other HDF5 file (an LCP, a capture) raises
:class:`TrajectoryFileError` (a ``ValueError``) with one line saying which.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._json import jsonable
from ..trajectory_data import STATUS_NAMES, ContactLog, TrajectoryData
from .hdf5_check import DamagedHdf5Error, check_global_heaps
from .hdf5_check import probe as probe_file

__all__ = ["FORMAT", "FORMAT_VERSION", "TrajectoryFileError", "save_trajectory", "read_trajectory"]

#: Value of the root attribute ``format``.
FORMAT = "lcpsim-trajectory"
#: Value of the root attribute ``format_version``.
FORMAT_VERSION = 4

# Per-step datasets: name → (dtype, shape after T; "B" = bodies).
_PER_STEP: dict[str, tuple[str, tuple[Any, ...]]] = {
    "time": ("f8", ()),
    "positions": ("f8", ("B", 3)),
    "orientations": ("f8", ("B", 4)),
    "velocities": ("f8", ("B", 6)),
    "pivots": ("i8", ()),
    "residual": ("f8", ()),
    "solver_residual": ("f8", ()),
    "lcp_size": ("i8", ()),
    "contacts": ("i8", ()),
    "normal_impulse": ("f8", ()),
    "friction_impulse": ("f8", (3,)),
    "max_lambda": ("f8", ()),
    "islands": ("i8", ()),
    "max_island_size": ("i8", ()),
    "parts": ("i8", ()),
    "stage_counts": ("i8", (4,)),
    "joint_force": ("f8", ("J", 3)),
    "joint_torque": ("f8", ("J", 3)),
    "joint_position": ("f8", ("J",)),
    "joint_error": ("f8", ("J", 2)),
}
# Per-step datasets new in a format version: name → that version (older files hold none).
_SINCE = {"parts": 2, "stage_counts": 3, "joint_force": 4, "joint_torque": 4, "joint_position": 4, "joint_error": 4}
_INITIAL: dict[str, int] = {"initial_positions": 3, "initial_orientations": 4, "initial_velocities": 6}
_CONTACT_TAIL: dict[str, tuple[str, tuple[int, ...]]] = {
    "points": ("f8", (3,)),
    "normals": ("f8", (3,)),
    "fn": ("f8", ()),
    "friction": ("f8", (3,)),
    "lam": ("f8", ()),
    "body_a": ("i8", ()),
    "body_b": ("i8", ()),
}


class TrajectoryFileError(ValueError):
    """A file that is not a readable lcpsim trajectory."""


def save_trajectory(path: str | os.PathLike[str], traj: TrajectoryData) -> str:
    """Writes ``traj`` to ``path`` (created or overwritten); returns the path."""
    import h5py  # type: ignore[import-untyped]

    from .. import __version__

    names = [str(s) for s in STATUS_NAMES]
    codes = {s: i for i, s in enumerate(names)}
    try:
        status = np.array([codes[str(s)] for s in traj.status], dtype=np.int8)
    except KeyError as e:
        raise ValueError(f"trajectory status {e.args[0]!r} is not one of {', '.join(names)}") from None
    with h5py.File(path, "w") as f:
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["lcpsim_version"] = __version__
        f.attrs["dt"] = float(traj.dt)
        f.attrs["config"] = json.dumps(jsonable(traj.config or {}))
        f.attrs["status_names"] = json.dumps(names)
        f.create_dataset("status", data=status)
        for name, (dtype, _) in _PER_STEP.items():
            f.create_dataset(name, data=np.asarray(getattr(traj, name), dtype=dtype))
        for name in _INITIAL:
            f.create_dataset(name, data=np.asarray(getattr(traj, name), dtype=np.float64))
        log = traj.contact_log
        if log is not None:
            g = f.create_group("contact_log")
            g.create_dataset("offsets", data=np.asarray(log.offsets, dtype=np.int64))
            for name, (dtype, _) in _CONTACT_TAIL.items():
                g.create_dataset(name, data=np.asarray(getattr(log, name), dtype=dtype))
    return os.fspath(path)


def read_trajectory(path: str | os.PathLike[str], probe: bool = True) -> dict[str, Any]:
    """Reads a trajectory written by :func:`save_trajectory`: the keyword
    arguments of :class:`~lcpsim.trajectory.Trajectory` (``Trajectory.load``
    builds it from them). With ``probe``
    (default) an HDF5 file is first read in a child process
    (:func:`~lcpsim.io.hdf5_check.probe`): the HDF5 library can crash or loop
    on a damaged file where no Python exception reaches; that is then a
    :class:`TrajectoryFileError` too."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(2, "No such file or directory", os.fspath(path))
    if probe and p.is_file() and _is_hdf5(p):
        try:
            probe_file(p, kind="trajectory")
        except DamagedHdf5Error as e:
            raise TrajectoryFileError(str(e)) from None
    return _load(p, path)


def _is_hdf5(p: Path) -> bool:
    """Whether ``p`` has the HDF5 signature where the library looks for it
    (offset 0, then 512, 1024, 2048, …: after a user block)."""
    size, at = p.stat().st_size, 0
    with open(p, "rb") as fh:
        while at + 8 <= size:
            fh.seek(at)
            if fh.read(8) == b"\x89HDF\r\n\x1a\n":
                return True
            at = 512 if at == 0 else 2 * at
    return False


def _load(p: Path, path: str | os.PathLike[str]) -> dict[str, Any]:
    """:func:`read_trajectory` in this process (the probe's child reads with it)."""
    import h5py

    try:
        check_global_heaps(p)  # a damaged global heap would hang HDF5 itself
        f = h5py.File(p, "r", locking=False)
    except DamagedHdf5Error as e:
        raise TrajectoryFileError(str(e)) from None
    except (OSError, RuntimeError) as e:
        raise TrajectoryFileError(f"{path}: not a readable HDF5 file (truncated or not HDF5: {_reason(e)})") from None
    with f:
        try:
            return _checked(f, path)
        except (KeyError, RuntimeError, TypeError) as e:  # h5py on damaged metadata
            raise TrajectoryFileError(f"{path}: damaged trajectory file ({_reason(e)})") from None


def _checked(f: Any, path: str | os.PathLike[str]) -> dict[str, Any]:
    """The format checks, then :func:`_read`."""
    fmt = f.attrs.get("format")
    if isinstance(fmt, bytes):
        fmt = fmt.decode()
    if fmt != FORMAT:
        what = f"its format is {fmt!r}" if fmt else f"it holds {', '.join(sorted(f.keys())[:4]) or 'nothing'}"
        raise TrajectoryFileError(
            f"{path}: not an lcpsim trajectory ({what}); write one with Trajectory.save or "
            "`lcpsim view SCENE --save FILE.h5`"
        )
    version = int(f.attrs.get("format_version", 0))
    if version > FORMAT_VERSION:
        raise TrajectoryFileError(f"{path}: trajectory format version {version} is newer than this lcpsim reads")
    try:
        return _read(f, path, version)
    except (KeyError, OSError, json.JSONDecodeError) as e:
        raise TrajectoryFileError(f"{path}: damaged trajectory file ({_reason(e)})") from None


def _read(f: Any, path: str | os.PathLike[str], version: int) -> dict[str, Any]:
    names = np.array(json.loads(f.attrs["status_names"]))
    codes = f["status"][()].astype(np.int64)
    T = codes.shape[0]
    if codes.size and (codes.min() < 0 or codes.max() >= names.size):
        raise TrajectoryFileError(f"{path}: damaged trajectory file (status code out of range)")
    B = f["initial_positions"].shape[0]
    J = 0
    if version >= _SINCE["joint_position"]:
        shape = f["joint_position"].shape
        J = shape[1] if len(shape) == 2 else -1  # -1: refused below as a damaged shape
    sizes = {"B": B, "J": J}
    data: dict[str, Any] = {}
    for name, (dtype, tail) in _PER_STEP.items():
        want = (T, *(sizes.get(d, d) for d in tail))
        if version < _SINCE.get(name, 0):
            # not recorded then: before retakes every step was one part; no stage counts, no joints
            data[name] = np.ones(T, dtype=np.int64) if name == "parts" else np.zeros(want, dtype=dtype)
            continue
        a = f[name][()].astype(dtype)
        if a.shape != want:
            raise TrajectoryFileError(f"{path}: damaged trajectory file ({name} has shape {a.shape}, expected {want})")
        data[name] = a
    for name, width in _INITIAL.items():
        a = f[name][()].astype(np.float64)
        if a.shape != (B, width):
            raise TrajectoryFileError(f"{path}: damaged trajectory file ({name} has shape {a.shape})")
        data[name] = a
    log = None
    if "contact_log" in f:
        g = f["contact_log"]
        offsets = g["offsets"][()].astype(np.int64)
        n = int(offsets[-1]) if offsets.size else -1
        if offsets.shape != (T + 1,) or offsets[0] != 0 or np.any(np.diff(offsets) < 0):
            raise TrajectoryFileError(f"{path}: damaged trajectory file (contact_log/offsets)")
        fields: dict[str, Any] = {}
        for name, (dtype, tail) in _CONTACT_TAIL.items():
            a = g[name][()].astype(dtype)
            if a.shape != (n, *tail):
                raise TrajectoryFileError(f"{path}: damaged trajectory file (contact_log/{name} has shape {a.shape})")
            fields[name] = a
        log = ContactLog(offsets=offsets, **fields)
    return dict(
        dt=float(f.attrs["dt"]),
        status=names[codes],
        config=json.loads(f.attrs.get("config", "{}")) or None,
        contact_log=log,
        **data,
    )


def _reason(e: BaseException) -> str:
    """An error's text on one line."""
    return " ".join(str(e).split()) or type(e).__name__
