#!/usr/bin/env python3
"""Joints beside MuJoCo: a 20-link chain piled on the ground, and a
two-finger gripper lifting a cube.

Both engines run the same MJCF string (nested bodies, ball and slide joints,
``velocity`` actuators): MuJoCo compiles it (its joints are reduced
coordinates, so they never open), lcpsim reads it with ``World.from_mjcf``
(joints as ``add_ball``/``add_slider``, actuators as motors driven by
``World.set_control``). Same masses, sizes, μ, dt.

chain    20 boxes 0.1 m × 0.03 m × 0.03 m, 0.1 kg, on ball joints end to end,
         standing almost upright (tilted 0.1 rad) with its foot 1 cm above the
         ground; released, it collapses into a pile. 3,000 steps of 1 ms.
gripper  a 1 kg, 0.1 m cube (μ = 1) on the ground; a 1 kg palm on a vertical
         slider to the world, two 0.2 kg fingers on sliders to the palm, their
         pads with torsional friction (condim 4, 0.02 m). The
         fingers close at 0.1 m/s with at most 20 N each (1 s), the palm
         rises 0.2 m at 0.1 m/s, reached and left over 0.2 s (2.2 s), then
         holds (2 s). lcpsim: velocity motors
         (hard complementarity rows with a force bound); MuJoCo: ``velocity``
         actuators (kv = 1000 N·s/m, forcerange ±20 N; palm ±200 N).

MuJoCo's default (Euler) integrator goes unstable on the chain (it
reports a bad acceleration and resets the state, after which the chain falls
afresh): the chain is run with each of its integrators, Euler, implicitfast,
implicit and RK4, and the step each went unstable at (if it did) is printed.

Reported per engine and scene: steps/s of the stepping loop (median of
``--rounds`` runs, engines interleaved in the same process), lcpsim's failed
LCPs, the largest joint error (lcpsim: ``World.joint_error``; MuJoCo: 0 by
construction), the deepest penetration (lcpsim: its contacts' gaps; MuJoCo:
``contact.dist``), and for the gripper the cube's lift and its slip against
the finger while lifting and holding.

    python3 benchmarks/joints.py              # both scenes, 3 rounds
    python3 benchmarks/joints.py --rounds 1 --scenes gripper
    python3 benchmarks/joints.py --engines lcpsim   # lcpsim alone

Two builds of lcpsim A/B in one window: the build under test installed, a copy
of the other's package directory (``python/lcpsim`` with its compiled
``_core``) in DIR, then alternately, at least twice each:

    python3 benchmarks/joints.py --engines lcpsim --rounds 1
    PYTHONPATH=DIR python3 benchmarks/joints.py --engines lcpsim --rounds 1
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time

import numpy as np

import lcpsim
from lcpsim import World

DT = 1e-3
LINKS, HALF, LINK_MASS, TILT = 20, (0.05, 0.015, 0.015), 0.1, 0.1


def chain_axis() -> np.ndarray:
    return np.array([math.sin(TILT), 0.0, math.cos(TILT)])


def chain_lcpsim() -> World:
    return World.from_mjcf(chain_mjcf())


def chain_mjcf() -> str:
    a = chain_axis()
    ang = math.pi / 2 - TILT
    links = ""
    for i in range(LINKS):
        pos = "0 0 0.01" if i == 0 else f"{2 * HALF[0]} 0 0"
        joint = '<freejoint/>' if i == 0 else f'<joint type="ball" pos="{-HALF[0]} 0 0"/>'
        # The first body turned so its local +x runs along the chain; children follow in its frame.
        frame = f' euler="0 {-math.degrees(ang)} 0"' if i == 0 else ""
        offset = f"{HALF[0] * a[0]} 0 {0.01 + HALF[0] * a[2]}" if i == 0 else pos
        links += (f'<body pos="{offset}"{frame}>{joint}<geom type="box" size="{HALF[0]} {HALF[1]} {HALF[2]}" '
                  f'mass="{LINK_MASS}"/>')
    links += "</body>" * LINKS
    return (f'<mujoco><option timestep="{DT}"/><default><geom friction="0.5 0.005 0.0001"/></default>'
            f'<worldbody><geom type="plane" size="5 5 0.1"/>{links}</worldbody></mujoco>')


# The pads' torsional friction (condim 4, friction[1] = 0.02 m: μ times about the mean
# radius of their 8 × 10 cm overlap with the cube, 2.7 cm). Without it a pad's load may sit
# on one corner of the face, where nothing resists the cube turning (docs/joints.md).
PAD = 'condim="4" friction="1 0.02 0.0001"'

GRIPPER_XML = f"""<mujoco><option timestep="{DT}"/><default><geom friction="1 0.005 0.0001"/></default>
<worldbody><geom type="plane" size="5 5 0.1"/>
 <body name="cube" pos="0 0 0.05"><freejoint/><geom type="box" size="0.05 0.05 0.05" mass="1"/></body>
 <body name="palm" pos="0 0 0.2"><joint name="lift" type="slide" axis="0 0 1"/>
  <geom type="box" size="0.15 0.05 0.02" mass="1"/>
  <body name="left" pos="-0.1 0 -0.1"><joint name="jl" type="slide" axis="1 0 0"/>
   <geom type="box" size="0.01 0.04 0.08" mass="0.2" {PAD}/></body>
  <body name="right" pos="0.1 0 -0.1"><joint name="jr" type="slide" axis="-1 0 0"/>
   <geom type="box" size="0.01 0.04 0.08" mass="0.2" {PAD}/></body>
 </body></worldbody>
<actuator><velocity name="lift" joint="lift" kv="1000" forcerange="-200 200" forcelimited="true"/>
 <velocity name="jl" joint="jl" kv="1000" forcerange="-20 20" forcelimited="true"/>
 <velocity name="jr" joint="jr" kv="1000" forcerange="-20 20" forcelimited="true"/></actuator></mujoco>"""


def gripper_lcpsim() -> tuple[World, dict]:
    w = World.from_mjcf(GRIPPER_XML)
    w.set_control("jl", 0.1)
    w.set_control("jr", 0.1)
    return w, {"cube": w.body_id("cube"), "finger": w.body_id("left")}


PHASES = (1000, 2200, 2000)  # steps closing, lifting, holding; fingers close at 0.1 m/s throughout


def lift_speed(phase: int, s: int) -> float:
    """The palm's speed at step ``s`` of ``phase``: 0.1 m/s while lifting, ramped over 0.2 s."""
    return 0.1 * min(1.0, s / 200, (PHASES[1] - s) / 200) if phase == 1 else 0.0


def run_lcpsim_chain() -> dict:
    w = chain_lcpsim()
    fails, deepest, worst = 0, 0.0, 0.0
    t = 0.0
    for _ in range(3000):
        t0 = time.perf_counter()
        rec = w.step()
        t += time.perf_counter() - t0
        fails += not rec.ok
        if rec.contacts:
            deepest = max(deepest, -float(np.min(rec.gaps)))
        worst = max(worst, max(w.joint_error(j)[0] for j in range(w.joint_count)))
    return {"steps_per_s": 3000 / t, "failed": fails, "joint_error": worst, "deepest": deepest,
            "top": float(np.max(w.positions[:, 2]))}


def run_mujoco_chain(integrator: str = "Euler") -> dict:
    """MuJoCo on the chain; ``unstable_at``: the step where it reported a bad
    acceleration (and reset the state), if it did."""
    import mujoco

    xml = chain_mjcf().replace("<option ", f'<option integrator="{integrator}" ')
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    deepest, t, unstable = 0.0, 0.0, None
    for i in range(3000):
        t0 = time.perf_counter()
        mujoco.mj_step(m, d)
        t += time.perf_counter() - t0
        if unstable is None and d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number:
            unstable = i
        if d.ncon:
            deepest = max(deepest, -float(np.min(d.contact.dist[: d.ncon])))
    return {"steps_per_s": 3000 / t, "failed": 0, "joint_error": 0.0, "deepest": deepest,
            "top": float(np.max(d.xpos[1:, 2])), "unstable_at": unstable}


def run_lcpsim_gripper() -> dict:
    w, ids = gripper_lcpsim()
    t, slips, fails = 0.0, [], 0
    grip = lambda: w.positions[ids["cube"], 2] - w.positions[ids["finger"], 2]
    for phase, steps in enumerate(PHASES):
        start = grip()
        for s in range(steps):
            w.set_control("lift", lift_speed(phase, s))
            t0 = time.perf_counter()
            rec = w.step()
            t += time.perf_counter() - t0
            fails += not rec.ok
        slips.append(abs(grip() - start))
    err = max(w.joint_error(j)[0] for j in range(w.joint_count))
    return {"steps_per_s": sum(PHASES) / t, "failed": fails, "joint_error": err,
            "lift": float(w.positions[ids["cube"], 2] - 0.05), "slip_lift": slips[1], "slip_hold": slips[2]}


def run_mujoco_gripper() -> dict:
    import mujoco

    m = mujoco.MjModel.from_xml_string(GRIPPER_XML)
    d = mujoco.MjData(m)
    cube, left = m.body("cube").id, m.body("left").id
    t, slips = 0.0, []
    grip = lambda: d.xpos[cube, 2] - d.xpos[left, 2]
    d.ctrl[1:] = 0.1
    mujoco.mj_forward(m, d)
    for phase, steps in enumerate(PHASES):
        start = grip()
        for s in range(steps):
            d.ctrl[0] = lift_speed(phase, s)
            t0 = time.perf_counter()
            mujoco.mj_step(m, d)
            t += time.perf_counter() - t0
        slips.append(abs(grip() - start))
    return {"steps_per_s": sum(PHASES) / t, "failed": 0, "joint_error": 0.0,
            "lift": float(d.xpos[cube, 2] - 0.05), "slip_lift": slips[1], "slip_hold": slips[2]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scenes", default="chain,gripper", help="comma-separated: chain, gripper")
    ap.add_argument("--engines", default="lcpsim,mujoco", help="comma-separated: lcpsim, mujoco")
    args = ap.parse_args()
    scenes, engines = args.scenes.split(","), args.engines.split(",")
    for name, given, known in (("--scenes", scenes, ("chain", "gripper")), ("--engines", engines, ("lcpsim", "mujoco"))):
        if not given or any(g not in known for g in given):
            ap.error(f"{name} must name some of {', '.join(known)}; got {','.join(given)!r}")
    print(f"lcpsim {lcpsim.__version__} ({os.path.dirname(lcpsim.__file__)}), dt = {DT} s, "
          f"{args.rounds} rounds (median steps/s)")
    # MuJoCo writes its warnings (the chain's instability) to MUJOCO_LOG.TXT in the working directory.
    os.chdir(tempfile.mkdtemp(prefix="joints_bench_"))
    chain = {"lcpsim": run_lcpsim_chain, "mujoco": run_mujoco_chain,
             **{f"mujoco_{i.lower()}": (lambda i=i: run_mujoco_chain(i)) for i in ("implicitfast", "implicit", "RK4")}}
    gripper = {"lcpsim": run_lcpsim_gripper, "mujoco": run_mujoco_gripper}
    for scene, runs in (("chain", chain), ("gripper", gripper)):
        if scene not in scenes:
            continue
        runs = {k: v for k, v in runs.items() if k.split("_")[0] in engines}
        results: dict[str, list[dict]] = {name: [] for name in runs}
        for _ in range(args.rounds):
            for name, run in runs.items():
                results[name].append(run())
        med = {k: float(np.median([r["steps_per_s"] for r in v])) for k, v in results.items()}
        ratios = [f"{k} {med['lcpsim'] / v:.3f}x" for k, v in med.items() if k != "lcpsim" and "lcpsim" in med]
        print(f"\n{scene}: " + ", ".join(f"{k} {v:,.0f} steps/s" for k, v in med.items())
              + ("; lcpsim ÷ " + ", ".join(ratios) if ratios else ""))
        for name, rs in results.items():
            r = rs[-1]
            extra = {k: v for k, v in r.items() if k != "steps_per_s"}
            print(f"  {name:19s} " + ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                                             for k, v in extra.items()))


if __name__ == "__main__":
    main()
