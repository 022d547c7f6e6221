"""The source note's slope test: a μ = 1 unit cube released at rest on a slope just
steeper than 45°.

With tan θ > μ the cube must slide, with a = g (sin θ − μ cos θ), and since
μ = 1 ≤ 1 it must not tip: sliding caps friction at μN = N, which puts the
resultant of the normal forces exactly on the downhill edge. Any
extra friction — e.g. a cone row accepted at ``μ fn − Eᵀ fd ≥ −zero_tol/s`` —
holds the cube, and it rests or tips.

Outcome: decided by how the motion starts, not by a window
(:mod:`.onset`): ``tip`` once the cube unambiguously pivots about its
downhill edge, ``slide`` once it follows ½·g·(sin θ − μ cos θ)·t² with its
tilt at round-off, ``rest`` once it stands still on its face, each confirmed
over 0.02 s of solved steps; looked for over ``max(seconds, horizon_s)``
and ``undecided`` if none is confirmed by then. ``decided_at_s``,
``tip_onset_s`` and ``first_excess_s`` (the first step whose friction along
the downhill line exceeds μ·Σfn: the source note's cone slack in use) say when.
With μ = 1 on a slope steeper than 45° the sliding state (the load exactly
on the downhill edge) is unstable, so a long enough window shows any cube
tipping; the verdict of the old window classification (:func:`classify`:
tip if rotated > 5°, else slide if it moved ≥ half the analytic distance)
is kept as ``window_outcome`` for comparison.

Positions are float64 and the displacement is projected on the slope's
downhill direction, so micrometres are resolved (at 45.0001° the analytic
slide in 1 s is 12.1 µm). Besides the outcome the result reports the LCP
failures, when the first one happened, the largest energy gain — a failed
solve whose last iterate is applied can launch the cube — and the friction
beyond the cone in solved steps, ``|Σ friction·d| − μ Σ fn`` (N·s, > 0 is
impossible for an exact solution): ``cone_excess_max_Ns``,
``cone_excess_steps`` and ``held_steps_before_failure`` (solved steps with
excess friction before the first failure), the direct trace of the source note's
tolerance artifact.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from typing import Any, Mapping, Sequence

import numpy as np

from ..scenes import Scene, cube_on_slope
from ._common import G, begin_run, body_energy, downsample, envelope, parse_scale, scale_label, scale_value
from .presets import parse_solver
from .document import Doc
from .experiment import (
    Experiment, ReportContext, add_common_arguments, add_simulation_arguments, base_config, header, scale_argument,
)
from .figure import label_axes, save, solver_label, traced, two_panels
from .onset import OnsetOptions, cone_excess, observe, precise_tilt

__all__ = ["DEFAULTS", "run", "classify", "expected_slide", "TIP_DEG"]

#: Rotation (degrees) beyond which a cube counts as tipped.
TIP_DEG = 5.0

#: Config of a single cube simulated on its own (slope and push tests).
CUBE_DEFAULTS: dict[str, Any] = {
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

DEFAULTS: dict[str, Any] = {"seed": 0, "angle_deg": 45.0001, **CUBE_DEFAULTS, "horizon_s": OnsetOptions.horizon_s}


def expected_slide(angle_deg: float, mu: float, seconds: float, g: float = G) -> float:
    """½·g·(sin θ − μ cos θ)·T² of a sliding, non-tipping block; 0 when tan θ ≤ μ."""
    th = math.radians(angle_deg)
    a = g * (math.sin(th) - mu * math.cos(th))
    return 0.5 * a * seconds * seconds if a > 0 else 0.0


def classify(slide_m: float, expected_m: float, max_tilt_deg: float) -> str:
    """The window verdict of a run: ``tip`` if rotated more than :data:`TIP_DEG`, else ``slide`` if it
    moved at least half of a positive ``expected_m`` (more than 1e-6 m where none is expected), else
    ``rest``. The push test's outcome; the slope test's is decided at onset (see the module docs)."""
    if not math.isfinite(max_tilt_deg) or max_tilt_deg > TIP_DEG:
        return "tip"
    if not math.isfinite(slide_m):
        return "tip"
    if expected_m > 0:
        return "slide" if slide_m >= 0.5 * expected_m else "rest"
    return "slide" if slide_m > 1e-6 else "rest"


def make_scene(config: Mapping[str, Any]) -> Scene:
    """The cube on its slope, ready to run, as a slope config (``DEFAULTS`` merged) describes it."""
    return cube_on_slope(
        float(config["angle_deg"]),
        float(config["mu"]),
        size=float(config["size"]),
        mass=float(config["mass"]),
        dt=float(config["dt"]),
        friction_dirs=int(config["friction_dirs"]),
        cone_scale=parse_scale(config["scale"]),
        **parse_solver(config["solver"]).world_kwargs(),
    )


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs one slope test; returns ``{"outcome", "slide_distance_m", "expected_slide_m", "tilt_deg", "lcp_failures", …}``."""
    t0, cfg, scale, solver, dt, steps = begin_run("slope", DEFAULTS, config)
    seconds = float(cfg["seconds"])
    scene = make_scene(cfg)
    angle, mu = float(cfg["angle_deg"]), float(cfg["mu"])
    horizon = float(cfg["horizon_s"])
    if not (math.isfinite(horizon) and horizon >= 0):
        raise ValueError(f"slope: horizon_s must be >= 0, got {cfg['horizon_s']!r}")
    b = scene.body
    assert scene.direction is not None
    onset = observe(scene.world, b, scene.direction, scene.normal, angle, mu, steps, OnsetOptions(horizon_s=horizon))
    traj = scene.world.run(steps)
    along = (traj.positions[:, b] - traj.initial_positions[b]) @ scene.direction
    tilt = np.degrees(precise_tilt(traj.orientations[:, b], traj.initial_orientations[b]))
    T = steps * dt
    expected = expected_slide(angle, mu, T)
    slide = float(along[-1])
    max_tilt = float(np.nanmax(tilt)) if tilt.size else 0.0
    energy = body_energy(traj, scene.world, b)
    # Friction beyond the cone along the downhill line (physical units): > 0 is
    # impossible for an exact solution; the source note's artifact shows up here.
    friction_d = traj.friction_impulse @ scene.direction
    excess = np.abs(friction_d) - mu * traj.normal_impulse
    solved = traj.status == "solved"
    beyond = solved & cone_excess(friction_d, traj.normal_impulse, mu, OnsetOptions.excess_rtol)
    before = np.arange(len(traj)) < (int(np.nonzero(~traj.ok)[0][0]) if (~traj.ok).any() else len(traj))
    held = beyond & before
    firsts = [float(traj.time[np.argmax(beyond)])] if beyond.any() else []
    if onset.first_excess_s is not None:
        firsts.append(onset.first_excess_s)
    has = traj.status != "no_contact"
    failed = np.nonzero(~traj.ok)[0]
    statuses, counts = np.unique(traj.status[has], return_counts=True)
    result: dict[str, Any] = envelope("slope", cfg, t0)
    result.update(
        {
            "solver": solver.to_dict(),
            "scale": scale_label(scale),
            "s": scale_value(scale, dt),
            "seconds": T,
            "steps": steps,
            "outcome": onset.outcome,
            "decided_at_s": onset.decided_at_s,
            "tip_onset_s": onset.tip_onset_s,
            "first_excess_s": min(firsts) if firsts else None,
            "onset_probed_s": onset.probed_s,
            "window_outcome": classify(slide, expected, max_tilt),
            "slide_distance_m": slide,
            "expected_slide_m": expected,
            "slide_rel_error": (slide / expected - 1.0) if expected > 0 else None,
            "tilt_deg": max_tilt,
            "final_tilt_deg": float(tilt[-1]),
            "lcps": int(has.sum()),
            "lcp_failures": int(failed.size),
            "by_status": {str(s): int(c) for s, c in zip(statuses, counts)},
            "first_failure_s": float(traj.time[failed[0]]) if failed.size else None,
            "slide_at_first_failure_m": float(along[failed[0]]) if failed.size else None,
            "tilt_at_first_failure_deg": float(tilt[failed[0]]) if failed.size else None,
            "energy_gain_J": float(np.nanmax(energy - energy[0])),
            "cone_excess_max_Ns": float(np.nanmax(np.where(solved, excess, -np.inf), initial=0.0)),
            "cone_excess_steps": int(beyond.sum()),
            "held_steps_before_failure": int(held.sum()),
            "max_residual": float(np.nanmax(traj.residual[has], initial=0.0)),
            "max_speed": float(np.nanmax(np.linalg.norm(traj.velocities[:, b, :3], axis=1), initial=0.0)),
        }
    )
    if cfg["trace"]:
        i = downsample(len(traj))
        result["trace"] = {
            "time": traj.time[i].tolist(),
            "slide_m": along[i].tolist(),
            "tilt_deg": tilt[i].tolist(),
            "expected_m": [expected_slide(angle, mu, t) for t in traj.time[i]],
        }
    result["wall_time_s"] = time.perf_counter() - t0
    return result


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--angle-deg", "--angle", dest="angle_deg", type=float, default=45.0001, help="slope angle (default: 45.0001)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--scale", type=scale_argument, default="none", metavar="none|dt|S", help="cone scale (default: none)")
    add_horizon_argument(p)
    add_simulation_arguments(p)
    add_common_arguments(p)


def add_horizon_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--horizon", dest="horizon_s", type=float, default=OnsetOptions.horizon_s, metavar="SECONDS",
                   help="look for the motion's onset up to max(--seconds, this) "
                        f"(default: {OnsetOptions.horizon_s:g}); else the outcome is undecided")


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    return {
        **base_config(args), "angle_deg": args.angle_deg, "mu": args.mu, "scale": args.scale,
        "seconds": args.seconds, "dt": args.dt, "friction_dirs": args.friction_dirs, "trace": bool(args.plot),
        "horizon_s": args.horizon_s,
    }


def when(t: float | None) -> str:
    """A time in s for a table cell or summary line, "—" for None."""
    return "—" if t is None else f"{t:.3f}"


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim slope`` prints."""
    c = r["config"]
    lines = [
        header(r),
        f"cube 1 m, {c['mass']} kg on {c['angle_deg']}°, μ = {c['mu']}, s = {r['scale']}, h = {c['dt']:g} s, T = {r['seconds']:g} s",
        f"outcome:   {r['outcome']}  (decided at t = {when(r['decided_at_s'])} s, tipping from {when(r['tip_onset_s'])} s, "
        f"first excess friction at {when(r['first_excess_s'])} s; window verdict: {r['window_outcome']})",
        f"slide:     {r['slide_distance_m']:.6e} m  (analytic slide: {r['expected_slide_m']:.6e} m)",
        f"rotation:  {r['tilt_deg']:.4g}° max, {r['final_tilt_deg']:.4g}° at the end",
        f"LCPs:      {r['lcps']}, failures {r['lcp_failures']}"
        + (f" (first at t = {r['first_failure_s']:.3f} s)" if r["first_failure_s"] is not None else ""),
        f"cone:      friction beyond μN in {r['cone_excess_steps']} solved steps (max {r['cone_excess_max_Ns']:.3e} N·s)",
        f"energy:    largest gain {r['energy_gain_J']:.3e} J",
    ]
    return "\n".join(lines)


def plot_slope(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Down-slope distance (symlog) and tilt against time for slope runs with a trace."""
    fig, ax1, ax2 = two_panels(10, 4.2)
    plotted_expected: set[tuple[float, float]] = set()
    for i, r, tr in traced(results):
        cfg = r["config"]
        lab = f"{solver_label(r)}, s = {r['scale']}, {cfg['angle_deg']}° → {r['outcome']}"
        ax1.plot(tr["time"], tr["slide_m"], color=f"C{i % 10}", label=lab)
        if r.get("tip_onset_s") is not None:  # where the tipping began
            ax2.axvline(r["tip_onset_s"], color=f"C{i % 10}", lw=0.8, ls=":")
        key = (float(cfg["angle_deg"]), float(cfg["mu"]))
        if key not in plotted_expected:
            plotted_expected.add(key)
            ax1.plot(tr["time"], tr["expected_m"], "k--", lw=1, label=f"analytic slide, {key[0]}°")
        ax2.plot(tr["time"], np.maximum(tr["tilt_deg"], 1e-14), color=f"C{i % 10}", ls="-" if i % 2 else "--", label=lab)
    from matplotlib.ticker import SymmetricalLogLocator

    ax1.set_yscale("symlog", linthresh=1e-6)
    ax1.set_ylim(-10.0, 10.0)
    ax1.yaxis.set_major_locator(SymmetricalLogLocator(base=100, linthresh=1e-6))
    label_axes(ax1, "time (s)", "down-slope displacement (m, clipped at ±10)", title="Slope test: displacement",
               legend=7)
    ax2.set_yscale("log")
    ax2.set_ylim(1e-14, 400)
    ax2.axhline(math.degrees(OnsetOptions.tilt_tol_rad), color="k", lw=0.8, ls=":", label="round-off limit of tilt")
    label_axes(ax2, "time (s)", "rotation (deg, floor 1e-14)", title="Slope test: rotation (dotted: onset of tipping)")
    return save(fig, path)


#: The report's slope runs: both presets at 45.0001° and 45.2°, at these scales.
REPORT_SCALES = ["none", 1e-3, 1e-6]
REPORT_ANGLES = (45.0001, 45.2)


def report_run(ctx: ReportContext) -> dict[str, Any]:
    def runs() -> list[dict[str, Any]]:
        return [
            run({"seed": ctx.seed, "solver": solver, "angle_deg": angle, "scale": sc, "seconds": ctx.seconds,
                 "trace": True})
            for solver in ("classic", "robust")
            for angle in REPORT_ANGLES
            for sc in REPORT_SCALES
        ]

    return {"slope": ctx.step("slope tests", runs)}


def report_figures(res: dict[str, Any], ctx: ReportContext) -> dict[str, str]:
    figs = {}
    for angle in REPORT_ANGLES:
        tag = str(angle).replace(".", "_")
        figs[f"slope_{tag}"] = plot_slope(
            [r for r in res["slope"] if r["config"]["angle_deg"] == angle], ctx.path(f"slope_{tag}.png")
        )
    return figs


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    d.section(
        "Slope test",
        """`lcpsim slope --angle-deg A --mu 1 --scale S --solver P --seconds T`. A μ = 1 cube on a slope just steeper
        than 45° must slide with ½·g·(sin θ − μ cos θ)·T² and not tip. The outcome is decided by the motion's onset,
        whatever T: tip once the cube pivots about its downhill edge (tilt beyond round-off and growing, all normal
        impulse on the downhill points, ω about that edge), slide once it follows the analytic distance with its tilt
        at round-off, rest once it stands on its face — each held for 0.02 s. The window verdict (tip if rotated > 5°
        within T, else slide if it moved ≥ half the analytic distance) is beside it: with μ = 1 the sliding state is
        unstable, so that verdict depends on T. `cone excess` counts solved steps whose friction along the downhill
        line exceeds μ·Σfn (impossible for an exact solution): the source note's artifact at work; `first excess` is
        when the first one happened.""",
    )
    srows = []
    for r in res["slope"]:
        srows.append([
            r["solver"]["name"], f"{r['config']['angle_deg']:g}", r["scale"], r["outcome"], when(r["decided_at_s"]),
            when(r["tip_onset_s"]), when(r["first_excess_s"]), r["window_outcome"], r["slide_distance_m"],
            r["expected_slide_m"], r["tilt_deg"], r["lcp_failures"], when(r["first_failure_s"]),
            r["cone_excess_steps"], r["energy_gain_J"],
        ])
    d.table(["solver", "angle (°)", "s", "outcome", "decided at (s)", "tip onset (s)", "first excess (s)",
             f"window verdict ({ctx.seconds:g} s)", "slide (m)", "analytic (m)", "max rotation (°)", "LCP failures",
             "first failure (s)", "cone-excess steps", "energy gain (J)"], srows)
    d.img(ctx.rel(figs["slope_45_0001"]), "slope test at 45.0001°")
    d.img(ctx.rel(figs["slope_45_2"]), "slope test at 45.2°")


EXPERIMENT = Experiment.of_module(
    __name__, "the source note's slope test: does a μ = 1 cube slide, rest or tip?", plot=plot_slope
)
