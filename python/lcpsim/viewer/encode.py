"""The viewer's data: a trajectory turned into the JSON object the page reads.

Frames are states: frame ``i`` shows the state after step ``frame_step[i]``
(0 = the initial state) with that step's contacts. Arrays travel as base64
of little-endian typed arrays (``{"dtype", "shape", "b64"}``): poses and
contacts in single precision (drawing needs no more), the selected body's
readouts (position, displacement, tilt, down-slope distance) in double
precision, computed here. Joints (when the trajectory's ``config`` lists
them) travel as each kept state's anchor (as side B carries it) and axis (as
side A carries it, the world's if A is the world), computed here from the
poses and each joint's geometry in its bodies' frames, so they move with
their bodies. Every step's LCP status is kept (one byte a step)
for the timeline strip; a long run keeps every ``stride``-th state plus the
last one and every failed step, with ``stride`` the smallest that fits the
byte budget — the page says so when ``stride > 1``.
"""

from __future__ import annotations

import base64
import math
from typing import Any, Callable, Mapping

import numpy as np
from numpy.typing import NDArray

from ..trajectory_data import NO_CONTACT, STATUS_NAMES, TrajectoryData, quat_rotate

__all__ = ["payload", "choose_frames", "frame_bytes", "joint_frames", "STATUS_COLORS"]

#: Timeline colours by status; every status not listed is a failure ("failed").
STATUS_COLORS = {
    "solved": "#6aa86a",
    NO_CONTACT: "#b7bcc4",
    "regularized": "#e08a1e",
    "failed": "#c0191f",
}
_OK = ("solved", NO_CONTACT)
# Bytes per frame before base64 (its 4/3 is applied by frame_bytes): frame_step, frame_time,
# pivots, residual, contact offset, the focus readouts (3 + 3 + 1 + 1 doubles), per dynamic body
# a pose (7 floats), per contact point, normal, friction (3 floats each), fn and λ, per joint
# an anchor and an axis (3 floats each).
_FRAME_FIXED = 4 + 8 + 4 + 4 + 4 + 8 * 8
_PER_BODY = 7 * 4
_PER_CONTACT = 11 * 4
_PER_JOINT = 6 * 4


def _b64(a: NDArray[Any], dtype: str) -> dict[str, Any]:
    with np.errstate(over="ignore"):  # beyond single precision (a blown-up run): ±inf, drawn as nothing
        arr = np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<"))
    return {"dtype": dtype.lstrip("<"), "shape": list(arr.shape), "b64": base64.b64encode(arr.tobytes()).decode()}


def frame_bytes(dynamic: int, contacts: NDArray[np.int64], joints: int = 0) -> NDArray[np.float64]:
    """Encoded bytes of each frame (base64 included), given the contacts of each."""
    fixed = _FRAME_FIXED + _PER_BODY * dynamic + _PER_JOINT * joints
    return (fixed + _PER_CONTACT * contacts.astype(np.float64)) * 4.0 / 3.0


def choose_frames(
    cost: NDArray[np.float64], failed: NDArray[np.int64], budget: float, start_stride: int = 1
) -> tuple[NDArray[np.int64], int]:
    """States to keep (sorted) and the stride: every ``stride``-th state, the last, and the
    failed ones (themselves thinned if they alone would take over a quarter of the budget).
    ``cost[i]`` is state i's bytes; the smallest stride ≥ ``start_stride`` that fits wins."""
    n = cost.shape[0]
    if cost[0] + cost[-1] > budget:
        raise ValueError(f"max_bytes leaves {budget:.0f} bytes for frames: too small for even two frames")
    keep_failed = failed
    fail_cost = float(cost[failed].sum())
    if fail_cost > budget / 4:
        keep_failed = failed[:: int(math.ceil(fail_cost / (budget / 4)))]
    stride = max(1, int(start_stride), int(cost.sum() // budget))
    while True:
        idx = np.union1d(np.union1d(np.arange(0, n, stride), [n - 1]), keep_failed).astype(np.int64)
        if cost[idx].sum() <= budget or stride >= n:
            return idx, stride
        stride = max(stride + 1, int(stride * 1.05))


def _slope(
    bodies: list[dict[str, Any]], gravity: NDArray[np.float64]
) -> tuple[NDArray[np.float64] | None, NDArray[np.float64]]:
    """Down-slope direction of the first plane not level with gravity (None if all are level),
    and that plane's normal (else "up", against gravity)."""
    g = gravity / (np.linalg.norm(gravity) or 1.0)
    for b in bodies:
        if b.get("kind") != "plane":
            continue
        n = np.asarray(b["normal"], dtype=float)
        n = n / np.linalg.norm(n)
        d = g - (g @ n) * n
        if np.linalg.norm(d) > 1e-9:
            return np.asarray(d / np.linalg.norm(d)), n
    return None, (-g if np.linalg.norm(g) > 0 else np.array([0.0, 0.0, 1.0]))


def payload(
    traj: TrajectoryData,
    *,
    body: int | None,
    direction: Any,
    direction_label: str | None,
    budget: float,
) -> dict[str, Any]:
    """The page's data object; poses and contacts of at most ``budget`` bytes of frames."""
    from ..experiments.onset import precise_tilt

    config = traj.config or {}
    nb = traj.bodies
    cfg_bodies = list(config.get("bodies") or [])
    if len(cfg_bodies) != nb:  # shapes unknown: markers
        cfg_bodies = [{"kind": "unknown", "static": False} for _ in range(nb)]
    moving = np.ptp(traj.positions, axis=0).max(axis=1) > 0 if len(traj) else np.zeros(nb, bool)
    dynamic = [i for i, b in enumerate(cfg_bodies) if b["kind"] != "plane" and (not b.get("static") or moving[i])]
    if body is None:
        body = dynamic[0] if dynamic else -1
    elif not (0 <= body < nb and body in dynamic):
        raise ValueError(f"body must be the index of a moving body (one of {dynamic}), got {body!r}")
    gravity = np.asarray((config.get("params") or {}).get("gravity", (0.0, 0.0, -9.81)), dtype=float)
    d, up = _slope(cfg_bodies, gravity)
    label = "down-slope distance"
    if direction is not None:
        d = np.asarray(direction, dtype=float)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or not np.linalg.norm(d) > 0:
            raise ValueError(f"direction must be 3 finite numbers, not all 0, got {direction!r}")
        d = d / np.linalg.norm(d)
        label = "distance along the scene's direction"
    label = direction_label or label

    T = len(traj)
    pos = np.concatenate([traj.initial_positions[None], traj.positions])  # (T+1, B, 3)
    quat = np.concatenate([traj.initial_orientations[None], traj.orientations])
    log = traj.contact_log
    contacts = np.zeros(T + 1, np.int64)
    if log is not None:
        contacts[1:] = log.counts
    codes = _status_codes(traj.status)
    failed_steps = np.nonzero(~np.isin(traj.status, _OK))[0] + 1  # as states
    joints = list(config.get("joints") or [])
    if len(joints) != traj.joints:  # geometry unknown: not drawn
        joints = []
    cost = frame_bytes(len(dynamic), contacts, len(joints))
    idx, stride = choose_frames(cost, failed_steps.astype(np.int64), budget)
    arrays: dict[str, Any] = {
        "frame_step": _b64(idx, "<i4"),
        "frame_time": _b64(np.concatenate([[traj.time[0] - traj.dt if T else 0.0], traj.time])[idx], "<f8"),
        "frame_pivots": _b64(np.concatenate([[0], traj.pivots])[idx], "<i4"),
        "frame_residual": _b64(np.concatenate([[0.0], traj.residual])[idx], "<f4"),
        "step_status": _b64(codes, "<u1"),
        "pose": _b64(np.concatenate([pos[idx][:, dynamic], quat[idx][:, dynamic]], axis=2), "<f4"),
    }
    if body >= 0:
        disp = pos[idx, body] - pos[0, body]
        arrays["focus_position"] = _b64(pos[idx, body], "<f8")
        arrays["focus_displacement"] = _b64(disp, "<f8")
        arrays["focus_tilt_deg"] = _b64(np.degrees(precise_tilt(quat[idx, body], quat[0, body])), "<f8")
        arrays["focus_along"] = _b64(disp @ d if d is not None else np.zeros(len(idx)), "<f8")
    if log is not None:
        arrays.update(_contacts(log, idx))
    if joints:
        anchor, axis = joint_frames(joints, pos[idx], quat[idx])
        arrays["j_anchor"], arrays["j_axis"] = _b64(anchor, "<f4"), _b64(axis, "<f4")
    ref = _impulse_reference(log)
    size = _body_size(cfg_bodies, dynamic)
    return {
        "format": "lcpsim-view",
        "version": 1,
        "steps": T,
        "dt": traj.dt,
        "frames": int(idx.size),
        "stride": stride,
        "bodies": [_body_json(b, i, traj) for i, b in enumerate(cfg_bodies)],
        "dynamic": dynamic,
        "focus": body,
        "direction": None if d is None else d.tolist(),
        "direction_label": label,
        "joints": [{"kind": j["kind"], "bodies": [j["body_a"], j["body_b"]]} for j in joints],
        "has_contacts": log is not None,
        "max_contacts": int(contacts.max(initial=0)),
        "status_names": [str(s) for s in STATUS_NAMES],
        "failed_statuses": [str(s) for s in STATUS_NAMES if s not in _OK],
        "status_colors": STATUS_COLORS,
        "failed_runs": _runs(failed_steps),
        "impulse": {
            "length_per_Ns": 0.6 * size / ref,
            "legend": f"arrow of {0.6 * size:.3g} m = {ref:.3g} N·s",
        },
        "view": _view(pos, dynamic, d, up, size),
        "arrays": arrays,
    }


def _status_codes(status: NDArray[np.str_]) -> NDArray[np.uint8]:
    lookup = {str(s): i for i, s in enumerate(STATUS_NAMES)}
    return np.array([lookup[str(s)] for s in status], dtype=np.uint8)


def _contacts(log: Any, idx: NDArray[np.int64]) -> dict[str, Any]:
    """The kept frames' contacts, concatenated; frame 0 (the initial state) has none."""
    steps = idx[idx > 0] - 1
    a = np.concatenate([np.zeros(idx.size - steps.size, np.int64), log.offsets[steps]])
    b = np.concatenate([np.zeros(idx.size - steps.size, np.int64), log.offsets[steps + 1]])
    counts = b - a
    rows = np.concatenate([np.arange(s, e) for s, e in zip(a, b)]) if counts.sum() else np.zeros(0, np.int64)
    pick: Callable[[str], NDArray[Any]] = lambda f: getattr(log, f)[rows]  # noqa: E731
    return {
        "c_offsets": _b64(np.concatenate([[0], np.cumsum(counts)]), "<i4"),
        "c_point": _b64(pick("points"), "<f4"),
        "c_normal": _b64(pick("normals"), "<f4"),
        "c_fn": _b64(pick("fn"), "<f4"),
        "c_friction": _b64(pick("friction"), "<f4"),
        "c_lam": _b64(pick("lam"), "<f4"),
    }


def joint_frames(
    joints: list[Mapping[str, Any]], pos: NDArray[np.float64], quat: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Each joint's anchor as side B carries it and its axis as side A carries it (the world's
    if A is the world), for states of poses ``pos`` (F, B, 3) and ``quat`` (F, B, 4):
    (F, J, 3) each, from the joints' geometry in their bodies' frames (``World.config``)."""
    frames = pos.shape[0]
    anchor, axis = np.zeros((frames, len(joints), 3)), np.zeros((frames, len(joints), 3))
    for j, joint in enumerate(joints):
        b, a = joint["body_b"], joint["body_a"]
        anchor[:, j] = pos[:, b] + quat_rotate(quat[:, b], joint["anchor"][1])
        axis[:, j] = joint["axis"][0] if a is None else quat_rotate(quat[:, a], joint["axis"][0])
    return anchor, axis


def _runs(steps: NDArray[np.int64]) -> list[list[int]]:
    """Consecutive failed steps as [first, last] runs (at most 500, the rest merged into the last)."""
    runs: list[list[int]] = []
    for s in steps.tolist():
        if runs and s == runs[-1][1] + 1:
            runs[-1][1] = s
        else:
            runs.append([s, s])
    if len(runs) > 500:
        runs = runs[:499] + [[runs[499][0], runs[-1][1]]]
    return runs


def _impulse_reference(log: Any) -> float:
    """The impulse an arrow of 0.6 body sizes stands for: the 95th percentile of positive fn."""
    if log is None or log.fn.size == 0:
        return 1.0
    fn = log.fn[np.isfinite(log.fn) & (log.fn > 0)]
    return float(np.percentile(fn, 95)) if fn.size else 1.0


def _body_size(bodies: list[dict[str, Any]], dynamic: list[int]) -> float:
    sizes = []
    for i in dynamic:
        b = bodies[i]
        if b["kind"] == "box":
            sizes.append(2 * max(b["half_extents"]))
        elif b["kind"] == "sphere":
            sizes.append(2 * b["radius"])
        elif b["kind"] in ("capsule", "cylinder"):
            sizes.append(2 * max(b["radius"], b["half_length"]))
        elif b["kind"] == "convex" and b.get("vertices"):
            sizes.append(2 * float(np.max(np.linalg.norm(np.asarray(b["vertices"], dtype=float), axis=1))))
        elif b["kind"] == "compound" and b.get("parts"):
            sizes.append(2 * max(float(np.linalg.norm(p["position"])) for p in b["parts"]) + _body_size(b["parts"], list(range(len(b["parts"])))))
    return float(np.median(sizes)) if sizes else 1.0


def _body_json(b: Mapping[str, Any], i: int, traj: TrajectoryData) -> dict[str, Any]:
    keys = ("kind", "static", "half_extents", "radius", "normal", "offset", "half_length", "vertices", "faces", "parts",
            "heights")
    out = {k: b[k] for k in keys if k in b}
    out["position"] = traj.initial_positions[i].tolist()
    out["orientation"] = traj.initial_orientations[i].tolist()
    return out


def _view(
    pos: NDArray[np.float64], dynamic: list[int], d: NDArray[np.float64] | None, up: NDArray[np.float64],
    size: float,
) -> dict[str, Any]:
    """Camera and ground: looking at every place the bodies went, from the side of the
    motion ``d`` (so it crosses the screen) and above the surface with normal ``up``."""
    p = pos[:, dynamic].reshape(-1, 3) if dynamic else np.zeros((1, 3))
    p = p[np.all(np.isfinite(p), axis=1)]
    lo, hi = (p.min(axis=0), p.max(axis=0)) if p.size else (np.zeros(3), np.zeros(3))
    # A body launched far away (a failed solve's impulse) must not shrink the rest to a dot:
    # frame the initial layout and up to 20 body sizes around it.
    start = pos[0, dynamic] if dynamic else np.zeros((1, 3))
    lo = np.maximum(lo, start.min(axis=0) - 20 * size)
    hi = np.minimum(hi, start.max(axis=0) + 20 * size)
    target = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo) / 2 + size)
    side = np.array([0.35, -1.0, 0.0])
    if d is not None and np.linalg.norm(d[:2]) > 1e-9:
        h = np.array([d[0], d[1], 0.0]) / np.linalg.norm(d[:2])
        side = np.cross([0.0, 0.0, 1.0], h) * -1.0 + 0.25 * h
    eye = side / np.linalg.norm(side) + 0.6 * up
    eye = eye / np.linalg.norm(eye) * radius * 4.2
    return {
        "target": target.tolist(),
        "eye_offset": eye.tolist(),
        "center": target.tolist(),
        "size": size,
        "plane_size": float(max(8 * size, 5 * radius)),
        "grid": float(size / 4),
    }
