"""One step from Python: lcpsim's ``World.step()`` (its record's fields are
converted when read), the same with one field read (``.fn``), its Rust
core's ``step`` (no ``StepRecord`` wrapper), ``World.run`` per step, beside
MuJoCo's ``mj_step`` called from Python and ``mj_step(nstep=)``.

Scenes: a cube sliding down 30° (μ 0.5), a cube resting on 30° (μ 0.7), a
resting 10-box stack (lcpsim only). MuJoCo's cube is the one of
``benchmarks/peers/sim_peers.py`` (the same slope, size, mass, μ, dt 1 ms,
elliptic cone). Each figure is the minimum over repetitions of the mean over
a batch of steps (the machine is shared), every batch a plain ``for`` loop of
calls (each record let go at once), lcpsim's as MuJoCo's. The Rust side stage by stage:
``crates/sim/examples/step_budget.rs``.

    python benchmarks/step_budget.py [STEPS] [REPS]

MuJoCo is not a dependency of lcpsim: install it beside (``pip install mujoco``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Callable

sys.path.insert(0, str(Path(__file__).resolve().parent / "peers"))
from sim_peers import mujoco_xml  # noqa: E402  (the same cube on a slope as the peers benchmark)



def best(f: Callable[[int], object], n: int, reps: int) -> float:
    """Fastest mean µs per step over `reps` batches of `n` steps."""
    out = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        f(n)
        out = min(out, (time.perf_counter() - t0) / n)
    return out * 1e6


def lcpsim_rows(steps: int, reps: int) -> list[tuple[str, float, float, float, float]]:
    from lcpsim import scenes

    rows = []
    for name, make in [
        ("cube sliding on 30°, μ 0.5", lambda: scenes.cube_on_slope(30.0, 0.5)),
        ("cube resting on 30°, μ 0.7", lambda: scenes.cube_on_slope(30.0, 0.7)),
        ("10-box stack, resting", lambda: scenes.box_stack(10)),
    ]:
        w = make().world
        for _ in range(100):
            w.step()
        core = w._core
        n = steps if "stack" not in name else max(steps // 10, 50)
        # Plain loops, as MuJoCo's below (each record let go at once).
        def step_loop(k: int) -> None:
            for _ in range(k):
                w.step()

        def step_fn_loop(k: int) -> None:
            for _ in range(k):
                w.step().fn

        def core_loop(k: int) -> None:
            for _ in range(k):
                core.step()

        step = best(step_loop, n, reps)
        step_fn = best(step_fn_loop, n, reps)
        core_step = best(core_loop, n, reps)
        run = best(lambda k: w.run(k), n, reps)
        rows.append((name, step, step_fn, core_step, run))
    return rows


def mujoco_rows(steps: int, reps: int) -> list[tuple[str, float, float]]:
    try:
        import mujoco
    except ImportError as e:  # pragma: no cover - optional
        print(f"(MuJoCo not measured: {e})")
        return []
    rows = []
    for name, angle, mu in [("cube sliding on 30°, μ 0.5", 30.0, 0.5), ("cube resting on 30°, μ 0.7", 30.0, 0.7)]:
        m = mujoco.MjModel.from_xml_string(mujoco_xml(angle, mu, "elliptic"))
        d = mujoco.MjData(m)
        for _ in range(100):
            mujoco.mj_step(m, d)
        assert d.ncon > 0, "the cube must touch the slope"

        def loop(k: int) -> None:
            for _ in range(k):
                mujoco.mj_step(m, d)

        rows.append((f"{name} (ncon {d.ncon})", best(loop, steps, reps), best(lambda k: mujoco.mj_step(m, d, nstep=k), steps, reps)))
    return rows


def main() -> None:
    steps = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    print(f"µs per step, min over {reps} batches of {steps} steps")
    print(f"{'lcpsim':<34} {'World.step':>10} {'step().fn':>10} {'_core.step':>10} {'World.run':>10}")
    for name, a, b, c, d in lcpsim_rows(steps, reps):
        print(f"{name:<34} {a:>10.2f} {b:>10.2f} {c:>10.2f} {d:>10.2f}")
    print(f"{'MuJoCo':<34} {'mj_step':>10} {'nstep=':>10}")
    for name, a, b in mujoco_rows(steps, reps):
        print(f"{name:<34} {a:>10.2f} {b:>10.2f}")


if __name__ == "__main__":
    main()
