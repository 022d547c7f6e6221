"""The Python engines of ``many_bodies.py`` and the worker loop they share with
Rapier's (``benchmarks/rapier_bench``): one engine × scene per process.

A worker builds the scene (lcpsim and MuJoCo from the scene's MJCF file,
PyBullet and Rapier from the description file), then runs ``reps`` fresh repetitions of ``steps`` steps,
each stopped once its wall clock passes ``budget`` seconds. It prints JSON
lines: ``ready`` (RSS after building), ``progress`` (steps done, seconds spent
stepping), ``sample`` (the dynamic boxes' poses and contact count, first
repetition only, every ``sample_every`` steps; a stepping call never crosses
a sample, so the seconds between samples are exact), ``stats`` (lcpsim's
counts so far, after each sample) and ``rep``. Only the stepping
calls are timed: building, sampling and reading out are not.

Engines keep their defaults except what the scene fixes — dt, gravity, μ = 0.5
for every pair, no restitution — and sleeping, switched off where an engine
has it on by default (PyBullet; Rapier in rapier_bench), so that every engine
solves every contact every step as lcpsim and MuJoCo do.
"""

from __future__ import annotations

import json
import math
import sys
import time
from typing import Any

import numpy as np

from many_scenes import describe, load

#: Target wall-clock length of one stepping call (steps are batched between samples).
CHUNK_SECONDS = 0.25


def emit(event: str, **fields: Any) -> None:
    print(json.dumps({"event": event, **fields}), flush=True)


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


class LcpsimEngine:
    """lcpsim's ``World.run`` (the loop in Rust), the scene from its MJCF file."""

    def __init__(self, scene_key: str, desc: dict[str, Any]) -> None:
        world, how = load(scene_key)
        mine = describe(world, how)
        if mine["boxes"] != desc["boxes"]:
            raise RuntimeError("lcpsim built a different scene from the description (layout changed?)")
        self.w = world
        self.dyn = np.array([i for i in range(world.body_count)
                             if world.body(i).kind == "box" and not world.body(i).is_static])
        self.stats = {"lcps": 0, "failures": 0, "max_lcp_size": 0, "max_contacts": 0, "pivots": 0,
                      "max_pivots": 0, "statuses": {},
                      # Per step: pivots (every island's, every attempt's), contacts, LCP failed (0/1).
                      "step_pivots": [], "step_contacts": [], "step_failed": [],
                      # Per stepping call, where lcpsim reports them (Trajectory.lcp_stats().stages):
                      # [first step, steps, islands answered by each stage of STAGES in turn, by any other].
                      "stage_calls": [], "stages_recorded": False, "backstop_recorded": False,
                      "backstop_islands": 0.0, "stage_islands": 0}
        self.last_contacts = 0
        self.done = 0

    #: The island solve chain's stages, in order; the last one (the dense Lemke) is the backstop.
    STAGES = ("previous_basis", "guessed_basis", "structured_lemke", "dense_lemke")
    #: lcpsim's names of them where they differ (``lcpsim.trajectory.STAGES``: the last one is "dense").
    ALIASES = {"dense": "dense_lemke"}

    def record_stages(self, traj: Any, k: int) -> None:
        """The solve chain's stages of this call's islands, where ``lcp_stats()`` has them
        (``stages``: islands per stage; ``backstop_fraction``: the share of islands that
        reached the dense Lemke); nothing otherwise (the report says "not recorded")."""
        ls = traj.lcp_stats()
        s = self.stats
        stages = getattr(ls, "stages", None)
        islands = None
        if stages is not None:
            s["stages_recorded"] = True
            stages = {self.ALIASES.get(name, name): v for name, v in stages.items()}
            counts = [int(stages.get(name, 0)) for name in self.STAGES]
            other = sum(int(v) for name, v in stages.items() if name not in self.STAGES)
            s["stage_calls"].append([self.done, k, *counts, other])
            islands = sum(int(v) for v in stages.values())
            for name, v in stages.items():
                if name not in self.STAGES:
                    s.setdefault("other_stages", {})
                    s["other_stages"][name] = s["other_stages"].get(name, 0) + int(v)
        frac = getattr(ls, "backstop_fraction", None)
        if frac is not None:
            s["backstop_recorded"] = True
            if islands is None:
                islands = int(traj.islands.sum())
            s["backstop_islands"] += float(frac) * islands
            s["stage_islands"] += islands

    def step(self, k: int) -> None:
        traj = self.w.run(k)
        has = traj.status != "no_contact"
        s = self.stats
        s["step_pivots"] += traj.pivots.astype(int).tolist()
        s["step_contacts"] += traj.contacts.astype(int).tolist()
        s["step_failed"] += (~traj.ok).astype(int).tolist()
        self.record_stages(traj, k)
        self.done += k
        s["lcps"] += int(has.sum())
        s["failures"] += traj.failures
        s["max_lcp_size"] = max(s["max_lcp_size"], int(traj.lcp_size.max(initial=0)))
        s["max_contacts"] = max(s["max_contacts"], int(traj.contacts.max(initial=0)))
        s["pivots"] += int(traj.pivots[has].sum())
        s["max_pivots"] = max(s["max_pivots"], int(traj.pivots.max(initial=0)))
        for st in traj.status[has]:
            s["statuses"][str(st)] = s["statuses"].get(str(st), 0) + 1
        if hasattr(traj, "max_island_size"):  # lcpsim with contact islands: one LCP per island
            s["max_islands"] = max(s.get("max_islands", 0), int(traj.islands.max(initial=0)))
            s["max_island_lcp"] = max(s.get("max_island_lcp", 0), int(traj.max_island_size.max(initial=0)))
        self.last_contacts = int(traj.contacts[-1]) if len(traj) else 0

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        return self.w.positions[self.dyn], self.w.orientations[self.dyn]

    def contacts(self) -> int:
        return self.last_contacts


class MujocoEngine:
    """MuJoCo with its defaults (pyramidal cone, Newton solver, soft contacts),
    ``mj_step(m, d, nstep)`` from Python; the scene's MJCF file."""

    def __init__(self, scene_key: str, desc: dict[str, Any]) -> None:
        import mujoco

        self.mj = mujoco
        self.m = mujoco.MjModel.from_xml_path(desc["mjcf"])
        self.d = mujoco.MjData(self.m)
        mujoco.mj_forward(self.m, self.d)
        self.n = sum(not b["static"] for b in desc["boxes"])
        self.stats = {"max_contacts": 0}

    def step(self, k: int) -> None:
        self.mj.mj_step(self.m, self.d, nstep=k)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        qpos = self.d.qpos.reshape(self.n, 7)
        return qpos[:, :3].copy(), qpos[:, 3:].copy()

    def contacts(self) -> int:
        c = int(self.d.ncon)
        self.stats["max_contacts"] = max(self.stats["max_contacts"], c)
        return c


class PybulletEngine:
    """PyBullet (DIRECT) with its defaults (sequential impulses, 50 iterations)
    but no sleeping (as for Rapier: every contact solved every step),
    ``stepSimulation`` per step from Python; every body's lateral friction is
    √μ because Bullet multiplies the two bodies' values."""

    def __init__(self, scene_key: str, desc: dict[str, Any]) -> None:
        import pybullet as pb

        self.pb = pb
        self.cid = pb.connect(pb.DIRECT)
        pb.setGravity(0, 0, -desc["gravity"], physicsClientId=self.cid)
        pb.setTimeStep(desc["dt"], physicsClientId=self.cid)
        f = math.sqrt(desc["mu"])
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=self.cid)
        all_ids = [pb.createMultiBody(0, plane, physicsClientId=self.cid)]
        self.ids = []
        shapes: dict[tuple[float, ...], int] = {}
        for b in desc["boxes"]:
            key = tuple(b["half"])
            if key not in shapes:
                shapes[key] = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(key), physicsClientId=self.cid)
            w, x, y, z = b["quat"]
            body = pb.createMultiBody(0.0 if b["static"] else b["mass"], shapes[key], basePosition=b["pos"],
                                      baseOrientation=[x, y, z, w], physicsClientId=self.cid)
            all_ids.append(body)
            if not b["static"]:
                self.ids.append(body)
        for body in all_ids:
            pb.changeDynamics(body, -1, lateralFriction=f, restitution=0.0, rollingFriction=0.0,
                              spinningFriction=0.0, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING,
                              physicsClientId=self.cid)
        self.stats = {"max_contacts": 0}

    def step(self, k: int) -> None:
        for _ in range(k):
            self.pb.stepSimulation(physicsClientId=self.cid)

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        pos = np.empty((len(self.ids), 3))
        quat = np.empty((len(self.ids), 4))
        for i, body in enumerate(self.ids):
            p, o = self.pb.getBasePositionAndOrientation(body, physicsClientId=self.cid)
            pos[i], quat[i] = p, (o[3], o[0], o[1], o[2])
        return pos, quat

    def contacts(self) -> int:
        c = len(self.pb.getContactPoints(physicsClientId=self.cid))
        self.stats["max_contacts"] = max(self.stats["max_contacts"], c)
        return c


ENGINES = {"lcpsim": LcpsimEngine, "mujoco": MujocoEngine, "pybullet": PybulletEngine}


def sample(engine: Any, step: int) -> None:
    pos, quat = engine.poses()
    emit("sample", step=step, pos=np.asarray(pos).tolist(), quat=np.asarray(quat).tolist(),
         contacts=engine.contacts())


def run_rep(make: Any, steps: int, budget: float, sample_every: int, rep: int) -> None:
    engine = make()
    if rep == 0:
        emit("ready", rss_mb=rss_mb())
        sample(engine, 0)
    done, seconds, rate = 0, 0.0, 0.0
    wall = time.perf_counter()
    timed_out = False
    while done < steps:
        if time.perf_counter() - wall > budget:
            timed_out = True
            break
        next_sample = (done // sample_every + 1) * sample_every
        k = 1 if rate == 0 else max(1, int(rate * CHUNK_SECONDS))
        k = min(k, next_sample - done, steps - done)
        t0 = time.perf_counter()
        engine.step(k)
        dt = time.perf_counter() - t0
        seconds += dt
        done += k
        rate = k / dt if dt > 0 else 1e9
        emit("progress", rep=rep, steps=done, seconds=seconds)
        if rep == 0 and (done == next_sample or done == steps):
            sample(engine, done)
            if "step_pivots" in getattr(engine, "stats", {}):
                # lcpsim's counts so far: what a run killed in a stepping call still reports.
                emit("stats", rep=rep, steps=done, stats=engine.stats)
    if rep == 0 and timed_out:
        sample(engine, done)
    emit("rep", rep=rep, steps=done, seconds=seconds, timed_out=timed_out, stats=getattr(engine, "stats", {}))


def worker(engine: str, scene_key: str, desc_path: str, steps: int, budget: float, sample_every: int,
           reps: int) -> int:
    with open(desc_path) as f:
        desc = json.load(f)
    cls = ENGINES[engine]
    emit("start", engine=engine, scene=scene_key)
    start, last = time.perf_counter(), 0.0
    for rep in range(max(1, reps)):
        if rep > 0 and time.perf_counter() - start + last > budget:
            break
        t0 = time.perf_counter()
        run_rep(lambda: cls(scene_key, desc), steps, budget, sample_every, rep)
        last = time.perf_counter() - t0
    return 0


if __name__ == "__main__":
    e, s, p, n, b, k, r = sys.argv[1:8]
    raise SystemExit(worker(e, s, p, int(n), float(b), int(k), int(r)))
