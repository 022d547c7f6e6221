"""Trajectories: the state after every step of a run and each step's LCP
outcome (:class:`Trajectory`), their LCP statistics (:class:`LcpStats`) and,
when the run recorded them, every step's contacts (:class:`ContactLog`).

``World.run`` returns a :class:`Trajectory`; ``World.run(steps, record_contacts=True)``
also keeps each step's contact points, normals and impulses. A trajectory
saves to HDF5 and loads back (:meth:`Trajectory.save`, :meth:`Trajectory.load`,
format in :mod:`lcpsim.io.trajectory_file`) and draws itself as one
self-contained 3-D page (:meth:`Trajectory.to_html`, :mod:`lcpsim.viewer`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from .trajectory_data import NO_CONTACT, STAGES, STATUS_NAMES, ContactLog, LcpStats, quat_angle

__all__ = ["Trajectory", "LcpStats", "ContactLog", "NO_CONTACT", "STATUS_NAMES", "STAGES", "quat_angle"]


@dataclass(frozen=True)
class Trajectory:
    """The state after every step of a run, and each step's LCP outcome.

    ``T`` steps, ``B`` bodies (static ones included, in body order): ``time`` (T,) the time after
    each step; ``positions`` (T, B, 3); ``orientations`` (T, B, 4) as (w, x, y, z); ``velocities``
    (T, B, 6) as ``[v; ω]``. Per step: ``status`` (T,) strings (``"no_contact"`` without an LCP),
    ``pivots``, ``residual`` (physical units), ``solver_residual``, ``lcp_size``, ``contacts``,
    ``normal_impulse`` (Σ fn, N·s), ``friction_impulse`` (T, 3) (Σ over contacts of the friction
    impulse on body A), ``max_lambda`` (largest physical λ, m/s), ``islands`` and
    ``max_island_size`` (largest island LCP), ``parts`` (1, or more where a failed LCP had the
    step taken again in halves: ``World(max_halvings=)``; the step is solved only if every part
    was, ``pivots`` counts every attempt, the other per-step figures are the last part's),
    ``stage_counts`` (T, 4) the islands answered by each stage of the solve chain, columns in the
    order of :data:`STAGES` (the last part's; zeros in files written before it was recorded).
    ``initial_*`` hold the state before the first step.
    ``config`` is the world's :meth:`World.config` when the run started (its bodies' shapes, the
    parameters, the scene); ``contact_log`` every step's contacts when the run recorded them
    (``World.run(..., record_contacts=True)``), else None.
    """

    dt: float
    time: NDArray[np.float64]
    positions: NDArray[np.float64]
    orientations: NDArray[np.float64]
    velocities: NDArray[np.float64]
    status: NDArray[np.str_]
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

    def save(self, path: str | os.PathLike[str]) -> str:
        """Writes this trajectory to an HDF5 file (:mod:`lcpsim.io.trajectory_file`); returns the path."""
        from .io.trajectory_file import save_trajectory

        return save_trajectory(path, self)

    @classmethod
    def load(cls, path: str | os.PathLike[str], probe: bool = True) -> "Trajectory":
        """Reads a trajectory written by :meth:`save` (a ``TrajectoryFileError`` if it is not one;
        ``probe``: :func:`lcpsim.io.trajectory_file.read_trajectory`)."""
        from .io.trajectory_file import read_trajectory

        return cls(**read_trajectory(path, probe=probe))

    def to_html(self, path: str | os.PathLike[str], **options: Any) -> str:
        """Writes the self-contained 3-D viewer page of this run (:func:`lcpsim.viewer.write_html`:
        ``title``, ``body``, ``direction``, ``max_bytes``); returns the path."""
        from .viewer import write_html

        return write_html(self, path, **options)

    @classmethod
    def _from_parts(
        cls,
        dt: float,
        parts: Sequence[Mapping[str, Any]],
        initial: Mapping[str, Any],
        config: Mapping[str, Any] | None = None,
        contact_log: ContactLog | None = None,
    ) -> "Trajectory":
        def cat(key: str) -> NDArray[Any]:
            return parts[0][key] if len(parts) == 1 else np.concatenate([p[key] for p in parts])

        return cls(
            dt=dt,
            time=cat("time"),
            positions=cat("position"),
            orientations=cat("orientation"),
            velocities=np.concatenate([cat("velocity"), cat("angular_velocity")], axis=2),
            status=STATUS_NAMES[cat("status").astype(np.int64) + 1],
            pivots=cat("pivots"),
            residual=cat("residual"),
            solver_residual=cat("solver_residual"),
            lcp_size=cat("lcp_size"),
            contacts=cat("contacts"),
            normal_impulse=cat("normal_impulse"),
            friction_impulse=cat("friction_impulse"),
            max_lambda=cat("max_lambda"),
            islands=cat("islands"),
            max_island_size=cat("max_island_size"),
            parts=cat("parts"),
            stage_counts=cat("stage_counts"),
            initial_positions=initial["position"],
            initial_orientations=initial["orientation"],
            initial_velocities=np.concatenate([initial["velocity"], initial["angular_velocity"]], axis=1),
            config=config,
            contact_log=contact_log,
        )
