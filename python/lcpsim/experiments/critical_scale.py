"""The critical friction-cone scale of the slope test: the scale below which
the cube is *held* (rests or tips) although it should slide.

The seed found ≈ 4e-3 at 45° + 1e-4 with its own (unstated) units. Here a
1 kg, 1 m cube at h = 1e-3 s (DESIGN §2): the slope test (:mod:`.slope`) is
run on a grid of one scale per decade from ``hi`` (1 = unscaled) down to
``lo``; the largest grid scale where the cube is held, just below one where
it slides, brackets the switch, and bisection in log scale narrows that
bracket to ``tol_decades``. ``critical_scale`` is the bracket's geometric
mean — or ``None`` when the cube is held already unscaled (``held_at_hi``)
or slides at every scale down to ``lo`` (``slides_everywhere``). Outcomes
need not be monotone in s (a failed LCP can launch the cube at any scale):
every run is listed in ``outcomes``, and ``monotone`` says whether the grid
was.
"""

from __future__ import annotations

import math
import time
from typing import Any, Mapping

from . import slope
from ._common import envelope, merge_config
from .presets import parse_solver

__all__ = ["DEFAULTS", "run", "HELD"]

#: Outcomes that count as held.
HELD = ("rest", "tip")

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "angle_deg": 45.0001,
    "mu": 1.0,
    "solver": "robust",
    "seconds": 1.0,
    "dt": 1e-3,
    "friction_dirs": 8,
    "lo": 1e-8,
    "hi": 1.0,
    "tol_decades": 0.05,
}


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the search; returns ``{"critical_scale", "bracket": [lo, hi], "outcomes": […], …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("critical-scale", DEFAULTS, config)
    lo, hi = float(cfg["lo"]), float(cfg["hi"])
    if not (0 < lo < hi <= 1.0):
        raise ValueError(f"critical-scale: need 0 < lo < hi <= 1, got lo={lo}, hi={hi}")
    tol = float(cfg["tol_decades"])
    if not tol > 0:
        raise ValueError(f"critical-scale: tol_decades must be > 0, got {tol}")
    base = {k: cfg[k] for k in ("seed", "angle_deg", "mu", "solver", "seconds", "dt", "friction_dirs")}
    runs: dict[float, dict[str, Any]] = {}

    def test(s: float) -> bool:
        if s not in runs:
            r = slope.run({**base, "scale": "none" if s == 1.0 else s})
            runs[s] = {
                "scale": s,
                "outcome": r["outcome"],
                "slide_distance_m": r["slide_distance_m"],
                "tilt_deg": r["tilt_deg"],
                "lcp_failures": r["lcp_failures"],
                "first_failure_s": r["first_failure_s"],
                "energy_gain_J": r["energy_gain_J"],
                "stage": "grid" if not bisecting else "bisection",
            }
        return runs[s]["outcome"] in HELD

    bisecting = False
    # One scale per decade, hi down to lo.
    decades = int(math.floor(math.log10(hi / lo) + 1e-9))
    grid = [hi * 10.0**-i for i in range(decades + 1)]
    if grid[-1] > lo * (1 + 1e-12):
        grid.append(lo)
    held = [test(s) for s in grid]
    monotone = all(not held[i] or held[i + 1] for i in range(len(held) - 1))
    bracket: list[float] | None = None
    note = ""
    if held[0]:
        note = "held_at_hi"
    elif not any(held):
        note = "slides_everywhere"
    else:
        j = held.index(True)  # largest held grid scale; grid[j-1] slides
        b_lo, b_hi = grid[j], grid[j - 1]
        bisecting = True
        while math.log10(b_hi / b_lo) > tol:
            mid = math.sqrt(b_lo * b_hi)
            if test(mid):
                b_lo = mid
            else:
                b_hi = mid
        bracket = [b_lo, b_hi]
    critical = math.sqrt(bracket[0] * bracket[1]) if bracket else None
    out = envelope("critical-scale", cfg, t0)
    out.update(
        {
            "solver": parse_solver(cfg["solver"]).to_dict(),
            "critical_scale": critical,
            "bracket": bracket,
            "note": note,
            "monotone": monotone,
            "expected_slide_m": slope.expected_slide(float(cfg["angle_deg"]), float(cfg["mu"]), float(cfg["seconds"])),
            "outcomes": [runs[s] for s in sorted(runs, reverse=True)],
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out
