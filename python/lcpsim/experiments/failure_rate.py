"""Failure rate of a solver over the seed corpus at several friction-cone scales.

The seed note counted Lemke failures over the LCPs of one simulation at
s = 1e-3, 1e-4 and 1e-6 (DESIGN §2: 3.9 %, ≈ 2.1 %, 0). Here, by default
(``mode = "resolve"``), the *same* LCPs — the seed corpus, assembled unscaled
along physical trajectories — are scaled by each s (``D M D``, ``D q``) and
solved with the chosen solver, so that the rates at different scales compare
one solver on one set of problems. ``mode = "simulate"`` instead re-runs every
corpus simulation with the solver and the scale in the loop, as the seed did
(its trajectories, and so its LCPs, then differ from scale to scale, and a
failed step feeds the next one).

A failure is either (report both counts):

* a **status failure**: the solver returned a status other than ``solved``;
* a **residual failure**: the answer mapped back to physical units (fn, fd
  unchanged, ``λ = s·λ_scaled``) has a natural residual ``‖min(z, w)‖∞``
  above ``tol`` on the *unscaled* LCP — whatever the solver said. An answer
  the solver called ``solved`` that fails here is counted in
  ``accepted_wrong``: the tolerance artifact of DESIGN §2.

``failures`` is the union, ``rate = failures / lcps``. Beside the absolute
``tol`` every row also counts ``rel_residual_failures`` against issue 5's
criterion ``‖min(z, w)‖∞ ≤ rel_tol·(1 + ‖q‖∞)`` (physical units, unscaled
``q``) and ``rel_failures`` (that or a status failure).

**Comparison** (issue 5): ``solvers`` (a list; default ``[solver]``) ×
``corpora`` (``"seed"``, ``"hard"``) × ``scales``, one row each in
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

import time
from typing import Any, Mapping

import numpy as np

from ..certification import ETA_CERTIFIED, Certificate, certify_batch
from ._common import envelope, merge_config, parse_scale, scale_label, scale_value
from .presets import Solver, parse_solver
from .seed_corpus import DEFAULTS as CORPUS_DEFAULTS
from .seed_corpus import build_world, generate, scaled, simulations, solve_scaled

__all__ = ["DEFAULTS", "HARD_DEFAULTS", "CORPORA", "run", "SEED_VALUES"]

DEFAULTS: dict[str, Any] = {
    "seed": 0,
    "scales": ["none", 1e-3, 1e-4, 1e-6],
    "solver": "robust",
    "tol": 1e-6,
    "mode": "resolve",
    "corpus": {},
    "max_lcps": None,
    "threads": 0,
    # Issue 5: the comparison table.
    "solvers": None,
    "corpora": ["seed"],
    "hard": {},
    "rel_tol": 1e-9,
    "certify": None,
    "certify_max_n": 40,
}

#: The corpora a comparison can run on.
CORPORA: tuple[str, ...] = ("seed", "hard")

#: Hard-corpus config: ``count`` LCPs from ``lcpsim.generate.hard_corpus(seed, count, s)``
#: (``seed`` defaults to the experiment's seed).
HARD_DEFAULTS: dict[str, Any] = {"count": 200, "seed": None}

#: Relative threshold of ``certified_residual`` (exact residual ≤ this·(1 + ‖q‖∞)).
CERT_RESIDUAL_TOL = 1e-14

#: The seed note's rates (fraction of LCPs) by scale.
SEED_VALUES: dict[str, float] = {"0.001": 97 / 2499, "0.0001": 0.0208, "1e-06": 0.0}


def _corpus_config(cfg: Mapping[str, Any]) -> dict[str, Any]:
    c = {**dict(cfg.get("corpus") or {})}
    c.setdefault("seed", cfg["seed"])
    unknown = set(c) - set(CORPUS_DEFAULTS)
    if unknown:
        raise ValueError(f"corpus: unknown key(s) {sorted(unknown)} (valid: {', '.join(sorted(CORPUS_DEFAULTS))})")
    return c


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
    corpora = _list(cfg["corpora"], "corpora") or ["seed"]
    bad = [c for c in corpora if c not in CORPORA]
    if bad or len(set(corpora)) != len(corpora):
        raise ValueError(f"failure-rate: corpora must be distinct names out of {', '.join(CORPORA)}, got {corpora!r}")
    tol = float(cfg["tol"])
    rel_tol = float(cfg["rel_tol"])
    mode = str(cfg["mode"])
    if mode not in ("resolve", "simulate"):
        raise ValueError(f"failure-rate: mode must be 'resolve' or 'simulate', got {mode!r}")
    cert_names = _certify_names(cfg, solvers)
    cert_max_n = int(cfg["certify_max_n"])
    threads = int(cfg["threads"])
    ccfg = _corpus_config(cfg)
    hcfg = _hard_config(cfg) if "hard" in corpora else None
    dt = float(ccfg.get("dt", CORPUS_DEFAULTS["dt"]))
    comparison: list[dict[str, Any]] = []
    summaries: dict[str, Any] = {}
    for corpus_name in corpora:
        if corpus_name == "seed":
            rows_by_solver, summaries["seed"] = _seed_rows(
                solvers, scales, ccfg, cfg, dt, mode, tol, rel_tol, cert_names, cert_max_n, threads
            )
        else:
            assert hcfg is not None
            rows_by_solver, summaries["hard"] = _hard_rows(
                solvers, scales, hcfg, dt, tol, rel_tol, cert_names, cert_max_n, threads
            )
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
            "corpus": summaries.get("seed", summaries.get(corpora[0])),
            "corpora": summaries,
            "certify": sorted(cert_names),
            "certify_max_n": cert_max_n,
            "rows": first,
            "comparison": comparison,
            "seed_values": SEED_VALUES,
        }
    )
    out["wall_time_s"] = time.perf_counter() - t0
    return out


def _seed_rows(
    solvers: list[Solver],
    scales: list[Any],
    ccfg: dict[str, Any],
    cfg: Mapping[str, Any],
    dt: float,
    mode: str,
    tol: float,
    rel_tol: float,
    cert_names: set[str],
    cert_max_n: int,
    threads: int,
) -> tuple[dict[str, list[dict[str, Any]]], dict[str, Any]]:
    """The seed corpus: each solver's rows per scale, and the corpus summary."""
    out: dict[str, list[dict[str, Any]]] = {s.name: [] for s in solvers}
    if mode == "resolve":
        corpus = generate(ccfg).subsample(cfg["max_lcps"], int(cfg["seed"]))
        summary = {"name": "seed", **corpus.summary()}
        qnorm = {id(g): np.abs(g.q).max(axis=1) for g in corpus.groups}
        for solver in solvers:
            for scale in scales:
                s = scale_value(scale, dt)
                acc = _Acc(certify=solver.name in cert_names)
                for g in corpus.groups:
                    r = solve_scaled(g, solver, s, threads=threads)
                    acc.add(r.status, r.residual, r.pivots, tol, size=g.n, rel_bound=rel_tol * (1.0 + qnorm[id(g)]))
                    if acc.certify and g.n <= cert_max_n:
                        Ms, qs, d = scaled(g.M, g.q, g.contacts, g.friction_dirs, s)
                        acc.add_cert(Ms, qs, r.basis, r.z / d, threads)
                out[solver.name].append({"scale": scale_label(scale), "s": s, **acc.row()})
    else:
        sims = simulations(ccfg)
        summary = {"name": "seed", "simulations": [sp.name for sp in sims]}
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
    tol: float,
    rel_tol: float,
    cert_names: set[str],
    cert_max_n: int,
    threads: int,
) -> tuple[dict[str, list[dict[str, Any]]], dict[str, Any]]:
    """The hard corpus, generated at each scale, judged on the scenes at s = 1."""
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
            acc = _Acc(certify=solver.name in cert_names)
            for n, (Ms, qs, d, M1, q1) in stacks.items():
                res = solver.solve_batch(Ms, qs, threads=threads)
                z = res.z * d
                w = np.einsum("bij,bj->bi", M1, z) + q1
                residual = np.abs(np.minimum(z, w)).max(axis=1)
                acc.add(tuple(res.status), residual, np.asarray(res.pivots), tol, size=n,
                        rel_bound=rel_tol * (1.0 + np.abs(q1).max(axis=1)))
                if acc.certify and n <= cert_max_n:
                    acc.add_cert(Ms, qs, res.basis, res.z, threads)
            out[solver.name].append({"scale": scale_label(scale), "s": s, **acc.row()})
    return out, summary


class _Acc:
    """Counts over batches of answers."""

    def __init__(self, certify: bool = False) -> None:
        self.certify = certify
        self.cert_lcps = 0
        self.certified = 0
        self.certified_eta = 0
        self.certified_residual = 0
        self.certified_either = 0
        self.cert_by_status: dict[str, int] = {}
        self.max_eta = 0.0
        self.rel_measured = True
        self.rel_fail = 0
        self.rel_union = 0
        self.rel_accepted_wrong = 0
        self.lcps = 0
        self.status_fail = 0
        self.resid_fail = 0
        self.union = 0
        self.accepted_wrong = 0
        self.by_status: dict[str, int] = {}
        self.max_res_solved = 0.0
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
            self.rel_fail += int(bad_rel.sum())
            self.rel_union += int((~ok | bad_rel).sum())
            self.rel_accepted_wrong += int((ok & bad_rel).sum())
        else:
            self.rel_measured = False  # simulate mode: reported as None
        self.lcps += len(st)
        self.status_fail += int((~ok).sum())
        self.resid_fail += int(bad_r.sum())
        self.union += int(fail.sum())
        self.accepted_wrong += int((ok & bad_r).sum())
        for s in np.unique(st):
            self.by_status[str(s)] = self.by_status.get(str(s), 0) + int((st == s).sum())
        if ok.any():
            self.max_res_solved = max(self.max_res_solved, float(np.nanmax(np.asarray(residual)[ok])))
        self.pivots.append(np.asarray(pivots))
        sizes = np.broadcast_to(np.asarray(size), st.shape)
        for n in np.unique(sizes):
            m = sizes == n
            e = self.by_size.setdefault(int(n), [0, 0])
            e[0] += int(m.sum())
            e[1] += int(fail[m].sum())

    def add_cert(
        self, Ms: np.ndarray, qs: np.ndarray, bases: np.ndarray | None, zs: np.ndarray, threads: int
    ) -> None:
        """Certifies a batch of answers (on the LCPs as the solver saw them)."""
        b = int(qs.shape[0])
        self.cert_lcps += b
        if bases is None:  # no basis: nothing to certify, none certified
            self.cert_by_status["no_basis"] = self.cert_by_status.get("no_basis", 0) + b
            return
        certs: list[Certificate] = certify_batch(Ms, qs, bases, zs, threads=threads)
        qn = np.abs(qs).max(axis=1)
        for c, qi in zip(certs, qn.tolist()):
            self.cert_by_status[c.status] = self.cert_by_status.get(c.status, 0) + 1
            self.certified += int(c.certified)
            self.certified_eta += int(c.backward_error <= ETA_CERTIFIED)
            small = c.natural_residual <= CERT_RESIDUAL_TOL * (1.0 + qi)
            self.certified_residual += int(small)
            self.certified_either += int(small or c.backward_error <= ETA_CERTIFIED)
            self.max_eta = max(self.max_eta, float(c.backward_error))

    def row(self) -> dict[str, Any]:
        n = max(self.lcps, 1)
        piv = np.concatenate(self.pivots) if self.pivots else np.zeros(0)
        measured = self.rel_measured
        cn = max(self.cert_lcps, 1)
        cert: dict[str, Any] = {
            "cert_lcps": self.cert_lcps if self.certify else None,
            "certified": self.certified if self.certify else None,
            "certified_share": self.certified / cn if self.certify and self.cert_lcps else None,
            "certified_eta": self.certified_eta if self.certify else None,
            "certified_eta_share": self.certified_eta / cn if self.certify and self.cert_lcps else None,
            "certified_residual": self.certified_residual if self.certify else None,
            "certified_residual_share": self.certified_residual / cn if self.certify and self.cert_lcps else None,
            "certified_either": self.certified_either if self.certify else None,
            "certified_either_share": self.certified_either / cn if self.certify and self.cert_lcps else None,
            "cert_by_status": dict(sorted(self.cert_by_status.items())) if self.certify else None,
            "max_backward_error": self.max_eta if self.certify and self.cert_lcps else None,
        }
        return {
            "lcps": self.lcps,
            "failures": self.union,
            "rate": self.union / n,
            "status_failures": self.status_fail,
            "status_rate": self.status_fail / n,
            "residual_failures": self.resid_fail,
            "residual_rate": self.resid_fail / n,
            "accepted_wrong": self.accepted_wrong,
            "by_status": dict(sorted(self.by_status.items())),
            "max_residual_solved": self.max_res_solved,
            "pivots_median": float(np.median(piv)) if piv.size else 0.0,
            "pivots_max": int(piv.max(initial=0)),
            "by_size": {str(k): {"lcps": v[0], "failures": v[1]} for k, v in sorted(self.by_size.items())},
            "rel_residual_failures": self.rel_fail if measured else None,
            "rel_residual_rate": self.rel_fail / n if measured else None,
            "rel_failures": self.rel_union if measured else None,
            "rel_rate": self.rel_union / n if measured else None,
            "rel_accepted_wrong": self.rel_accepted_wrong if measured else None,
            **cert,
        }
