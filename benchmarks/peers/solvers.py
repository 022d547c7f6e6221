"""The solvers of the peers' run: lcpsim, Siconos and Drake, each behind
``prepare(M, q) -> (run, finish)``; only ``run()`` is timed and
``finish(raw) -> (ok, z, status)`` reads its answer."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

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
