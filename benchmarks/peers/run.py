#!/usr/bin/env python3
"""lcpsim beside Siconos and Drake on the same LCPs, in one run (issue 6).

Run it in the peers' venv (``bash benchmarks/peers/setup.sh`` makes it)::

    benchmarks/peers/.venv/bin/python benchmarks/peers/run.py

Solvers, each called once per problem from Python, one call per timed solve:

- lcpsim robust (``solve_lcp(M, q)``: lexicographic Lemke, the default) and
  lcpsim classic (``pivoting="classic"``: the seed note's absolute tolerances);
- Siconos 4.4 (Debian ``python3-siconos``) through ``siconos.numerics``:
  ``lcp_lexicolemke``, ``lcp_pivot``, ``lcp_newton_FB``, default options
  (tolerance 1e-6 on the problem as given);
- Drake (PyPI ``drake``): ``MobyLcpSolver`` and ``UnrevisedLemkeSolver``
  through a ``MathematicalProgram`` with ``AddLinearComplementarityConstraint``
  (Moby's ``Solve`` runs ``SolveLcpLemkeRegularized``; Drake binds no other
  Moby entry point in Python).

What is inside the timer: lcpsim's call takes numpy ``M, q`` and returns its
result object (conversion included). For the peers the problem object is built
outside the timer (``sn.LCP(M, q)``, ``SolverOptions``, output arrays; Drake's
``MathematicalProgram`` with its constraint) and only the solve call — plus
Drake's ``GetSolution`` — is timed, which favours the peers. Every solver is
handed fresh copies of ``M`` and ``q`` made just before (so the input is in
cache, as after a simulator's assembly, for lcpsim as much as for a peer whose
problem object was just built).

Timing modes, both from ``time.perf_counter`` around each call:

- *interleaved* (the headline): ``--passes`` passes over a problem set; in a
  pass every problem is solved once by every solver in turn (order rotated),
  so each call finds caches and branch predictors warmed by other code, as a
  simulator's solve would, and load changes hit all solvers alike. Per
  problem the median over passes.
- *back-to-back*: ``--repeats`` consecutive calls of one solver on one problem
  (warm caches), median per problem. Skipped for slow sets.

The ratio of a peer to lcpsim robust is the median over problems of the
per-problem time ratio (paired), so problems of different sizes weigh alike.

Failures: by the solver's own word (Siconos ``info != 0``, Drake
``is_success()`` false, lcpsim ``status != "solved"``) and by an independent
check of the returned ``z``: the natural residual ``‖min(z, Mz + q)‖∞`` above
``--tol`` (1e-6), computed both in the units the solver was given and in
physical units — for a cone-scaled contact LCP ``z_phys = D z`` (λ multiplied
by s) on the unscaled problem ``(M₁, q₁)``, impulses in N·s, velocities in m/s.
A solve counts as failed if the solver says so or its physical residual is
above the tolerance; "said solved, wrong" counts those the solver called solved.

Writes ``benchmarks/RESULTS.md`` (with the simulation throughput of
``sim_peers.py`` unless ``--no-sim``) and ``benchmarks/peers/results.json.gz`` (raw per-problem results: labels,
sizes, statuses, residuals, median times; gzip-compressed JSON).
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import gzip
import importlib
import json
import os
import platform
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator

# One BLAS thread (set before numpy loads OpenBLAS): the peers' LAPACK calls must
# not spin extra threads on a shared 2-core machine.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
RESULTS_MD = ROOT / "benchmarks" / "RESULTS.md"
RESULTS_JSON = HERE / "results.json.gz"  # gzip-compressed JSON

# ---------------------------------------------------------------------------
# Console: peers print from C to fds 1 and 2; those go to a log, progress to the real stderr.
# ---------------------------------------------------------------------------

_REAL_ERR: int | None = None


def say(*parts: Any) -> None:
    msg = (" ".join(str(p) for p in parts) + "\n").encode()
    os.write(_REAL_ERR if _REAL_ERR is not None else 2, msg)


@contextlib.contextmanager
def peers_chatter_to(path: Path) -> Iterator[None]:
    """Redirects fds 1 and 2 (C-level printf of Siconos, Drake logging) to ``path``."""
    global _REAL_ERR
    sys.stdout.flush()
    sys.stderr.flush()
    saved_out, saved_err = os.dup(1), os.dup(2)
    log = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    _REAL_ERR = saved_err
    os.dup2(log, 1)
    os.dup2(log, 2)
    try:
        yield
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(saved_out, 1)
        os.dup2(saved_err, 2)
        os.close(log)
        os.close(saved_out)
        os.close(saved_err)
        _REAL_ERR = None


# ---------------------------------------------------------------------------
# Problems
# ---------------------------------------------------------------------------


@dataclass
class Problem:
    """``(M, q)`` as given to the solvers; ``d`` the cone-scaling diagonal and
    ``(M1, q1)`` the unscaled problem for the physical residual (None: the
    problem is its own physical form)."""

    M: np.ndarray
    q: np.ndarray
    label: str
    group: str
    d: np.ndarray | None = None
    M1: np.ndarray | None = None
    q1: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.q.shape[0])

    def residuals(self, z: np.ndarray) -> tuple[float, float]:
        """(natural residual in the units given, in physical units); NaN → inf."""

        def nat(M: np.ndarray, q: np.ndarray, z: np.ndarray) -> float:
            if z.shape != q.shape or not np.all(np.isfinite(z)):
                return float("inf")
            with np.errstate(all="ignore"):
                r = float(np.max(np.abs(np.minimum(z, M @ z + q))))
            return r if np.isfinite(r) else float("inf")

        given = nat(self.M, self.q, z)
        if self.d is None or self.M1 is None or self.q1 is None:
            return given, given
        return given, nat(self.M1, self.q1, self.d * z)


@dataclass
class ProblemSet:
    key: str
    title: str
    description: str
    problems: list[Problem]
    back_to_back: bool = True
    passes: int | None = None  # None: the --passes default
    group_order: list[str] = field(default_factory=list)


def scale_label(s: float) -> str:
    return "none" if s == 1.0 else f"{s:g}"


def contact_sets(scales: list[float], per_size: int, seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    out = []
    for s in scales:
        probs = []
        for nc in (1, 2, 4):
            for i in range(per_size):
                p = generate.contact_lcp(nc, 8, s, seed + i)
                p1 = p.at_scale(1.0)
                probs.append(
                    Problem(p.M, p.q, p.label, f"n = {p.n}", p.cone_diagonal() if s != 1.0 else None, p1.M, p1.q)
                )
        out.append(
            ProblemSet(
                f"contact/s={scale_label(s)}",
                f"Contact LCPs (DESIGN §5 cube), s = {scale_label(s)}",
                f"`lcpsim.generate.contact_lcp(nc, 8, s, seed)`, nc ∈ {{1, 2, 4}} (n = 10, 20, 40), seeds "
                f"{seed}…{seed + per_size - 1}: unit cube on a 0–60° slope, μ ∈ [0.1, 1.5], random velocity, "
                f"h = 0.01, friction-cone scale s = {scale_label(s)}.",
                probs,
                group_order=["n = 10", "n = 20", "n = 40"],
            )
        )
    return out


def seed_corpus_sets(scales: list[float], per_size: int, seed: int) -> tuple[list[ProblemSet], str]:
    """The experiments' seed corpus (``lcpsim.experiments.seed_corpus``), if installed.

    Hook: any module providing ``generate(config) -> corpus`` whose ``groups``
    each have ``M`` (b, n, n), ``q`` (b, n) unscaled, ``contacts`` and
    ``friction_dirs`` is used; the LCPs are scaled here by ``D = diag(I, I, s·I)``.
    """
    try:
        sc = importlib.import_module("lcpsim.experiments.seed_corpus")
        corpus = sc.generate()
    except Exception as e:  # not there yet, or broken: say so in the report
        return [], f"seed corpus not included: `lcpsim.experiments.seed_corpus` unavailable ({type(e).__name__}: {e})"
    rng = np.random.default_rng(seed)
    picked = []
    for g in corpus.groups:
        idx = np.sort(rng.choice(len(g.q), size=min(per_size, len(g.q)), replace=False))
        picked.append((g, idx))
    out = []
    for s in scales:
        probs = []
        for g, idx in picked:
            nc, k = int(g.contacts), int(g.friction_dirs)
            d = np.ones(g.q.shape[1])
            d[nc * (k + 1) :] = s
            for i in idx:
                M1, q1 = np.ascontiguousarray(g.M[i]), np.ascontiguousarray(g.q[i])
                M, q = (M1, q1) if s == 1.0 else (M1 * d[:, None] * d[None, :], q1 * d)
                probs.append(
                    Problem(M, q, f"seed/{int(g.index[i])}", f"n = {g.n}", d if s != 1.0 else None, M1, q1)
                )
        out.append(
            ProblemSet(
                f"seed/s={scale_label(s)}",
                f"Seed corpus (simulation LCPs), s = {scale_label(s)}",
                f"`lcpsim.experiments.seed_corpus.generate()` (default config, {len(corpus)} LCPs from cube "
                f"simulations at h = 1e-3, assembled unscaled); a seeded subset of at most {per_size} per size, "
                f"scaled by D = diag(I, I, s·I) with s = {scale_label(s)}.",
                probs,
                group_order=[f"n = {g.n}" for g, _ in picked],
            )
        )
    return out, f"seed corpus: {len(corpus)} LCPs, {per_size} per size sampled"


def hard_sets(scales: list[float], count: int, seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    def bucket(n: int) -> str:
        return "n ≤ 40" if n <= 40 else "41 ≤ n ≤ 100" if n <= 100 else "n > 100"

    out = []
    for s in scales:
        probs = []
        for p in generate.hard_corpus(seed, count, s):
            p1 = p.at_scale(1.0)
            probs.append(Problem(p.M, p.q, p.label, bucket(p.n), p.cone_diagonal() if s != 1.0 else None, p1.M, p1.q))
        out.append(
            ProblemSet(
                f"hard/s={scale_label(s)}",
                f"Hard contact LCPs, s = {scale_label(s)}",
                f"`lcpsim.generate.hard_corpus({seed}, {count}, s)`: the seven families of issue 5 in turn (many, "
                f"duplicate, nearly parallel, collinear contacts; mass ratios to 1e4; thin rods with cond(M_b) to 1e8; "
                f"mixed), k = 8 (some 4 and 16), n = "
                f"{min(p.n for p in probs)}–{max(p.n for p in probs)}, s = {scale_label(s)}.",
                probs,
                back_to_back=False,
                group_order=["n ≤ 40", "41 ≤ n ≤ 100", "n > 100"],
            )
        )
    return out


def spd_sets(sizes: list[tuple[int, int]], seed: int) -> list[ProblemSet]:
    from lcpsim import generate

    out = []
    for n, count in sizes:
        probs = []
        for i in range(count):
            p = generate.spd_lcp(n, seed + i)
            probs.append(Problem(p.M, p.q, p.label, f"n = {n}"))
        big = n >= 500
        out.append(
            ProblemSet(
                f"spd/n={n}",
                f"Random SPD LCPs, n = {n}",
                f"`lcpsim.generate.spd_lcp({n}, seed)`, seeds {seed}…{seed + count - 1}: M = A Aᵀ/n + 0.1 I "
                f"(A uniform in [−1, 1]), q uniform in [−1, 1].",
                probs,
                back_to_back=not big,
                passes=1 if big else None,
                group_order=[f"n = {n}"],
            )
        )
    return out


# ---------------------------------------------------------------------------
# Solvers: prepare(M, q) -> (run, finish); only run() is timed; finish(raw) -> (ok, z, status)
# ---------------------------------------------------------------------------

Prepared = tuple[Callable[[], Any], Callable[[Any], tuple[bool, np.ndarray, str]]]


@dataclass
class Solver:
    key: str
    name: str
    family: str
    prepare: Callable[[np.ndarray, np.ndarray], Prepared]
    note: str = ""


def lcpsim_solvers() -> list[Solver]:
    import lcpsim

    def make(**opts: Any) -> Callable[[np.ndarray, np.ndarray], Prepared]:
        def prepare(M: np.ndarray, q: np.ndarray) -> Prepared:
            def finish(r: Any) -> tuple[bool, np.ndarray, str]:
                return bool(r.ok), np.asarray(r.z), str(r.status)

            return (lambda: lcpsim.solve_lcp(M, q, **opts)), finish

        return prepare

    return [
        Solver("lcpsim_robust", "lcpsim robust", "lcpsim", make(), "`solve_lcp(M, q)` (lexicographic, the default)"),
        Solver("lcpsim_classic", "lcpsim classic", "lcpsim", make(pivoting="classic"), "`pivoting=\"classic\"`"),
    ]


def siconos_solvers() -> tuple[list[Solver], str]:
    try:
        import siconos.numerics as sn
    except Exception as e:
        return [], f"Siconos unavailable: {e}"

    def make(fn: Callable[..., int], solver_id: int) -> Callable[[np.ndarray, np.ndarray], Prepared]:
        def prepare(M: np.ndarray, q: np.ndarray) -> Prepared:
            n = q.shape[0]
            problem = sn.LCP(np.ascontiguousarray(M), np.ascontiguousarray(q))
            options = sn.SolverOptions(solver_id)
            z, w = np.zeros(n), np.zeros(n)

            def finish(info: int) -> tuple[bool, np.ndarray, str]:
                return info == 0, z, f"info={info}"

            return (lambda: fn(problem, z, w, options)), finish

        return prepare

    return [
        Solver("siconos_lexicolemke", "Siconos lexicolemke", "Siconos", make(sn.lcp_lexicolemke, sn.SICONOS_LCP_LEMKE),
               "`lcp_lexicolemke`, `SolverOptions(SICONOS_LCP_LEMKE)`"),
        Solver("siconos_pivot", "Siconos pivot", "Siconos", make(sn.lcp_pivot, sn.SICONOS_LCP_PIVOT),
               "`lcp_pivot`, `SolverOptions(SICONOS_LCP_PIVOT)` (default pivoting rule)"),
        Solver("siconos_newton_fb", "Siconos Newton-FB", "Siconos",
               make(sn.lcp_newton_FB, sn.SICONOS_LCP_NEWTON_FB_FBLSA),
               "`lcp_newton_FB`, `SolverOptions(SICONOS_LCP_NEWTON_FB_FBLSA)`, z₀ = 0"),
    ], "ok"


def drake_solvers() -> tuple[list[Solver], str]:
    try:
        from pydrake.solvers import MathematicalProgram, MobyLcpSolver, UnrevisedLemkeSolver
    except Exception as e:
        return [], f"Drake unavailable: {e}"

    def make(solver_class: Any) -> Callable[[np.ndarray, np.ndarray], Prepared]:
        def prepare(M: np.ndarray, q: np.ndarray) -> Prepared:
            # A fresh solver per call: UnrevisedLemkeSolver keeps the last basis and would
            # warm-start a repeated solve of the same problem; every other call here is cold.
            solver = solver_class()
            prog = MathematicalProgram()
            x = prog.NewContinuousVariables(q.shape[0], "z")
            prog.AddLinearComplementarityConstraint(M, q, x)

            def run() -> Any:
                r = solver.Solve(prog)
                return r, r.GetSolution(x)

            def finish(raw: Any) -> tuple[bool, np.ndarray, str]:
                r, z = raw
                return bool(r.is_success()), np.asarray(z, dtype=float), str(r.get_solution_result()).split(".")[-1]

            return run, finish

        return prepare

    return [
        Solver("drake_moby", "Drake Moby", "Drake", make(MobyLcpSolver),
               "`MobyLcpSolver().Solve(prog)` → `SolveLcpLemkeRegularized`"),
        Solver("drake_unrevised", "Drake UnrevisedLemke", "Drake", make(UnrevisedLemkeSolver),
               "`UnrevisedLemkeSolver().Solve(prog)`"),
    ], "ok"


# ---------------------------------------------------------------------------
# Measurement
# ---------------------------------------------------------------------------


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


# ---------------------------------------------------------------------------
# Summaries
# ---------------------------------------------------------------------------


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


def fmt_time(t: float | None) -> str:
    if t is None:
        return "—"
    if t < 1e-3:
        return f"{t * 1e6:.1f} µs"
    if t < 1.0:
        return f"{t * 1e3:.2f} ms"
    return f"{t:.2f} s"


def fmt_ratio(r: float | None) -> str:
    return "—" if r is None else f"{r:.2f}×"


def fmt_count(k: int, n: int) -> str:
    if k == 0:
        return "0"
    pct = 100.0 * k / n
    return f"{k} ({pct:.1f} %)" if pct < 1 else f"{k} ({pct:.0f} %)"


def table(summary: dict[str, Any], solvers: list[Solver], b2b: bool) -> list[str]:
    head = ["group", "solver", "failed", "own word", "resid. > tol (given)", "resid. > tol (phys.)",
            "said solved, wrong", "median (interleaved)", "× robust"]
    if b2b:
        head += ["median (back-to-back)", "× robust"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for g, gs in summary.items():
        if g == "all" and len(summary) == 2:
            continue  # one group: "all" repeats it
        label = f"{g}" if g != "all" else f"all (n = {gs['sizes'][0]}–{gs['sizes'][2]})"
        for s in solvers:
            r = gs["solvers"][s.key]
            n = r["problems"]
            cells = [label, s.name, fmt_count(r["failed"], n), fmt_count(r["own_word"], n),
                     fmt_count(r["residual_given"], n), fmt_count(r["residual_physical"], n),
                     fmt_count(r["said_solved_wrong"], n),
                     fmt_time(r["median_s_interleaved"]), fmt_ratio(r["ratio_interleaved"])]
            if b2b:
                cells += [fmt_time(r["median_s_back_to_back"]), fmt_ratio(r["ratio_back_to_back"])]
            lines.append("| " + " | ".join(cells) + " |")
            label = ""
    return lines


# ---------------------------------------------------------------------------
# Machine and versions
# ---------------------------------------------------------------------------


def loadavg() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "?"


def machine() -> dict[str, Any]:
    cpu = "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = "?"
    try:
        kb = int(Path("/proc/meminfo").read_text().split()[1])
        mem = f"{kb / 2**20:.1f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "cores_usable": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "memory": mem,
        "kernel": platform.release(),
        "os": platform.platform(),
    }


def versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    v: dict[str, str] = {"python": platform.python_version()}
    for dist in ("numpy", "lcpsim", "drake", "mujoco", "pybullet"):
        try:
            v[dist] = version(dist)
        except PackageNotFoundError:
            v[dist] = "not installed"
    try:
        v["siconos"] = subprocess.run(
            ["dpkg-query", "-W", "-f=${Version}", "python3-siconos"], capture_output=True, text=True, check=False
        ).stdout.strip() or "?"
    except OSError:
        v["siconos"] = "?"
    rev = Path(sys.prefix) / "lcpsim-revision.txt"
    if rev.exists():
        v["lcpsim_revision"] = rev.read_text().strip()
    else:
        try:
            v["lcpsim_revision"] = subprocess.run(
                ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
            ).stdout.strip() + " (work tree)"
        except OSError:
            v["lcpsim_revision"] = "?"
    return v


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

TARGETS = [
    # (set-key prefix, groups, peer, target ratio)
    ("contact/", ("n = 20", "n = 40"), "siconos_lexicolemke", 5.0),
    ("contact/", ("n = 20", "n = 40"), "drake_moby", 10.0),
    ("spd/n=1000", ("n = 1000",), "siconos_lexicolemke", 4.0),
]


def headline(results: dict[str, Any], solvers: list[Solver], tol: float) -> tuple[list[str], dict[str, Any]]:
    """Targets of issue 6 checked on this run, plus pooled failure rates on the contact sets."""
    names = {s.key: s.name for s in solvers}
    sets = results["sets"]
    lines = ["| target | measured (interleaved) | back-to-back | interleaved, on the problems the peer got right "
             "| lcpsim robust failures there | met? |",
             "|---|---|---|---|---|---|"]
    data: dict[str, Any] = {}
    for prefix, groups, peer, goal in TARGETS:
        if peer not in names:
            continue
        for g in groups:
            ri, rb, rr, fails, total = [], [], [], 0, 0
            for key, s in sets.items():
                if not key.startswith(prefix) or g not in s["summary"]:
                    continue
                row = s["summary"][g]["solvers"]
                if row[peer]["ratio_interleaved"] is not None:
                    ri.append(row[peer]["ratio_interleaved"])
                if row[peer]["ratio_back_to_back"] is not None:
                    rb.append(row[peer]["ratio_back_to_back"])
                if row[peer]["ratio_interleaved_right"] is not None:
                    rr.append(row[peer]["ratio_interleaved_right"])
                fails += row["lcpsim_robust"]["failed"]
                total += row["lcpsim_robust"]["problems"]
            if not ri:
                continue
            lo, hi = min(ri), max(ri)
            span = f"{np.median(ri):.2f}× (sets: {lo:.2f}–{hi:.2f}×)" if len(ri) > 1 else f"{ri[0]:.2f}×"
            bspan = "—" if not rb else (f"{np.median(rb):.2f}×" + (f" ({min(rb):.2f}–{max(rb):.2f}×)" if len(rb) > 1 else ""))
            rspan = "—" if not rr else (f"{np.median(rr):.2f}×" + (f" ({min(rr):.2f}–{max(rr):.2f}×)" if len(rr) > 1 else ""))
            met = "yes" if np.median(ri) >= goal and fails == 0 else "no"
            lines.append(f"| {g}: lcpsim robust ≥ {goal:g}× faster than {names[peer]} | {span} | {bspan} | {rspan} | "
                         f"{fails} of {total} | {met} |")
            data[f"{prefix}{g}:{peer}"] = {"goal": goal, "ratios_interleaved": ri, "ratios_back_to_back": rb,
                                           "ratios_interleaved_peer_right": rr,
                                           "robust_failures": fails, "problems": total, "met": met == "yes"}
    # Pooled failure rates over every contact scale, sizes 20 and 40, with each
    # solver's time ratio to lcpsim robust (median over the scales, as above).
    pooled = ["", "Failures pooled over all contact-LCP scales (n = 20 and 40; failed = own word or physical "
              f"residual > {tol:g}), and time ÷ lcpsim robust's (median over the scales; interleaved, back-to-back "
              "in brackets):", "", "| solver | failed | own word | said solved, wrong | × robust, n = 20 | "
              "× robust, n = 40 |", "|---|---|---|---|---|---|"]
    for s in solvers:
        f = o = w = t = 0
        ratios: dict[str, tuple[list[float], list[float]]] = {"n = 20": ([], []), "n = 40": ([], [])}
        for key, st in sets.items():
            if not key.startswith("contact/"):
                continue
            for g, (ri, rb) in ratios.items():
                if g in st["summary"]:
                    r = st["summary"][g]["solvers"][s.key]
                    f, o, w, t = f + r["failed"], o + r["own_word"], w + r["said_solved_wrong"], t + r["problems"]
                    for out, k in ((ri, "ratio_interleaved"), (rb, "ratio_back_to_back")):
                        if r[k] is not None:
                            out.append(r[k])
        cells = [f"{fmt_ratio(float(np.median(ri)) if ri else None)} "
                 f"({fmt_ratio(float(np.median(rb)) if rb else None)})" for ri, rb in ratios.values()]
        if t:
            pooled.append(f"| {s.name} | {fmt_count(f, t)} of {t} | {fmt_count(o, t)} | {fmt_count(w, t)} | "
                          f"{cells[0]} | {cells[1]} |")
    return lines + pooled, data


def write_report(results: dict[str, Any], solvers: list[Solver], sim_md: list[str] | None) -> None:
    m, v, cfg = results["machine"], results["versions"], results["config"]
    lines = [
        "# Benchmarks: lcpsim beside Siconos, Drake, MuJoCo and PyBullet",
        "",
        "Written by `benchmarks/peers/run.py` — do not edit by hand; rerun instead:",
        "",
        "```bash",
        "bash benchmarks/peers/setup.sh                      # peers + lcpsim wheel in benchmarks/peers/.venv",
        f"benchmarks/peers/.venv/bin/python {results['command']}",
        "```",
        "",
        "Raw per-problem results (statuses, residuals, median times): `benchmarks/peers/results.json.gz`.",
        "",
        "## Machine and versions",
        "",
        f"- date: {results['date']} (run took {results['duration_s'] / 60:.1f} min)",
        f"- CPU: {m['cpu']}, {m['cores']} cores ({m['cores_usable']} usable), {m['memory']} RAM, "
        f"Linux {m['kernel']}",
        f"- load average (1, 5, 15 min) before / after: {results['load_before']} / {results['load_after']} — "
        "the machine is shared with other jobs, so absolute times are noisy; ratios come from the same run, "
        "interleaved per problem",
        f"- Python {v['python']}, numpy {v['numpy']}; lcpsim {v['lcpsim']} ({v.get('lcpsim_revision', '?')}); "
        f"Siconos {v['siconos']} (Debian python3-siconos); Drake {v['drake']}; MuJoCo {v['mujoco']}; "
        f"PyBullet {v['pybullet']}",
        f"- threads: OMP/OPENBLAS/MKL_NUM_THREADS = {cfg['threads_env']}",
        f"- timing: `time.perf_counter()` around each call; {cfg['passes']} interleaved passes, "
        f"{cfg['repeats']} back-to-back repeats (see below); tolerance {cfg['tol']:g}",
        "",
        "## How it is measured",
        "",
        "Every solver is called once per problem from Python (one call = one solve):",
        "",
    ]
    for s in solvers:
        lines.append(f"- **{s.name}**: {s.note}")
    lines += [
        "",
        "lcpsim's timed call takes numpy `M, q` and returns its result object. For the peers the problem object is "
        "built before the timer starts (Siconos `LCP`, `SolverOptions`, output arrays; Drake's "
        "`MathematicalProgram` with `AddLinearComplementarityConstraint`); only the solve call (and Drake's "
        "`GetSolution`) is timed — this favours the peers. Each solver is handed fresh copies of `M` and `q` made "
        "just before (in cache, as after a simulator's assembly — for lcpsim as for a peer whose problem object "
        "was just built from them).",
        "",
        "- **interleaved** (headline): passes over a set; in each pass every problem is solved once by every "
        "solver in turn (rotating order), median per problem over passes. Each call finds the caches as other "
        "code left them, as in a simulator, and load changes hit all solvers alike.",
        "- **back-to-back**: repeated calls of one solver on one problem (warm caches), median per problem. "
        "Not run for the hard corpus and SPD n = 1000.",
        "- **× robust** is the median over problems of (solver's time / lcpsim robust's time) on the same "
        "problem: above 1 means lcpsim robust is faster. Times of failed solves count too.",
        f"- **failed** = the solver said it failed (**own word**: Siconos `info ≠ 0`, Drake `is_success()` false, "
        f"lcpsim status ≠ `solved`) or its answer has a natural residual ‖min(z, Mz+q)‖∞ > {cfg['tol']:g} in "
        "physical units. **resid. > tol (given)**: the residual in the units of the problem the solver was given; "
        "**(phys.)**: for a cone-scaled contact LCP, z mapped back (z_phys = D z, D = diag(I, I, s·I): λ times s) "
        "and the residual taken on the unscaled problem (N·s, m/s); the same as (given) for unscaled and SPD "
        "problems. **said solved, wrong**: the solver reported success and the physical residual is above the "
        "tolerance.",
        "",
        "## Targets (issue 6)",
        "",
        "Judged on the interleaved ratio (median over the contact sets, one per scale; the range over the sets "
        "in brackets) and on lcpsim robust having no failure there. The column on the problems the peer got "
        "right leaves out its failed solves, which often end early on a wrong answer.",
        "",
    ]
    hl, _ = headline(results, solvers, cfg["tol"])
    lines += hl
    lines += ["", "## Problem sets", ""]
    for note in results.get("notes", []):
        lines.append(f"- {note}")
    if results.get("notes"):
        lines.append("")
    for key, s in results["sets"].items():
        lines += [f"### {s['title']}", "", s["description"], ""]
        lines += table(s["summary"], solvers, s["back_to_back"])
        lines.append("")
    if sim_md:
        lines += sim_md
    # many_bodies.py owns the section from "## Many bodies" to the end: keep it.
    sys.path.insert(0, str(HERE))
    from many_bodies_report import tail

    kept = tail(RESULTS_MD.read_text()) if RESULTS_MD.exists() else ""
    RESULTS_MD.write_text("\n".join(lines) + "\n" + kept)


# ---------------------------------------------------------------------------
# Main
# ---------------------------------------------------------------------------


def render_only() -> int:
    """RESULTS.md from the last run's results.json.gz (e.g. after a change of wording)."""
    with gzip.open(RESULTS_JSON, "rt") as f:
        results = json.load(f)
    solvers = [Solver(k, v["name"], v["family"], lambda M, q: None, v["call"])  # type: ignore[arg-type,return-value]
               for k, v in results["solvers"].items()]
    sim_md = None
    if results.get("simulation"):
        sys.path.insert(0, str(HERE))
        import sim_peers

        sim_md = sim_peers.render(results["simulation"])
    write_report(results, solvers, sim_md)
    say(f"rewrote {RESULTS_MD.relative_to(ROOT)} from {RESULTS_JSON.relative_to(ROOT)}")
    return 0


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--contact-per-size", type=int, default=300, help="contact LCPs per size and scale")
    ap.add_argument("--contact-scales", default="1,1e-2,1e-3,1e-4,1e-6,1e-8")
    ap.add_argument("--seed-per-size", type=int, default=100, help="seed-corpus LCPs per size and scale")
    ap.add_argument("--seed-scales", default="1,1e-2,1e-3,1e-4,1e-6,1e-8")
    ap.add_argument("--hard-count", type=int, default=70, help="hard contact LCPs per scale")
    ap.add_argument("--hard-scales", default="1,1e-3,1e-6")
    ap.add_argument("--spd", default="40:30,200:10,1000:3", help="size:count,… of random SPD LCPs")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--passes", type=int, default=3, help="interleaved passes")
    ap.add_argument("--repeats", type=int, default=5, help="back-to-back repeats per solver and problem")
    ap.add_argument("--slow", type=float, default=1.0, help="a call slower than this (s) is not repeated")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--only", default="", help="comma-separated set prefixes to run (contact,seed,hard,spd)")
    ap.add_argument("--skip-solvers", default="", help="comma-separated solver keys to leave out")
    ap.add_argument("--no-sim", action="store_true", help="leave out the simulation throughput (sim_peers.py)")
    ap.add_argument("--quick", action="store_true", help="smoke run: few problems, one pass")
    ap.add_argument("--no-write", action="store_true", help="print only; do not write RESULTS.md / results.json.gz")
    ap.add_argument("--render", action="store_true", help="rewrite RESULTS.md from results.json.gz without running")
    return ap.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.render:
        return render_only()
    if args.quick:
        args.contact_per_size, args.seed_per_size, args.hard_count = 5, 5, 7
        args.spd, args.passes, args.repeats = "40:2,200:1", 1, 2
    floats = lambda s: [float(x) for x in s.split(",") if x]  # noqa: E731
    only = [x for x in args.only.split(",") if x]
    want = lambda name: not only or name in only  # noqa: E731

    started = time.perf_counter()
    load_before = loadavg()
    say(f"lcpsim peers benchmark — load {load_before}")
    solvers = lcpsim_solvers()
    notes = []
    for make in (siconos_solvers, drake_solvers):
        got, msg = make()
        solvers += got
        if not got:
            notes.append(msg)
            say(msg)
    skip = set(x for x in args.skip_solvers.split(",") if x)
    solvers = [s for s in solvers if s.key not in skip]

    sets: list[ProblemSet] = []
    if want("contact"):
        sets += contact_sets(floats(args.contact_scales), args.contact_per_size, args.seed)
    if want("seed"):
        got, msg = seed_corpus_sets(floats(args.seed_scales), args.seed_per_size, args.seed)
        sets += got
        notes.append(msg)
        say(msg)
    if want("hard"):
        sets += hard_sets(floats(args.hard_scales), args.hard_count, args.seed)
    if want("spd"):
        sets += spd_sets([(int(a), int(b)) for a, b in (x.split(":") for x in args.spd.split(",") if x)], args.seed)

    def med(ts: list[float]) -> float | None:
        return float(f"{np.median(ts):.4g}") if ts else None

    results: dict[str, Any] = {"sets": {}}
    with peers_chatter_to(HERE / "peers_output.log"):
        for ps in sets:
            say(f"{ps.key}: {len(ps.problems)} problems × {len(solvers)} solvers")
            recs = measure(ps, solvers, args.passes, args.repeats, args.slow)
            summary = summarize(ps, recs, args.tol, "lcpsim_robust")
            results["sets"][ps.key] = {
                "title": ps.title,
                "description": ps.description,
                "back_to_back": ps.back_to_back and args.repeats > 0,
                "summary": summary,
                "raw": {
                    "labels": [p.label for p in ps.problems],
                    "n": [p.n for p in ps.problems],
                    "solvers": {
                        k: {
                            "ok": [r.ok for r in rr],
                            "status": [r.status for r in rr],
                            "residual_given": [float(f"{r.res_given:.3g}") for r in rr],
                            "residual_physical": [float(f"{r.res_phys:.3g}") for r in rr],
                            "t_interleaved_median": [med(r.t_inter) for r in rr],
                            "t_interleaved_samples": [len(r.t_inter) for r in rr],
                            "t_back_to_back_median": [med(r.t_b2b) for r in rr],
                            "t_back_to_back_samples": [len(r.t_b2b) for r in rr],
                        }
                        for k, rr in recs.items()
                    },
                },
            }
            for line in table(summary, solvers, ps.back_to_back and args.repeats > 0):
                say(line)

    sim_md = None
    sim_results = None
    if not args.no_sim:
        sys.path.insert(0, str(HERE))
        import sim_peers

        say("simulation throughput (sim_peers.py)")
        with peers_chatter_to(HERE / "sim_output.log"):
            sim_results = sim_peers.run_all(progress=say)
        sim_md = sim_peers.render(sim_results)
        for line in sim_md:
            say(line)

    results.update(
        {
            "command": "benchmarks/peers/run.py" + ("" if argv is None and len(sys.argv) <= 1 else " " + shlex.join(
                argv if argv is not None else sys.argv[1:])),
            "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "duration_s": time.perf_counter() - started,
            "load_before": load_before,
            "load_after": loadavg(),
            "machine": machine(),
            "versions": versions(),
            "notes": notes,
            "config": {
                **{k: v for k, v in vars(args).items()},
                "threads_env": "/".join(os.environ.get(k, "unset") for k in
                                        ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")),
            },
            "solvers": {s.key: {"name": s.name, "family": s.family, "call": s.note} for s in solvers},
            "simulation": sim_results,
        }
    )
    _, results["targets"] = headline(results, solvers, args.tol)
    if not args.no_write:
        with open(RESULTS_JSON, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as gz:
            gz.write(json.dumps(results, separators=(",", ":"), default=str).encode())
        write_report(results, solvers, sim_md)
        say(f"wrote {RESULTS_MD.relative_to(ROOT)} and {RESULTS_JSON.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
