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
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from .trajectory_data import NO_CONTACT, STAGES, STATUS_NAMES, ContactLog, LcpStats, TrajectoryData, quat_angle

__all__ = ["Trajectory", "LcpStats", "ContactLog", "NO_CONTACT", "STATUS_NAMES", "STAGES", "quat_angle"]

# Per-step fields kept under the compiled step's own name.
_PER_STEP_AS_RECORDED = (
    "time", "pivots", "residual", "solver_residual", "lcp_size", "contacts", "normal_impulse",
    "friction_impulse", "max_lambda", "islands", "max_island_size", "parts", "stage_counts",
    "joint_force", "joint_torque", "joint_position", "joint_error",
)


class Trajectory(TrajectoryData):
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
    ``J`` joints (``World.add_hinge`` …, in joint order): ``joint_force`` and ``joint_torque``
    (T, J, 3) what each joint's side A exerted on side B over the step (N, N·m about the anchor;
    the mean over the step, as ``StepRecord.joint_force``), ``joint_position`` (T, J) each joint's
    coordinate after the step (``World.joint_position``: a hinge's angle in rad, a slider's
    displacement in m) and ``joint_error`` (T, J, 2) its position error (``World.joint_error``:
    largest linear m, angular rad); J = 0 in files written before they were recorded.
    ``initial_*`` hold the state before the first step.
    ``config`` is the world's :meth:`World.config` when the run started (its bodies' shapes, the
    parameters, the scene); ``contact_log`` every step's contacts when the run recorded them
    (``World.run(..., record_contacts=True)``), else None.
    """

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
            positions=cat("position"),
            orientations=cat("orientation"),
            velocities=np.concatenate([cat("velocity"), cat("angular_velocity")], axis=2),
            status=STATUS_NAMES[cat("status").astype(np.int64) + 1],
            initial_positions=initial["position"],
            initial_orientations=initial["orientation"],
            initial_velocities=np.concatenate([initial["velocity"], initial["angular_velocity"]], axis=1),
            config=config,
            contact_log=contact_log,
            **{name: cat(name) for name in _PER_STEP_AS_RECORDED},
        )
