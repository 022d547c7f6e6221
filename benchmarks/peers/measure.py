"""Timing of the peers' run (interleaved passes and back-to-back repeats,
see ``run.py``'s doc) and its per-group summaries: failures by the
solver's own word and by residual, median times, paired ratios."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from common import say
from problems import Problem, ProblemSet
from solvers import Solver


@dataclass
class Record:
    ok: bool = False
    status: str = ""
    res_given: float = float("inf")
    res_phys: float = float("inf")
    t_inter: list[float] = field(default_factory=list)
    t_b2b: list[float] = field(default_factory=list)


def timed_call(solver: Solver, p: Problem) -> tuple[float, tuple[bool, np.ndarray, str]]:
    # Every solver gets M and q freshly made (in cache, as a simulator that
    # has just assembled them would pass them); a peer's problem object is
    # built from them before the timer starts.
    run, finish = solver.prepare(p.M.copy(), p.q.copy())
    t0 = time.perf_counter()
    raw = run()
    t = time.perf_counter() - t0
    return t, finish(raw)


def measure(ps: ProblemSet, solvers: list[Solver], passes: int, repeats: int, slow: float) -> dict[str, list[Record]]:
    """Runs every solver on every problem of ``ps`` (see the module doc for the modes)."""
    recs = {s.key: [Record() for _ in ps.problems] for s in solvers}
    passes = ps.passes or passes
    started = time.perf_counter()
    for ip in range(passes):
        for i, p in enumerate(ps.problems):
            k = (i + ip) % len(solvers)
            for s in solvers[k:] + solvers[:k]:  # rotated order
                r = recs[s.key][i]
                if ip > 0 and r.t_inter and r.t_inter[0] > slow:
                    continue  # one sample is enough for a call this slow
                t, (ok, z, status) = timed_call(s, p)
                r.t_inter.append(t)
                if ip == 0:
                    r.ok, r.status = ok, status
                    r.res_given, r.res_phys = p.residuals(z)
        say(f"  {ps.key}: pass {ip + 1}/{passes} done ({time.perf_counter() - started:.1f} s)")
    if ps.back_to_back and repeats > 0:
        for i, p in enumerate(ps.problems):
            for s in solvers:
                r = recs[s.key][i]
                if r.t_inter and r.t_inter[0] > slow:
                    continue
                for _ in range(repeats):
                    t, _res = timed_call(s, p)
                    r.t_b2b.append(t)
        say(f"  {ps.key}: back-to-back done ({time.perf_counter() - started:.1f} s)")
    return recs


def summarize(ps: ProblemSet, recs: dict[str, list[Record]], tol: float, ref: str) -> dict[str, Any]:
    """Per group (size) and per solver: counts, failures, median times, paired ratios to ``ref``."""
    groups = ps.group_order or sorted({p.group for p in ps.problems})
    out: dict[str, Any] = {}
    for g in groups + ["all"]:
        idx = [i for i, p in enumerate(ps.problems) if g == "all" or p.group == g]
        if not idx:
            continue
        sizes = [ps.problems[i].n for i in idx]
        rows = {}
        for key, rr in recs.items():
            sel = [rr[i] for i in idx]
            own = sum(not r.ok for r in sel)
            bad_given = sum(not (r.res_given <= tol) for r in sel)
            bad_phys = sum(not (r.res_phys <= tol) for r in sel)
            wrong = sum(r.ok and not (r.res_phys <= tol) for r in sel)
            failed = sum((not r.ok) or not (r.res_phys <= tol) for r in sel)
            row: dict[str, Any] = {
                "problems": len(sel),
                "own_word": own,
                "residual_given": bad_given,
                "residual_physical": bad_phys,
                "said_solved_wrong": wrong,
                "failed": failed,
                "max_residual_physical": max(r.res_phys for r in sel),
            }
            for mode, attr in (("interleaved", "t_inter"), ("back_to_back", "t_b2b")):
                per = [float(np.median(getattr(r, attr))) if getattr(r, attr) else None for r in sel]
                ref_per = [
                    float(np.median(getattr(recs[ref][i], attr))) if getattr(recs[ref][i], attr) else None for i in idx
                ]
                have = [t for t in per if t is not None]
                row[f"median_s_{mode}"] = float(np.median(have)) if have else None
                pairs = [a / b for a, b in zip(per, ref_per) if a is not None and b is not None and b > 0]
                row[f"ratio_{mode}"] = float(np.median(pairs)) if pairs else None
                right = [
                    a / b
                    for a, b, r in zip(per, ref_per, sel)
                    if a is not None and b is not None and b > 0 and r.ok and r.res_phys <= tol
                ]
                row[f"ratio_{mode}_right"] = float(np.median(right)) if right else None
            rows[key] = row
        out[g] = {"sizes": [min(sizes), int(np.median(sizes)), max(sizes)], "solvers": rows}
    return out
