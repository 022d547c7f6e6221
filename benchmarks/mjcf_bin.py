#!/usr/bin/env python3
"""The mixed-shape bin, one MJCF file run by MuJoCo and by lcpsim.

The scene (``benchmarks/scenes/mixed_bin.xml``, written by ``--write-scene``
from a seed, so it is the same file every time): a floor plane and four static
box walls make a 1.2 m × 1.2 m bin; 50 free bodies — 10 each of boxes,
spheres, capsules, cylinders and convex meshes (a skewed octahedron, collided
as its hull by both engines) — start in a loose column above it with seeded
random orientations and fall in. μ = 0.5, dt = 2 ms (the file's), 2,500 steps
(5 s): the pour, the pile forming and settling.

Each engine runs the file in its own process (``run_worker`` of
``benchmarks/peers/many_bodies.py``: an address-space cap and a wall-clock
budget): MuJoCo with its defaults (pyramidal cone, Newton solver, soft
contacts; ``mujoco.mj_step(m, d, nstep)``, its native loop), lcpsim through
``World.from_mjcf`` and ``World.run`` (the exact LCP, Lemke). Reported per
engine: steps/s (stepping calls only), lcpsim's failed LCPs, and the deepest
penetration over the sampled states, measured for both engines by the same
code — MuJoCo's own collision detection (``mj_forward`` on the state, the
most negative ``contact.dist``) — so the two states are judged alike.

    python3 benchmarks/mjcf_bin.py                 # both engines, prints the table
    python3 benchmarks/mjcf_bin.py --steps 500     # a shorter run
    python3 benchmarks/mjcf_bin.py --write-scene   # regenerate the XML (same seed, same file)
    python3 benchmarks/mjcf_bin.py --pairs 1250    # lcpsim's contact points per touching pair
    python3 benchmarks/mjcf_bin.py --manifold-ab 1-8 --steps 2500  # parry's points vs the support points

Needs ``mujoco`` (``pip install 'lcpsim[mjcf]'``) and lcpsim installed.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
SCENE = HERE / "scenes" / "mixed_bin.xml"
ENGINES = ("mujoco", "lcpsim")

# ----- the scene ---------------------------------------------------------------------------

#: A skewed octahedron (m): the convex mesh of the scene.
ROCK = [(0.08, 0, 0), (-0.06, 0, 0), (0, 0.07, 0), (0, -0.05, 0), (0.01, 0.01, 0.08), (0, 0, -0.06)]
KINDS = ("box", "sphere", "capsule", "cylinder", "mesh")


def scene_xml(n: int = 50, seed: int = 7) -> str:
    """The bin and ``n`` bodies (kinds in turn), 3 × 3 per layer, 0.25 m between layers."""
    rng = np.random.default_rng(seed)
    half, height, wall = 0.6, 0.8, 0.05
    fr = 'friction="0.5 0.005 0.0001"'
    walls = []
    for k, (x, y, hx, hy) in enumerate([(half + wall, 0, wall, half + 2 * wall), (-half - wall, 0, wall, half + 2 * wall),
                                        (0, half + wall, half, wall), (0, -half - wall, half, wall)]):
        walls.append(f'    <geom name="wall{k}" type="box" pos="{x:g} {y:g} {height / 2:g}" '
                     f'size="{hx:g} {hy:g} {height / 2:g}" {fr}/>')
    bodies = []
    for k in range(n):
        p = (-0.3 + 0.3 * (k % 3), -0.3 + 0.3 * ((k // 3) % 3), 0.15 + 0.25 * (k // 9))
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        kind = KINDS[k % len(KINDS)]
        size = {"box": 'size="0.07 0.06 0.05"', "sphere": 'size="0.07"', "capsule": 'size="0.05 0.06"',
                "cylinder": 'size="0.06 0.05"', "mesh": 'mesh="rock"'}[kind]
        pos = " ".join(f"{v:.4f}" for v in p)
        quat = " ".join(f"{v:.6f}" for v in q)
        bodies.append(f'    <body name="{kind}{k}" pos="{pos}" quat="{quat}"><freejoint/>'
                      f'<geom type="{kind}" {size} density="500" {fr}/></body>')
    verts = "  ".join(" ".join(f"{c:g}" for c in v) for v in ROCK)
    return "\n".join([
        '<mujoco model="mixed_bin">',
        "  <!-- Written by benchmarks/mjcf_bin.py --write-scene (seed 7); run by MuJoCo and lcpsim alike. -->",
        '  <option timestep="0.002" gravity="0 0 -9.81"/>',
        f'  <asset><mesh name="rock" vertex="{verts}"/></asset>',
        "  <worldbody>",
        f'    <geom name="floor" type="plane" size="0 0 1" {fr}/>',
        *walls,
        *bodies,
        "  </worldbody>",
        "</mujoco>",
        "",
    ])


# ----- the workers (one process per engine) ---------------------------------------------------


def emit(event: str, **fields: Any) -> None:
    print(json.dumps({"event": event, **fields}), flush=True)


def free_bodies(m: Any) -> list[str]:
    """The names of MuJoCo's moving bodies, in qpos order."""
    import mujoco

    return [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, m.nbody) if m.body_jntnum[b] > 0]


def worker(engine: str, xml_path: str, steps: int, every: int, budget: float) -> None:
    import mujoco

    m = mujoco.MjModel.from_xml_path(xml_path)
    names = free_bodies(m)
    if engine == "mujoco":
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)

        def step(k: int) -> dict[str, Any]:
            mujoco.mj_step(m, d, nstep=k)
            return {}

        def state() -> list[float]:
            return d.qpos.tolist()
    else:
        from lcpsim import World

        w = World.from_mjcf(xml_path)
        ids = [w.body_id(n) for n in names]
        emit("com_offsets", offsets=[np.asarray(w.body(i).com_offset if w.body(i).com_offset is not None
                                                else np.zeros(3)).tolist() for i in ids])

        def step(k: int) -> dict[str, Any]:
            st = w.run(k).lcp_stats()
            stages = {f"stage_{name}": int(v) for name, v in (getattr(st, "stages", None) or {}).items()}
            return {"failures": int(st.failures), "lcps": int(st.lcps), **stages}

        def state() -> list[float]:
            p, q = w.positions[ids], w.orientations[ids]
            return np.concatenate([p, q], axis=1).ravel().tolist()

    emit("ready")
    emit("sample", step=0, state=state())
    done, seconds, totals = 0, 0.0, {"failures": 0, "lcps": 0}
    while done < steps and seconds < budget:
        k = min(every, steps - done)
        t0 = time.perf_counter()
        out = step(k)
        seconds += time.perf_counter() - t0
        done += k
        for key, v in out.items():
            totals[key] = totals.get(key, 0) + v
        emit("sample", step=done, state=state(), seconds=seconds, **totals)
    emit("done", steps=done, seconds=seconds, **totals)


def points_per_pair(xml_path: str, steps: int) -> None:
    """lcpsim's first ``steps`` steps one by one: how many pairs had k contact points, over all
    steps and by the kinds of the pair's two shapes; the islands' LCP sizes."""
    from collections import Counter

    from lcpsim import World

    w = World.from_mjcf(xml_path)
    kind = [w.body(i).kind for i in range(w.body_count)]
    pairs: Counter[int] = Counter()
    by_kinds: dict[str, Counter[int]] = {}
    sizes: list[int] = []
    for _ in range(steps):
        r = w.step()
        for (a, b), k in Counter(zip(np.asarray(r.body_a).tolist(), np.asarray(r.body_b).tolist())).items():
            pairs[k] += 1
            by_kinds.setdefault("–".join(sorted((kind[a], kind[b]))), Counter())[k] += 1
        sizes.extend(np.asarray(r.island_lcp_size).tolist())

    def row(c: Counter[int]) -> str:
        contacts = sum(k * n for k, n in c.items())
        return (f"{sum(c.values()):,} pair-steps, {contacts:,} contacts ({contacts / sum(c.values()):.2f} a pair); "
                "by points: " + ", ".join(f"{k}: {n:,}" for k, n in sorted(c.items())))

    print(f"{steps} steps, all pairs: {row(pairs)}")
    for name, c in sorted(by_kinds.items(), key=lambda kv: -sum(k * n for k, n in kv[1].items())):
        print(f"  {name}: {row(c)}")
    n = np.asarray(sizes)
    print(f"{n.size:,} island LCPs, n: median {np.median(n):.0f}, 90th percentile {np.percentile(n, 90):.0f}, "
          f"max {n.max()}; share of all unknowns in islands of n > 100: {n[n > 100].sum() / n.sum():.1%}")


def states_worker(xml_path: str, steps: int, every: int, out: str) -> None:
    """Runs lcpsim on the file and saves the state of every moving body each ``every`` steps."""
    from lcpsim import World

    w = World.from_mjcf(xml_path)
    moving = [i for i in range(w.body_count) if not w.body(i).is_static]
    saved = []
    for _ in range(steps // every):
        w.run(every)
        saved.append(np.concatenate([w.positions[moving], w.orientations[moving], w.velocities[moving]], axis=1))
    np.save(out, np.asarray(saved))


def replay_worker(xml_path: str, states: str, steps: int) -> None:
    """From each saved state, ``steps`` steps of lcpsim (a fresh world each time: cold, then warm);
    emits the stepping seconds and the contacts over them."""
    from lcpsim import World

    seconds, contacts = 0.0, 0
    for state in np.load(states):
        w = World.from_mjcf(xml_path)
        moving = [i for i in range(w.body_count) if not w.body(i).is_static]
        for k, i in enumerate(moving):
            w.set_position(i, state[k, :3])
            w.set_orientation(i, state[k, 3:7])
            w.set_velocity(i, state[k, 7:13])
        for _ in range(steps):
            t0 = time.perf_counter()
            r = w.step()
            seconds += time.perf_counter() - t0
            contacts += len(r.gaps)
    emit("done", seconds=seconds, contacts=contacts)


def manifold_ab(seeds: list[int], steps: int, every: int, window: int) -> None:
    """Every point of parry's manifolds kept (``LCPSIM_MANIFOLD=parry``) against the support points
    (the default), on the same states: the bin of each seed run ``steps`` steps with parry's points,
    its state saved every ``every`` steps, and from each saved state ``window`` steps of each, in
    their own processes, one after the other (the trajectories of two whole runs part, so whole
    runs would compare two different piles)."""
    import tempfile

    ratios = []

    def run(arm: str, *args: str) -> str:
        env = {k: v for k, v in os.environ.items() if k != "LCPSIM_MANIFOLD"}
        if arm == "parry":
            env["LCPSIM_MANIFOLD"] = "parry"
        return subprocess.run([sys.executable, __file__, *args], env=env, capture_output=True, text=True,
                              check=True).stdout

    with tempfile.TemporaryDirectory() as tmp:
        print("| seed | steps/s, parry's points | steps/s, support points | ratio | contacts, parry's → support |")
        print("|---|---|---|---|---|")
        for seed in seeds:
            path, states = Path(tmp) / f"mixed_bin_{seed}.xml", Path(tmp) / f"states_{seed}.npy"
            path.write_text(scene_xml(seed=seed))
            run("parry", "--states-worker", str(path), str(steps), str(every), str(states))
            rate, contacts = {}, {}
            for arm in ("parry", "support"):
                out = run(arm, "--replay-worker", str(path), str(states), str(window))
                done = next(json.loads(line) for line in out.splitlines() if '"event": "done"' in line)
                rate[arm], contacts[arm] = (steps // every) * window / done["seconds"], done["contacts"]
            ratios.append(rate["support"] / rate["parry"])
            print(f"| {seed} | {rate['parry']:,.1f} | {rate['support']:,.1f} | {ratios[-1]:.3f} | "
                  f"{contacts['parry']:,} → {contacts['support']:,} |", flush=True)
    print(f"geometric mean of the ratios over {len(seeds)} seeds: {np.exp(np.mean(np.log(ratios))):.3f}")


# ----- the judge: one penetration measure for both ----------------------------------------------


def _quat(mujoco: Any, r: np.ndarray) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(r).reshape(9))
    return q


def _mat(mujoco: Any, q: np.ndarray) -> np.ndarray:
    r = np.zeros(9)
    mujoco.mju_quat2Mat(r, np.asarray(q, dtype=float))
    return r.reshape(3, 3)


def lcpsim_qpos(m: Any, state: list[float], offsets: list[list[float]]) -> np.ndarray:
    """MuJoCo's qpos of lcpsim's poses: lcpsim puts each body at its geom's frame (a mesh's at
    its hull's centre, ``com_offset`` from it); MuJoCo's body frame is the geom's turned back by
    ``geom_pos``, ``geom_quat``."""
    import mujoco

    s = np.asarray(state).reshape(-1, 7)
    qpos = np.zeros(m.nq)
    movers = [b for b in range(1, m.nbody) if m.body_jntnum[b] > 0]
    for k, b in enumerate(movers):
        g = int(m.body_geomadr[b])
        r_g = _mat(mujoco, s[k, 3:])
        p_g = s[k, :3] - r_g @ np.asarray(offsets[k])
        r_b = r_g @ _mat(mujoco, m.geom_quat[g]).T
        p_b = p_g - r_b @ m.geom_pos[g]
        a = int(m.jnt_qposadr[int(m.body_jntadr[b])])
        qpos[a : a + 3], qpos[a + 3 : a + 7] = p_b, _quat(mujoco, r_b)
    return qpos


def deepest(m: Any, qpos: np.ndarray) -> float:
    """MuJoCo's deepest overlap (m) between any two geoms at ``qpos``: −min(contact.dist, 0)."""
    import mujoco

    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_forward(m, d)
    return float(-min(0.0, d.contact.dist[: d.ncon].min())) if d.ncon else 0.0


def judge(engine: str, xml_path: str, events: list[dict[str, Any]]) -> dict[str, Any]:
    import mujoco

    m = mujoco.MjModel.from_xml_path(xml_path)
    samples = [e for e in events if e["event"] == "sample"]
    done = next((e for e in events if e["event"] == "done"), None) or (samples[-1] if samples else {})
    offsets = next((e["offsets"] for e in events if e["event"] == "com_offsets"), None)
    out: dict[str, Any] = {"steps": done.get("steps", done.get("step", 0)), "seconds": done.get("seconds", 0.0)}
    out["steps_per_second"] = out["steps"] / out["seconds"] if out["seconds"] else None
    out["failed_lcps"] = done.get("failures") if engine == "lcpsim" else None
    out["lcps"] = done.get("lcps") if engine == "lcpsim" else None
    # lcpsim's islands by the stage of the solve chain that answered them (lcp_stats().stages).
    out["islands_by_stage"] = {k[len("stage_"):]: v for k, v in done.items() if k.startswith("stage_")}
    # Steps/s over each sampling interval: the pour, the pile forming, the settled pile.
    timed = [(0, 0.0)] + [(s["step"], s["seconds"]) for s in samples if "seconds" in s]
    out["window_rates"] = [[b[0], (b[0] - a[0]) / (b[1] - a[1]) if b[1] > a[1] else None] for a, b in zip(timed, timed[1:])]
    depths = []
    for s in samples:
        q = np.asarray(s["state"]) if engine == "mujoco" else lcpsim_qpos(m, s["state"], offsets or [])
        depths.append(deepest(m, q))
    out["max_penetration_m"] = max(depths) if depths else None
    out["final_penetration_m"] = depths[-1] if depths else None
    if samples:
        last = np.asarray(samples[-1]["state"]).reshape(-1, 7)
        out["lowest_z_m"], out["highest_z_m"] = float(last[:, 2].min()), float(last[:, 2].max())
        out["outside_bin"] = int((np.abs(last[:, :2]) > 0.6).any(axis=1).sum())
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=str(SCENE), help="the MJCF file (default benchmarks/scenes/mixed_bin.xml)")
    ap.add_argument("--steps", type=int, default=2500)
    ap.add_argument("--every", type=int, default=250, help="steps between sampled states")
    ap.add_argument("--budget", type=float, default=600.0, help="seconds of stepping per engine")
    ap.add_argument("--mem-cap-gb", type=float, default=4.0)
    ap.add_argument("--engines", default=",".join(ENGINES))
    ap.add_argument("--rounds", type=int, default=3, help="runs per engine, engine after engine (median steps/s)")
    ap.add_argument("--write-scene", action="store_true", help="write the scene file and stop")
    ap.add_argument("--json", help="also write the results here")
    ap.add_argument("--pairs", type=int, metavar="STEPS", help="print lcpsim's contact points per pair and stop")
    ap.add_argument("--manifold-ab", metavar="SEEDS", help="lcpsim with parry's points and the support points, "
                    "from the same states of the bins of seeds FIRST-LAST (--steps each), and stop")
    ap.add_argument("--window", type=int, default=50, help="with --manifold-ab: steps from each saved state")
    ap.add_argument("--states-worker", nargs=4, help=argparse.SUPPRESS)
    ap.add_argument("--replay-worker", nargs=3, help=argparse.SUPPRESS)
    ap.add_argument("--worker", nargs=5, metavar=("ENGINE", "XML", "STEPS", "EVERY", "BUDGET"), help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        e, x, n, k, b = a.worker
        worker(e, x, int(n), int(k), float(b))
        return 0
    if a.pairs:
        points_per_pair(a.scene, a.pairs)
        return 0
    if a.states_worker:
        x, n, k, out = a.states_worker
        states_worker(x, int(n), int(k), out)
        return 0
    if a.replay_worker:
        x, states, n = a.replay_worker
        replay_worker(x, states, int(n))
        return 0
    if a.manifold_ab:
        first, _, last = a.manifold_ab.partition("-")
        manifold_ab(list(range(int(first), int(last or first) + 1)), a.steps, a.every, a.window)
        return 0
    if a.write_scene:
        Path(a.scene).parent.mkdir(parents=True, exist_ok=True)
        Path(a.scene).write_text(scene_xml())
        print(f"wrote {a.scene}")
        return 0
    sys.path.insert(0, str(HERE / "peers"))
    from many_bodies import crash_reason, run_worker

    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=HERE).stdout.strip()
    results: dict[str, Any] = {"scene": os.path.relpath(a.scene, HERE.parent), "steps": a.steps, "commit": commit,
                               "loadavg_before": os.getloadavg(), "engines": {}}
    for rnd in range(a.rounds):
        for engine in a.engines.split(","):
            cmd = [sys.executable, __file__, "--worker", engine, a.scene, str(a.steps), str(a.every), str(a.budget)]
            run = run_worker(cmd, a.budget + 120, int(a.mem_cap_gb * 2**30))
            r = judge(engine, a.scene, run["events"])
            r["peak_rss_mb"] = run["peak_rss_mb"]
            if run["killed"] or run["returncode"]:
                r["error"] = "killed" if run["killed"] else crash_reason(run["stderr"], run["returncode"])
            # The first round's state and counts (the runs are deterministic); every round's rate.
            first = results["engines"].setdefault(engine, r)
            first.setdefault("rates", []).append(r["steps_per_second"])
    for r in results["engines"].values():
        rates = [x for x in r["rates"] if x]
        r["steps_per_second"] = float(np.median(rates)) if rates else None
    results["loadavg_after"] = os.getloadavg()
    mj = results["engines"].get("mujoco", {}).get("steps_per_second")
    print(f"mixed bin ({results['scene']}, {a.steps} steps, commit {commit}, {a.rounds} rounds, load "
          f"{results['loadavg_before'][0]:.2f} before, {results['loadavg_after'][0]:.2f} after)")
    print("| engine | steps | steps/s, median (× MuJoCo) | failed LCPs | deepest penetration: any sample / last "
          "| lowest / highest z | outside the bin |")
    print("|---|---|---|---|---|---|---|")
    for engine, r in results["engines"].items():
        rate = r["steps_per_second"] or 0.0
        ratio = f" ({rate / mj:.3g}×)" if rate and mj else ""
        fails = "—" if r["failed_lcps"] is None else f"{r['failed_lcps']} ({r['lcps']} steps with an LCP)"
        pen = r["max_penetration_m"] if r["max_penetration_m"] is not None else float("nan")
        last = r["final_penetration_m"] if r["final_penetration_m"] is not None else float("nan")
        print(f"| {engine} | {r['steps']} | {rate:,.1f}{ratio} | {fails} | "
              f"{pen * 1e3:.2f} / {last * 1e3:.2f} mm | {r.get('lowest_z_m', float('nan')):.3f} / {r.get('highest_z_m', float('nan')):.3f} m"
              f" | {r.get('outside_bin')} |" + (f" {r['error']}" if "error" in r else ""))
    for engine, r in results["engines"].items():
        w = ", ".join(f"{x:,.0f}" for _, x in r["window_rates"] if x)
        print(f"{engine}, first round, steps/s per {a.every} steps: {w}")
        if r.get("islands_by_stage"):
            total = sum(r["islands_by_stage"].values())
            print(f"{engine}, islands answered by each stage: " + ", ".join(
                f"{k} {v:,} ({v / total:.1%})" for k, v in r["islands_by_stage"].items()))
    if a.json:
        Path(a.json).write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
