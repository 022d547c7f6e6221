"""The source note's pushed cube: a 1 kg unit cube at rest on level ground, μ = 1,
pushed horizontally at its centre of mass.

It must stay iff F ≤ μ m g (9.81 N), with a friction force of exactly F;
above that it slides with a = (F − μ m g)/m. The source note pushed
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

import argparse
import os
import time
from typing import Any, Mapping, Sequence

import numpy as np

from ..scenes import Scene, pushed_cube
from ._common import G, begin_run, downsample, envelope, parse_scale, scale_label, scale_value
from .presets import parse_solver
from .slope import CUBE_DEFAULTS, classify
from .document import Doc
from .experiment import (
    Experiment, ReportContext, add_common_arguments, add_simulation_arguments, base_config, header, scale_argument,
)
from .figure import label_axes, save, solver_label, traced, two_panels

__all__ = ["DEFAULTS", "run", "NOTE_VALUES"]

DEFAULTS: dict[str, Any] = {"seed": 0, "force": 9.79, **CUBE_DEFAULTS}

#: The source note's pushed cube (9.79 N): λ and the four normal impulses (N·s).
NOTE_VALUES: dict[str, Any] = {
    "outcome": "rest",
    "lambda_max": 2.1616814368153648e-19,
    "normal_impulses": [0.0, 1.000000000002777392e-05, 0.00489499999999991782, 0.0049050000000000022402],
    "friction_impulse_Ns": 0.004895 + 0.004895,
}


def make_scene(config: Mapping[str, Any]) -> Scene:
    """The pushed cube, ready to run, as a push config (``DEFAULTS`` merged) describes it."""
    return pushed_cube(
        float(config["force"]), float(config["mu"]), size=float(config["size"]), mass=float(config["mass"]),
        dt=float(config["dt"]), friction_dirs=int(config["friction_dirs"]), cone_scale=parse_scale(config["scale"]),
        **parse_solver(config["solver"]).world_kwargs(),
    )


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the push; returns ``{"outcome", "friction_force_N", "lambda_max", …}``."""
    t0, cfg, scale, solver, dt, steps = begin_run("push", DEFAULTS, config)
    F, mu, m = float(cfg["force"]), float(cfg["mu"]), float(cfg["mass"])
    scene = make_scene(cfg)
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
            "note_values": NOTE_VALUES,
        }
    )
    if cfg["trace"]:
        i = downsample(len(traj))
        out["trace"] = {"time": traj.time[i].tolist(), "displacement_m": along[i].tolist(), "friction_N": friction[i].tolist()}
    out["wall_time_s"] = time.perf_counter() - t0
    return out


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", type=float, default=9.79, help="horizontal push at the centre of mass, N (default: 9.79)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--scale", type=scale_argument, default="none", metavar="none|dt|S", help="cone scale (default: none)")
    add_simulation_arguments(p)
    add_common_arguments(p)


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    return {
        **base_config(args), "force": args.force, "mu": args.mu, "scale": args.scale, "seconds": args.seconds,
        "dt": args.dt, "friction_dirs": args.friction_dirs, "trace": bool(args.plot),
    }


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim push`` prints."""
    c = r["config"]
    fn = ", ".join(f"{x:.6g}" for x in r["normal_impulses"])
    off = ", ".join(f"{x:+.3g}" for x in r["contact_offsets_m"])
    lines = [
        header(r),
        f"cube {c['mass']} kg, μ = {c['mu']}, push {c['force']} N at the centre of mass, s = {r['scale']}, T = {r['seconds']:g} s",
        f"outcome:   {r['outcome']}  (exact: {r['expected_outcome']})",
        f"friction:  {r['friction_force_N']:.12g} N  (exact: {r['expected_friction_N']:.12g} N)",
        f"λ max:     {r['lambda_max']:.3e} m/s   (source note: ~1e-19)",
        f"fn:        {fn} N·s at offsets {off} m along the push   (source note: 0, 1e-05, 0.004895, 0.004905)",
        f"moved:     {r['displacement_m']:.4e} m  (exact: {r['expected_displacement_m']:.4e} m); LCP failures {r['lcp_failures']}",
    ]
    return "\n".join(lines)


def plot_push(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Displacement and friction force against time for push runs with a trace."""
    fig, ax1, ax2 = two_panels(10, 4)
    for i, r, tr in traced(results):
        lab = f"F = {r['config']['force']} N, {solver_label(r)}, s = {r['scale']} → {r['outcome']}"
        ax1.plot(tr["time"], tr["displacement_m"], color=f"C{i}", label=lab)
        ax2.plot(tr["time"], tr["friction_N"], color=f"C{i}", label=lab)
    ax1.set_yscale("symlog", linthresh=1e-9)
    label_axes(ax1, "time (s)", "displacement along the push (m)", legend=7)
    label_axes(ax2, "time (s)", "friction force (N)")
    return save(fig, path)


def plot_push_sweep(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Friction force and displacement against the applied force (one run per force and solver)."""
    fig, ax1, ax2 = two_panels(10, 4)
    by: dict[str, list[Mapping[str, Any]]] = {}
    for r in results:
        by.setdefault(f"{solver_label(r)}, s = {r['scale']}", []).append(r)
    for i, (lab, rs) in enumerate(sorted(by.items())):
        rs = sorted(rs, key=lambda r: r["config"]["force"])
        F = [r["config"]["force"] for r in rs]
        ax1.plot(F, [r["friction_force_N"] for r in rs], "o-", color=f"C{i}", label=lab)
        ax2.plot(F, [max(r["displacement_m"], 1e-12) for r in rs], "o-", color=f"C{i}", label=lab)
    if results:
        F = sorted({r["config"]["force"] for r in results})
        ax1.plot(F, [min(f, 9.81) for f in F], "k--", lw=1, label="exact: min(F, μmg)")
    ax1.axvline(9.81, color="grey", ls=":", lw=1)
    ax2.axvline(9.81, color="grey", ls=":", lw=1)
    label_axes(ax1, "push F (N)", "friction force, last step (N)", legend=7)
    ax2.set_yscale("log")
    label_axes(ax2, "push F (N)", "displacement after the run (m)")
    fig.suptitle("Pushed 1 kg cube, μ = 1 (μmg = 9.81 N)")
    return save(fig, path)


#: The report's push forces (N), around μmg = 9.81 N.
REPORT_FORCES = [9.70, 9.75, 9.79, 9.80, 9.81, 9.82, 9.83, 9.90]


def find(results: Sequence[Mapping[str, Any]], solver: str, scale: str, force: float) -> Mapping[str, Any]:
    """The result of ``solver`` at ``scale`` and ``force`` among the report's runs."""
    return next(r for r in results
                if r["solver"]["name"] == solver and r["scale"] == scale and r["config"]["force"] == force)


def report_run(ctx: ReportContext) -> dict[str, Any]:
    def runs() -> list[dict[str, Any]]:
        return [
            run({"seed": ctx.seed, "solver": solver, "scale": sc, "force": F, "seconds": ctx.seconds,
                 "trace": F in (9.79, 9.83)})
            for solver in ("robust", "classic")
            for sc in ("none", "dt")
            for F in REPORT_FORCES
        ]

    return {"push": ctx.step("pushed cube", runs)}


def report_figures(res: dict[str, Any], ctx: ReportContext) -> dict[str, str]:
    pushes = res["push"]
    return {
        "push_sweep": plot_push_sweep(pushes, ctx.path("push_sweep.png")),
        "push_trace": plot_push([r for r in pushes if r.get("trace") and r["scale"] == "none"],
                                ctx.path("push_trace.png")),
    }


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    d.section(
        "Pushed cube",
        """`lcpsim push --force F --mu 1 --solver P`: a 1 kg cube, μ = 1, pushed at its centre of mass; it must stay iff
        F ≤ μmg = 9.81 N with friction exactly F, and slide above.""",
    )
    prows = []
    for r in res["push"]:
        prows.append([r["solver"]["name"], r["scale"], r["config"]["force"], r["outcome"], r["expected_outcome"],
                      f"{r['friction_force_N']:.10g}", r["lambda_max"], r["displacement_m"], r["lcp_failures"]])
    d.table(["solver", "s", "F (N)", "outcome", "exact", "friction (N)", "λ max", "moved (m)", "LCP failures"], prows)
    rp = find(res["push"], "robust", "none", 9.79)
    d.p(
        "Normal impulses at 9.79 N (robust, unscaled), by position along the push: "
        + ", ".join(f"{x:.6g} N·s at {o:+.2f} m" for x, o in zip(rp["normal_impulses"], rp["contact_offsets_m"]))
        + " — the load sits on the leading edge, as the source note's 0, 1e-5, 0.004895, 0.004905 show."
    )
    d.img(ctx.rel(figs["push_sweep"]), "push sweep")
    d.img(ctx.rel(figs["push_trace"]), "push traces")


EXPERIMENT = Experiment.of_module(__name__, "the source note's pushed cube (9.79 N, μ = 1)", plot=plot_push)
