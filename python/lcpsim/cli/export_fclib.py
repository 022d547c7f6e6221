"""FCLib on the command line: ``lcpsim export-fclib CAPTURE.h5 --out DIR``,
and the FCLib branch of ``lcpsim solve FILE.hdf5`` (the faceted LCP, its LCP
residual and the exact-cone residual of its answer)."""

from __future__ import annotations

import argparse
import json

from .command import EXIT_NOT_SOLVED, EXIT_OK, CliError, Command, register_command

__all__ = ["run_fclib_solve"]


def run_fclib_solve(args: argparse.Namespace) -> int:
    """``lcpsim solve FILE`` for an FCLib file (called by :mod:`.solve`)."""
    from ..faceting import solve_fclib
    from ..io.fclib import read_fclib

    if getattr(args, "index", None) is not None:
        raise CliError(f"{args.file}: an FCLib file holds one problem; --index does not apply")
    if args.dump or args.certify:
        raise CliError(f"{args.file}: --dump and --certify apply to plain LCP files, not to FCLib problems")
    k = 8 if args.friction_dirs is None else args.friction_dirs
    if k < 2:
        raise CliError(f"--friction-dirs must be at least 2, got {k}")
    prob = read_fclib(args.file)
    opts = {k: v for k, v in {
        "pivoting": args.pivoting, "piv_tol": args.piv_tol, "zero_tol": args.zero_tol, "max_pivots": args.max_pivots,
    }.items() if v is not None}
    if (args.method or "lemke") != "lemke":
        opts = {}
    ans = solve_fclib(prob, k=k, scale=args.scale, method=args.method or "lemke", **opts)
    if args.json:
        print(json.dumps({"file": args.file, "format": "fclib", "title": prob.title, "method": ans.lcp.method, **ans.to_dict()}))
    else:
        f = ans.faceted
        lines = [
            f"file:      {args.file} (FCLib local problem, {f.nc} contacts" + (f": {prob.title}" if prob.title else "") + ")",
            f"LCP:       faceted cone, k = {f.k}, scale s = {f.scale:g}, n = {f.q.shape[0]}",
            f"method:    {ans.lcp.method}",
            f"status:    {ans.lcp.status}" + ("" if ans.ok else "   (not solved)"),
            f"pivots:    {ans.lcp.pivots}",
            f"LCP residual:        {ans.residual:.3e}   ‖min(z, Mz+q)‖∞ of the faceted LCP (s = 1)",
            f"exact-cone residual: {ans.exact_residual:.3e}   ‖natural map‖₂ / ‖q‖₂ on the Coulomb cone",
        ]
        print("\n".join(lines))
    return EXIT_OK if ans.ok else EXIT_NOT_SOLVED


def _configure_export(p: argparse.ArgumentParser) -> None:
    p.add_argument("capture", help="an HDF5 capture (World.run(..., capture=PATH), lcpsim simulate --capture)")
    p.add_argument("--out", required=True, metavar="DIR", help="directory for the FCLib files (created)")
    p.add_argument("--index", type=int, action="append", default=None, metavar="K",
                   help="export only record K (repeatable; default: every record)")
    p.add_argument("--storage", choices=["csc", "csr", "triplet"], default="csc", help="matrix storage (default: csc)")


def _run_export(args: argparse.Namespace) -> int:
    from ..faceting import export_capture
    from ..io.capture import is_capture

    if not is_capture(args.capture):
        raise CliError(f"{args.capture}: not an lcpsim capture (HDF5 with format attribute 'lcpsim-corpus')")
    paths = export_capture(args.capture, args.out, indices=args.index, storage=args.storage)
    print(f"wrote {len(paths)} FCLib local problem(s) to {args.out}")
    return EXIT_OK


register_command(
    Command("export-fclib", "write the LCPs of a capture as FCLib local problems", _configure_export, _run_export)
)
