#!/usr/bin/env python3
"""How `lcpsim.solve_lcp` scales on contact LCPs of cube heaps, n ≈ 400 → 40,000.

The LCPs are captured from lcpsim itself: a settled heap of unit cubes (the
final state of a heap run of ``benchmarks/peers/many_bodies.py``, by default
MuJoCo's heap of 1,000 cubes in 4 walls; ``--block`` or no such file: a
connected block of cubes, lcpsim's ``box_pile`` with towers side by side) is
cut into sub-heaps — the k cubes nearest the centre of the floor, which rest
on one another as they did in the heap — put at rest into an lcpsim World, and stepped once with
``World.run(1, capture=PATH)``; ``lcpsim.open_capture(PATH)`` gives the step's
LCP (the capturing step uses PGS with one iteration so that it costs little;
the LCP is assembled before any solver sees it). Then ``solve_lcp(M, q)``
(Lemke, defaults) is timed on it. Whatever form of LCP lcpsim captures and
solves (dense today; per island or sparse later), this script only calls
``solve_lcp`` on what was captured, summed over the step's LCPs.

With contact islands (one LCP per island), lcpsim sees a MuJoCo-settled heap
(slightly interpenetrating in places, apart in others) as many islands; the
fit then runs over every island's LCP, and ``--block`` gives one connected
LCP per size.

Each size runs in its own process under an address-space cap; sizes grow
geometrically and stop when the next one is predicted (n from the contacts per
cube so far, time from the fitted power law) to exceed the memory cap (the
dense M alone is n² · 8 B) or the time cap. Reported per size: cubes, LCPs
captured, n, time per solve, pivots, status, the dense M's size and the
process's peak RSS; and the exponent p of time ∝ n^p (log-log least squares).

The structured Lemke (``lcp::structured``: ``M = J M_b⁻¹ Jᵀ + K`` handed over as
its sparse factors, never formed) is timed beside it on the same sub-heaps, by
the Rust example ``structured_scaling`` (built here with cargo; the sub-heap's
boxes are passed as a text file, the LCP assembled as one LCP of all the
step's contacts). It goes on past the dense solver's limits, up to every cube
of the heap; its own table and fitted exponent follow the dense one. Up to
``--structured-dense-max-n`` the example also times the dense Lemke on the same
LCP in the same process (the speed-up column when the dense table is not run).

    benchmarks/peers/.venv/bin/python benchmarks/lcp_scaling.py [--max-solve-s 300] [--mem-cap-gb 6]
        [--only dense|structured] [--structured-dense-max-n 3100] [--structured-binary PATH]
"""

from __future__ import annotations

import argparse
import gc
import gzip
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
PEERS = HERE / "peers"
SIZES = [10, 16, 25, 40, 63, 100, 160, 250, 400, 630, 1000]
# The structured Lemke also at 52 cubes (n ≈ 1,440): the size where it first beat the dense Lemke 10×.
STRUCTURED_SIZES = sorted(SIZES + [52])


# --------------------------------------------------------------------------- the heaps


def settled_heap(path: Path, scene: str, engines: list[str]) -> tuple[dict[str, Any], str] | None:
    """(scene description with the boxes at the engine's final poses, where from), or None."""
    if not path.exists():
        return None
    with gzip.open(path, "rt") as f:
        res = json.load(f)
    entry = res["scenes"].get(scene)
    if entry is None:
        return None
    for eng in engines:
        s = entry["engines"].get(eng, {})
        fs = s.get("final_state")
        if not fs or not s.get("finite"):
            continue
        desc = json.loads(json.dumps(entry["initial_state"]))
        dyn = [b for b in desc["boxes"] if not b["static"]]
        for b, p, q in zip(dyn, fs["pos"], fs["quat"]):
            b["pos"], b["quat"] = p, q
        return desc, f"{scene} after {fs['step']} steps of {eng} ({path.name})"
    return None


def block_heap(cubes: int) -> tuple[dict[str, Any], str]:
    """A connected block: lcpsim's box_pile with towers side by side (spacing 1)."""
    sys.path.insert(0, str(PEERS))
    from many_scenes import describe
    from lcpsim import scenes

    side = math.ceil(math.sqrt(cubes / 5))
    nz = math.ceil(cubes / side**2)
    w = scenes.box_pile(side, side, nz, spacing=1.0).world
    return describe(w, f"box_pile({side}, {side}, {nz}, spacing=1.0)"), f"a block of box_pile({side}, {side}, {nz}, spacing=1.0)"


def sub_heap(desc: dict[str, Any], k: int) -> Any:
    """An lcpsim World at rest with the static boxes and the k cubes of ``desc`` nearest
    the point (0, 0, 0) at the centre of the floor: a chunk of the heap that
    rests as it did (what holds a cube up is lower, so nearer) and hangs together."""
    import lcpsim

    w = lcpsim.World(dt=desc["dt"], method="pgs", max_iterations=1)
    w.add_ground(mu=desc["mu"])
    dyn = [b for b in desc["boxes"] if not b["static"]]
    for b in desc["boxes"]:
        if b["static"]:
            w.add_box(half_extents=b["half"], position=b["pos"], orientation=b["quat"], mu=desc["mu"], static=True)
    for b in sorted(dyn, key=lambda b: float(np.linalg.norm(b["pos"])))[:k]:
        w.add_box(half_extents=b["half"], mass=b["mass"], position=b["pos"], orientation=b["quat"], mu=desc["mu"])
    return w


# --------------------------------------------------------------------------- one size (child process)


def one_size(desc_path: str, k: int, reps: int, max_solve_s: float) -> dict[str, Any]:
    import lcpsim

    with open(desc_path) as f:
        desc = json.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "heap.h5")
        t0 = time.perf_counter()
        w = sub_heap(desc, k)
        w.run(1, capture=path)
        capture_s = time.perf_counter() - t0
        del w  # the world's own copy of M, before the corpus's is read
        gc.collect()
        out: dict[str, Any] = {"cubes": k, "capture_s": capture_s, "lcps": []}
        with lcpsim.open_capture(path) as corpus:
            for rec in corpus:
                M, q = rec.M, rec.q  # as captured (dense today), handed to solve_lcp unchanged
                times, r = [], None
                for _ in range(reps):
                    t0 = time.perf_counter()
                    r = lcpsim.solve_lcp(M, q)
                    times.append(time.perf_counter() - t0)
                    if sum(times) > max_solve_s / 3:
                        break
                assert r is not None
                out["lcps"].append({"n": int(np.shape(q)[0]), "contacts": int(rec.contacts),
                                    "seconds": float(np.median(times)), "repeats": len(times),
                                    "pivots": int(r.pivots), "status": r.status, "m_bytes": stored_bytes(M)})
    out["n"] = sum(lp["n"] for lp in out["lcps"])
    out["n_max"] = max((lp["n"] for lp in out["lcps"]), default=0)
    out["seconds"] = sum(lp["seconds"] for lp in out["lcps"])
    out["pivots"] = sum(lp["pivots"] for lp in out["lcps"])
    out["m_bytes"] = sum(lp["m_bytes"] for lp in out["lcps"])
    out["statuses"] = sorted({lp["status"] for lp in out["lcps"]})
    return out


def stored_bytes(M: Any) -> int:
    """Bytes of M as captured: a dense array's, or a sparse matrix's arrays'."""
    if hasattr(M, "nbytes"):
        return int(M.nbytes)
    return int(sum(getattr(M, a).nbytes for a in ("data", "indices", "indptr") if hasattr(M, a)))


# --------------------------------------------------------------------------- the structured Lemke


ROOT = HERE.parent


def structured_binary(prebuilt: str | None = None) -> Path:
    """Builds the Rust example ``structured_scaling`` (release) and returns its path; or
    ``prebuilt``, an example binary built elsewhere (another commit's, for a before/after)."""
    if prebuilt:
        return Path(prebuilt)
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "lcpsim-sim", "--example", "structured_scaling"],
                   cwd=ROOT, check=True)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "examples" / "structured_scaling"


def write_boxes(desc: dict[str, Any], path: str) -> None:
    """The boxes of ``desc`` as the example reads them: ``static hx hy hz px py pz qw qx qy qz mass mu``."""
    with open(path, "w") as f:
        for b in desc["boxes"]:
            row = [int(b["static"]), *b["half"], *b["pos"], *b["quat"], b["mass"], desc["mu"]]
            f.write(" ".join(repr(float(x)) for x in row) + "\n")


def run_structured_child(binary: Path, boxes: str, k: int, mem_cap: int, timeout: float,
                         dense_max_n: int) -> dict[str, Any]:
    """One size by the structured Lemke (its own process, address space capped), and by the
    dense Lemke in the same process after it when n ≤ ``dense_max_n``."""
    cmd = [str(binary), boxes, str(k), str(dense_max_n)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                              preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (mem_cap, mem_cap)))
    except subprocess.TimeoutExpired:
        return {"cubes": k, "error": f"killed after {timeout:.0f} s"}
    if proc.returncode != 0:
        return {"cubes": k, "error": (proc.stderr.strip().splitlines() or [f"exit {proc.returncode}"])[-1]}
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    s = res.pop("structured")
    row = {"cubes": k, "n": res["n"], "contacts": res["contacts"], "seconds": s["seconds"],
           "solve_seconds": s.get("solve_seconds"), "pivots": s["pivots"], "status": s["status"],
           "accepted": s["accepted"], "residual": s.get("residual"),
           "peak_rss_mb": res.get("peak_rss_mb_structured", res["peak_rss_mb"])}
    if "dense" in res:
        d = res["dense"]
        row["dense"] = {"seconds": d["seconds"], "pivots": d["pivots"], "status": d["status"],
                        "residual": d.get("residual")}
    return row


def _sweep_start(desc: dict[str, Any], mem_cap_gb: float) -> tuple[int, int, list[dict[str, Any]], str]:
    """A size sweep's memory cap (bytes), dynamic cubes, rows so far and stop reason."""
    return int(mem_cap_gb * (1 << 30)), sum(not b["static"] for b in desc["boxes"]), [], "every size ran"


def _predicted_stop(last: dict[str, Any], k: int, n_next: float, p: float, max_solve_s: float) -> str | None:
    """Why the sweep stops before ``k`` cubes, if one solve at ``n_next`` is predicted (time ∝ n^p) to
    take longer than ``max_solve_s``."""
    t_next = last["seconds"] * (n_next / last["n"]) ** p
    if t_next <= max_solve_s:
        return None
    return (f"stopped before {k} cubes: n ≈ {n_next:,.0f}, one solve predicted to take "
            f"{t_next:.3g} s > {max_solve_s:g} s (time ∝ n^{p:.2f})")


def _append_row(rows: list[dict[str, Any]], row: dict[str, Any], k: int, label: str = "") -> str | None:
    """Keeps ``row`` (the run of ``k`` cubes); the sweep's stop reason if it ended in an error."""
    rows.append(row)
    if "error" not in row:
        return None
    print(f"  {label}{k} cubes: {row['error']}", flush=True)
    return f"stopped at {k} cubes: {row['error']}"


def run_structured(desc: dict[str, Any], max_solve_s: float, mem_cap_gb: float, dense_max_n: int,
                   prebuilt: str | None = None) -> dict[str, Any]:
    """Every size up to the whole heap, or until a solve is predicted to exceed ``max_solve_s``."""
    binary = structured_binary(prebuilt)
    cap, n_dyn, rows, stop = _sweep_start(desc, mem_cap_gb)
    with tempfile.TemporaryDirectory() as tmp:
        boxes = os.path.join(tmp, "boxes.txt")
        write_boxes(desc, boxes)
        for k in [k for k in STRUCTURED_SIZES if k <= n_dyn]:
            done = [r for r in rows if "error" not in r and r["n"] > 0]
            p = fit_exponent([(r["n"], r["seconds"]) for r in done if r["n"] >= 100])
            if done and p:
                n_next = max(r["n"] / r["cubes"] for r in done) * k
                if too_slow := _predicted_stop(done[-1], k, n_next, p, max_solve_s):
                    stop = too_slow
                    break
            row = run_structured_child(binary, boxes, k, cap, timeout=3 * max_solve_s + 120, dense_max_n=dense_max_n)
            if failed := _append_row(rows, row, k, "structured, "):
                stop = failed
                break
            print(f"  structured, {k} cubes: n = {row['n']}, {row['seconds']:.4g} s, {row['pivots']} pivots, "
                  f"{row['status']}, peak RSS {row['peak_rss_mb']:.0f} MB", flush=True)
    pts = [(r["n"], r["seconds"]) for r in rows if "error" not in r and r["n"] >= 100]
    return {"rows": rows, "stop": stop, "exponent": fit_exponent(pts)}


def table_head(cols: list[str]) -> list[str]:
    """A markdown table's header and rule."""
    return ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]


def error_row(r: dict[str, Any], ncols: int) -> str:
    """A size that did not run: its cubes and the error, the other cells empty."""
    return f"| {r['cubes']} | **{r['error']}** |" + " |" * (ncols - 2)


def render_structured(res: dict[str, Any], dense: dict[str, Any] | None) -> list[str]:
    """The structured Lemke's table, with the dense solve's time where both ran (the dense
    table's, else the example's own dense Lemke on the same LCP)."""
    dense_s = {r["cubes"]: r["dense"]["seconds"] for r in res["rows"] if "dense" in r}
    dense_s |= {r["cubes"]: r["seconds"] for r in (dense or {}).get("rows", []) if "error" not in r}
    lines = [
        "### Contact LCPs of heaps: the structured Lemke",
        "",
        "The same sub-heaps, each step's contacts as one LCP, solved by `lcp::structured` (`M = J M_b⁻¹ Jᵀ + K` as "
        "sparse factors: sparse LU of the basis in the augmented space, eta updates; no dense M). Command: "
        "`benchmarks/peers/.venv/bin/python benchmarks/lcp_scaling.py` (the Rust example `structured_scaling`).",
        "",
        *table_head(["cubes", "n", "contacts", "time (s)", "pivots", "status", "peak RSS (MB)", "dense Lemke (s)",
                     "speed-up"]),
    ]
    for r in res["rows"]:
        if "error" in r:
            lines.append(error_row(r, 9))
            continue
        d = dense_s.get(r["cubes"])
        dense_cells = f"{d:.4g} | {d / r['seconds']:.1f}×" if d else " | "
        lines.append(f"| {r['cubes']} | {r['n']:,} | {r['contacts']:,} | {r['seconds']:.4g} | {r['pivots']:,} | "
                     f"{r['status']} | {r['peak_rss_mb']:,.0f} | {dense_cells} |")
    p = res["exponent"]
    lines += ["", f"Fitted exponent (time ∝ n^p, n ≥ 100): p = {p:.2f}." if p else "Too few sizes for a fit.",
              f"Where it stops: {res['stop']}.", ""]
    return lines


# --------------------------------------------------------------------------- driver


def lcp_points(rows: list[dict[str, Any]]) -> list[tuple[int, float]]:
    """(n, seconds) of every LCP solved with n ≥ 100: the points of the fit (each island's
    LCP on its own once lcpsim splits a step's contacts into islands)."""
    return [(lp["n"], lp["seconds"]) for r in rows if "error" not in r for lp in r["lcps"] if lp["n"] >= 100]


def fit_exponent(points: list[tuple[int, float]]) -> float | None:
    """p of t ≈ a·n^p by least squares on (log n, log t)."""
    if len(points) < 2:
        return None
    x = np.log([n for n, _ in points])
    y = np.log([t for _, t in points])
    return float(np.polyfit(x, y, 1)[0])


def run_child(desc_path: str, k: int, reps: int, max_solve_s: float, mem_cap: int, timeout: float) -> dict[str, Any]:
    cmd = [sys.executable, __file__, "--one", desc_path, str(k), str(reps), str(max_solve_s)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (mem_cap, mem_cap)))
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        return {"cubes": k, "error": f"killed after {timeout:.0f} s"}
    finally:
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    if proc.returncode != 0:
        return {"cubes": k, "error": (err.strip().splitlines() or [f"exit {proc.returncode}"])[-1]}
    res = json.loads(out.strip().splitlines()[-1])
    res["peak_rss_mb_upto"] = peak  # max over all children so far (sizes grow, so this one's)
    return res


def run_all(desc: dict[str, Any], source: str, max_solve_s: float, mem_cap_gb: float, reps: int) -> dict[str, Any]:
    cap, n_dyn, rows, stop = _sweep_start(desc, mem_cap_gb)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "heap.json")
        with open(path, "w") as f:
            json.dump(desc, f)
        for k in [k for k in SIZES if k <= n_dyn]:
            done = [r for r in rows if "error" not in r and r["n"] > 0]
            if done:
                per_cube = max(r["n"] / r["cubes"] for r in done)
                n_next = per_cube * k
                # Peak RSS grows like the dense M (n² · 8 B): in the simulator, the corpus
                # read-back, the solver's copies; the last size's ratio predicts the next.
                copies = max(3.0, done[-1]["peak_rss_mb_upto"] * 2**20 / done[-1]["m_bytes"])
                need = copies * 8 * n_next**2
                if need > cap:
                    stop = (f"stopped before {k} cubes: n ≈ {n_next:,.0f} predicted, needing about {copies:.1f} × "
                            f"n² · 8 B = {need / 2**30:.1f} GiB > the {mem_cap_gb:g} GiB cap")
                    break
                p = fit_exponent(lcp_points(done)) or 3.0  # as if one LCP
                if too_slow := _predicted_stop(done[-1], k, n_next, p, max_solve_s):
                    stop = too_slow
                    break
            row = run_child(path, k, reps, max_solve_s, cap, timeout=3 * max_solve_s + 120)
            if failed := _append_row(rows, row, k):
                stop = failed
                break
            print(f"  {k} cubes: {len(row['lcps'])} LCP(s), n = {row['n']}, {row['seconds']:.4g} s, "
                  f"{row['pivots']} pivots, {row['statuses']}, peak RSS ≤ {row['peak_rss_mb_upto']:.0f} MB",
                  flush=True)
    return {"source": source, "rows": rows, "stop": stop, "exponent": fit_exponent(lcp_points(rows)),
            "max_solve_s": max_solve_s, "mem_cap_gb": mem_cap_gb}


def render(res: dict[str, Any]) -> list[str]:
    lines = [
        "### Contact LCPs of heaps: solve time against n",
        "",
        f"LCPs captured from sub-heaps (the k cubes nearest the centre of the floor) of {res['source']}, one step each; `solve_lcp` "
        "(Lemke, defaults) timed on each (median of up to 3 calls). Command: "
        "`benchmarks/peers/.venv/bin/python benchmarks/lcp_scaling.py`.",
        "",
        "| cubes | LCPs | n (largest, if several) | contacts | time to solve them (s) | pivots | status | M as captured (MB) "
        "| peak RSS (MB) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in res["rows"]:
        if "error" in r:
            lines.append(f"| {r['cubes']} | **{r['error']}** | | | | | | | |")
            continue
        contacts = sum(lp["contacts"] or 0 for lp in r["lcps"])
        n = f"{r['n']:,}" if len(r["lcps"]) == 1 else f"{r['n']:,} ({r.get('n_max', 0):,})"
        lines.append(f"| {r['cubes']} | {len(r['lcps'])} | {n} | {contacts:,} | {r['seconds']:.4g} | "
                     f"{r['pivots']:,} | {', '.join(r['statuses'])} | {r['m_bytes'] / 1e6:,.1f} | "
                     f"{r['peak_rss_mb_upto']:,.0f} |")
    p = res["exponent"]
    lines += ["", f"Fitted exponent (time ∝ n^p over every LCP with n ≥ 100): p = {p:.2f}." if p
              else "Too few sizes for a fit.",
              f"Where it stops: {res['stop']}."]
    good = [r for r in res["rows"] if "error" not in r and r["n"] > 0]
    if p and good:
        last = good[-1]
        t40k = last["seconds"] * (40_000 / last["n"]) ** p
        lines.append(f"Extrapolated from the largest size along that power law, one dense solve at n = 40,000 "
                     f"(the 10×10×10 towers) would take about {t40k / 3600:,.0f} h and M alone 12.8 GB.")
    if res.get("measured_at"):
        lines.append(f"Measured at {res['measured_at']}; data in `benchmarks/lcp_scaling.json`.")
    lines.append("")
    return lines


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "--one":
        _, _, path, k, reps, max_s = sys.argv
        print(json.dumps(one_size(path, int(k), int(reps), float(max_s))))
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--results", default=str(PEERS / "many_bodies.json.gz"), help="many_bodies.py's result file")
    ap.add_argument("--scene", default="heap1000")
    ap.add_argument("--engines", default="mujoco,rapier,pybullet,lcpsim", help="whose final heap to take, in order")
    ap.add_argument("--block", action="store_true", help="use a block of box_pile towers instead of a settled heap")
    ap.add_argument("--max-solve-s", type=float, default=300.0, help="stop when one solve would take longer")
    ap.add_argument("--mem-cap-gb", type=float, default=6.0)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=str(HERE / "lcp_scaling.json"))
    ap.add_argument("--only", choices=["dense", "structured"], help="run one solver only")
    ap.add_argument("--structured-dense-max-n", type=int, default=3100,
                    help="the structured example also runs the dense Lemke up to this n (speed-up column)")
    ap.add_argument("--structured-binary", help="a prebuilt structured_scaling example to time instead of building one")
    args = ap.parse_args()
    found = None if args.block else settled_heap(Path(args.results), args.scene, args.engines.split(","))
    desc, source = found if found else block_heap(max(SIZES))
    print(f"heaps from {source}", flush=True)
    res: dict[str, Any] = {"source": source}
    if args.only != "structured":
        res = run_all(desc, source, args.max_solve_s, args.mem_cap_gb, args.reps)
    if args.only != "dense":
        res["structured"] = run_structured(desc, args.max_solve_s, args.mem_cap_gb, args.structured_dense_max_n,
                                           args.structured_binary)
    rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                         cwd=Path(__file__).parent).stdout.strip()
    res["measured_at"] = f"commit {rev or 'unknown'}"
    Path(args.out).write_text(json.dumps(res, indent=1))
    lines = render(res) if "rows" in res else []
    if "structured" in res:
        lines += render_structured(res["structured"], res if "rows" in res else None)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
