"""Joints of a :class:`lcpsim.World`: ball, hinge, slider and fixed joints
between two bodies, or a body and the world (``body_a=None``).

A joint is a set of bilateral velocity rows eliminated from each step's
contact LCP (the contact LCP keeps its Stewart–Trinkle form on the
joint-projected inverse mass), with its drift corrected apart from the
contacts' stabilization; see ``docs/joints.md``. The methods here are those
of :class:`lcpsim.World`.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

Vec = Sequence[float] | NDArray[np.float64]

#: The joint kinds, in the core's spelling.
JOINT_KINDS = ("ball", "hinge", "slider", "fixed")


def _body(world: Any, body: Any, field: str, *, world_ok: bool) -> int | None:
    """A body index of ``world`` (None for the world where allowed), named ``field`` in errors."""
    if body is None and world_ok:
        return None
    n = world._core.body_count
    if isinstance(body, bool) or not isinstance(body, (int, np.integer)) or not 0 <= int(body) < n:
        what = "None (the world) or " if world_ok else ""
        raise ValueError(f"{field} must be {what}a body index in [0, {n}), got {body!r}")
    return int(body)


def _axis(axis: Any) -> tuple[float, float, float]:
    try:
        a = tuple(float(x) for x in np.asarray(axis, dtype=float).reshape(3))
    except (TypeError, ValueError):
        raise ValueError(f"axis must be 3 real numbers, got {axis!r}") from None
    if not all(math.isfinite(x) for x in a):
        raise ValueError(f"axis must be finite, got {axis!r}")
    if a == (0.0, 0.0, 0.0):
        raise ValueError(f"axis must be a non-zero vector, got {axis!r}")
    return a


def _limits(limits: Any, field: str = "limits") -> tuple[float, float] | None:
    if limits is None:
        return None
    try:
        lo, hi = (float(x) for x in limits)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be (lower, upper), got {limits!r}") from None
    if math.isnan(lo) or math.isnan(hi) or lo > hi:
        raise ValueError(f"{field} must be (lower, upper) with lower <= upper, got {limits!r}")
    return lo, hi


def _damping(damping: Any) -> float:
    try:
        d = float(damping)
    except (TypeError, ValueError):
        raise ValueError(f"damping must be a real number, got {damping!r}") from None
    if not (math.isfinite(d) and d >= 0.0):
        raise ValueError(f"damping must be finite and >= 0, got {damping!r}")
    return d


def _motor(speed: Any, max_force: Any) -> tuple[float, float]:
    try:
        s, f = float(speed), float(max_force)
    except (TypeError, ValueError):
        raise ValueError(f"motor must be (speed, max_force) real numbers, got ({speed!r}, {max_force!r})") from None
    if not math.isfinite(s):
        raise ValueError(f"speed must be finite, got {speed!r}")
    if not (math.isfinite(f) and f >= 0.0):
        raise ValueError(f"max_force must be finite and >= 0, got {max_force!r}")
    return s, f


class JointsMixin:
    """The joint methods of :class:`lcpsim.World` (``self._core`` the core world)."""

    _core: Any

    def _add_joint(
        self,
        kind: str,
        body_a: Any,
        body_b: Any,
        anchor: Vec,
        axis: Vec | None,
        limits: Any,
        motor: Any,
        damping: Any = 0.0,
    ) -> int:
        a = _body(self, body_a, "body_a", world_ok=True)
        b = _body(self, body_b, "body_b", world_ok=False)
        ax = _axis(axis) if axis is not None else None
        lim = _limits(limits)
        drive = None
        if motor is not None:
            try:
                speed, max_force = motor
            except (TypeError, ValueError):
                raise ValueError(f"motor must be (speed, max_force), got {motor!r}") from None
            drive = _motor(speed, max_force)
        d = _damping(damping)
        j = int(self._core.add_joint(kind, a, b, anchor, ax, lim))
        if drive is not None:
            self._core.set_motor(j, *drive)
        if d > 0.0:
            self._core.set_joint_damping(j, d)
        return j

    def add_hinge(self, body_a: int | None, body_b: int, anchor: Vec, axis: Vec, *,
                  limits: Any = None, motor: Any = None, damping: float = 0.0) -> int:
        """A hinge: ``body_b`` turns about ``axis`` (world, at creation) through
        ``anchor`` (world) relative to ``body_a`` (None: the world). Returns the
        joint's index. ``limits``: ``(lower, upper)`` of the angle (rad, 0 at
        creation, positive turning B about ``axis``): a hard stop, a
        complementarity row of the contact LCP. ``motor``: ``(speed, max_force)``
        as for :meth:`set_motor`. ``damping``: as for :meth:`set_joint_damping`
        (N·m·s/rad)."""
        return self._add_joint("hinge", body_a, body_b, anchor, axis, limits, motor, damping)

    def add_slider(self, body_a: int | None, body_b: int, anchor: Vec, axis: Vec, *,
                   limits: Any = None, motor: Any = None, damping: float = 0.0) -> int:
        """A slider (prismatic joint): ``body_b`` translates along ``axis``
        relative to ``body_a`` without turning. Returns the joint's index.
        ``limits``: ``(lower, upper)`` of B's displacement along ``axis`` (m, 0 at creation);
        ``damping`` (N·s/m) as for :meth:`set_joint_damping`."""
        return self._add_joint("slider", body_a, body_b, anchor, axis, limits, motor, damping)

    def add_ball(self, body_a: int | None, body_b: int, anchor: Vec) -> int:
        """A ball joint: the bodies' points at ``anchor`` stay together."""
        return self._add_joint("ball", body_a, body_b, anchor, None, None, None)

    def add_fixed(self, body_a: int | None, body_b: int, anchor: Vec | None = None) -> int:
        """A weld: ``body_b`` keeps its pose relative to ``body_a``
        (``anchor`` defaults to ``body_b``'s centre of mass)."""
        b = _body(self, body_b, "body_b", world_ok=False)
        if anchor is None:
            anchor = self._core.body(b)["position"]
        return self._add_joint("fixed", body_a, b, anchor, None, None, None)

    def set_motor(self, joint: int, speed: float, max_force: float) -> None:
        """A velocity motor on a hinge or slider: its rate (rad/s about the
        axis, m/s along it) driven to ``speed`` with at most ``max_force``
        (N·m, N) either way, as complementarity rows of the contact LCP (the
        friction pattern with a constant bound). ``max_force=0`` turns it off."""
        self._core.set_motor(self._joint(joint), *_motor(speed, max_force))

    def set_joint_damping(self, joint: int, damping: float) -> None:
        """Viscous damping of a hinge's or slider's rate: a force ``-damping·q̇``
        (N·m·s/rad, N·s/m), integrated implicitly (stable for any ``damping``:
        a joint row with compliance ``1/(dt·damping)``, eliminated with the
        others). ``0`` turns it off."""
        self._core.set_joint_damping(self._joint(joint), _damping(damping))

    def set_control(self, actuator: int | str, value: float) -> None:
        """Sets an MJCF ``<velocity>`` actuator's control (by name or index, in
        the model's order): its joint's motor drives the actuator's rate to
        ``value`` (clamped to ``ctrlrange`` if the model limits it; the joint's
        rate is ``value / gear``) with at most ``forcerange`` (× ``gear``)."""
        acts = getattr(self, "_actuators", [])
        if isinstance(actuator, str):
            found = [i for i, a in enumerate(acts) if a.name == actuator]
            if not found:
                known = ", ".join(a.name for a in acts) or "none"
                raise ValueError(f"actuator must name an actuator of the model, got {actuator!r} (actuators: {known})")
            k = found[0]
        elif isinstance(actuator, bool) or not isinstance(actuator, (int, np.integer)) or not 0 <= int(actuator) < len(acts):
            raise ValueError(f"actuator must be an actuator name or an index in [0, {len(acts)}), got {actuator!r}")
        else:
            k = int(actuator)
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"value must be a real number, got {value!r}") from None
        if not math.isfinite(v):
            raise ValueError(f"value must be finite, got {value!r}")
        a = acts[k]
        if a.ctrlrange is not None:
            v = min(max(v, a.ctrlrange[0]), a.ctrlrange[1])
        self._core.set_motor(a.joint, v / a.gear, a.max_force)

    def _joint(self, joint: Any) -> int:
        n = self._core.joint_count
        if isinstance(joint, bool) or not isinstance(joint, (int, np.integer)) or not 0 <= int(joint) < n:
            raise ValueError(f"joint must be a joint index in [0, {n}), got {joint!r}")
        return int(joint)

    @property
    def joint_count(self) -> int:
        """Number of joints."""
        return int(self._core.joint_count)

    def joint_error(self, joint: int) -> tuple[float, float]:
        """A joint's position error now: (largest linear error in m, largest angular error in rad)."""
        lin, ang = self._core.joint_error(self._joint(joint))
        return float(lin), float(ang)

    def joint_position(self, joint: int) -> float:
        """A hinge's angle (rad) or a slider's displacement (m) now, 0 at creation."""
        return float(self._core.joint_position(self._joint(joint)))

    def joint_reactions(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The last step's joint reactions, what side A exerts on side B at the
        anchor: forces (J, 3) in N and torques (J, 3) in N·m (mean over the step)."""
        f, t = self._core.joint_reactions()
        return np.asarray(f), np.asarray(t)

    def joint_params(self) -> dict[str, Any]:
        """``drift`` (Baumgarte β of the joints, default 1), ``settle_passes``
        (position projections per step, default 3), ``settle_tol`` (1e-10) and
        ``rank_tol`` (the rank cut of ``G M⁻¹ Gᵀ``, 1e-9)."""
        return dict(self._core.joint_params())

    def set_joint_params(self, **params: Any) -> None:
        """Changes any of :meth:`joint_params`' fields (validated)."""
        unknown = set(params) - {"drift", "rank_tol", "settle_passes", "settle_tol"}
        if unknown:
            raise ValueError(f"unknown joint parameter(s): {sorted(unknown)}")
        self._core.set_joint_params(**params)
