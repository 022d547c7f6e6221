"""The critical friction-cone scale of the slope test: the scale below which
the cube is *held* (rests or tips) although it should slide.

The source note found ≈ 4e-3 at 45° + 1e-4 with its own (unstated) units. Here a
1 kg, 1 m cube at h = 1e-3 s: the slope test (:mod:`.slope`,
its outcome decided by the motion's onset, so independent of ``seconds``)
is run on a grid of one scale per decade from ``hi`` (1 = unscaled) down to
``lo``; the largest grid scale where the cube is held, just below one where
it slides, brackets the switch, and bisection in log scale narrows that
bracket to ``tol_decades``. ``bracket_outcomes`` are the outcomes at its
ends; ``critical_scale`` is the bracket's geometric mean — or ``None`` when
the cube is held already unscaled (``held_at_hi``), slides at every scale
down to ``lo`` (``slides_everywhere``), or a run at the bracket's end is
``undecided`` (``note`` = ``undecided``: the search stops there rather than
guess). Outcomes need not be monotone in s (a failed LCP can launch the cube
at any scale): every run is listed in ``outcomes``, and ``monotone`` says
whether the grid was.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from typing import Any, Mapping, Sequence

from . import slope
from ._common import envelope, merge_config
from .presets import parse_solver
from .document import Doc
from .experiment import Experiment, ReportContext, add_common_arguments, add_simulation_arguments, base_config, header
from .figure import OUTCOME_COLORS, pyplot, save, solver_label

__all__ = ["DEFAULTS", "run", "HELD"]

#: Outcomes that count as held.
HELD = ("rest", "tip")
#: What each run of the search reports (besides its scale and stage).
RUN_KEYS = ("outcome", "decided_at_s", "tip_onset_s", "first_excess_s", "window_outcome", "slide_distance_m",
            "tilt_deg", "lcp_failures", "first_failure_s", "energy_gain_J")

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
    "horizon_s": slope.DEFAULTS["horizon_s"],
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
    base = {k: cfg[k] for k in ("seed", "angle_deg", "mu", "solver", "seconds", "dt", "friction_dirs", "horizon_s")}
    runs: dict[float, dict[str, Any]] = {}

    def test(s: float, stage: str) -> str:
        """``held``, ``slide`` or ``undecided`` at scale s."""
        if s not in runs:
            r = slope.run({**base, "scale": "none" if s == 1.0 else s})
            runs[s] = {k: r[k] for k in RUN_KEYS} | {"scale": s, "stage": stage}
        o = runs[s]["outcome"]
        return "held" if o in HELD else o

    # One scale per decade, hi down to lo.
    decades = int(math.floor(math.log10(hi / lo) + 1e-9))
    grid = [hi * 10.0**-i for i in range(decades + 1)]
    if grid[-1] > lo * (1 + 1e-12):
        grid.append(lo)
    kinds = [test(s, "grid") for s in grid]
    decided = [k for k in kinds if k != "undecided"]
    monotone = all(not (a == "held" and b == "slide") for a, b in zip(decided, decided[1:]))
    bracket: list[float] | None = None
    note = ""
    if kinds[0] != "slide":
        note = "held_at_hi" if kinds[0] == "held" else "undecided"
    elif "held" not in kinds:
        note = "undecided" if "undecided" in kinds else "slides_everywhere"
    else:
        j = kinds.index("held")  # largest held grid scale
        b_lo, b_hi = grid[j], grid[j - 1]
        if kinds[j - 1] == "undecided":
            note = "undecided"
        while not note and math.log10(b_hi / b_lo) > tol:
            mid = math.sqrt(b_lo * b_hi)
            k = test(mid, "bisection")
            if k == "undecided":  # never guess: the bracket ends at the undecided run
                note, b_hi = "undecided", mid
            elif k == "held":
                b_lo = mid
            else:
                b_hi = mid
        bracket = [b_lo, b_hi]
    critical = math.sqrt(bracket[0] * bracket[1]) if bracket and not note else None
    out = envelope("critical-scale", cfg, t0)
    out.update(
        {
            "solver": parse_solver(cfg["solver"]).to_dict(),
            "critical_scale": critical,
            "bracket": bracket,
            "bracket_outcomes": [runs[b]["outcome"] for b in bracket] if bracket else None,
            "note": note,
            "monotone": monotone,
            "expected_slide_m": slope.expected_slide(float(cfg["angle_deg"]), float(cfg["mu"]), float(cfg["seconds"])),
            "outcomes": [runs[s] for s in sorted(runs, reverse=True)],
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--angle-deg", "--angle", dest="angle_deg", type=float, default=45.0001, help="slope angle (default: 45.0001)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--lo", type=float, default=1e-8, help="smallest scale searched (default: 1e-8)")
    p.add_argument("--hi", type=float, default=1.0, help="largest scale searched (default: 1, unscaled)")
    p.add_argument("--tol-decades", type=float, default=0.05, help="bracket width in decades (default: 0.05)")
    slope.add_horizon_argument(p)
    add_simulation_arguments(p)
    add_common_arguments(p)


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    return {
        **base_config(args), "angle_deg": args.angle_deg, "mu": args.mu, "lo": args.lo, "hi": args.hi,
        "tol_decades": args.tol_decades, "seconds": args.seconds, "dt": args.dt, "friction_dirs": args.friction_dirs,
        "horizon_s": args.horizon_s,
    }


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim critical-scale`` prints."""
    c = r["config"]
    lines = [
        header(r),
        f"slope {c['angle_deg']}°, μ = {c['mu']}, T = {c['seconds']:g} s; analytic slide {r['expected_slide_m']:.4e} m",
        f"critical scale: {critical_text(r, digits=4)}   (source note: 4e-3 at 45.0001°)",
        f"outcomes monotone in s: {r['monotone']}",
        "",
        f"{'s':>11} {'outcome':>9} {'decided':>8} {'tip from':>8} {'excess':>7} {'window':>7} {'slide (m)':>11} "
        f"{'rot (°)':>9} {'fails':>5}  stage",
    ]
    for o in r["outcomes"]:
        lines.append(
            f"{o['scale']:>11.4g} {o['outcome']:>9} {slope.when(o['decided_at_s']):>8} {slope.when(o['tip_onset_s']):>8} "
            f"{slope.when(o['first_excess_s']):>7} {o['window_outcome']:>7} {o['slide_distance_m']:>11.3e} "
            f"{o['tilt_deg']:>9.3g} {o['lcp_failures']:>5}  {o['stage']}"
        )
    return "\n".join(lines)


def plot_critical_scale(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Outcome of every slope run against the scale, one row per search; the
    critical scale as a vertical line, the source note's 4e-3 dotted."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.9 * len(results)))
    for i, r in enumerate(results):
        for o in r["outcomes"]:
            mk = "o" if o.get("stage") == "grid" else "|"
            ax.plot([o["scale"]], [i], mk, color=OUTCOME_COLORS.get(o["outcome"], "k"), ms=9)
        c = r.get("critical_scale")
        if c:
            ax.plot([c, c], [i - 0.35, i + 0.35], "k-", lw=2)
            ax.annotate(f"{c:.3g}", (c, i + 0.38), ha="center", fontsize=8)
        if r.get("bracket"):  # the outcomes at the bracket's ends
            lo_o, hi_o = r["bracket_outcomes"]
            ax.annotate(f"{lo_o} | {hi_o}", (math.sqrt(r["bracket"][0] * r["bracket"][1]), i - 0.4), ha="center",
                        va="top", fontsize=7)
    ax.axvline(4e-3, color="grey", ls=":", label="source note: 4e-3")
    for name, col in OUTCOME_COLORS.items():
        ax.plot([], [], "o", color=col, label=name)
    ax.set_xscale("log")
    ax.set_yticks(range(len(results)), [f"{r['config']['angle_deg']}°, {solver_label(r)}" for r in results])
    ax.set_ylim(-0.7, len(results) - 0.2)
    ax.set_xlabel("friction-cone scale s (1 = unscaled)")
    ax.set_title("Critical scale (outcomes decided at onset): below it the cube is held (rest/tip)")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    ax.grid(axis="x", alpha=0.3)
    return save(fig, path)


def critical_text(r: dict[str, Any], digits: int = 3) -> str:
    """The critical scale of a result with its bracket and the outcomes at the bracket's ends."""
    c, b = r["critical_scale"], r["bracket"]
    ends = (f"[{b[0]:.{digits}g} ({r['bracket_outcomes'][0]}), {b[1]:.{digits}g} ({r['bracket_outcomes'][1]})]"
            if b else "")
    if c is not None:
        return f"{c:.{digits}g}  {ends}" + ("" if r["monotone"] else " (outcomes not monotone in s)")
    lo, hi = r["config"]["lo"], r["config"]["hi"]
    return {
        "held_at_hi": f"none: held already at s = {hi:g}",
        "slides_everywhere": f"none: slides at every s ≥ {lo:g}",
        "undecided": f"none: undecided {ends}".rstrip(),
    }.get(r["note"], "—")


def report_run(ctx: ReportContext) -> dict[str, Any]:
    def runs() -> list[dict[str, Any]]:
        return [
            run({"seed": ctx.seed, "solver": solver, "angle_deg": angle, "seconds": ctx.seconds})
            for solver in ("classic", "robust")
            for angle in (45.0001, 45.2)
        ]

    return {"critical_scale": ctx.step("critical scales", runs)}


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    d.section(
        "Critical scale",
        """`lcpsim critical-scale --angle-deg A --mu 1 --solver classic`: one slope test per decade from s = 1 down to
        1e-8, then bisection in log s between the largest held scale and the slide above it. Each test's outcome is
        decided by the motion's onset (see the slope test), so the answer does not depend on the simulated time; the
        bracket is given with the outcomes at its ends.""",
    )
    crows = []
    for r in res["critical_scale"]:
        crows.append([r["solver"]["name"], f"{r['config']['angle_deg']:g}", critical_text(r),
                      ", ".join(f"{o['scale']:.2g}:{o['outcome']}" for o in r["outcomes"] if o["stage"] == "grid")])
    d.table(["solver", "angle (°)", "critical scale [bracket (outcome at its ends)]", "grid outcomes (s:outcome)"],
            crows)
    d.img(ctx.rel(figs["critical_scale"]), "critical scale")


EXPERIMENT = Experiment.of_module(
    __name__, "the cone scale below which the slope cube is held instead of sliding", plot=plot_critical_scale
)
