"""The seed's pushed cube: a 1 kg unit cube at rest on level ground, μ = 1,
pushed horizontally at its centre of mass.

It must stay iff F ≤ μ m g (9.81 N), with a friction force of exactly F;
above that it slides with a = (F − μ m g)/m (DESIGN §3). The seed pushed
with 9.79 N: the cube stayed, λ ≈ 1e-19 (far below its user zero) and the
normal impulses 0, 1e-5, 0.004895, 0.004905 N·s showed the load moving onto
the leading edge (the push at the centre of mass tips the contact pressure
forward: a moment F·(size/2) about the base).

Outcome: ``tip`` if the cube rotated more than 5°, else ``slide`` if it
moved along the push at least half of the analytic ½·(F/m − μg)·T² (or more
than 1e-6 m when none is expected), else ``rest``. ``friction_force_N`` is
the friction impulse of the last step along −push divided by h;
``lambda_max`` the largest λ (physical units, m/s) over the run;
``normal_impulses`` the last step's fn per contact with each contact's
position along the push relative to the centre (``contact_offsets_m``).
"""

from __future__ import annotations

import time
from typing import Any, Mapping

import numpy as np

from ..scenes import pushed_cube
from ._common import G, downsample, envelope, merge_config, parse_scale, scale_label, scale_value
from .presets import parse_solver
from .slope import classify

__all__ = ["DEFAULTS", "run", "SEED_VALUES"]

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "force": 9.79,
    "mu": 1.0,
    "scale": "none",
    "solver": "robust",
    "seconds": 1.0,
    "dt": 1e-3,
    "friction_dirs": 8,
    "size": 1.0,
    "mass": 1.0,
    "trace": False,
}

#: The seed note's pushed cube (9.79 N): λ and the four normal impulses (N·s).
SEED_VALUES: dict[str, Any] = {
    "outcome": "rest",
    "lambda_max": 2.1616814368153648e-19,
    "normal_impulses": [0.0, 1.000000000002777392e-05, 0.00489499999999991782, 0.0049050000000000022402],
    "friction_impulse_Ns": 0.004895 + 0.004895,
}


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the push; returns ``{"outcome", "friction_force_N", "lambda_max", …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("push", DEFAULTS, config)
    scale = parse_scale(cfg["scale"])
    solver = parse_solver(cfg["solver"])
    dt = float(cfg["dt"])
    steps = int(round(float(cfg["seconds"]) / dt))
    if steps < 1:
        raise ValueError(f"push: seconds must be at least one time step, got {cfg['seconds']}")
    F, mu, m = float(cfg["force"]), float(cfg["mu"]), float(cfg["mass"])
    scene = pushed_cube(
        F, mu, size=float(cfg["size"]), mass=m, dt=dt, friction_dirs=int(cfg["friction_dirs"]),
        cone_scale=scale, **solver.world_kwargs(),
    )
    traj = scene.world.run(steps)
    b = scene.body
    assert scene.direction is not None
    d = scene.direction
    along = (traj.positions[:, b] - traj.initial_positions[b]) @ d
    tilt = np.degrees(traj.tilt(b))
    T = steps * dt
    a = F / m - mu * G
    expected = 0.5 * a * T * T if a > 0 else 0.0
    outcome = classify(float(along[-1]), expected, float(np.nanmax(tilt)))
    friction = -(traj.friction_impulse @ d) / dt  # N, along −push
    rec = scene.world.last_record
    has = traj.status != "no_contact"
    if rec.contacts:
        offsets = (rec.points - traj.positions[-1, b]) @ d
        order = np.argsort(offsets, kind="stable")
        fn = rec.fn[order]
        lam = rec.lam[order]
        offsets = offsets[order]
    else:
        fn = lam = offsets = np.zeros(0)
    out = envelope("push", cfg, t0)
    out.update(
        {
            "solver": solver.to_dict(),
            "scale": scale_label(scale),
            "s": scale_value(scale, dt),
            "seconds": T,
            "outcome": outcome,
            "expected_outcome": "slide" if a > 0 else "rest",
            "friction_force_N": float(friction[-1]),
            "friction_force_mean_N": float(np.mean(friction)),
            "expected_friction_N": min(F, mu * m * G),
            "lambda_max": float(np.nanmax(traj.max_lambda[has], initial=0.0)),
            "displacement_m": float(along[-1]),
            "expected_displacement_m": expected,
            "tilt_deg": float(np.nanmax(tilt)),
            "normal_impulses": fn.tolist(),
            "lambdas": lam.tolist(),
            "contact_offsets_m": offsets.tolist(),
            "normal_impulse_sum": float(fn.sum()),
            "lcps": int(has.sum()),
            "lcp_failures": int((~traj.ok).sum()),
            "seed_values": SEED_VALUES,
        }
    )
    if cfg["trace"]:
        i = downsample(len(traj))
        out["trace"] = {"time": traj.time[i].tolist(), "displacement_m": along[i].tolist(), "friction_N": friction[i].tolist()}
    out["wall_time_s"] = time.perf_counter() - t0
    return out
