"""LCP solve times: median time per solve from Python, per call and
batched, for contact-structured LCPs (the Stewart–Trinkle layout, sizes 20 and 40) and random
SPD LCPs (40, 200, 1000), with the classic Lemke (the source note's tolerances) measured in the same
run as the baseline. `--rust` also runs the criterion bench (Rust-only times).

    python benchmarks/lcp_bench.py [--repeat 2000] [--rust]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np

import lcpsim
from lcpsim import generate


def per_call(problems, repeat: int, **options) -> tuple[float, int]:
    """Median seconds per `solve_lcp` call, cycling through `problems`; and failures."""
    times, failures = [], 0
    for i in range(repeat):
        p = problems[i % len(problems)]
        t0 = time.perf_counter()
        r = lcpsim.solve_lcp(p.M, p.q, **options)
        times.append(time.perf_counter() - t0)
        failures += (not r.ok) and i < len(problems)
    return statistics.median(times), failures


def batched(problems, **options) -> float:
    """Seconds per problem in one `solve_lcp_batch` call (GIL released)."""
    Ms = np.stack([p.M for p in problems])
    qs = np.stack([p.q for p in problems])
    t0 = time.perf_counter()
    lcpsim.solve_lcp_batch(Ms, qs, **options)
    return (time.perf_counter() - t0) / len(problems)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=2000)
    ap.add_argument("--rust", action="store_true", help="also run `cargo bench -p lcpsim-lcp --bench lemke`")
    args = ap.parse_args()
    print(f"lcpsim {lcpsim.__version__}, Python {platform.python_version()}, numpy {np.__version__}, {platform.processor() or platform.machine()}")
    print(f"{'problem set':<24} {'solver':<9} {'per call':>10} {'batched':>10} {'vs classic':>11} {'failures':>9}")
    sets = []
    for nc in (2, 4):
        for scale in (1.0, 1e-3, 1e-6):
            sets.append((f"contact n={10 * nc} s={scale:g}", [generate.contact_lcp(nc, 8, scale, seed) for seed in range(64)], args.repeat))
    for n, reps in ((40, 500), (200, 50), (1000, 3)):
        sets.append((f"SPD n={n}", [generate.spd_lcp(n, seed) for seed in range(min(reps, 8))], reps))
    for name, problems, repeat in sets:
        base, _ = per_call(problems, repeat, pivoting="classic")
        for solver, opts in (("robust", {}), ("classic", {"pivoting": "classic"})):
            t, fails = per_call(problems, repeat, **opts)
            tb = batched(problems, **opts)
            print(f"{name:<24} {solver:<9} {t * 1e6:>8.1f}µs {tb * 1e6:>8.1f}µs {base / t:>10.2f}x {fails:>6}/{len(problems)}")
    if args.rust:
        root = Path(__file__).resolve().parent.parent
        subprocess.run(["cargo", "bench", "-p", "lcpsim-lcp", "--bench", "lemke"], cwd=root, check=True)


if __name__ == "__main__":
    main()
