"""``lcpsim report``: every experiment at its default size, one page.

Writes to the output directory ``index.html`` and ``report.md`` (the same
content), the figures as PNG, the 3-D viewer pages (``view_*.html``, see
:mod:`.views`), and ``results.json`` with every result (each
carrying its config, seed and lcpsim version). For each claim of the source
note the page puts the source note's number beside ours — with the
``classic`` preset (the source note's solver setting) and with ``robust`` (lcpsim's
default) — and says why they differ. Each experiment's runs, figures and
section come from its :class:`~.experiment.ReportPart` (see :mod:`.registry`);
this module adds the cube corpus, the claims table and the page itself.
"""

from __future__ import annotations

import json
import os
import sys
import time
from typing import IO, Any

from . import push
from ._common import jsonable
from .critical_scale import critical_text
from .document import Doc, pct
from .experiment import ReportContext
from .failure_rate import COMPARE_SCALES, COMPARE_SOLVERS, row_at
from .failure_rate import REPORT_SCALES as SCALES
from .push import REPORT_FORCES as PUSH_FORCES
from .registry import REGISTRY
from .cube_corpus import DEFAULTS as CORPUS_DEFAULTS
from .cube_corpus import generate, simulations
from .slope import REPORT_SCALES as SLOPE_SCALES
from .views import View, add_links, add_many_body_section, make_views

__all__ = ["make_report", "Doc", "SCALES", "SLOPE_SCALES", "PUSH_FORCES", "COMPARE_SOLVERS", "COMPARE_SCALES"]

TITLE = "lcpsim: the source note's experiments"

UNITS_NOTE = (
    "The source note does not state its units, mass, cube size or time step; every figure here is for "
    "a 1 kg, 1 m cube at h = 1e-3 s with impulses in N·s and k = 8 friction directions, so an absolute "
    "tolerance such as the source note's user zero of 1e-6 bites at different problems and different scales than in "
    "the source note's runs. Where a number differs, the phenomenon — not the number — is what is compared."
)


def make_report(
    out_dir: str | os.PathLike[str],
    *,
    seed: int = 0,
    quick: bool = False,
    log: IO[str] | None = sys.stderr,
) -> dict[str, Any]:
    """Runs everything and writes the report; returns ``{"index_html", "report_md", "results_json", …}``."""
    ctx = ReportContext(out=os.fspath(out_dir), seed=seed, quick=quick, log=log)
    out = ctx.out
    os.makedirs(out, exist_ok=True)
    parts = [e.report for e in REGISTRY.values() if e.report is not None]
    results: dict[str, Any] = {"corpus": _corpus_results(ctx)}
    for part in parts:
        results.update(part.run(ctx))
    if log is not None:
        log.write("report: figures …\n")
    figs: dict[str, str] = {}
    for part in parts:
        figs.update(part.figures(results, ctx))
    views = make_views(results, ctx)

    doc = _document(results, figs, views, ctx, time.perf_counter() - ctx.started)
    from .. import __version__

    results_path = os.path.join(out, "results.json")
    with open(results_path, "w") as fh:
        json.dump(jsonable({"lcpsim_version": __version__, "seed": seed, "quick": quick, "results": results}), fh)
    md_path = os.path.join(out, "report.md")
    html_path = os.path.join(out, "index.html")
    with open(md_path, "w") as fh:
        fh.write(doc.markdown())
    with open(html_path, "w") as fh:
        fh.write(doc.html(TITLE))
    return {
        "index_html": html_path,
        "report_md": md_path,
        "results_json": results_path,
        "figures": {k: os.path.relpath(v, out) for k, v in figs.items()},
        "views": [v.path for v in views],
        "wall_time_s": time.perf_counter() - ctx.started,
    }


def _corpus_results(ctx: ReportContext) -> dict[str, Any]:
    cc = {**CORPUS_DEFAULTS, **ctx.corpus, "seed": ctx.seed}
    corp = ctx.step("cube corpus", lambda: generate(cc))
    return {"config": cc, **corp.summary(), "simulations_spec": [s.to_dict() for s in simulations(cc)]}


def _document(res: dict[str, Any], figs: dict[str, str], views: list[View], ctx: ReportContext, wall: float) -> Doc:
    from .. import __version__

    d = Doc()
    d.h(1, TITLE)
    d.p(
        f"lcpsim {__version__}, seed {ctx.seed}{' (quick sizes)' if ctx.quick else ''}; generated in {wall:.0f} s. "
        "Every number below is recomputed by `lcpsim report` (each experiment also has its own command, "
        "shown with its section); `results.json` holds every result with its config, seed and version."
    )
    d.p(UNITS_NOTE)
    d.p(
        "Solvers: **classic** = Lemke with the classic pivoting rule, piv_tol 1e-12, zero_tol 1e-6, applied to the LCP "
        "as assembled (scaled by s) — the source note's setting; **robust** = lcpsim's default Lemke (lexicographic, "
        "equilibrated, accepted by its residual). Every answer is judged in physical units: λ mapped back "
        "(λ = s·λ_scaled), residual ‖min(z, w)‖∞ on the unscaled LCP."
    )
    d.h(2, "The source note's claims beside ours")
    d.table(["claim", "source note", "ours: classic preset", "ours: robust"], _claims(res))
    for para in _differences_text(res):
        d.p(para)
    _corpus_section(d, res["corpus"])
    for e in REGISTRY.values():
        if e.report is not None:
            e.report.section(d, res, figs, ctx)
            add_links(d, e.name, views)
    add_many_body_section(d, views, ctx)
    return d


def _claims(res: dict[str, Any]) -> list[list[Any]]:
    """Rows of the summary table: each claim of the source note, its number, ours with both presets."""
    frs, frr = res["failure_rate"]["classic"], res["failure_rate"]["robust"]
    crit = {(r["solver"]["name"], r["config"]["angle_deg"]): r for r in res["critical_scale"]}
    inv = {(r["solver"]["name"], r["scale"]): r for r in res["invariance"]}
    pat = {(r["solver"]["name"], r["scale"]): r for r in res["patterns"]}
    rows = []
    for sc, noteval in (("0.001", "3.9 % (97 of 2499)"), ("0.0001", "≈ 2.1 %"), ("1e-06", "0")):
        s_row, r_row = row_at(frs, sc), row_at(frr, sc)
        rows.append([
            f"Lemke failure rate, s = {sc}", noteval,
            f"{pct(s_row['status_rate'])} status; {pct(s_row['rate'])} incl. residual > 1e-6" if s_row else "—",
            f"{pct(r_row['rate'])}" if r_row else "—",
        ])
    for angle, noteval in ((45.0001, "≈ 4e-3"), (45.2, "— (an independent classic implementation: tips for s ≤ 0.1)")):
        rows.append([f"critical scale, {angle}°, μ = 1", noteval, critical_text(crit[("classic", angle)]),
                     critical_text(crit[("robust", angle)])])
    si, ri = inv[("classic", "0.001")], inv[("robust", "0.001")]
    rows.append([
        "scaling invariance of fn, fd (s = 1e-3, relative)", "~1e-16",
        f"{max(si['max_rel_dfn'], si['max_rel_dfd']):.2e} (same basis; {si['different_basis']} LCPs changed basis, "
        f"{si['status_changed']} changed status)",
        f"{max(ri['max_rel_dfn'], ri['max_rel_dfd']):.2e} (same basis; {ri['different_basis']} changed basis)",
    ])
    sp, rp = push.find(res["push"], "classic", "none", 9.79), push.find(res["push"], "robust", "none", 9.79)
    rows.append(["pushed cube 9.79 N: outcome, λ", "stays, λ ≈ 1e-19", f"{sp['outcome']}, λ max {sp['lambda_max']:.2e}",
                 f"{rp['outcome']}, λ max {rp['lambda_max']:.2e}"])
    rows.append([
        "pushed cube: normal impulses (N·s)", "0, 1e-5, 0.004895, 0.004905",
        ", ".join(f"{x:.6g}" for x in sorted(sp["normal_impulses"])),
        ", ".join(f"{x:.6g}" for x in sorted(rp["normal_impulses"])),
    ])
    ps, pr = pat[("classic", "0.001")], pat[("robust", "0.001")]
    rows.append([
        "impossible patterns; scaling changes patterns (s = 1e-3)", "none; scaling does not matter",
        f"{ps['impossible']['unscaled'] + ps['impossible']['scaled']} LCPs in solved answers "
        f"(+{ps['impossible']['unscaled_failed'] + ps['impossible']['scaled_failed']} in failed); "
        f"{ps['changed']} of {ps['contacts']} contacts change",
        f"{pr['impossible']['unscaled'] + pr['impossible']['scaled']} LCPs; {pr['changed']} of {pr['contacts']} change",
    ])
    return rows


def _corpus_section(d: Doc, c: dict[str, Any]) -> None:
    d.h(2, "The cube corpus")
    d.p(
        f"{c['lcps']} LCPs from {len(c['simulations'])} simulations of a 1 kg unit cube (h = 1e-3 s, k = 8), "
        "stepped unscaled with the robust solver: drops flat, on an edge and on a corner, sliding to rest, "
        "pushed at 9.79 N and 12 N, slopes at 20°, 30°, 45.0001°, 45.2°, and seeded random tumbles onto slopes "
        "(see `lcpsim.experiments.cube_corpus`). By size: "
        + ", ".join(f"n = {n}: {k}" for n, k in c["by_size"].items()) + "."
    )
    d.table(["simulation", "slope (°)", "μ", "LCPs"],
            [[s["name"], f"{s['angle_deg']:g}", f"{s['mu']:g}", s["lcps"]] for s in c["simulations"]])


def _g(x: Any, fmt: str = ".3g") -> str:
    return "—" if x is None else format(x, fmt)


def _differences_text(res: dict[str, Any]) -> list[str]:
    """Paragraphs saying where and why our figures differ from the source note's."""
    frs = res["failure_rate"]["classic"]
    crit = {(r["solver"]["name"], r["config"]["angle_deg"]): r for r in res["critical_scale"]}
    sl = {(r["solver"]["name"], r["config"]["angle_deg"], r["scale"]): r for r in res["slope"]}
    sp = push.find(res["push"], "classic", "none", 9.79)
    parts = []
    s3, s6 = row_at(frs, "0.001"), row_at(frs, "1e-06")
    if s3 and s6:
        parts.append(
            f"**Failure rates.** With the source note's setting our status failures fall from {pct(s3['status_rate'])} at "
            f"s = 1e-3 to {pct(s6['status_rate'])} at s = 1e-6 — the source note's trend (3.9 % → 0) — at other levels: "
            "the source note's one simulation, units and Lemke are not ours, and our corpus mixes many scenes. Judged in "
            "physical units the improvement is an artifact: the answers accepted at s = 1e-6 fail the unscaled "
            f"residual in {pct(s6['residual_rate'])} of the LCPs (friction without normal force, friction beyond "
            "the cone) — the source note's looser cone. The robust solver fails on none at any scale."
        )
    a, b = sl.get(("classic", 45.2, "none")), sl.get(("classic", 45.2, "0.001"))
    c0, c2 = crit[("classic", 45.0001)], crit[("classic", 45.2)]
    if a and b:
        txt = (
            "**Slope test and critical scale.** With the classic preset the 45.2° cube "
            f"{'slides' if a['outcome'] == 'slide' else a['outcome'] + 's'} unscaled ({_g(a['slide_distance_m'])} m in "
            f"{a['seconds']:g} s; analytic {_g(a['expected_slide_m'])} m; {a['lcp_failures']} failed LCPs) and at "
            f"s = 1e-3 ends as '{b['outcome']}' with {b['held_steps_before_failure']} solved steps carrying friction "
            "beyond μ·Σfn before any failure — the cube held by the looser cone, the source note's phenomenon."
        )
        if b["lcp_failures"]:
            st = ", ".join(f"{k} {v}" for k, v in b["by_status"].items() if k != "solved")
            txt += (
                f" There our classic Lemke then fails (first at t = {_g(b['first_failure_s'])} s; {st}); the "
                "simulator applies a failed solve's last iterate"
                + (f", which launches the cube (energy gain {_g(b['energy_gain_J'], '.2g')} J), so this 'tip' ends "
                   "as a blow-up." if b["energy_gain_J"] > 1e-6 else ".")
            )
        txt += (
            f" The switch lies at s ≈ {_g(c2['critical_scale'])}; an independent classic implementation "
            "tipped for s ≤ 0.1."
        )
        parts.append(txt)
    z = sl.get(("classic", 45.0001, "none"))
    lo = sl.get(("classic", 45.0001, "1e-06"))
    if z and lo:
        txt = (
            " At 45.0001° the stick solution of our 1 kg, 1 m cube violates the cone by only ~2.4e-8 N·s — below "
            "the user zero even unscaled — so a classic Lemke should hold it at every s ≤ 1, and the source note's 4e-3 "
            f"(its own units) has no counterpart here. Ours, unscaled: '{z['outcome']}', "
            f"{_g(z['slide_distance_m'])} m (analytic {_g(z['expected_slide_m'])} m)"
        )
        if z["lcp_failures"]:
            st = ", ".join(f"{k} {v}" for k, v in z["by_status"].items() if k != "solved")
            txt += (
                f", with failed LCPs from t = {_g(z['first_failure_s'])} s ({st}; a failed step applies no impulse, "
                "so the cube drops for that step)"
            )
        txt += (
            f"; at s = 1e-6: '{lo['outcome']}', {_g(lo['slide_distance_m'])} m with {lo['cone_excess_steps']} steps "
            f"of excess friction and {_g(lo['tilt_deg'])}° rotation (a held cube tipping slowly moves its centre "
            "down-slope too, and can pass the half-distance test). "
            + ("Outcomes are not monotone in s there; " if not c0["monotone"] else "")
            + f"the search reports {_g(c0['critical_scale']) if c0['critical_scale'] is not None else c0['note']}."
        )
        parts[-1] += txt
    rob = [r for r in res["slope"] if r["solver"]["name"] == "robust"]
    if rob:
        worst = max(abs(r["slide_rel_error"]) for r in rob if r["slide_rel_error"] is not None)
        parts[-1] += (
            f" The robust solver slides at every scale, within {100 * worst:.2f} % of the analytic distance, with no "
            "LCP failure."
        )
    parts.append(
        f"**Pushed cube.** The source note's λ ≈ 1e-19 is round-off in its solver; ours is {_g(sp['lambda_max'], '.2g')} with "
        f"the classic preset (unscaled; {sp['lcp_failures']} failed LCPs) and exactly 0 with robust. The normal "
        "impulses match the source note's to the digits shown."
    )
    return parts
