"""The seed's experiments on the command line (issue 4)::

    lcpsim failure-rate --scales none,1e-3,1e-4,1e-6 --solver seed
    lcpsim failure-rate --solvers seed,robust,pgs,newton_fb --corpus seed,hard --scales none,1e-2,1e-3,1e-4,1e-6,1e-8
    lcpsim slope --angle-deg 45.0001 --mu 1 --scale 1e-3 --solver seed --seconds 1
    lcpsim critical-scale --angle-deg 45.2 --mu 1 --solver seed
    lcpsim invariance --digits 20
    lcpsim patterns --scale 1e-3
    lcpsim push --force 9.79 --mu 1
    lcpsim report --out report
    lcpsim sweep sweep.yaml

Every experiment command takes ``--json`` (print the result), ``--plot FILE``
(write a PNG), ``--solver`` (a preset — ``seed``, ``robust`` (default),
``pgs``, ``newton_fb`` — or ``method:key=value,…``) and ``--seed``. A scale is
a number, ``none`` (unscaled) or ``dt`` (the time step). Exit codes: 0 done,
2 invalid input.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any, Callable

from .main import EXIT_OK, CliError, Command, register_command

__all__: list[str] = []


def _solver_help() -> str:
    return "solver: seed | robust | lemke | pgs | newton_fb | method:key=value,… (default: robust)"


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--solver", default="robust", metavar="SOLVER", help=_solver_help())
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--plot", metavar="FILE", default=None, help="write a plot (PNG)")
    p.add_argument("--out", metavar="FILE", default=None, help="also write the JSON result to FILE")


def _corpus_opts(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("seed corpus")
    g.add_argument("--corpus-steps", type=int, default=None, metavar="N", help="steps per simulation (default: 600)")
    g.add_argument("--corpus-random", type=int, default=None, metavar="N", help="random tumbling drops (default: 8)")
    g.add_argument("--max-lcps", type=int, default=None, metavar="N", help="use at most N LCPs (seeded subset)")
    g.add_argument("--threads", type=int, default=0, help="solver threads (default 0: one per core)")


def _corpus_cfg(args: argparse.Namespace) -> dict[str, Any]:
    c: dict[str, Any] = {}
    if args.corpus_steps is not None:
        c["steps"] = args.corpus_steps
    if args.corpus_random is not None:
        c["n_random"] = args.corpus_random
    return {"corpus": c, "max_lcps": args.max_lcps, "threads": args.threads}


def _base(args: argparse.Namespace) -> dict[str, Any]:
    from ..experiments.presets import parse_solver

    parse_solver(args.solver)  # validate early: a bad name is a one-line error
    return {"solver": args.solver, "seed": args.seed}


def _emit(args: argparse.Namespace, result: dict[str, Any], text: Callable[[dict[str, Any]], str]) -> int:
    from ..experiments._common import jsonable

    if getattr(args, "plot", None):
        from ..experiments.plotting import plot_result

        plot_result(result, args.plot)
    data = jsonable(result)
    if getattr(args, "out", None):
        with open(args.out, "w") as fh:
            json.dump(data, fh, indent=1)
    if args.json:
        print(json.dumps(data))
    else:
        print(text(result))
        if getattr(args, "plot", None):
            print(f"plot:      {args.plot}")
    return EXIT_OK


def _header(r: dict[str, Any]) -> str:
    s = r.get("solver") or {}
    opts = ", ".join(f"{k}={v}" for k, v in (s.get("options") or {}).items())
    return f"lcpsim {r['lcpsim_version']} {r['experiment']}: solver {s.get('name')} ({s.get('method')}{', ' + opts if opts else ''}), seed {r['seed']}"


# ---------------------------------------------------------------- failure-rate


def _cfg_failure_rate(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scales", default="none,1e-3,1e-4,1e-6", help="comma-separated scales (default: none,1e-3,1e-4,1e-6)")
    p.add_argument("--tol", type=float, default=1e-6, help="physical-unit residual tolerance (default: 1e-6)")
    p.add_argument("--rel-tol", type=float, default=1e-9,
                   help="also count residuals above REL_TOL·(1 + ‖q‖∞), physical units (default: 1e-9, issue 5)")
    p.add_argument("--mode", choices=("resolve", "simulate"), default="resolve",
                   help="re-solve the corpus LCPs per scale (default) or re-simulate per scale")
    g = p.add_argument_group("comparison (issue 5)")
    g.add_argument("--solvers", default=None, metavar="LIST",
                   help="comma-separated solvers to compare, e.g. seed,robust,pgs,newton_fb (overrides --solver)")
    g.add_argument("--corpus", default="seed", metavar="LIST",
                   help="comma-separated corpora: seed (the seed corpus) and/or hard (lcpsim.generate.hard_corpus) "
                   "(default: seed)")
    g.add_argument("--hard-count", type=int, default=None, metavar="N", help="LCPs in the hard corpus (default: 200)")
    g.add_argument("--certify", default=None, metavar="LIST",
                   help="solvers whose answers are certified exactly (n ≤ --certify-max-n); 'none' for none "
                   "(default: robust/lemke when listed)")
    g.add_argument("--certify-max-n", type=int, default=40, metavar="N", help="largest LCP certified (default: 40)")
    _common(p)
    _corpus_opts(p)


def _text_failure_rate(r: dict[str, Any]) -> str:
    lines = [_header(r), f"mode {r['mode']}, residual tolerance {r['tol']:g} (physical units)", ""]
    hdr = f"{'scale':>8} {'LCPs':>6} {'failures':>9} {'rate':>8} {'status':>7} {'st.rate':>8} {'resid.':>7} {'accepted wrong':>15}  statuses"
    lines += [hdr, "-" * len(hdr)]
    for row in r["rows"]:
        st = ", ".join(f"{k} {v}" for k, v in row["by_status"].items() if k != "solved") or "-"
        lines.append(
            f"{row['scale']:>8} {row['lcps']:>6} {row['failures']:>9} {100 * row['rate']:>7.2f}% {row['status_failures']:>7}"
            f" {100 * row['status_rate']:>7.2f}% {row['residual_failures']:>7} {row['accepted_wrong']:>15}  {st}"
        )
    seed = r.get("seed_values") or {}
    lines.append("\nseed note (status failures): " + ", ".join(f"s = {k}: {100 * v:.1f} %" for k, v in seed.items()))
    return "\n".join(lines)


def _share(count: Any, total: Any) -> str:
    if count is None or not total:
        return "—"
    return f"{count}/{total} ({100 * count / total:.1f}%)"


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
            lines.append(f"seed corpus: {c['lcps']} LCPs")
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


def _text_failure_rate_any(r: dict[str, Any]) -> str:
    if len(r.get("solvers") or []) > 1 or len(r.get("corpora") or {}) > 1 or "hard" in (r.get("corpora") or {}):
        return _text_comparison(r)
    text = _text_failure_rate(r)
    if r.get("certify"):
        text += "\n\n" + _text_comparison(r)
    return text


def _run_failure_rate(args: argparse.Namespace) -> int:
    from ..experiments import failure_rate
    from ..experiments._common import parse_scales

    cfg = {**_base(args), **_corpus_cfg(args), "scales": parse_scales(args.scales), "tol": args.tol, "mode": args.mode}
    cfg["scales"] = ["none" if s is None else s for s in cfg["scales"]]
    cfg["rel_tol"] = args.rel_tol
    if args.solvers:
        from ..experiments.presets import parse_solver

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
    return _emit(args, failure_rate.run(cfg), _text_failure_rate_any)


# ---------------------------------------------------------------- slope


def _scale_arg(text: str) -> Any:
    from ..experiments._common import parse_scale

    try:
        s = parse_scale(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
    return "none" if s is None else s


def _sim_opts(p: argparse.ArgumentParser, seconds: float = 1.0) -> None:
    p.add_argument("--seconds", type=float, default=seconds, help=f"simulated time (default: {seconds:g})")
    p.add_argument("--dt", type=float, default=1e-3, help="time step h (default: 1e-3)")
    p.add_argument("--friction-dirs", type=int, default=8, metavar="K", help="friction directions (default: 8)")


def _cfg_slope(p: argparse.ArgumentParser) -> None:
    p.add_argument("--angle-deg", "--angle", dest="angle_deg", type=float, default=45.0001, help="slope angle (default: 45.0001)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--scale", type=_scale_arg, default="none", metavar="none|dt|S", help="cone scale (default: none)")
    _sim_opts(p)
    _common(p)


def _text_slope(r: dict[str, Any]) -> str:
    c = r["config"]
    lines = [
        _header(r),
        f"cube 1 m, {c['mass']} kg on {c['angle_deg']}°, μ = {c['mu']}, s = {r['scale']}, h = {c['dt']:g} s, T = {r['seconds']:g} s",
        f"outcome:   {r['outcome']}",
        f"slide:     {r['slide_distance_m']:.6e} m  (analytic slide: {r['expected_slide_m']:.6e} m)",
        f"rotation:  {r['tilt_deg']:.4g}° max, {r['final_tilt_deg']:.4g}° at the end",
        f"LCPs:      {r['lcps']}, failures {r['lcp_failures']}"
        + (f" (first at t = {r['first_failure_s']:.3f} s)" if r["first_failure_s"] is not None else ""),
        f"cone:      friction beyond μN in {r['cone_excess_steps']} solved steps (max {r['cone_excess_max_Ns']:.3e} N·s)",
        f"energy:    largest gain {r['energy_gain_J']:.3e} J",
    ]
    return "\n".join(lines)


def _run_slope(args: argparse.Namespace) -> int:
    from ..experiments import slope

    cfg = {
        **_base(args), "angle_deg": args.angle_deg, "mu": args.mu, "scale": args.scale,
        "seconds": args.seconds, "dt": args.dt, "friction_dirs": args.friction_dirs, "trace": bool(args.plot),
    }
    return _emit(args, slope.run(cfg), _text_slope)


# ---------------------------------------------------------------- critical-scale


def _cfg_critical(p: argparse.ArgumentParser) -> None:
    p.add_argument("--angle-deg", "--angle", dest="angle_deg", type=float, default=45.0001, help="slope angle (default: 45.0001)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--lo", type=float, default=1e-8, help="smallest scale searched (default: 1e-8)")
    p.add_argument("--hi", type=float, default=1.0, help="largest scale searched (default: 1, unscaled)")
    p.add_argument("--tol-decades", type=float, default=0.05, help="bracket width in decades (default: 0.05)")
    _sim_opts(p)
    _common(p)


def _text_critical(r: dict[str, Any]) -> str:
    c = r["config"]
    crit = r["critical_scale"]
    if crit is None:
        res = {"held_at_hi": f"held already at s = {c['hi']:g}", "slides_everywhere": f"slides at every s down to {c['lo']:g}"}.get(
            r["note"], "none")
    else:
        res = f"{crit:.4g}  (bracket {r['bracket'][0]:.4g} … {r['bracket'][1]:.4g})"
    lines = [
        _header(r),
        f"slope {c['angle_deg']}°, μ = {c['mu']}, T = {c['seconds']:g} s; analytic slide {r['expected_slide_m']:.4e} m",
        f"critical scale: {res}   (seed note: 4e-3 at 45.0001°)",
        f"outcomes monotone in s: {r['monotone']}",
        "",
        f"{'s':>11} {'outcome':>8} {'slide (m)':>12} {'rot (°)':>9} {'fails':>6}  stage",
    ]
    for o in r["outcomes"]:
        lines.append(
            f"{o['scale']:>11.4g} {o['outcome']:>8} {o['slide_distance_m']:>12.4e} {o['tilt_deg']:>9.3g} {o['lcp_failures']:>6}  {o['stage']}"
        )
    return "\n".join(lines)


def _run_critical(args: argparse.Namespace) -> int:
    from ..experiments import critical_scale

    cfg = {
        **_base(args), "angle_deg": args.angle_deg, "mu": args.mu, "lo": args.lo, "hi": args.hi,
        "tol_decades": args.tol_decades, "seconds": args.seconds, "dt": args.dt, "friction_dirs": args.friction_dirs,
    }
    return _emit(args, critical_scale.run(cfg), _text_critical)


# ---------------------------------------------------------------- invariance


def _cfg_invariance(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scale", type=_scale_arg, default=1e-3, metavar="dt|S", help="cone scale compared with unscaled (default: 1e-3)")
    p.add_argument("--digits", type=int, default=None, metavar="N", help="print example vectors with N significant digits (as the seed: 20)")
    _common(p)
    _corpus_opts(p)


def _text_invariance(r: dict[str, Any], digits: int | None = None) -> str:
    lines = [
        _header(r),
        f"{r['lcps']} LCPs, unscaled vs s = {r['scale']} (λ_scaled·s against λ); solved both times: {r['compared']}",
        f"same Lemke basis: {r['same_basis']}; different basis: {r['different_basis']} "
        f"(both valid solutions: {r['different_basis_both_valid']}); status changed: {r['status_changed']}",
        "",
        "same basis (round-off only):",
        f"  max |Δfn| = {r['max_abs_dfn']:.3e} N·s   relative {r['max_rel_dfn']:.3e}",
        f"  max |Δfd| = {r['max_abs_dfd']:.3e} N·s   relative {r['max_rel_dfd']:.3e}",
        f"  max relative λ error = {r['max_rel_lambda_err']:.3e}",
        "all pairs solved both times:",
        "  " + ", ".join(f"{k} {v:.3e}" for k, v in r["all_pairs"].items()),
        "seed note: fn, fd agree to ~1e-16",
    ]
    if digits:
        for ex in r.get("examples", []):
            lines += ["", f"Size = {ex['n']}, {ex['contacts']} contact points (LCP {ex['lcp']}, {ex['simulation']} step {ex['step']})",
                      "Before", " ".join(f"{x:.{digits}g}" for x in ex["before"]),
                      "After", " ".join(f"{x:.{digits}g}" for x in ex["after"])]
    return "\n".join(lines)


def _run_invariance(args: argparse.Namespace) -> int:
    from ..experiments import invariance

    if args.digits is not None and not 1 <= args.digits <= 40:
        raise CliError(f"--digits must be in 1…40, got {args.digits}")
    cfg = {**_base(args), **_corpus_cfg(args), "scale": args.scale}
    r = invariance.run(cfg)
    return _emit(args, r, lambda x: _text_invariance(x, args.digits))


# ---------------------------------------------------------------- patterns


def _cfg_patterns(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scale", type=_scale_arg, default=1e-3, metavar="dt|S", help="cone scale (default: 1e-3)")
    p.add_argument("--zero-rel", type=float, default=1e-9, help="relative zero for the signs (default: 1e-9)")
    _common(p)
    _corpus_opts(p)


def _text_patterns(r: dict[str, Any]) -> str:
    pats = r["patterns"]
    lines = [_header(r), f"{r['lcps']} LCPs, {r['contacts']} contacts; unscaled vs s = {r['scale']}", ""]
    lines.append(f"{'(fn,Σfd,λ)':>11} {'unscaled':>9} {'scaled':>9}  meaning")
    for p in pats:
        lines.append(f"{'(' + ','.join(p) + ')':>11} {r['counts_unscaled'][p]:>9} {r['counts_scaled'][p]:>9}  {r['meaning'][p]}")
    lines += ["", "cross table (rows unscaled, columns scaled):", " " * 9 + "".join(f"{'(' + ','.join(p) + ')':>9}" for p in pats)]
    for p, row in zip(pats, r["cross"]):
        lines.append(f"{'(' + ','.join(p) + ')':>9}" + "".join(f"{v:>9}" for v in row))
    imp = r["impossible"]
    lines += [
        "",
        f"contacts whose pattern changed with scaling: {r['changed']}",
        f"LCPs with an impossible pattern: unscaled {imp['unscaled']} (+{imp['unscaled_failed']} in failed solves), "
        f"scaled {imp['scaled']} (+{imp['scaled_failed']} in failed solves)",
    ]
    for x in r["impossible_lcps"][:10]:
        lines.append(f"  LCP {x['lcp']} ({x['simulation']} step {x['step']}, {x['solve']}, {x['status']}): "
                     f"{', '.join(x['patterns'])} fn {x['fn']} Σfd {x['sum_fd']} λ {x['lambda']}")
    if len(r["impossible_lcps"]) > 10:
        lines.append(f"  … {len(r['impossible_lcps']) - 10} more listed in --json")
    return "\n".join(lines)


def _run_patterns(args: argparse.Namespace) -> int:
    from ..experiments import patterns

    cfg = {**_base(args), **_corpus_cfg(args), "scale": args.scale, "zero_rel": args.zero_rel}
    return _emit(args, patterns.run(cfg), _text_patterns)


# ---------------------------------------------------------------- push


def _cfg_push(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", type=float, default=9.79, help="horizontal push at the centre of mass, N (default: 9.79)")
    p.add_argument("--mu", type=float, default=1.0, help="friction coefficient (default: 1)")
    p.add_argument("--scale", type=_scale_arg, default="none", metavar="none|dt|S", help="cone scale (default: none)")
    _sim_opts(p)
    _common(p)


def _text_push(r: dict[str, Any]) -> str:
    c = r["config"]
    fn = ", ".join(f"{x:.6g}" for x in r["normal_impulses"])
    off = ", ".join(f"{x:+.3g}" for x in r["contact_offsets_m"])
    lines = [
        _header(r),
        f"cube {c['mass']} kg, μ = {c['mu']}, push {c['force']} N at the centre of mass, s = {r['scale']}, T = {r['seconds']:g} s",
        f"outcome:   {r['outcome']}  (exact: {r['expected_outcome']})",
        f"friction:  {r['friction_force_N']:.12g} N  (exact: {r['expected_friction_N']:.12g} N)",
        f"λ max:     {r['lambda_max']:.3e} m/s   (seed note: ~1e-19)",
        f"fn:        {fn} N·s at offsets {off} m along the push   (seed note: 0, 1e-05, 0.004895, 0.004905)",
        f"moved:     {r['displacement_m']:.4e} m  (exact: {r['expected_displacement_m']:.4e} m); LCP failures {r['lcp_failures']}",
    ]
    return "\n".join(lines)


def _run_push(args: argparse.Namespace) -> int:
    from ..experiments import push

    cfg = {
        **_base(args), "force": args.force, "mu": args.mu, "scale": args.scale, "seconds": args.seconds,
        "dt": args.dt, "friction_dirs": args.friction_dirs, "trace": bool(args.plot),
    }
    return _emit(args, push.run(cfg), _text_push)


# ---------------------------------------------------------------- report


def _cfg_report(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="report", metavar="DIR", help="output directory (default: report)")
    p.add_argument("--quick", action="store_true", help="small sizes (a smoke test, seconds instead of minutes)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def _run_report(args: argparse.Namespace) -> int:
    from ..experiments.report import make_report

    summary = make_report(args.out, seed=args.seed, quick=args.quick, log=sys.stderr)
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"report: {summary['index_html']}")
        print(f"        {summary['report_md']}")
        print(f"wall time {summary['wall_time_s']:.1f} s")
    return EXIT_OK


# ---------------------------------------------------------------- sweep


def _cfg_sweep(p: argparse.ArgumentParser) -> None:
    p.add_argument("config", help="sweep config (YAML or JSON): experiment, base, grid, output")
    p.add_argument("--output", "-o", default=None, metavar="FILE", help="results file (.h5 or .parquet); overrides the config's")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS", help="an existing Dask scheduler (default: a local cluster)")
    p.add_argument("--workers", type=int, default=None, help="local cluster workers (default: cores)")
    p.add_argument("--no-progress", action="store_true", help="no progress line")
    p.add_argument("--json", action="store_true", help="print every result as JSON lines at the end")


def _run_sweep(args: argparse.Namespace) -> int:
    from ..experiments import sweep

    cfg = sweep.load_config(args.config)
    out = sweep.run_sweep(
        cfg, output=args.output, scheduler=args.scheduler, workers=args.workers,
        progress=None if args.no_progress else sys.stderr,
    )
    if args.json:
        for rec in sweep.load_results(out["output"]):
            print(json.dumps(rec))
    else:
        print(sweep.summary_text(out))
    return EXIT_OK


for _name, _help, _cfg, _run in (
    ("failure-rate", "failure rate of solvers over the seed and hard corpora per friction-cone scale", _cfg_failure_rate, _run_failure_rate),
    ("slope", "the seed's slope test: does a μ = 1 cube slide, rest or tip?", _cfg_slope, _run_slope),
    ("critical-scale", "the cone scale below which the slope cube is held instead of sliding", _cfg_critical, _run_critical),
    ("invariance", "fn, fd unchanged and λ·s by cone scaling, over the seed corpus", _cfg_invariance, _run_invariance),
    ("patterns", "sign patterns (fn, Σfd, λ) per contact, unscaled × scaled", _cfg_patterns, _run_patterns),
    ("push", "the seed's pushed cube (9.79 N, μ = 1)", _cfg_push, _run_push),
    ("report", "run every experiment and write an HTML + Markdown report", _cfg_report, _run_report),
    ("sweep", "run a grid of experiment cases on Dask, resumable", _cfg_sweep, _run_sweep),
):
    register_command(Command(_name, _help, _cfg, _run))
