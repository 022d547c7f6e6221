"""The 10-box stack beside MuJoCo in one window, at both cones and two lengths.

``benchmarks/scenes/stack10.xml`` (the peers benchmark's stack: 1 kg unit
cubes, μ = 0.5, dt 1 ms) run by lcpsim (``World.from_mjcf``, ``World.run``)
at 8 friction directions and at the file's cone (MuJoCo's default pyramid:
4 directions), and by MuJoCo (``mj_step(m, d, nstep)``), one after the other
in each round, so every round's ratios share the machine's state. The
length of the run matters where a scene's later steps cost more than its
first ones (the stack's did until its boxes stopped rocking by round-off:
``benchmarks/step_budget.md``): give it as STEPS.

    python benchmarks/stack_window.py [STEPS] [ROUNDS]      # defaults 4000, 3

MuJoCo is not a dependency of lcpsim: install it beside (``pip install mujoco``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

XML = Path(__file__).resolve().parent / "scenes" / "stack10.xml"


def main() -> None:
    import mujoco
    from lcpsim import World

    steps = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    model = mujoco.MjModel.from_xml_path(str(XML))
    print(f"10-box stack ({XML.name}), {steps} steps, steps/s (x MuJoCo in the same round)")
    for r in range(rounds):
        rates = {}
        for k in (8, 4):
            world = World.from_mjcf(XML, friction_dirs=k)
            t = time.perf_counter()
            traj = world.run(steps)
            rates[k] = steps / (time.perf_counter() - t)
            failures = traj.lcp_stats().failures
            assert failures == 0, f"{failures} failed LCPs at {k} friction directions"
        data = mujoco.MjData(model)
        t = time.perf_counter()
        mujoco.mj_step(model, data, steps)
        mj = steps / (time.perf_counter() - t)
        cells = "  ".join(f"lcpsim k={k}: {v:,.0f} ({v / mj:.3f}x)" for k, v in rates.items())
        print(f"round {r + 1}: {cells}  MuJoCo: {mj:,.0f}", flush=True)


if __name__ == "__main__":
    main()
