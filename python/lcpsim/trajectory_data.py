"""The plain data of trajectories, below :mod:`lcpsim.trajectory`, the trajectory
file (:mod:`lcpsim.io.trajectory_file`) and the viewer (:mod:`lcpsim.viewer`),
which all import it: the step statuses (:data:`NO_CONTACT`, :data:`STATUS_NAMES`),
the stages of the solve chain (:data:`STAGES`), every step's contacts
(:class:`ContactLog`), a run's LCP statistics (:class:`LcpStats`) and what the file
writer and the viewer read of a trajectory (:class:`TrajectoryView`).
:mod:`lcpsim.trajectory` re-exports all of them but :class:`TrajectoryView`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._json import fields_dict
from .lcp import STATUSES

__all__ = ["ContactLog", "LcpStats", "NO_CONTACT", "STATUS_NAMES", "STAGES", "TrajectoryView", "quat_angle"]

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


class TrajectoryView(Protocol):
    """What the trajectory file writer and the viewer read of a
    :class:`~lcpsim.trajectory.Trajectory` (the writer reads the other per-step
    arrays by name too)."""

    @property
    def dt(self) -> float: ...
    @property
    def time(self) -> NDArray[np.float64]: ...
    @property
    def positions(self) -> NDArray[np.float64]: ...
    @property
    def orientations(self) -> NDArray[np.float64]: ...
    @property
    def status(self) -> NDArray[np.str_]: ...
    @property
    def pivots(self) -> NDArray[np.int64]: ...
    @property
    def residual(self) -> NDArray[np.float64]: ...
    @property
    def initial_positions(self) -> NDArray[np.float64]: ...
    @property
    def initial_orientations(self) -> NDArray[np.float64]: ...
    @property
    def config(self) -> Mapping[str, Any] | None: ...
    @property
    def contact_log(self) -> ContactLog | None: ...
    @property
    def bodies(self) -> int: ...
    def __len__(self) -> int: ...
    def lcp_stats(self) -> LcpStats: ...
