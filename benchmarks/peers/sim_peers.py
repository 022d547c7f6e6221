#!/usr/bin/env python3
"""Simulation throughput and slope outcome: lcpsim beside MuJoCo and PyBullet.

A 1 kg unit cube released at rest, one face flat on a plane tilted by θ about
the y axis (it descends towards +x), μ = 1 (the knife edge of the source note: tan θ just
above μ, so the cube must slide — and, μ ≤ 1, not tip), g = 9.81,
dt = 1e-3, 2 s (2000 steps). For each simulator: steps per second (wall clock
of the 2000 steps only, median of ``--runs`` fresh runs) and the outcome —
``tip`` if the cube rotated more than 5° at any time, else ``slide`` if it moved
down-slope at least half the analytic ½·g·(sin θ − μ cos θ)·t², else ``rest``
(the rule of ``lcpsim.experiments.slope``). Two sanity cases beside the knife
edge: 30° / μ 0.5 (slides 1.314 m in 2 s) and 20° / μ 0.5 (must rest).

Runs in the peers' venv (``bash benchmarks/peers/setup.sh``)::

    benchmarks/peers/.venv/bin/python benchmarks/peers/sim_peers.py

``run.py`` calls :func:`run_all` and puts :func:`render`'s section into
``benchmarks/RESULTS.md``; run alone, this prints the section and writes
``benchmarks/peers/sim_results.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

HERE = Path(__file__).resolve().parent
G = 9.81
DT = 1e-3
SECONDS = 2.0
TIP_DEG = 5.0

#: (angle in degrees, μ)
CASES: list[tuple[float, float]] = [(45.0001, 1.0), (45.2, 1.0), (30.0, 0.5), (20.0, 0.5)]


def expected_slide(angle_deg: float, mu: float, t: float) -> float:
    th = math.radians(angle_deg)
    a = G * (math.sin(th) - mu * math.cos(th))
    return 0.5 * a * t * t if a > 0 else 0.0


def classify(slide: float, expected: float, tilt_deg: float) -> str:
    if not (math.isfinite(tilt_deg) and math.isfinite(slide)) or tilt_deg > TIP_DEG:
        return "tip"
    if expected > 0:
        return "slide" if slide >= 0.5 * expected else "rest"
    return "slide" if slide > 1e-6 else "rest"


#: A slide counts as right if within this relative error of the analytic distance.
SLIDE_RTOL = 0.1


def verdict(c: dict[str, Any]) -> tuple[str, bool]:
    """(what must happen, whether the run did it): the right outcome and, for a slide,
    the analytic distance within ``SLIDE_RTOL``."""
    must = "slide" if c["expected_slide_m"] > 0 else "rest"
    if c["outcome"] != must:
        return must, False
    if must == "slide":
        return must, abs(c["slide_rel_error"]) <= SLIDE_RTOL
    return must, True


def quat_angle_deg(q0: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation angle between unit quaternions (any convention, same for both), degrees."""
    d = np.clip(np.abs(np.asarray(q) @ np.asarray(q0)), 0.0, 1.0)
    return np.degrees(2.0 * np.arccos(d))


def slope_frame(angle_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(normal, downhill, quaternion wxyz of the rotation by θ about y)."""
    th = math.radians(angle_deg)
    normal = np.array([math.sin(th), 0.0, math.cos(th)])
    downhill = np.array([math.cos(th), 0.0, -math.sin(th)])
    quat = np.array([math.cos(th / 2), 0.0, math.sin(th / 2), 0.0])
    return normal, downhill, quat


# Each runner: (angle, mu, steps) -> (seconds for the steps, positions (T, 3), quaternions (T, 4), extra)
Runner = Callable[[float, float, int], tuple[float, np.ndarray, np.ndarray, dict[str, Any]]]


# --------------------------------------------------------------------------- lcpsim


def lcpsim_rust_loop(**world: Any) -> Runner:
    def run(angle: float, mu: float, steps: int) -> tuple[float, np.ndarray, np.ndarray, dict[str, Any]]:
        from lcpsim import scenes

        s = scenes.cube_on_slope(angle, mu, dt=DT, **world)
        t0 = time.perf_counter()
        traj = s.world.run(steps)
        t = time.perf_counter() - t0
        pos = np.vstack([traj.initial_positions[s.body], traj.positions[:, s.body]])
        quat = np.vstack([traj.initial_orientations[s.body], traj.orientations[:, s.body]])
        return t, pos, quat, {"lcp_failures": traj.failures, "downhill": s.direction}

    return run


def lcpsim_python_loop(**world: Any) -> Runner:
    def run(angle: float, mu: float, steps: int) -> tuple[float, np.ndarray, np.ndarray, dict[str, Any]]:
        from lcpsim import scenes

        s = scenes.cube_on_slope(angle, mu, dt=DT, **world)
        w, b = s.world, s.body
        pos = np.empty((steps + 1, 3))
        quat = np.empty((steps + 1, 4))
        st = w.body(b)
        pos[0], quat[0] = st.position, st.orientation
        failures = 0
        t_steps = 0.0
        for i in range(steps):
            t0 = time.perf_counter()
            rec = w.step()
            t_steps += time.perf_counter() - t0
            failures += not rec.ok
            st = w.body(b)  # state read-out outside the timer, as for the peers
            pos[i + 1], quat[i + 1] = st.position, st.orientation
        return t_steps, pos, quat, {"lcp_failures": failures, "downhill": s.direction}

    return run


# --------------------------------------------------------------------------- MuJoCo


def mujoco_xml(angle: float, mu: float, cone: str) -> str:
    normal, _, q = slope_frame(angle)
    # plain floats: numpy 2's repr of its scalars ("np.float64(…)") is not MJCF
    c, q = [float(x) for x in 0.5 * normal], [float(x) for x in q]
    return f"""
<mujoco>
  <option timestep="{DT}" gravity="0 0 -{G}" cone="{cone}"/>
  <worldbody>
    <geom name="slope" type="plane" size="0 0 1" quat="{q[0]!r} 0 {q[2]!r} 0" friction="{mu} 0.005 0.0001"/>
    <body name="cube" pos="{c[0]!r} {c[1]!r} {c[2]!r}" quat="{q[0]!r} 0 {q[2]!r} 0">
      <freejoint/>
      <geom type="box" size="0.5 0.5 0.5" mass="1" friction="{mu} 0.005 0.0001"/>
    </body>
  </worldbody>
</mujoco>"""


def mujoco_python_loop(cone: str) -> Runner:
    def run(angle: float, mu: float, steps: int) -> tuple[float, np.ndarray, np.ndarray, dict[str, Any]]:
        import mujoco

        m = mujoco.MjModel.from_xml_string(mujoco_xml(angle, mu, cone))
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        pos = np.empty((steps + 1, 3))
        quat = np.empty((steps + 1, 4))
        pos[0], quat[0] = d.qpos[:3], d.qpos[3:7]
        t_steps = 0.0
        for i in range(steps):
            t0 = time.perf_counter()
            mujoco.mj_step(m, d)
            t_steps += time.perf_counter() - t0
            pos[i + 1], quat[i + 1] = d.qpos[:3], d.qpos[3:7]
        return t_steps, pos, quat, {}

    return run


def mujoco_rollout(cone: str) -> Runner:
    """MuJoCo's own C loop (``mujoco.rollout``), one thread, the full state recorded."""

    def run(angle: float, mu: float, steps: int) -> tuple[float, np.ndarray, np.ndarray, dict[str, Any]]:
        import mujoco
        from mujoco import rollout

        m = mujoco.MjModel.from_xml_string(mujoco_xml(angle, mu, cone))
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        s0 = np.empty(mujoco.mj_stateSize(m, spec))
        mujoco.mj_getState(m, d, s0, spec)
        t0 = time.perf_counter()
        state, _ = rollout.rollout(m, d, s0[None, :], nstep=steps)
        t = time.perf_counter() - t0
        # FULLPHYSICS layout: time, qpos (pos 3, quat 4), qvel, …
        traj = np.vstack([s0[None, :], state[0]])
        return t, traj[:, 1:4], traj[:, 4:8], {}

    return run


# --------------------------------------------------------------------------- PyBullet


def pybullet_python_loop() -> Runner:
    def run(angle: float, mu: float, steps: int) -> tuple[float, np.ndarray, np.ndarray, dict[str, Any]]:
        import pybullet as pb

        cid = pb.connect(pb.DIRECT)
        try:
            pb.setGravity(0, 0, -G, physicsClientId=cid)
            pb.setTimeStep(DT, physicsClientId=cid)
            normal, _, q = slope_frame(angle)
            xyzw = [q[1], q[2], q[3], q[0]]
            plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid)
            ground = pb.createMultiBody(0, plane, baseOrientation=xyzw, physicsClientId=cid)
            box = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.5, 0.5, 0.5], physicsClientId=cid)
            cube = pb.createMultiBody(1.0, box, basePosition=list(0.5 * normal), baseOrientation=xyzw,
                                      physicsClientId=cid)
            for body in (ground, cube):  # Bullet multiplies the two: μ = 1·μ
                pb.changeDynamics(body, -1, lateralFriction=1.0 if body == ground else mu,
                                  rollingFriction=0.0, spinningFriction=0.0, restitution=0.0, physicsClientId=cid)
            pos = np.empty((steps + 1, 3))
            quat = np.empty((steps + 1, 4))

            def read(i: int) -> None:
                p, o = pb.getBasePositionAndOrientation(cube, physicsClientId=cid)
                pos[i], quat[i] = p, (o[3], o[0], o[1], o[2])

            read(0)
            t_steps = 0.0
            for i in range(steps):
                t0 = time.perf_counter()
                pb.stepSimulation(physicsClientId=cid)
                t_steps += time.perf_counter() - t0
                read(i + 1)
        finally:
            pb.disconnect(cid)
        return t_steps, pos, quat, {}

    return run


# --------------------------------------------------------------------------- driver

SIMULATORS: list[tuple[str, str, Callable[[], Runner]]] = [
    ("lcpsim_run", "lcpsim robust, `World.run` (loop in Rust)", lambda: lcpsim_rust_loop()),
    ("lcpsim_step", "lcpsim robust, `World.step` per step from Python", lambda: lcpsim_python_loop()),
    ("mujoco_pyramidal", "MuJoCo, pyramidal cone (default), `mj_step` per step from Python",
     lambda: mujoco_python_loop("pyramidal")),
    ("mujoco_elliptic", "MuJoCo, elliptic cone, `mj_step` per step from Python", lambda: mujoco_python_loop("elliptic")),
    ("mujoco_rollout", "MuJoCo, pyramidal cone, `mujoco.rollout` (loop in C)", lambda: mujoco_rollout("pyramidal")),
    ("pybullet", "PyBullet (DIRECT), `stepSimulation` per step from Python", lambda: pybullet_python_loop()),
]

CONTACT_MODELS = [
    "**lcpsim**: hard contact, the Stewart–Trinkle / Anitescu–Potra LCP (8 friction directions, "
    "the slope along one of them) solved exactly by Lemke each step; no penetration compliance, ERP 0.2 "
    "position correction.",
    "**MuJoCo**: soft contacts — a convex optimization over constraint forces with a spring–damper reference "
    "(`solref` 0.02 s, `solimp` 0.9–0.95), so contacts penetrate slightly and forces follow from the "
    "penetration and velocity; friction in a pyramidal (default: 2·2 edges for condim 3) or elliptic cone; "
    "Newton solver. Its regularization lets a little sliding happen under static friction and shifts the "
    "friction limit at the knife edge.",
    "**PyBullet**: Bullet's sequential-impulse (projected Gauss–Seidel) solver, 50 iterations by default, "
    "two friction directions per contact each clamped to |f| ≤ μ·fn (a box, not a cone), split-impulse "
    "penetration recovery; μ of a pair is the product of the bodies' μ.",
]


def run_case(runner: Runner, angle: float, mu: float, runs: int) -> dict[str, Any]:
    steps = int(round(SECONDS / DT))
    times = []
    first: tuple[np.ndarray, np.ndarray, dict[str, Any]] | None = None
    for r in range(runs):
        t, pos, quat, extra = runner(angle, mu, steps)
        times.append(t)
        if first is None:
            first = (pos, quat, extra)
    assert first is not None
    pos, quat, extra = first
    downhill = extra.get("downhill")
    if downhill is None:
        _, downhill, _ = slope_frame(angle)
    along = (pos - pos[0]) @ downhill
    tilt = quat_angle_deg(quat[0], quat)
    expected = expected_slide(angle, mu, SECONDS)
    slide = float(along[-1])
    max_tilt = float(np.nanmax(tilt))
    out = {
        "angle_deg": angle,
        "mu": mu,
        "steps": steps,
        "seconds_per_run": times,
        "steps_per_second": steps / float(np.median(times)),
        "slide_m": slide,
        "expected_slide_m": expected,
        "slide_rel_error": (slide / expected - 1.0) if expected > 0 else None,
        "max_tilt_deg": max_tilt,
        "outcome": classify(slide, expected, max_tilt),
    }
    out["must"], out["right"] = verdict(out)
    if "lcp_failures" in extra:
        out["lcp_failures"] = int(extra["lcp_failures"])
    return out


def run_all(runs: int = 3, progress: Callable[..., None] = print) -> dict[str, Any]:
    from importlib.metadata import PackageNotFoundError, version

    results: dict[str, Any] = {"config": {"dt": DT, "seconds": SECONDS, "runs": runs, "tip_deg": TIP_DEG},
                               "simulators": {}, "versions": {}}
    for dist in ("lcpsim", "mujoco", "pybullet"):
        try:
            results["versions"][dist] = version(dist)
        except PackageNotFoundError:
            results["versions"][dist] = "not installed"
    for key, title, make in SIMULATORS:
        entry: dict[str, Any] = {"title": title, "cases": []}
        try:
            runner = make()
            for angle, mu in CASES:
                c = run_case(runner, angle, mu, runs)
                entry["cases"].append(c)
                progress(f"  {key} {angle}° μ {mu}: {c['outcome']}, slide {c['slide_m']:.6g} m "
                         f"(analytic {c['expected_slide_m']:.6g}), tilt {c['max_tilt_deg']:.3g}°, "
                         f"{c['steps_per_second']:,.0f} steps/s")
        except Exception as e:  # a peer missing or broken: reported, not fatal
            entry["error"] = f"{type(e).__name__}: {e}"
            progress(f"  {key}: {entry['error']}")
        results["simulators"][key] = entry
    return results


def render(results: dict[str, Any]) -> list[str]:
    cfg = results["config"]
    lines = [
        "## Simulation: cube on a slope beside MuJoCo and PyBullet",
        "",
        f"1 kg unit cube released at rest on a plane tilted by θ, dt = {cfg['dt']:g} s, {cfg['seconds']:g} s "
        f"({int(cfg['seconds'] / cfg['dt'])} steps); steps/s = steps / wall-clock time of the steps "
        f"(median of {cfg['runs']} fresh runs; model building and state read-out not timed). Outcome: **tip** if the "
        f"cube rotated more than {cfg['tip_deg']:g}° at any time, else **slide** if it moved down-slope at least half "
        "of ½·g·(sin θ − μ cos θ)·t², else **rest**. At θ = 45.0001° and 45.2° with μ = 1 the cube must "
        "**slide** (tan θ > μ) without tipping (μ ≤ 1); at 30°/μ 0.5 it slides 1.3143 m; at 20°/μ 0.5 it must rest.",
        "",
        "| simulator | steps/s (median over the cases) | right |",
        "|---|---|---|",
    ]
    for key, e in results["simulators"].items():
        if e["cases"]:
            sps = float(np.median([c["steps_per_second"] for c in e["cases"]]))
            right = sum(c["right"] for c in e["cases"])
            lines.append(f"| {e['title']} | {sps:,.0f} | {right} of {len(e['cases'])} |")
    lines += [
        "",
        "A run is right (✓) if the outcome is what must happen and a slide is within "
        f"{SLIDE_RTOL:.0%} of the analytic distance.",
        "",
        "| simulator | θ, μ | must | outcome | slide (m) | analytic (m) | max tilt | steps/s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for key, e in results["simulators"].items():
        if "error" in e and not e["cases"]:
            lines.append(f"| {e['title']} | — | — | not run: {e['error']} | | | | |")
            continue
        first = True
        for c in e["cases"]:
            must, right = verdict(c)
            if right:
                outcome = f"{c['outcome']} ✓"
            elif c["outcome"] == must:
                outcome = f"**{c['outcome']}, {c['slide_m'] / c['expected_slide_m']:.3g}× the distance** ✗"
            else:
                outcome = f"**{c['outcome']}** ✗"
            if c.get("lcp_failures"):
                outcome += f" ({c['lcp_failures']} LCP failures)"
            lines.append(
                f"| {e['title'] if first else ''} | {c['angle_deg']:g}°, {c['mu']:g} | {must} | {outcome} | "
                f"{c['slide_m']:.6g} | {c['expected_slide_m']:.6g} | {c['max_tilt_deg']:.3g}° | "
                f"{c['steps_per_second']:,.0f} |"
            )
            first = False
    lines += ["", "How the contact models differ:", ""]
    lines += [f"- {m}" for m in CONTACT_MODELS]
    lines.append("")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    res = run_all(args.runs)
    print("\n".join(render(res)))
    if not args.no_write:
        (HERE / "sim_results.json").write_text(json.dumps(res, indent=1, default=str))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
