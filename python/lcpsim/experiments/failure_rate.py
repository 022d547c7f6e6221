"""Failure rate of a solver over the cube corpus at several friction-cone scales.

The source note counted Lemke failures over the LCPs of one simulation at
s = 1e-3, 1e-4 and 1e-6 (the source note: 3.9 %, ≈ 2.1 %, 0). Here, by default
(``mode = "resolve"``), the *same* LCPs — the cube corpus, assembled unscaled
along physical trajectories — are scaled by each s (``D M D``, ``D q``) and
solved with the chosen solver, so that the rates at different scales compare
one solver on one set of problems. ``mode = "simulate"`` instead re-runs every
corpus simulation with the solver and the scale in the loop, as the source note did
(its trajectories, and so its LCPs, then differ from scale to scale, and a
failed step feeds the next one).

A failure is either (report both counts):

* a **status failure**: the solver returned a status other than ``solved``;
* a **residual failure**: the answer mapped back to physical units (fn, fd
  unchanged, ``λ = s·λ_scaled``) has a natural residual ``‖min(z, w)‖∞``
  above ``tol`` on the *unscaled* LCP — whatever the solver said. An answer
  the solver called ``solved`` that fails here is counted in
  ``accepted_wrong``: the source note's tolerance artifact.

``failures`` is the union, ``rate = failures / lcps``. Beside the absolute
``tol`` every row also counts ``rel_residual_failures`` against the comparison's
criterion ``‖min(z, w)‖∞ ≤ rel_tol·(1 + ‖q‖∞)`` (physical units, unscaled
``q``) and ``rel_failures`` (that or a status failure).

**Comparison**: ``solvers`` (a list; default ``[solver]``) ×
``corpora`` (``"cubes"``, ``"hard"``) × ``scales``, one row each in
``comparison``; ``rows`` stays the first solver on the first corpus. The
``hard`` corpus is :func:`lcpsim.generate.hard_corpus` (``hard.count`` LCPs,
seeded, up to 16 contacts, duplicate and nearly parallel contacts, mass
ratios to 1e4, ill-conditioned bodies) generated *at* each scale s; its
answers are mapped back (``λ = s·λ``) and judged on the same scenes generated
at s = 1. Solvers in ``certify`` (default: ``robust``/``lemke`` when listed)
get every answer of size n ≤ ``certify_max_n`` (40) checked exactly
(:func:`lcpsim.certify` on the LCP as the solver saw it): ``certified``
(the exact check passes), ``certified_eta`` (Oettli–Prager backward error
η ≤ 1e-14: the exact solution of an LCP within 1e-14 relative of the given
one), ``certified_residual`` (the exact basis solution's natural residual
≤ 1e-14·(1 + ‖q‖∞)) and ``certified_either`` (one of the last two), each out
of ``cert_lcps``.
"""

from __future__ import annotations

import argparse
import functools
import os
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from ..certification import certify_batch
from ..result import ETA_CERTIFIED, Certificate
from ._common import envelope, merge_config, parse_scale, parse_scales, scale_label, scale_value
from .presets import Solver, parse_solver
from .cube_corpus import DEFAULTS as CORPUS_DEFAULTS
from .cube_corpus import (
    build_world, experiment_corpus, generate, physical_answers, scaled, simulations, solve_scaled,
)
from .document import Doc, pct
from .experiment import (
    Experiment, ReportContext, add_common_arguments, add_corpus_arguments, base_config, corpus_config, header,
)
from .figure import pyplot, save, solver_label

__all__ = ["DEFAULTS", "HARD_DEFAULTS", "CORPORA", "run", "NOTE_VALUES"]

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "scales": ["none", 1e-3, 1e-4, 1e-6],
    "solver": "robust",
    "tol": 1e-6,
    "mode": "resolve",
    "corpus": {},
    "max_lcps": None,
    "threads": 0,
    # The comparison table.
    "solvers": None,
    "corpora": ["cubes"],
    "hard": {},
    "rel_tol": 1e-9,
    "certify": None,
    "certify_max_n": 40,
}

#: The corpora a comparison can run on.
CORPORA: tuple[str, ...] = ("cubes", "hard")

#: Hard-corpus config: ``count`` LCPs from ``lcpsim.generate.hard_corpus(seed, count, s)``
#: (``seed`` defaults to the experiment's seed).
HARD_DEFAULTS: dict[str, Any] = {"count": 200, "seed": None}

#: Relative threshold of ``certified_residual`` (exact residual ≤ this·(1 + ‖q‖∞)).
CERT_RESIDUAL_TOL = 1e-14

#: The source note's rates (fraction of LCPs) by scale.
NOTE_VALUES: dict[str, float] = {"0.001": 97 / 2499, "0.0001": 0.0208, "1e-06": 0.0}


def _list(x: Any, what: str) -> list[Any]:
    if x is None:
        return []
    if isinstance(x, str):
        return [t.strip() for t in x.split(",") if t.strip()]
    if isinstance(x, (list, tuple)):
        return list(x)
    raise ValueError(f"failure-rate: {what} must be a list or a comma-separated string, got {x!r}")


def _hard_config(cfg: Mapping[str, Any]) -> dict[str, Any]:
    h = {**HARD_DEFAULTS, **dict(cfg.get("hard") or {})}
    unknown = set(h) - set(HARD_DEFAULTS)
    if unknown:
        raise ValueError(f"hard: unknown key(s) {sorted(unknown)} (valid: {', '.join(sorted(HARD_DEFAULTS))})")
    if h["seed"] is None:
        h["seed"] = int(cfg["seed"])
    count = h["count"]
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise ValueError(f"hard: count must be a positive integer, got {count!r}")
    h["count"] = int(count)
    h["seed"] = int(h["seed"])
    return h


def _certify_names(cfg: Mapping[str, Any], solvers: list[Solver]) -> set[str]:
    c = cfg["certify"]
    if c is None:  # auto: lcpsim's default Lemke
        return {s.name for s in solvers if s.name in ("robust", "lemke")}
    if isinstance(c, bool):
        return {s.name for s in solvers} if c else set()
    names = set(_list(c, "certify"))
    known = {s.name for s in solvers}
    if names - known:
        raise ValueError(f"failure-rate: certify names solver(s) {sorted(names - known)} not in solvers {sorted(known)}")
    return names


def run(config: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Runs the experiment; returns ``{"rows": [{"scale", "lcps", "failures", "rate", …}],
    "comparison": [{"solver", "corpus", "scale", …}], …}``."""
    t0 = time.perf_counter()
    cfg = merge_config("failure-rate", DEFAULTS, config)
    scales = [parse_scale(s) for s in (cfg["scales"] if not isinstance(cfg["scales"], str) else cfg["scales"].split(","))]
    names = _list(cfg["solvers"], "solvers") or [cfg["solver"]]
    solvers = [parse_solver(n) for n in names]
    if len({s.name for s in solvers}) != len(solvers):
        raise ValueError(f"failure-rate: a solver is listed twice in {names!r}")
    corpora = _list(cfg["corpora"], "corpora") or ["cubes"]
    bad = [c for c in corpora if c not in CORPORA]
    if bad or len(set(corpora)) != len(corpora):
        raise ValueError(f"failure-rate: corpora must be distinct names out of {', '.join(CORPORA)}, got {corpora!r}")
    tol = float(cfg["tol"])
    rel_tol = float(cfg["rel_tol"])
    mode = str(cfg["mode"])
    if mode not in ("resolve", "simulate"):
        raise ValueError(f"failure-rate: mode must be 'resolve' or 'simulate', got {mode!r}")
    judge = _Judge(tol, rel_tol, _certify_names(cfg, solvers), int(cfg["certify_max_n"]), int(cfg["threads"]))
    ccfg = experiment_corpus(cfg)
    hcfg = _hard_config(cfg) if "hard" in corpora else None
    dt = float(ccfg.get("dt", CORPUS_DEFAULTS["dt"]))
    comparison: list[dict[str, Any]] = []
    summaries: dict[str, Any] = {}
    for corpus_name in corpora:
        if corpus_name == "cubes":
            rows_by_solver, summaries["cubes"] = _cube_rows(solvers, scales, ccfg, cfg, dt, mode, judge)
        else:
            assert hcfg is not None
            rows_by_solver, summaries["hard"] = _hard_rows(solvers, scales, hcfg, dt, judge)
        for solver in solvers:
            comparison += [{"solver": solver.name, "corpus": corpus_name, **r} for r in rows_by_solver[solver.name]]
    first = [
        {k: v for k, v in r.items() if k not in ("solver", "corpus")}
        for r in comparison
        if r["solver"] == solvers[0].name and r["corpus"] == corpora[0]
    ]
    out = envelope("failure-rate", cfg, t0)
    out.update(
        {
            "solver": solvers[0].to_dict(),
            "solvers": [s.to_dict() for s in solvers],
            "mode": mode,
            "tol": tol,
            "rel_tol": rel_tol,
            "corpus": summaries.get("cubes", summaries.get(corpora[0])),
            "corpora": summaries,
            "certify": sorted(judge.cert_names),
            "certify_max_n": judge.cert_max_n,
            "rows": first,
            "comparison": comparison,
            "note_values": NOTE_VALUES,
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out


def _cube_rows(
    solvers: list[Solver],
    scales: list[Any],
    ccfg: dict[str, Any],
    cfg: Mapping[str, Any],
    dt: float,
    mode: str,
    judge: "_Judge",
) -> tuple[dict[str, list[dict[str, Any]]], dict[str, Any]]:
    """The cube corpus: each solver's rows per scale, and the corpus summary."""
    tol, rel_tol, cert_max_n, threads = judge.tol, judge.rel_tol, judge.cert_max_n, judge.threads
    out: dict[str, list[dict[str, Any]]] = {s.name: [] for s in solvers}
    if mode == "resolve":
        corpus = generate(ccfg).subsample(cfg["max_lcps"], int(cfg["seed"]))
        summary = {"name": "cubes", **corpus.summary()}
        qnorm = {id(g): np.abs(g.q).max(axis=1) for g in corpus.groups}
        for solver in solvers:
            for scale in scales:
                s = scale_value(scale, dt)
                acc = _Acc(certify=solver.name in judge.cert_names)
                for g in corpus.groups:
                    r = solve_scaled(g, solver, s, threads=threads)
                    acc.add(r.status, r.residual, r.pivots, tol, size=g.n, rel_bound=rel_tol * (1.0 + qnorm[id(g)]))
                    if acc.certify and g.n <= cert_max_n:
                        Ms, qs, d = scaled(g.M, g.q, g.contacts, g.friction_dirs, s)
                        acc.add_cert(Ms, qs, r.basis, r.z / d, threads)
                out[solver.name].append({"scale": scale_label(scale), "s": s, **acc.row()})
    else:
        sims = simulations(ccfg)
        summary = {"name": "cubes", "simulations": [sp.name for sp in sims]}
        for solver in solvers:
            for scale in scales:
                s = scale_value(scale, dt)
                acc = _Acc(certify=False)
                for spec in sims:
                    world, _ = build_world(
                        spec, dt=dt, friction_dirs=int(ccfg.get("friction_dirs", 8)), scale=scale, solver=solver
                    )
                    traj = world.run(spec.steps)
                    has = traj.status != "no_contact"
                    acc.add(tuple(traj.status[has]), traj.residual[has], traj.pivots[has], tol, size=traj.lcp_size[has])
                out[solver.name].append({"scale": scale_label(scale), "s": s, **acc.row()})
    return out, summary


def _hard_rows(
    solvers: list[Solver],
    scales: list[Any],
    hcfg: dict[str, Any],
    dt: float,
    judge: "_Judge",
) -> tuple[dict[str, list[dict[str, Any]]], dict[str, Any]]:
    """The hard corpus, generated at each scale, judged on the scenes at s = 1."""
    tol, rel_tol, cert_max_n, threads = judge.tol, judge.rel_tol, judge.cert_max_n, judge.threads
    from ..generate import hard_corpus

    seed, count = hcfg["seed"], hcfg["count"]
    base = hard_corpus(seed, count, 1.0)
    sizes = sorted({p.n for p in base})
    groups = {n: [i for i, p in enumerate(base) if p.n == n] for n in sizes}
    kinds: dict[str, int] = {}
    for p in base:
        kind = p.label.split("/", 1)[0]
        kinds[kind] = kinds.get(kind, 0) + 1
    summary = {
        "name": "hard",
        "seed": seed,
        "lcps": len(base),
        "by_kind": dict(sorted(kinds.items())),
        "by_size": {str(n): len(ix) for n, ix in groups.items()},
        "max_n": max(sizes),
    }
    out: dict[str, list[dict[str, Any]]] = {s.name: [] for s in solvers}
    for scale in scales:
        s = scale_value(scale, dt)
        probs = base if s == 1.0 else hard_corpus(seed, count, s)
        stacks = {}
        for n, ix in groups.items():
            Ms = np.stack([probs[i].M for i in ix])
            qs = np.stack([probs[i].q for i in ix])
            d = np.stack([probs[i].cone_diagonal() for i in ix])
            M1 = np.stack([base[i].M for i in ix])
            q1 = np.stack([base[i].q for i in ix])
            stacks[n] = (Ms, qs, d, M1, q1)
        for solver in solvers:
            acc = _Acc(certify=solver.name in judge.cert_names)
            for n, (Ms, qs, d, M1, q1) in stacks.items():
                res = solver.solve_batch(Ms, qs, threads=threads)
                _, _, residual = physical_answers(res.z, d, M1, q1)
                acc.add(tuple(res.status), residual, np.asarray(res.pivots), tol, size=n,
                        rel_bound=rel_tol * (1.0 + np.abs(q1).max(axis=1)))
                if acc.certify and n <= cert_max_n:
                    acc.add_cert(Ms, qs, res.basis, res.z, threads)
            out[solver.name].append({"scale": scale_label(scale), "s": s, **acc.row()})
    return out, summary


@dataclass(frozen=True)
class _Judge:
    """How answers are judged: the residual tolerances, which solvers' answers are
    certified (up to size ``cert_max_n``), and the solver threads."""

    tol: float
    rel_tol: float
    cert_names: set[str]
    cert_max_n: int
    threads: int


class _Acc:
    """Counts over batches of answers (``n``: the integer counts by name)."""

    #: The certification counts that the row also gives as a share of the certified LCPs.
    CERTIFIED = ("certified", "certified_eta", "certified_residual", "certified_either")

    def __init__(self, certify: bool = False) -> None:
        self.certify = certify
        self.n: Counter[str] = Counter()
        self.by_status: Counter[str] = Counter()
        self.cert_by_status: Counter[str] = Counter()
        self.max_eta = 0.0
        self.max_res_solved = 0.0
        self.rel_measured = True
        self.pivots: list[np.ndarray] = []
        self.by_size: dict[int, list[int]] = {}

    def add(
        self,
        status: tuple[str, ...],
        residual: np.ndarray,
        pivots: np.ndarray,
        tol: float,
        size: Any,
        rel_bound: np.ndarray | None = None,
    ) -> None:
        st = np.asarray(status)
        ok = st == "solved"
        bad_r = ~(np.asarray(residual) <= tol)  # NaN counts as a failure
        fail = ~ok | bad_r
        if rel_bound is not None:
            bad_rel = ~(np.asarray(residual) <= rel_bound)
            self._count(rel_fail=bad_rel, rel_union=~ok | bad_rel, rel_accepted_wrong=ok & bad_rel)
        else:
            self.rel_measured = False  # simulate mode: reported as None
        self.n["lcps"] += len(st)
        self._count(status_fail=~ok, resid_fail=bad_r, union=fail, accepted_wrong=ok & bad_r)
        for s in np.unique(st):
            self.by_status[str(s)] += int((st == s).sum())
        if ok.any():
            self.max_res_solved = max(self.max_res_solved, float(np.nanmax(np.asarray(residual)[ok])))
        self.pivots.append(np.asarray(pivots))
        sizes = np.broadcast_to(np.asarray(size), st.shape)
        for n in np.unique(sizes):
            m = sizes == n
            e = self.by_size.setdefault(int(n), [0, 0])
            e[0] += int(m.sum())
            e[1] += int(fail[m].sum())

    def _count(self, **masks: np.ndarray) -> None:
        for key, mask in masks.items():
            self.n[key] += int(mask.sum())

    def add_cert(
        self, Ms: np.ndarray, qs: np.ndarray, bases: np.ndarray | None, zs: np.ndarray, threads: int
    ) -> None:
        """Certifies a batch of answers (on the LCPs as the solver saw them)."""
        b = int(qs.shape[0])
        self.n["cert_lcps"] += b
        if bases is None:  # no basis: nothing to certify, none certified
            self.cert_by_status["no_basis"] += b
            return
        certs: list[Certificate] = certify_batch(Ms, qs, bases, zs, threads=threads)
        qn = np.abs(qs).max(axis=1)
        for c, qi in zip(certs, qn.tolist()):
            self.cert_by_status[c.status] += 1
            eta_ok = c.backward_error <= ETA_CERTIFIED
            small = c.natural_residual <= CERT_RESIDUAL_TOL * (1.0 + qi)
            self.n.update(certified=int(c.certified), certified_eta=int(eta_ok), certified_residual=int(small),
                          certified_either=int(small or eta_ok))
            self.max_eta = max(self.max_eta, float(c.backward_error))

    def row(self) -> dict[str, Any]:
        c = self.n
        n = max(c["lcps"], 1)
        piv = np.concatenate(self.pivots) if self.pivots else np.zeros(0)
        measured = self.rel_measured
        certified = self.certify and c["cert_lcps"] > 0
        cert: dict[str, Any] = {"cert_lcps": c["cert_lcps"] if self.certify else None}
        for key in self.CERTIFIED:
            cert[key] = c[key] if self.certify else None
            cert[f"{key}_share"] = c[key] / c["cert_lcps"] if certified else None
        cert["cert_by_status"] = dict(sorted(self.cert_by_status.items())) if self.certify else None
        cert["max_backward_error"] = self.max_eta if certified else None
        return {
            "lcps": c["lcps"],
            "failures": c["union"],
            "rate": c["union"] / n,
            "status_failures": c["status_fail"],
            "status_rate": c["status_fail"] / n,
            "residual_failures": c["resid_fail"],
            "residual_rate": c["resid_fail"] / n,
            "accepted_wrong": c["accepted_wrong"],
            "by_status": dict(sorted(self.by_status.items())),
            "max_residual_solved": self.max_res_solved,
            "pivots_median": float(np.median(piv)) if piv.size else 0.0,
            "pivots_max": int(piv.max(initial=0)),
            "by_size": {str(k): {"lcps": v[0], "failures": v[1]} for k, v in sorted(self.by_size.items())},
            "rel_residual_failures": c["rel_fail"] if measured else None,
            "rel_residual_rate": c["rel_fail"] / n if measured else None,
            "rel_failures": c["rel_union"] if measured else None,
            "rel_rate": c["rel_union"] / n if measured else None,
            "rel_accepted_wrong": c["rel_accepted_wrong"] if measured else None,
            **cert,
        }


# ---------------------------------------------------------------- command line, figures, report


def cli_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scales", default="none,1e-3,1e-4,1e-6", help="comma-separated scales (default: none,1e-3,1e-4,1e-6)")
    p.add_argument("--tol", type=float, default=1e-6, help="physical-unit residual tolerance (default: 1e-6)")
    p.add_argument("--rel-tol", type=float, default=1e-9,
                   help="also count residuals above REL_TOL·(1 + ‖q‖∞), physical units (default: 1e-9)")
    p.add_argument("--mode", choices=("resolve", "simulate"), default="resolve",
                   help="re-solve the corpus LCPs per scale (default) or re-simulate per scale")
    g = p.add_argument_group("comparison")
    g.add_argument("--solvers", default=None, metavar="LIST",
                   help="comma-separated solvers to compare, e.g. classic,robust,pgs,newton_fb (overrides --solver)")
    g.add_argument("--corpus", default="cubes", metavar="LIST",
                   help="comma-separated corpora: cubes (the cube corpus) and/or hard (lcpsim.generate.hard_corpus) "
                   "(default: cubes)")
    g.add_argument("--hard-count", type=int, default=None, metavar="N", help="LCPs in the hard corpus (default: 200)")
    g.add_argument("--certify", default=None, metavar="LIST",
                   help="solvers whose answers are certified exactly (n ≤ --certify-max-n); 'none' for none "
                   "(default: robust/lemke when listed)")
    g.add_argument("--certify-max-n", type=int, default=40, metavar="N", help="largest LCP certified (default: 40)")
    add_common_arguments(p)
    add_corpus_arguments(p)


def cli_config(args: argparse.Namespace) -> dict[str, Any]:
    cfg = {**base_config(args), **corpus_config(args), "scales": parse_scales(args.scales), "tol": args.tol, "mode": args.mode}
    cfg["scales"] = ["none" if s is None else s for s in cfg["scales"]]
    cfg["rel_tol"] = args.rel_tol
    if args.solvers:
        names = [t.strip() for t in args.solvers.split(",") if t.strip()]
        for n in names:
            parse_solver(n)
        cfg["solvers"] = names
    cfg["corpora"] = [t.strip() for t in args.corpus.split(",") if t.strip()]
    if args.hard_count is not None:
        cfg["hard"] = {"count": args.hard_count}
    if args.certify is not None:
        cfg["certify"] = [] if args.certify.strip().lower() in ("none", "") else args.certify
    cfg["certify_max_n"] = args.certify_max_n
    return cfg


def _text_failure_rate(r: dict[str, Any]) -> str:
    lines = [header(r), f"mode {r['mode']}, residual tolerance {r['tol']:g} (physical units)", ""]
    hdr = f"{'scale':>8} {'LCPs':>6} {'failures':>9} {'rate':>8} {'status':>7} {'st.rate':>8} {'resid.':>7} {'accepted wrong':>15}  statuses"
    lines += [hdr, "-" * len(hdr)]
    for row in r["rows"]:
        st = ", ".join(f"{k} {v}" for k, v in row["by_status"].items() if k != "solved") or "-"
        lines.append(
            f"{row['scale']:>8} {row['lcps']:>6} {row['failures']:>9} {100 * row['rate']:>7.2f}% {row['status_failures']:>7}"
            f" {100 * row['status_rate']:>7.2f}% {row['residual_failures']:>7} {row['accepted_wrong']:>15}  {st}"
        )
    note = r.get("note_values") or {}
    lines.append("\nsource note (status failures): " + ", ".join(f"s = {k}: {100 * v:.1f} %" for k, v in note.items()))
    return "\n".join(lines)


def _share(count: Any, total: Any, space: str = "") -> str:
    """``count/total (p%)``; "—" when not counted."""
    if count is None or not total:
        return "—"
    return f"{count}/{total} ({100 * count / total:.1f}{space}%)"


def _text_comparison(r: dict[str, Any]) -> str:
    lines = [
        f"lcpsim {r['lcpsim_version']} failure-rate comparison, seed {r['seed']}, mode {r['mode']}",
        f"residual failures in physical units (λ = s·λ_scaled, unscaled LCP): '> tol' means > {r['tol']:g}, "
        f"'> rel' means > {r['rel_tol']:g}·(1 + ‖q‖∞); certified (n ≤ {r['certify_max_n']}): exact / "
        "backward error η ≤ 1e-14 / η ≤ 1e-14 or exact residual ≤ 1e-14·(1 + ‖q‖∞)",
    ]
    for name, c in (r.get("corpora") or {}).items():
        if name == "hard":
            lines.append(f"hard corpus: {c['lcps']} LCPs (seed {c['seed']}, n up to {c['max_n']}), "
                         + ", ".join(f"{k} {v}" for k, v in c["by_kind"].items()))
        elif "lcps" in c:
            lines.append(f"cube corpus: {c['lcps']} LCPs")
    lines.append("")
    hdr = (f"{'solver':<10} {'corpus':<6} {'scale':>7} {'LCPs':>6} {'status':>7} {'> tol':>6} {'> rel':>6}"
           f" {'acc.wrong':>9}  {'certified exact':>19} {'η ≤ 1e-14':>19} {'η or resid.':>19}")
    lines += [hdr, "-" * len(hdr)]
    for row in r["comparison"]:
        rel = "—" if row.get("rel_residual_failures") is None else row["rel_residual_failures"]
        n = row.get("cert_lcps")
        lines.append(
            f"{row['solver']:<10} {row['corpus']:<6} {row['scale']:>7} {row['lcps']:>6} {row['status_failures']:>7}"
            f" {row['residual_failures']:>6} {rel:>6} {row['accepted_wrong']:>9}  {_share(row.get('certified'), n):>19}"
            f" {_share(row.get('certified_eta'), n):>19} {_share(row.get('certified_either'), n):>19}"
        )
    return "\n".join(lines)


def summary(r: dict[str, Any], args: argparse.Namespace | None = None) -> str:
    """The text ``lcpsim failure-rate`` prints: per scale, or the comparison table."""
    if len(r.get("solvers") or []) > 1 or len(r.get("corpora") or {}) > 1 or "hard" in (r.get("corpora") or {}):
        return _text_comparison(r)
    text = _text_failure_rate(r)
    if r.get("certify"):
        text += "\n\n" + _text_comparison(r)
    return text


def plot_failure_rate(results: Sequence[Mapping[str, Any]], path: str | os.PathLike[str]) -> str:
    """Failure rate per scale, one group of bars per solver: status failures
    (solid) and all failures incl. physical-unit residual (hatched); the source note's
    rates as black diamonds."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    scales = [row["scale"] for row in results[0]["rows"]]
    x = np.arange(len(scales))
    width = 0.8 / max(len(results), 1)
    for i, r in enumerate(results):
        rows = {row["scale"]: row for row in r["rows"]}
        st = [100 * rows[s]["status_rate"] if s in rows else np.nan for s in scales]
        al = [100 * rows[s]["rate"] if s in rows else np.nan for s in scales]
        off = (i - (len(results) - 1) / 2) * width
        c = f"C{i}"
        ax.bar(x + off, al, width * 0.95, color=c, alpha=0.35, hatch="//", label=f"{solver_label(r)}: any failure")
        ax.bar(x + off, st, width * 0.95, color=c, label=f"{solver_label(r)}: status ≠ solved")
    note = results[0].get("note_values") or {}
    for j, s in enumerate(scales):
        key = f"{float(s):g}" if s not in ("none", "dt") else s
        if key in note:
            ax.plot([j], [100 * note[key]], "kD", ms=7, label="source note" if j == 0 or "source note" not in
                    [t.get_label() for t in ax.lines] else None)
    ax.set_xticks(x, [f"s = {s}" for s in scales])
    ax.set_ylabel("LCPs failed (%)")
    n = results[0]["rows"][0]["lcps"]
    ax.set_title(f"Failure rate over the cube corpus ({n} LCPs, {results[0].get('mode', 'resolve')})")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    return save(fig, path)


#: The report's scales, and its solver comparison.
REPORT_SCALES = ["none", 1e-3, 1e-4, 1e-6, 1e-8]
COMPARE_SOLVERS = ["classic", "robust", "pgs", "newton_fb"]
COMPARE_SCALES = ["none", 1e-2, 1e-3, 1e-4, 1e-6, 1e-8]


def row_at(result: Mapping[str, Any], scale: str) -> dict[str, Any] | None:
    """The row of ``result`` at ``scale`` (its label), or None."""
    for r in result["rows"]:
        if r["scale"] == scale:
            row: dict[str, Any] = r
            return row
    return None


def report_run(ctx: ReportContext) -> dict[str, Any]:
    fr: dict[str, dict[str, Any]] = {}
    for name in ("classic", "robust"):
        cfg = {**ctx.base, "solver": name, "scales": REPORT_SCALES}
        fr[name] = ctx.step(f"failure rate ({name})", functools.partial(run, cfg))
    fr_sim = ctx.step(
        "failure rate (classic, simulated)",
        lambda: run({**ctx.base, "solver": "classic", "scales": REPORT_SCALES, "mode": "simulate"}),
    )
    # PGS is slow on these LCPs (10,000 sweeps when it fails): a seeded subset of the cube corpus.
    cmp_cfg = {
        **ctx.base,
        "solvers": COMPARE_SOLVERS,
        "corpora": ["cubes", "hard"],
        "scales": ["none", 1e-8] if ctx.quick else COMPARE_SCALES,
        "max_lcps": 100 if ctx.quick else 1000,
        "hard": {"count": 7 if ctx.quick else 70},
    }
    return {
        "failure_rate": {"classic": fr["classic"], "robust": fr["robust"], "classic_simulate": fr_sim},
        "comparison": ctx.step("solver comparison", functools.partial(run, cmp_cfg)),
    }


def report_figures(res: dict[str, Any], ctx: ReportContext) -> dict[str, str]:
    fr = res["failure_rate"]
    return {
        "failure_rate": plot_failure_rate([fr["classic"], fr["robust"]], ctx.path("failure_rate.png")),
        "failure_rate_sim": plot_failure_rate([fr["classic_simulate"]], ctx.path("failure_rate_simulate.png")),
    }


def report_section(d: Doc, res: dict[str, Any], figs: dict[str, str], ctx: ReportContext) -> None:
    fr = res["failure_rate"]
    d.h(2, "Failure rate per scale")
    d.p(
        "`lcpsim failure-rate --scales none,1e-3,1e-4,1e-6,1e-8 --solver classic` (and `--solver robust`). The same "
        "corpus LCPs are scaled by each s and re-solved. A failure is a status other than solved, or a "
        "physical-unit residual above 1e-6 (`accepted wrong`: the solver said solved, the unscaled residual "
        "disagrees — the tolerance artifact)."
    )
    hdr = ["solver", "s", "LCPs", "status failures", "residual failures", "accepted wrong", "any failure", "statuses"]
    trows = []
    for name, r_ in (("classic", fr["classic"]), ("robust", fr["robust"]), ("classic (simulate)", fr["classic_simulate"])):
        for r in r_["rows"]:
            trows.append([name, r["scale"], r["lcps"], f"{r['status_failures']} ({pct(r['status_rate'])})",
                          f"{r['residual_failures']} ({pct(r['residual_rate'])})", r["accepted_wrong"],
                          pct(r["rate"]), ", ".join(f"{k} {v}" for k, v in r["by_status"].items() if k != "solved") or "—"])
    d.table(hdr, trows)
    d.img(ctx.rel(figs["failure_rate"]), "failure rate per scale")
    d.p(
        "The source note counted failures over one simulation run at each scale; `--mode simulate` does that (each "
        "corpus simulation re-run with the classic preset in the loop; a failed step's last iterate is applied, so "
        "trajectories, and the LCP counts, differ per scale):"
    )
    d.img(ctx.rel(figs["failure_rate_sim"]), "failure rate per scale, simulated")
    _comparison_section(d, res["comparison"])


def _comparison_section(d: Doc, cmp: dict[str, Any]) -> None:
    cfg = cmp["config"]
    scales = ",".join("none" if x in (None, "none") else f"{float(x):g}" for x in cfg["scales"])
    cubes_c, hard_c = cmp["corpora"]["cubes"], cmp["corpora"]["hard"]
    d.h(2, "Solver comparison: classic, robust, PGS, Newton–FB")
    d.p(
        f"`lcpsim failure-rate --solvers {','.join(s['name'] for s in cmp['solvers'])} --corpus cubes,hard "
        f"--scales {scales} --max-lcps {cfg['max_lcps']} --hard-count {hard_c['lcps']}` "
        f"(drop `--max-lcps` for the whole cube corpus). Corpora: {cubes_c['lcps']} LCPs of the cube corpus "
        f"(a seeded subset), and {hard_c['lcps']} LCPs of the hard generator (`lcpsim.generate.hard_corpus`, seed "
        f"{hard_c['seed']}: " + ", ".join(f"{k} {v}" for k, v in hard_c["by_kind"].items())
        + f"; n up to {hard_c['max_n']}), generated at each scale s and judged on the same scenes at s = 1. "
        "Solvers: **classic** = classic Lemke (piv_tol 1e-12, zero_tol 1e-6, on the LCP as scaled); **robust** = "
        "lcpsim's default; **pgs**, **newton_fb** with their defaults. Counts: status ≠ solved; physical residual "
        f"> {cmp['tol']:g} and > {cmp['rel_tol']:g}·(1 + ‖q‖∞) (the relative criterion); accepted wrong = said "
        "solved, physical residual > 1e-6."
    )
    d.p(
        f"Certified (robust, LCPs with n ≤ {cmp['certify_max_n']}): the final basis re-solved in exact rational "
        "arithmetic from the floats as given (`solve_lcp(..., certify=True)`). *exact*: z ≥ 0, w ≥ 0, zᵀw = 0 "
        "hold exactly. On these rank-deficient contact LCPs entries that are exactly 0 in real arithmetic are "
        "±1e-17 after rounding, so a right basis often fails the exact check; *η ≤ 1e-14*: the answer is the exact "
        "solution of an LCP within 1e-14 (relative, entrywise) of the one given (Oettli–Prager backward error); "
        "*η or residual*: that, or the exact basis solution's natural residual ≤ 1e-14·(1 + ‖q‖∞) (resting "
        "contacts whose tangential q is ±1e-17, where a componentwise η is meaningless)."
    )
    trows = []
    for r in cmp["comparison"]:
        n = r.get("cert_lcps")
        trows.append([
            r["solver"], r["corpus"], r["scale"], r["lcps"], r["status_failures"], r["residual_failures"],
            "—" if r.get("rel_residual_failures") is None else r["rel_residual_failures"], r["accepted_wrong"],
            _share(r.get("certified"), n, " "), _share(r.get("certified_eta"), n, " "),
            _share(r.get("certified_either"), n, " "),
        ])
    d.table(["solver", "corpus", "s", "LCPs", "status failures", "residual > 1e-6", "residual > 1e-9·(1+‖q‖)",
             "accepted wrong", "certified exact", "η ≤ 1e-14", "η or residual"], trows)


EXPERIMENT = Experiment.of_module(
    __name__, "failure rate of solvers over the cube and hard corpora per friction-cone scale", plot=plot_failure_rate
)
