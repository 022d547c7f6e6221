"""``lcpsim solve FILE`` (an LCP file, a captured LCP or a failure dump) and
``lcpsim demo`` (a small contact LCP solved with each method)."""

from __future__ import annotations

import argparse
import json
import os
from typing import Any

import numpy as np

from .. import __version__, _core
from ..lcp import METHODS, PIVOTINGS, solve_lcp
from ..result import LcpResult
from .command import EXIT_NOT_SOLVED, EXIT_OK, CliError, Command, lemke_options, register_command

__all__: list[str] = []


# ---------------------------------------------------------------- solve


def _configure_solve(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "file",
        help="LCP file: .npz with arrays M, q, HDF5 (.h5) with datasets /M, /q, a capture (with --index), "
        "a failure dump (solve_lcp(..., dump=DIR)): replayed with its method and options unless overridden, "
        "or an FCLib local problem (solved as the faceted LCP; see --friction-dirs, --scale)",
    )
    p.add_argument("--index", type=int, default=None, metavar="K", help="problem K of a capture (lcpsim simulate --capture)")
    # Defaults are None here so that a dump's options apply unless given on the command line;
    # the help shows the compiled defaults.
    lemke = _core.LEMKE_DEFAULTS
    p.add_argument("--method", choices=METHODS, default=None, help="solver (default: lemke)")
    p.add_argument(
        "--pivoting", choices=PIVOTINGS, default=None, help=f"Lemke pivoting rule (default: {lemke['pivoting']})"
    )
    p.add_argument("--piv-tol", type=float, default=None, help=f"Lemke: smallest pivot (default: {lemke['piv_tol']:g})")
    p.add_argument("--zero-tol", type=float, default=None, help=f"Lemke: the user zero (default: {lemke['zero_tol']:g})")
    p.add_argument("--max-pivots", type=int, default=None, help="Lemke: pivot limit (default: max(1000, 50 n))")
    p.add_argument("--certify", action="store_true", help="check the final basis exactly (rational arithmetic)")
    p.add_argument("--dump", metavar="DIR", default=None, help="if not solved, write a failure dump into DIR")
    p.add_argument("--json", action="store_true", help="print the result as JSON (status, ok, pivots, residual, z, w)")
    p.add_argument("--friction-dirs", type=int, default=None, metavar="K", help="FCLib file: facets of the friction cone (default: 8)")
    p.add_argument("--scale", type=float, default=None, metavar="S", help="FCLib file: friction-cone scale s (default: 1)")


def _format_vector(x: np.ndarray) -> str:
    return np.array2string(x, precision=6, threshold=24, max_line_width=100, separator=", ")


def _summary(path: str, res: LcpResult, pivoting: str | None) -> str:
    n = res.z.shape[0]
    method = res.method + (f" ({pivoting})" if pivoting else "")
    lines = [
        f"file:      {path} (n = {n})",
        f"method:    {method}",
        f"status:    {res.status}" + ("" if res.ok else "   (not solved)"),
        f"pivots:    {res.pivots}" if res.method == "lemke" else f"iterations: {res.pivots}",
        f"residual:  {res.residual:.3e}   ‖min(z, Mz+q)‖∞",
        f"min z, w:  {res.min_z:.3e}, {res.min_w:.3e}   max |z_i w_i|: {res.max_complementarity:.3e}",
    ]
    c = res.certificate
    if c is not None:
        extra = "" if c.violation is None else f"; first violation {c.violation['kind']} at {c.violation['index']}"
        lines.append(
            f"certified: {c.certified} ({c.status}; backward error η = {c.backward_error:.2e}, exact residual "
            f"{c.natural_residual:.2e}, {c.violations} violation(s){extra})"
        )
    if res.dump_path:
        lines.append(f"dump:      {res.dump_path}")
    lines += [f"z = {_format_vector(res.z)}", f"w = {_format_vector(res.w)}"]
    return "\n".join(lines)


def _run_replay(args: argparse.Namespace) -> int:
    from ..io.dump import load_dump
    from ..io.forensics import replay

    if getattr(args, "index", None) is not None:
        raise CliError(f"{args.file}: a failure dump holds one LCP; --index does not apply")
    dump = load_dump(args.file)
    method = args.method or dump.method
    overrides = lemke_options(args, method)
    rep = replay(dump, method=args.method, certify=args.certify, dump=args.dump, **overrides)
    res = rep.result
    pivoting = rep.options.get("pivoting", "lexicographic") if rep.method == "lemke" else None
    if args.json:
        out = {"file": args.file, "n": int(res.z.shape[0]), **res.to_dict(), "replay": rep.to_dict()}
        if pivoting is not None:
            out["pivoting"] = pivoting
        print(json.dumps(out))
    else:
        opts = ", ".join(f"{k}={v}" for k, v in rep.options.items())
        lines = [
            f"replay of a failure dump written by lcpsim {dump.lcpsim_version or '?'}: dumped status {dump.status!r}",
            f"options:   {rep.method}({opts})",
            dump.trace_summary(),
            _summary(args.file, res, pivoting),
        ]
        if rep.overridden:
            lines.append(
                f"replay:    with changed options: status {res.status!r} (dumped {dump.status!r})"
                + (f", z differs by up to {rep.max_abs_dz:.3e}" if not rep.same_z else ", z identical")
            )
        elif rep.reproduced:
            lines.append(f"replay:    reproduces the dump (status {dump.status!r}, z identical)")
        elif rep.same_status:
            lines.append(f"replay:    reproduces status {dump.status!r}; z differs by up to {rep.max_abs_dz:.3e}")
        else:
            lines.append(f"replay:    does NOT reproduce the dump: status {res.status!r}, dumped {dump.status!r}")
        print("\n".join(lines))
    return EXIT_OK if res.ok else EXIT_NOT_SOLVED


def _run_solve(args: argparse.Namespace) -> int:
    from ..io.fclib import fclib_kind
    from ..io.dump import is_dump
    from ..io.hdf5_check import probe
    from ..io.lcp_file import file_format, load_lcp

    # The HDF5 library can crash or loop on a damaged file: read it in a child first.
    if os.path.isfile(args.file) and file_format(args.file) == "hdf5":
        probe(args.file, getattr(args, "index", None))
    if is_dump(args.file):
        return _run_replay(args)
    if fclib_kind(args.file):
        from .export_fclib import run_fclib_solve

        return run_fclib_solve(args)
    if args.friction_dirs is not None or args.scale is not None:
        raise CliError(f"{args.file}: --friction-dirs and --scale apply to FCLib files only")
    index = getattr(args, "index", None)
    M, q = load_lcp(args.file, index)
    method = args.method or "lemke"
    lemke = method == "lemke"
    kwargs = lemke_options(args, method)
    pivoting = kwargs.get("pivoting", "lexicographic") if lemke else None
    res = solve_lcp(M, q, method=method, certify=args.certify, dump=args.dump, **kwargs)
    if args.json:
        out = {"file": args.file, "n": int(res.z.shape[0]), **res.to_dict()}
        if index is not None:
            out["index"] = index
        if lemke:
            out["pivoting"] = pivoting
        print(json.dumps(out))
    else:
        name = args.file if index is None else f"{args.file} [{index}]"
        print(_summary(name, res, pivoting))
    return EXIT_OK if res.ok else EXIT_NOT_SOLVED


register_command(Command("solve", "solve an LCP stored in a file", _configure_solve, _run_solve))


# ---------------------------------------------------------------- demo


def _configure_demo(p: argparse.ArgumentParser) -> None:
    p.add_argument("--k", type=int, default=8, help="friction directions per contact (default: 8)")


def _run_demo(args: argparse.Namespace) -> int:
    from ..examples import cube_on_slope_lcp

    if args.k < 4 or args.k % 2:
        raise CliError(f"--k must be even and at least 4, got {args.k}")
    scenes = [
        ("resting, flat", cube_on_slope_lcp(0.0, 0.5, k=args.k)),
        ("20° slope, mu 0.5", cube_on_slope_lcp(20.0, 0.5, k=args.k)),
        ("30° slope, mu 0.5", cube_on_slope_lcp(30.0, 0.5, k=args.k)),
        ("30° slope, s=1e-3", cube_on_slope_lcp(30.0, 0.5, k=args.k, s=1e-3)),
    ]
    solvers: list[tuple[str, dict[str, Any]]] = [
        ("lemke lexicographic", dict(method="lemke", pivoting="lexicographic")),
        ("lemke classic", dict(method="lemke", pivoting="classic")),
        ("pgs", dict(method="pgs")),
        ("newton_fb", dict(method="newton_fb")),
    ]
    print(f"lcpsim {__version__} demo: one time step (h = 1e-3 s) of a 1 kg unit cube, 4 contacts, k = {args.k}")
    print("impulses in N·s; residual = ‖min(z, Mz+q)‖∞; Σfn = total normal impulse,")
    print("f_x = net friction impulse along the slope (−: uphill), max λ = sliding-speed multiplier\n")
    header = (
        f"{'scene':<19} {'n':>3}  {'solver':<20} {'status':<16} {'pivots':>6} {'residual':>9}"
        f"  {'Σfn':>10} {'f_x':>10} {'max λ':>9}"
    )
    print(header)
    print("-" * len(header))
    for name, lcp in scenes:
        for label, kw in solvers:
            res = solve_lcp(lcp.M, lcp.q, **kw)
            fn, fd, lam = lcp.split(res.z)
            fx = float(fd.sum(axis=0) @ np.cos(2 * np.pi * np.arange(lcp.k) / lcp.k))
            print(
                f"{name:<19} {lcp.M.shape[0]:>3}  {label:<20} {res.status:<16} {res.pivots:>6} "
                f"{res.residual:>9.2e}  {fn.sum():>10.3e} {fx:>10.3e} {lam.max():>9.2e}"
            )
    mgh = 9.81 * 1e-3
    c20, s20, c30 = np.cos(np.deg2rad(20)), np.sin(np.deg2rad(20)), np.cos(np.deg2rad(30))
    print(
        f"\nexact: flat Σfn = {mgh:.3e}, f_x = 0; 20° (sticks, tan θ < μ) Σfn = {mgh * c20:.3e}, "
        f"f_x = {-mgh * s20:.3e};\n       30° (slides, tan θ > μ) Σfn = {mgh * c30:.3e}, "
        f"f_x = −μ·Σfn = {-0.5 * mgh * c30:.3e}, λ > 0 (λ scales by 1/s)"
    )
    return EXIT_OK


register_command(
    Command("demo", "solve a small built-in contact LCP with each method", _configure_demo, _run_demo)
)
