"""Shared pieces of the experiments: configs, the result envelope (the scale
parsers are :mod:`lcpsim.scale`'s, re-exported).

Every experiment is a plain function ``run(config) -> dict`` of a JSON-ready
config (a mapping; missing keys take the experiment's defaults, unknown keys
are an error) that carries an explicit ``seed``. The returned dict carries the
full config, the seed and the lcpsim version, so a result file says what made
it, and a Dask worker can run any case from its config alone.
"""

from __future__ import annotations

import platform
import time
from typing import Any, Mapping

import numpy as np

from .._json import jsonable
from ..scale import parse_cone_scale as parse_scale
from ..scale import parse_cone_scales as parse_scales
from ..scale import scale_label, scale_value
from .presets import Solver, parse_solver

__all__ = [
    "G",
    "parse_scale",
    "scale_value",
    "scale_label",
    "parse_scales",
    "merge_config",
    "envelope",
    "jsonable",
]

#: Gravity (m/s²), the simulator's convention.
G = 9.81


def merge_config(name: str, defaults: Mapping[str, Any], config: Mapping[str, Any] | None) -> dict[str, Any]:
    """``defaults`` updated by ``config``; an unknown key is a ValueError naming it."""
    cfg = dict(defaults)
    for k, v in (config or {}).items():
        if k not in defaults:
            raise ValueError(f"{name}: unknown config key {k!r} (valid: {', '.join(sorted(defaults))})")
        cfg[k] = v
    return cfg


def envelope(experiment: str, config: Mapping[str, Any], started: float) -> dict[str, Any]:
    """The header every result carries: experiment, config, seed, version, timing."""
    from .. import __version__

    return {
        "experiment": experiment,
        "lcpsim_version": __version__,
        "seed": config.get("seed"),
        "config": jsonable(dict(config)),
        "wall_time_s": time.perf_counter() - started,
        "python": platform.python_version(),
    }


def body_energy(traj: Any, world: Any, body: int) -> np.ndarray:
    """(T + 1,) kinetic + potential energy (J) of one body before the first
    step and after every step: ½ m|v|² + ½ ωᵀ R I Rᵀ ω − m g·x."""
    b = world.body(body)
    m = float(b.mass)
    inertia = np.asarray(b.inertia, dtype=float)
    gvec = np.asarray(world.params["gravity"], dtype=float)
    pos = np.concatenate([traj.initial_positions[None, body], traj.positions[:, body]])
    quat = np.concatenate([traj.initial_orientations[None, body], traj.orientations[:, body]])
    vel = np.concatenate([traj.initial_velocities[None, body], traj.velocities[:, body]])
    w, x, y, z = (quat / np.linalg.norm(quat, axis=1, keepdims=True)).T
    R = np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=1,
    )
    om_b = np.einsum("tji,tj->ti", R, vel[:, 3:])  # body-frame ω = Rᵀ ω
    kin = 0.5 * m * (vel[:, :3] ** 2).sum(axis=1) + 0.5 * np.einsum("ti,ij,tj->t", om_b, inertia, om_b)
    return np.asarray(kin - m * pos @ gvec)


def downsample(n: int, max_points: int = 250) -> np.ndarray:
    """Indices of at most ``max_points`` evenly spread samples of ``n`` (first and last kept)."""
    if n <= max_points:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, max_points).round().astype(np.int64))


def begin_run(
    experiment: str, defaults: Mapping[str, Any], config: Mapping[str, Any] | None
) -> tuple[float, dict[str, Any], Any, Solver, float, int]:
    """The start of a timed cube run: ``(t0, cfg, scale, solver, dt, steps)`` with ``cfg``
    the merged configuration and ``steps`` its ``seconds`` at ``dt`` (a ValueError below one)."""
    t0 = time.perf_counter()
    cfg = merge_config(experiment, defaults, config)
    scale = parse_scale(cfg["scale"])
    solver = parse_solver(cfg["solver"])
    dt = float(cfg["dt"])
    steps = int(round(float(cfg["seconds"]) / dt))
    if steps < 1:
        raise ValueError(f"{experiment}: seconds must be at least one time step, got {cfg['seconds']}")
    return t0, cfg, scale, solver, dt, steps
