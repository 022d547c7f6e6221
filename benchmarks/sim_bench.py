"""Simulation throughput : steps per second with the stepping loop in
Rust (`World.run`) and with one `World.step` call per step from Python, for a
cube on a slope (4 contacts, LCP size 40), a 10-box stack and a 3×3×3 box pile,
with LCP sizes, pivots and failures. The baseline measured in the same run is
the same cube with the classic Lemke.

    python benchmarks/sim_bench.py [--seconds 2]
"""

from __future__ import annotations

import argparse
import platform
import time

import lcpsim
from lcpsim import scenes


def rate(scene, steps: int) -> tuple[float, object]:
    t0 = time.perf_counter()
    traj = scene.world.run(steps)
    return steps / (time.perf_counter() - t0), traj


def per_step_rate(scene, steps: int) -> float:
    t0 = time.perf_counter()
    for _ in range(steps):
        scene.world.step()
    return steps / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=2.0, help="simulated time per scene (dt = 1e-3)")
    args = ap.parse_args()
    steps = int(round(args.seconds / 1e-3))
    print(f"lcpsim {lcpsim.__version__}, Python {platform.python_version()}, {platform.processor() or platform.machine()}")
    print(f"{'scene':<28} {'run() steps/s':>14} {'step() steps/s':>15} {'LCP size':>9} {'pivots med/max':>15} {'failures':>9}")
    cases = [
        ("cube on 30° slope, μ 0.7", lambda **kw: scenes.cube_on_slope(30.0, 0.7, **kw), steps),
        ("cube on 45.0001°, μ 1", lambda **kw: scenes.cube_on_slope(45.0001, 1.0, **kw), steps),
        ("cube 30°, classic Lemke", lambda **kw: scenes.cube_on_slope(30.0, 0.7, pivoting="classic", **kw), steps),
        ("10-box stack", lambda **kw: scenes.box_stack(10, **kw), max(steps // 10, 50)),
        ("3×3×3 box pile", lambda **kw: scenes.box_pile(3, 3, 3, **kw), max(steps // 100, 10)),
    ]
    for name, build, n in cases:
        r, traj = rate(build(), n)
        r_step = per_step_rate(build(), min(n, 2000))
        st = traj.lcp_stats()
        print(f"{name:<28} {r:>14,.0f} {r_step:>15,.0f} {st.max_lcp_size:>9} {st.pivots_median:>7.0f}/{st.pivots_max:<7} {st.failures:>6}/{st.lcps}")


if __name__ == "__main__":
    main()
