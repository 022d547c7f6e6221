"""Where a `solve_lcp` call's time goes : median µs per call of the
public `lcpsim.solve_lcp`, of the bare compiled `_core.solve_lcp` on the same
arrays, and of the compiled call on a 1×1 LCP (the glue's fixed cost, the
solve itself being negligible), for contact LCPs of sizes 20 and 40.

    python benchmarks/lcp_overhead.py [--repeat 2000] [--rounds 5]

Each figure is the median over `rounds` rounds of the median over `repeat`
calls cycling through 64 problems (the same problems for every column).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import lcpsim
from lcpsim import _core, generate


def median_us(fn, problems, repeat: int) -> float:
    """Median µs per `fn(M, q)` call, cycling through `problems`."""
    times = []
    for i in range(repeat):
        M, q = problems[i % len(problems)]
        t0 = time.perf_counter()
        fn(M, q)
        times.append(time.perf_counter() - t0)
    return statistics.median(times) * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    tiny = [(np.array([[2.0]]), np.array([-1.0]))]
    cols = {
        "solve_lcp": lcpsim.solve_lcp,
        "_core": _core.solve_lcp,
    }
    print(f"{'problem set':<16} " + " ".join(f"{c:>10}" for c in cols) + f" {'overhead':>10} {'_core 1x1':>10}")
    for nc in (2, 4):
        problems = [(p.M, p.q) for p in (generate.contact_lcp(nc, 8, 1.0, s) for s in range(64))]
        rounds = {c: [] for c in cols}
        rounds["tiny"] = []
        for _ in range(args.rounds):
            for c, fn in cols.items():
                rounds[c].append(median_us(fn, problems, args.repeat))
            rounds["tiny"].append(median_us(_core.solve_lcp, tiny, args.repeat))
        med = {c: statistics.median(v) for c, v in rounds.items()}
        print(
            f"{f'contact n={10 * nc}':<16} "
            + " ".join(f"{med[c]:>8.2f}µs" for c in cols)
            + f" {med['solve_lcp'] - med['_core']:>8.2f}µs {med['tiny']:>8.2f}µs"
        )


if __name__ == "__main__":
    main()
