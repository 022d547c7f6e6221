"""The plain data of trajectories, below :mod:`lcpsim.trajectory`, the trajectory
file (:mod:`lcpsim.io.trajectory_file`) and the viewer (:mod:`lcpsim.viewer`),
which all import it: the step statuses (:data:`NO_CONTACT`, :data:`STATUS_NAMES`),
the stages of the solve chain (:data:`STAGES`), every step's contacts
(:class:`ContactLog`), a run's LCP statistics (:class:`LcpStats`) and a trajectory's
arrays with what is computed from them alone (:class:`TrajectoryData`, the base of
:class:`~lcpsim.trajectory.Trajectory`, which adds its file and its page).
:mod:`lcpsim.trajectory` re-exports all of them but :class:`TrajectoryData`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._json import fields_dict
from .lcp import STATUSES

__all__ = ["ContactLog", "LcpStats", "NO_CONTACT", "STATUS_NAMES", "STAGES", "TrajectoryData", "quat_angle", "quat_rotate"]

#: Status of a step without contacts (no LCP was solved).
NO_CONTACT = "no_contact"
#: Trajectory status codes from the compiled module: -1 = no contact, else an index into STATUSES;
#: ``STATUS_NAMES[code + 1]`` is the name.
STATUS_NAMES = np.array([NO_CONTACT, *STATUSES])
#: The stages of the island solve chain, in chain order (columns of ``Trajectory.stage_counts``).
STAGES = ("previous_basis", "guessed_basis", "structured_lemke", "dense")


def quat_angle(q0: ArrayLike, q1: ArrayLike) -> NDArray[np.float64] | float:
    """Rotation angle (rad) between unit quaternions ``q0`` and ``q1`` (w, x, y, z);
    broadcasts over leading dimensions."""
    d = np.abs(np.sum(np.asarray(q0, dtype=float) * np.asarray(q1, dtype=float), axis=-1))
    a = 2.0 * np.arccos(np.clip(d, -1.0, 1.0))
    return float(a) if np.ndim(a) == 0 else a


def quat_rotate(q: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """``v`` rotated by the unit quaternions ``q`` (w, x, y, z); broadcasts over leading dimensions."""
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    w, u = q[..., :1], q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return np.asarray(v + w * t + np.cross(u, t))


@dataclass(frozen=True)
class ContactLog:
    """Every step's contacts, concatenated over the run: step ``t`` owns rows
    ``offsets[t]:offsets[t + 1]``.

    ``points`` (N, 3) in m, ``normals`` (N, 3) unit, pointing from body B to
    body A; ``fn`` (N,) normal impulses (N·s); ``friction`` (N, 3) the friction
    impulse vector ``Σ_j fd_j d_j`` on body A (N·s); ``lam`` (N,) λ (m/s), all
    in physical units; ``body_a``, ``body_b`` (N,) body indices. A step whose
    LCP failed keeps the impulses the solver returned (the simulator applied none).
    """

    offsets: NDArray[np.int64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    fn: NDArray[np.float64]
    friction: NDArray[np.float64]
    lam: NDArray[np.float64]
    body_a: NDArray[np.int64]
    body_b: NDArray[np.int64]

    #: The per-contact fields, in file order.
    FIELDS = ("points", "normals", "fn", "friction", "lam", "body_a", "body_b")

    def __len__(self) -> int:
        return int(self.offsets.shape[0]) - 1

    @property
    def counts(self) -> NDArray[np.int64]:
        """(T,) contacts per step."""
        return np.diff(self.offsets)

    def at(self, step: int) -> dict[str, NDArray[Any]]:
        """Step ``step``'s contacts: field name → array (rows of that step only)."""
        if not 0 <= step < len(self):
            raise IndexError(f"step {step} out of range (the log holds {len(self)} steps)")
        a, b = int(self.offsets[step]), int(self.offsets[step + 1])
        return {f: getattr(self, f)[a:b] for f in self.FIELDS}

    @classmethod
    def from_records(cls, records: Sequence[Mapping[str, Any]]) -> "ContactLog":
        """The log of step records (``StepRecord`` or the compiled step's dicts), in step order."""
        counts = np.array([int(r["contacts"]) if isinstance(r, Mapping) else r.contacts for r in records], dtype=np.int64)
        get = (lambda r, f: r[f]) if records and isinstance(records[0], Mapping) else getattr

        def cat(f: str, tail: tuple[int, ...], dtype: Any) -> NDArray[Any]:
            parts = [np.asarray(get(r, f), dtype=dtype).reshape(-1, *tail) for r in records]
            return np.concatenate(parts) if parts else np.zeros((0, *tail), dtype=dtype)

        return cls(
            offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
            points=cat("points", (3,), np.float64),
            normals=cat("normals", (3,), np.float64),
            fn=cat("fn", (), np.float64),
            friction=cat("friction", (3,), np.float64),
            lam=cat("lam", (), np.float64),
            body_a=cat("body_a", (), np.int64),
            body_b=cat("body_b", (), np.int64),
        )


@dataclass(frozen=True)
class LcpStats:
    """LCP statistics of a run: how many LCPs were solved and how they ended."""

    steps: int
    lcps: int  # steps with an LCP
    failures: int  # LCPs not solved
    by_status: dict[str, int]  # every status that occurred (LCP steps only)
    max_residual: float  # physical units; 0 without LCPs
    pivots_median: float
    pivots_max: int
    max_lcp_size: int
    max_contacts: int
    retaken: int = 0  # steps taken again in parts after a failed LCP (``World(max_halvings=)``)
    stages: dict[str, int] = field(default_factory=dict)  # islands answered per stage of the solve chain
    backstop_fraction: float = 0.0  # of the islands solved, those answered by the last stage (``"dense"``)

    def to_dict(self) -> dict[str, Any]:
        return fields_dict(self)


@dataclass(frozen=True)
class TrajectoryData:
    """The arrays of a :class:`~lcpsim.trajectory.Trajectory` (described there) and what is
    computed from them alone; the trajectory adds its file and its page."""

    dt: float
    time: NDArray[np.float64]  # (T,) s, after each step
    positions: NDArray[np.float64]  # (T, B, 3) m
    orientations: NDArray[np.float64]  # (T, B, 4) (w, x, y, z)
    velocities: NDArray[np.float64]  # (T, B, 6) [v; ω]
    status: NDArray[np.str_]  # (T,) "no_contact" without an LCP
    pivots: NDArray[np.int64]
    residual: NDArray[np.float64]
    solver_residual: NDArray[np.float64]
    lcp_size: NDArray[np.int64]
    contacts: NDArray[np.int64]
    normal_impulse: NDArray[np.float64]
    friction_impulse: NDArray[np.float64]
    max_lambda: NDArray[np.float64]
    islands: NDArray[np.int64]
    max_island_size: NDArray[np.int64]
    parts: NDArray[np.int64]
    stage_counts: NDArray[np.int64]
    joint_force: NDArray[np.float64]  # (T, J, 3) N
    joint_torque: NDArray[np.float64]  # (T, J, 3) N·m
    joint_position: NDArray[np.float64]  # (T, J) rad or m
    joint_error: NDArray[np.float64]  # (T, J, 2) m, rad
    initial_positions: NDArray[np.float64]
    initial_orientations: NDArray[np.float64]
    initial_velocities: NDArray[np.float64]
    config: Mapping[str, Any] | None = None
    contact_log: ContactLog | None = None

    def __len__(self) -> int:
        return int(self.time.shape[0])

    @property
    def steps(self) -> int:
        return len(self)

    @property
    def bodies(self) -> int:
        return int(self.initial_positions.shape[0])

    @property
    def joints(self) -> int:
        return int(self.joint_position.shape[1])

    @property
    def linear_velocities(self) -> NDArray[np.float64]:
        """(T, B, 3)."""
        return self.velocities[:, :, :3]

    @property
    def angular_velocities(self) -> NDArray[np.float64]:
        """(T, B, 3)."""
        return self.velocities[:, :, 3:]

    @property
    def ok(self) -> NDArray[np.bool_]:
        """(T,) True where there was no LCP or it was solved."""
        return np.isin(self.status, ("solved", NO_CONTACT))

    @property
    def failures(self) -> int:
        """Steps whose LCP was not solved."""
        return int((~self.ok).sum())

    def displacement(self, body: int) -> NDArray[np.float64]:
        """Final minus initial position of ``body`` (m)."""
        if len(self) == 0:
            return np.zeros(3)
        return np.asarray(self.positions[-1, body] - self.initial_positions[body])

    def tilt(self, body: int) -> NDArray[np.float64]:
        """(T,) rotation angle of ``body`` from its initial orientation (rad)."""
        return np.asarray(quat_angle(self.orientations[:, body], self.initial_orientations[body]), dtype=float)

    def lcp_stats(self) -> LcpStats:
        """Counts, failures by status, max residual and pivot statistics over the LCP steps."""
        has = self.status != NO_CONTACT
        statuses, counts = np.unique(self.status[has], return_counts=True)
        piv = self.pivots[has]
        return LcpStats(
            steps=len(self),
            lcps=int(has.sum()),
            failures=self.failures,
            by_status={str(s): int(c) for s, c in zip(statuses, counts)},
            max_residual=float(self.residual[has].max(initial=0.0)),
            pivots_median=float(np.median(piv)) if piv.size else 0.0,
            pivots_max=int(piv.max(initial=0)),
            max_lcp_size=int(self.lcp_size.max(initial=0)),
            max_contacts=int(self.contacts.max(initial=0)),
            retaken=int((self.parts > 1).sum()),
            stages={name: int(c) for name, c in zip(STAGES, self.stage_counts.sum(axis=0))},
            backstop_fraction=float(self.stage_counts[:, -1].sum() / max(1, self.stage_counts.sum())),
        )
