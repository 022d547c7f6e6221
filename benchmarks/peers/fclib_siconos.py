"""lcpsim's faceted Lemke beside Siconos' 3-D friction-contact solvers on the
exact Coulomb cone, on FCLib problems exported by lcpsim's simulator.

Scenes (each run with k = 8 and written with ``World.run(..., fclib=DIR)``):
a resting 5-box stack, a 3-box stack pushed at its base by 0.97·μ·(weight)
at 20° from t1 (it rests on the exact cone but not on the 4- and 8-facet
ones), a heap of cubes, and cubes on slopes (rest at 20°, slide at 30°, slide
at 30° with the slope between two friction directions). Every problem is then
solved by

  - lcpsim: the Stewart–Trinkle LCP with k = 4, 8, 16, 32 facets, Lemke
    (``lcpsim.fclib.solve_fclib``); a failure is an LCP not solved;
  - Siconos (Debian's python3-siconos, run by /usr/bin/python3 in a child
    process): NSGS and the Alart–Curnier nonsmooth Newton (NSN_AC), tolerance
    ``--tol`` (default 1e-10) on Siconos' own error measure, at most 10,000
    iterations; a failure is info ≠ 0 (tolerance not reached);

and every answer r is judged by the same exact-cone residual
(``lcpsim.fclib.exact_cone_residual``: natural map over ‖q‖). Time is per
solve (the solver call only: lcpsim's ``solve_lcp`` on the assembled LCP,
Siconos' ``fc3d_driver``), best of ``--repeat`` (once if it takes over 1 s).

    PYTHONPATH=python python3 benchmarks/peers/fclib_siconos.py [--write] [--out FILE.json] [--repeat 3] [--tol 1e-10]

Not part of the test suite; prints the Markdown table; ``--write`` puts it into
benchmarks/RESULTS.md as its own section (kept by run.py and many_bodies.py).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import lcpsim
from lcpsim import faceting, scenes, solve_lcp
from lcpsim.io import fclib

KS = (4, 8, 16, 32)
SICONOS_PYTHON = os.environ.get("SICONOS_PYTHON", "/usr/bin/python3")

SICONOS_CHILD = r"""
import json, sys, time
import numpy as np
import siconos.numerics as sn
spec = json.load(sys.stdin)
out = []
for f in spec["files"]:
    d = np.load(f)
    W, q, mu = d["W"], d["q"], d["mu"]
    nc = mu.shape[0]
    row = {}
    for name, sid in (("NSGS", sn.SICONOS_FRICTION_3D_NSGS), ("NSN_AC", sn.SICONOS_FRICTION_3D_NSN_AC)):
        best, info, r = float("inf"), None, None
        for _ in range(spec["repeat"]):
            fcp = sn.FrictionContactProblem(3, nc, W, q, mu)
            so = sn.SolverOptions(sid)
            so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 10000
            so.dparam[sn.SICONOS_DPARAM_TOL] = spec["tol"]
            rr, uu = np.zeros(3 * nc), np.zeros(3 * nc)
            t = time.perf_counter()
            info = sn.fc3d_driver(fcp, rr, uu, so)
            best = min(best, time.perf_counter() - t)
            r = rr
            if best > 1.0:
                break
        row[name] = {"info": int(info), "time": best, "r": r.tolist(), "iterations": int(so.iparam[sn.SICONOS_IPARAM_ITER_DONE])}
    out.append(row)
print(json.dumps({"version": getattr(sn, "__version__", None), "results": out}))
"""


def export_scenes(root: Path) -> dict[str, list[Path]]:
    """The FCLib files of each scene (k = 8 simulations)."""
    groups: dict[str, list[Path]] = {}

    def run(name: str, scene, steps: int, keep: int, force=None) -> None:
        d = root / name
        if force is not None:
            scene.world.apply_force(*force)
        scene.world.run(steps, fclib=d)
        files = sorted(d.glob("*.hdf5"))
        last_steps = sorted({f.name.split("-")[0] for f in files})[-keep:]
        groups[name] = [f for f in files if f.name.split("-")[0] in last_steps]

    run("resting stack (5 boxes)", scenes.box_stack(5), 200, 3)
    s = scenes.box_stack(3, mu=0.5)
    a, F = np.deg2rad(20.0), 0.97 * 0.5 * 3 * 9.81
    d = root / "loaded"
    s.world.apply_force(s.bodies[0], (F * np.cos(a), F * np.sin(a), 0.0))
    s.world.run(1, fclib=d)
    groups["stack pushed at 0.97 μ, 20° (rests on the exact cone)"] = sorted(d.glob("*.hdf5"))
    run("heap (12 cubes)", scenes.cube_heap(12, seed=1), 400, 2)
    run("slope 20°, μ 0.5 (rests)", scenes.cube_on_slope(20.0, 0.5), 100, 3)
    run("slope 30°, μ 0.5 (slides)", scenes.cube_on_slope(30.0, 0.5), 100, 3)
    run("slope 30°, μ 0.5, slope between facets (slides)", scenes.cube_on_slope(30.0, 0.5, tangent_angle=np.pi / 8), 100, 3)
    return groups


def lcpsim_solve(p: fclib.FclibLocal, k: int, repeat: int) -> dict:
    lcp = faceting.to_lcp(p, k)
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        res = solve_lcp(lcp.M, lcp.q)
        best = min(best, time.perf_counter() - t)
        if best > 1.0:  # slow solves are timed once
            break
    r = lcp.impulse(res.z)
    return {"ok": res.ok, "time": best, "exact": faceting.exact_cone_residual(p.W, p.q, p.mu, r), "n": int(lcp.q.size)}


def siconos_solve(problems: list[fclib.FclibLocal], tmp: Path, repeat: int, tol: float) -> tuple[str | None, list[dict]]:
    files = []
    for j, p in enumerate(problems):
        f = tmp / f"p{j}.npz"
        np.savez(f, W=p.dense_W(), q=p.q, mu=p.mu)
        files.append(str(f))
    out = subprocess.run([SICONOS_PYTHON, "-c", SICONOS_CHILD], input=json.dumps({"files": files, "repeat": repeat, "tol": tol}),
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"Siconos child failed ({SICONOS_PYTHON}): {out.stderr[-2000:]}")
    d = json.loads(out.stdout)
    for row, p in zip(d["results"], problems):
        for v in row.values():
            v["exact"] = faceting.exact_cone_residual(p.W, p.q, p.mu, np.asarray(v.pop("r")))
    return d["version"], d["results"]


def table(rows: list[dict]) -> str:
    solvers = [f"lcpsim k={k}" for k in KS] + ["Siconos NSGS", "Siconos NSN_AC"]
    lines = [
        "| scene | problems | contacts | solver | failed | exact-cone residual median / max | time median (ms) |",
        "|---|---|---|---|---|---|---|",
    ]
    for g in rows:
        for s in solvers:
            rs = g["results"][s]
            ex = np.array([r["exact"] for r in rs])
            fails = sum(not r["ok"] for r in rs)
            t = np.median([r["time"] for r in rs]) * 1e3
            lines.append(
                f"| {g['scene']} | {len(rs)} | {g['contacts']} | {s} | {fails} | {np.median(ex):.1e} / {ex.max():.1e} | {t:.3g} |"
            )
    return "\n".join(lines)


RESULTS_MD = Path(__file__).resolve().parents[1] / "RESULTS.md"
#: This benchmark's section of RESULTS.md: from this heading to the next top-level one (or the end).
HEADING = "## FCLib problems on the exact cone: lcpsim's faceted Lemke beside Siconos"


def git_rev() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=RESULTS_MD.parent).stdout.strip()


def section(body: str, args: argparse.Namespace, version: str | None, wall: float, rev: str) -> list[str]:
    import platform

    cmd = "PYTHONPATH=python python3 benchmarks/peers/fclib_siconos.py" + (f" --tol {args.tol:g}" if args.tol != 1e-10 else "")
    return [
        HEADING,
        "",
        f"Written by `{cmd} --write` (lcpsim {lcpsim.__version__} at {rev}, Siconos {version or '4.4 (Debian python3-siconos)'}, "
        f"Python {platform.python_version()}; {wall / 60:.1f} min; load average {' '.join(f'{x:.1f}' for x in os.getloadavg())} "
        "on 2 shared cores, so times are rough). Problems exported by lcpsim's simulator (k = 8) with "
        "`World.run(..., fclib=DIR)`; each solved by lcpsim's faceted Lemke at k = 4, 8, 16, 32 "
        "(`lcpsim.fclib.solve_fclib`; failed = LCP not solved) and by Siconos' `fc3d_driver` with NSGS and the "
        f"Alart–Curnier nonsmooth Newton (NSN_AC), tolerance {args.tol:g} on Siconos' own error, at most 10,000 "
        "iterations (failed = info ≠ 0: that tolerance not reached). Every answer r is judged by the same "
        "exact-cone residual, ‖natural map‖₂ / ‖q‖₂ (`lcpsim.fclib.exact_cone_residual`, Acary et al. 2018). "
        f"Time: the solve call only, best of {args.repeat} (once if over 1 s). The faceted answers' residual is "
        "the faceting error where the friction must point between facets (the pushed stack, the slope between "
        "facets) and rounding where it need not.",
        "",
        body,
        "",
    ]


def write_section(lines: list[str]) -> None:
    md = RESULTS_MD.read_text()
    head, _, rest = md.partition("\n" + HEADING)
    later = rest.split("\n## ", 1)
    keep = "\n## " + later[1].rstrip("\n") + "\n" if len(later) == 2 else ""
    RESULTS_MD.write_text(head.rstrip("\n") + "\n\n" + "\n".join(lines).rstrip("\n") + "\n" + keep)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help="write the results as JSON here")
    ap.add_argument("--repeat", type=int, default=3, help="time each solve as the best of N (default 3)")
    ap.add_argument("--tol", type=float, default=1e-10, help="Siconos' tolerance (its own error measure; default 1e-10)")
    ap.add_argument("--write", action="store_true", help=f"put the table into {RESULTS_MD.name} (its own section)")
    args = ap.parse_args()
    t0, rev = time.perf_counter(), git_rev()  # the commit the run starts from
    rows = []
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        groups = export_scenes(tmp / "fclib")
        version = None
        for scene, files in groups.items():
            problems = [fclib.read_fclib(f) for f in files]
            res: dict[str, list[dict]] = {}
            for k in KS:
                res[f"lcpsim k={k}"] = [lcpsim_solve(p, k, args.repeat) for p in problems]
            version, sic = siconos_solve(problems, tmp, args.repeat, args.tol)
            for name in ("NSGS", "NSN_AC"):
                res[f"Siconos {name}"] = [dict(r[name], ok=r[name]["info"] == 0) for r in sic]
            ncs = sorted({p.nc for p in problems})
            rows.append({"scene": scene, "contacts": f"{ncs[0]}–{ncs[-1]}" if len(ncs) > 1 else str(ncs[0]), "results": res})
            print(f"{scene}: {len(problems)} problems", file=sys.stderr)
    print(f"lcpsim {lcpsim.__version__}, Siconos {version or '(python3-siconos)'} (tol {args.tol:g}); exact-cone residual = "
          "‖natural map‖₂/‖q‖₂; failed = LCP not solved (lcpsim) or info ≠ 0 (Siconos)\n")
    print(table(rows))
    if args.write:
        write_section(section(table(rows), args, version, time.perf_counter() - t0, rev))
    if args.out:
        Path(args.out).write_text(json.dumps(rows, indent=1, default=float))


if __name__ == "__main__":
    main()
