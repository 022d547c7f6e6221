"""The source note's experiments — presets, scales, classification, the
phenomena themselves and the command line (JSON keys, plots,
report). Small configs: the whole file runs in well under a minute."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

import lcpsim
from lcpsim.cli import main
from lcpsim.experiments import EXPERIMENTS, run_experiment
from lcpsim.experiments import critical_scale, failure_rate, invariance, patterns, push, slope
from lcpsim.experiments._common import parse_scale, scale_value
from lcpsim.experiments.presets import PRESETS, parse_solver
from lcpsim.experiments.cube_corpus import generate, scaled, simulations

G = 9.81
#: A small cube corpus for the tests (about 1,000 LCPs, all contact counts).
SMALL = {"corpus": {"n_random": 2, "steps": 150}}


def analytic(angle: float, mu: float, T: float) -> float:
    th = math.radians(angle)
    return 0.5 * G * (math.sin(th) - mu * math.cos(th)) * T * T


# ----------------------------------------------------------------- presets and scales


def test_presets():
    classic = parse_solver("classic")
    assert classic.method == "lemke" and dict(classic.options) == {"pivoting": "classic", "piv_tol": 1e-12, "zero_tol": 1e-6}
    assert parse_solver("robust").method == "lemke" and dict(parse_solver("robust").options) == {}
    s = parse_solver("lemke:pivoting=classic,zero_tol=1e-8")
    assert s.method == "lemke" and dict(s.options) == {"pivoting": "classic", "zero_tol": 1e-8}
    s = parse_solver("method=lemke,pivoting=classic,piv_tol=1e-10")
    assert dict(s.options) == {"pivoting": "classic", "piv_tol": 1e-10}
    s = parse_solver("classic:zero_tol=1e-8")
    assert dict(s.options) == {"pivoting": "classic", "piv_tol": 1e-12, "zero_tol": 1e-8}
    assert parse_solver("pgs").method == "pgs" and parse_solver("newton_fb:max_iterations=50").options == {"max_iterations": 50}
    assert parse_solver(classic.to_dict()) == classic
    assert parse_solver(parse_solver("lemke:pivoting=classic").spec).options == {"pivoting": "classic"}
    for bad in ("simplex", "lemke:pivoting=bland", "lemke:warp=9", "lemke:zero_tol", "", "pgs:piv_tol=1e-3"):
        with pytest.raises(ValueError):
            parse_solver(bad)
    assert set(PRESETS) >= {"classic", "robust", "pgs", "newton_fb"}


def test_scales():
    assert parse_scale("none") is None and parse_scale(None) is None and parse_scale("1") is None
    assert parse_scale("dt") == "dt" and parse_scale("1e-3") == 1e-3 and parse_scale(0.5) == 0.5
    assert scale_value("dt", 2e-3) == 2e-3 and scale_value(None, 1e-3) == 1.0 and scale_value(1e-6, 1e-3) == 1e-6
    for bad in ("0", "-1e-3", "huge", float("nan"), float("inf"), True):
        with pytest.raises(ValueError):
            parse_scale(bad)


def test_classify():
    c = slope.classify
    assert c(0.0, 1e-5, 6.0) == "tip"
    assert c(0.6e-5, 1e-5, 0.0) == "slide" and c(0.4e-5, 1e-5, 0.0) == "rest"
    assert c(2e-6, 0.0, 0.0) == "slide" and c(5e-7, 0.0, 0.0) == "rest"
    assert c(float("nan"), 1e-5, 0.0) == "tip"
    assert slope.expected_slide(45.0, 1.0, 1.0) == 0.0
    # At 45.0001° the analytic slide in 1 s is 12 µm.
    assert slope.expected_slide(45.0001, 1.0, 1.0) == pytest.approx(1.2107e-5, rel=1e-4)


def test_unknown_config_key_and_experiment():
    with pytest.raises(ValueError, match="angle"):
        slope.run({"angel_deg": 45})
    with pytest.raises(ValueError, match="unknown experiment"):
        run_experiment("nope")
    assert run_experiment("slope", {"seconds": 0.01})["experiment"] == "slope"


# ----------------------------------------------------------------- the corpus


def test_cube_corpus_is_seeded_and_covers_1_2_4_contacts():
    c1 = generate({**SMALL["corpus"], "seed": 3})
    c2 = generate({**SMALL["corpus"], "seed": 3}, cache=False)
    assert len(c1) == len(c2) > 500
    for g1, g2 in zip(c1.groups, c2.groups):
        assert np.array_equal(g1.M, g2.M) and np.array_equal(g1.q, g2.q)
    sizes = {g.contacts for g in c1.groups}
    assert {1, 2, 4} <= sizes
    names = [s.name for s in simulations({"seed": 3})]
    assert {"flat_drop", "edge_drop", "vertex_drop", "push_static", "slope_knife_45.2"} <= set(names)
    assert simulations({"seed": 3})[-1] != simulations({"seed": 4})[-1]
    # Scaling: D M D, D q with D = diag(I, I, sI).
    g = next(g for g in c1.groups if g.contacts == 2)
    Ms, qs, d = scaled(g.M[:1], g.q[:1], 2, 8, 1e-3)
    m = 2 * 9
    assert np.array_equal(Ms[0, :m, :m], g.M[0, :m, :m])
    assert np.allclose(Ms[0, m:, :2], 1e-3 * g.M[0, m:, :2], rtol=1e-15)
    assert np.all(g.mu() > 0)


# ----------------------------------------------------------------- the phenomena


def test_classic_preset_slides_unscaled_and_is_held_at_1e_3():
    """The source note's phenomenon at 45.2°, μ = 1, 1 kg unit cube, h = 1e-3: over
    2 s (0.097 m unscaled) the held cube has time to tip."""
    free = slope.run({"angle_deg": 45.2, "mu": 1.0, "scale": "none", "solver": "classic", "seconds": 2.0})
    held = slope.run({"angle_deg": 45.2, "mu": 1.0, "scale": 1e-3, "solver": "classic", "seconds": 2.0})
    assert free["outcome"] == "slide", free
    assert held["outcome"] in ("rest", "tip"), held
    # Held by friction beyond the cone before any failure: the tolerance artifact itself.
    assert held["held_steps_before_failure"] > 0 and held["cone_excess_max_Ns"] > 0


def test_classic_critical_scale_at_45_2():
    r = critical_scale.run({"angle_deg": 45.2, "mu": 1.0, "solver": "classic", "seconds": 2.0})
    assert r["critical_scale"] is not None, r
    assert 1e-6 < r["critical_scale"] < 1.0
    lo, hi = r["bracket"]
    assert lo < r["critical_scale"] < hi and math.log10(hi / lo) <= 0.05 + 1e-9
    assert {o["outcome"] for o in r["outcomes"] if o["scale"] == 1.0} == {"slide"}


@pytest.mark.parametrize("angle", [45.0001, 45.2])
@pytest.mark.parametrize("scale", ["none", 1e-3, 1e-6, 1e-8])
def test_robust_slides_at_every_scale(angle, scale):
    r = slope.run({"angle_deg": angle, "mu": 1.0, "scale": scale, "solver": "robust", "seconds": 1.0})
    exp = analytic(angle, 1.0, 1.0)
    assert r["expected_slide_m"] == pytest.approx(exp, rel=1e-12)
    assert r["outcome"] == "slide"
    assert r["slide_distance_m"] == pytest.approx(exp, rel=0.02)
    assert r["lcp_failures"] == 0 and r["cone_excess_steps"] == 0 and r["tilt_deg"] < 1e-3


def test_robust_critical_scale_slides_everywhere():
    r = critical_scale.run({"angle_deg": 45.0001, "solver": "robust", "seconds": 1.0})
    assert r["critical_scale"] is None and r["note"] == "slides_everywhere"
    assert all(o["outcome"] == "slide" for o in r["outcomes"])


@pytest.mark.parametrize("scale", ["none", "dt"])
def test_push(scale):
    stay = push.run({"force": 9.79, "mu": 1.0, "scale": scale})
    assert stay["outcome"] == "rest" and stay["expected_outcome"] == "rest"
    assert stay["friction_force_N"] == pytest.approx(9.79, abs=1e-9)
    assert stay["lambda_max"] < 1e-12 and stay["lcp_failures"] == 0
    # The load on the leading edge (the source note's 0, 1e-5, 0.004895, 0.004905 N·s).
    assert sorted(stay["normal_impulses"]) == pytest.approx([0.0, 1e-5, 0.004895, 0.004905], abs=1e-12)
    lead = [f for f, o in zip(stay["normal_impulses"], stay["contact_offsets_m"]) if o > 0]
    assert sum(lead) == pytest.approx(0.0098, abs=1e-12)
    go = push.run({"force": 9.83, "mu": 1.0, "scale": scale})
    assert go["outcome"] == "slide"
    assert go["friction_force_N"] == pytest.approx(9.81, abs=1e-8)
    assert go["displacement_m"] == pytest.approx(0.5 * (9.83 - 9.81) * 1.0, rel=0.02)


def test_invariance_robust_below_1e_12():
    r = invariance.run({**SMALL, "solver": "robust", "scale": 1e-3})
    assert r["lcps"] > 500 and r["compared"] == r["lcps"] and r["status_changed"] == 0
    assert r["max_rel_dfn"] < 1e-12 and r["max_rel_dfd"] < 1e-12 and r["max_rel_lambda_err"] < 1e-12
    assert r["max_abs_dfn"] < 1e-14 and r["max_abs_dfd"] < 1e-14
    # Any LCP that ended in another basis holds two valid solutions.
    assert r["different_basis"] == r["different_basis_both_valid"]
    for key in ("lcps", "max_abs_dfn", "max_abs_dfd", "max_rel_lambda_err"):
        assert key in r


def test_patterns_robust_has_no_impossible_pattern():
    for s in (1e-3, 1e-6):
        r = patterns.run({**SMALL, "solver": "robust", "scale": s})
        assert r["impossible"] == {"unscaled": 0, "scaled": 0, "unscaled_failed": 0, "scaled_failed": 0}
        assert r["impossible_lcps"] == []
        assert sum(r["counts_unscaled"].values()) == r["contacts"] == sum(map(sum, r["cross"]))
        # Sliding, static friction and breaking contacts all occur.
        assert r["counts_unscaled"]["+++"] > 0 and r["counts_unscaled"]["++0"] > 0 and r["counts_unscaled"]["000"] > 0


def test_patterns_classic_preset_shows_the_artifact():
    r = patterns.run({**SMALL, "solver": "classic", "scale": 1e-6})
    assert r["impossible"]["scaled"] > 0
    assert any(x["status"] == "solved" and x["solve"] == "scaled" for x in r["impossible_lcps"])


def test_failure_rate_counts():
    rob = failure_rate.run({**SMALL, "solver": "robust", "scales": ["none", 1e-3, 1e-6]})
    assert [row["scale"] for row in rob["rows"]] == ["none", "0.001", "1e-06"]
    for row in rob["rows"]:
        assert {"scale", "lcps", "failures", "rate"} <= set(row)
        assert row["failures"] == 0 and row["rate"] == 0.0
    classic = failure_rate.run({**SMALL, "solver": "classic", "scales": ["none", 1e-6]})
    for row in classic["rows"]:
        assert row["failures"] >= max(row["status_failures"], row["residual_failures"])
        assert row["failures"] <= row["status_failures"] + row["residual_failures"]
        assert row["rate"] == pytest.approx(row["failures"] / row["lcps"])
    # At s = 1e-6 the source note's Lemke accepts answers that are wrong in physical units.
    assert classic["rows"][1]["accepted_wrong"] > 0
    sim = failure_rate.run({**SMALL, "solver": "robust", "scales": ["dt"], "mode": "simulate"})
    assert sim["rows"][0]["s"] == 1e-3 and sim["rows"][0]["failures"] == 0 and sim["rows"][0]["lcps"] > 0


@pytest.mark.slow
def test_failure_rate_comparison():
    """Solvers × {cubes, hard} × scales, one row each; `rows` stays
    the first solver on the first corpus; robust is certified (n ≤ 40)."""
    r = failure_rate.run({**SMALL, "solvers": ["classic", "robust", "pgs", "newton_fb"], "corpora": ["cubes", "hard"],
                          "scales": ["none", 1e-6], "max_lcps": 150, "hard": {"count": 7}})
    assert [(c["solver"], c["corpus"], c["scale"]) for c in r["comparison"]][:3] == [
        ("classic", "cubes", "none"), ("classic", "cubes", "1e-06"), ("robust", "cubes", "none")]
    assert len(r["comparison"]) == 4 * 2 * 2 and r["certify"] == ["robust"]
    assert r["solver"]["name"] == "classic" and [row["scale"] for row in r["rows"]] == ["none", "1e-06"]
    assert r["corpora"]["hard"]["lcps"] == 7 and r["corpora"]["cubes"]["lcps"] == 150
    for c in r["comparison"]:
        assert {"lcps", "status_failures", "residual_failures", "rel_residual_failures", "accepted_wrong",
                "certified", "certified_eta", "cert_lcps"} <= set(c)
        if c["solver"] == "robust":
            assert c["status_failures"] == 0 and c["residual_failures"] == 0
            assert c["cert_lcps"] > 0 and 0 <= c["certified"] <= c["certified_eta"] <= c["cert_lcps"]
            assert c["corpus"] == "hard" or c["certified"] > 0
            assert c["certified_either"] == c["cert_lcps"]
        else:
            assert c["certified"] is None
    classic_hard = [c for c in r["comparison"] if c["solver"] == "classic" and c["corpus"] == "hard"]
    assert classic_hard[-1]["residual_failures"] > 0  # the source note's setting fails on the hard corpus at s = 1e-6
    json.dumps(r)
    with pytest.raises(ValueError, match="corpora"):
        failure_rate.run({**SMALL, "corpora": ["cubes", "soft"]})


@pytest.mark.slow
def test_cli_failure_rate_comparison(capsys):
    assert main(["failure-rate", "--solvers", "classic,robust", "--corpus", "cubes,hard", "--scales", "none,1e-8",
                 "--corpus-steps", "80", "--corpus-random", "0", "--max-lcps", "100", "--hard-count", "7"]) == 0
    out = capsys.readouterr().out
    assert "comparison" in out and "hard corpus: 7 LCPs" in out and "certified exact" in out
    assert out.count("robust ") >= 4


def test_every_result_carries_config_seed_version():
    small = {
        "failure-rate": {**SMALL, "scales": ["none"], "seed": 5},
        "slope": {"seconds": 0.05, "seed": 5},
        "critical-scale": {"seconds": 0.05, "lo": 1e-2, "seed": 5},
        "invariance": {**SMALL, "seed": 5, "max_lcps": 100},
        "patterns": {**SMALL, "seed": 5, "max_lcps": 100},
        "push": {"seconds": 0.05, "seed": 5},
    }
    for name in EXPERIMENTS:
        r = run_experiment(name, small[name])
        assert r["experiment"] == name and r["seed"] == 5 and r["lcpsim_version"] == lcpsim.__version__
        assert r["config"]["seed"] == 5
        json.dumps(r)  # JSON-ready


# ----------------------------------------------------------------- command line


def run_json(capsys, *argv):
    assert main(list(argv) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_cli_json_keys(capsys):
    r = run_json(capsys, "failure-rate", "--scales", "none,1e-3", "--solver", "classic", "--corpus-steps", "100",
                 "--corpus-random", "1", "--max-lcps", "300")
    assert [row["scale"] for row in r["rows"]] == ["none", "0.001"]
    assert {"scale", "lcps", "failures", "rate", "status_failures", "residual_failures"} <= set(r["rows"][0])
    r = run_json(capsys, "slope", "--angle-deg", "45.2", "--mu", "1", "--scale", "dt", "--seconds", "0.2")
    assert {"outcome", "slide_distance_m", "expected_slide_m", "tilt_deg", "lcp_failures"} <= set(r)
    assert r["s"] == 1e-3 and r["outcome"] == "slide"
    r = run_json(capsys, "critical-scale", "--angle-deg", "45.2", "--solver", "classic", "--seconds", "0.2", "--lo", "1e-3")
    assert {"critical_scale", "bracket", "outcomes"} <= set(r)
    r = run_json(capsys, "invariance", "--corpus-steps", "100", "--corpus-random", "1", "--max-lcps", "200")
    assert {"lcps", "max_abs_dfn", "max_abs_dfd", "max_rel_lambda_err"} <= set(r)
    r = run_json(capsys, "patterns", "--scale", "1e-3", "--corpus-steps", "100", "--corpus-random", "1", "--max-lcps", "200")
    assert {"counts_unscaled", "counts_scaled", "cross", "impossible_lcps"} <= set(r) and len(r["cross"]) == 8
    r = run_json(capsys, "push", "--force", "9.79", "--mu", "1", "--seconds", "0.1")
    assert {"outcome", "friction_force_N", "lambda_max"} <= set(r) and r["outcome"] == "rest"
    assert r["config"]["seed"] == 0 and r["lcpsim_version"] == lcpsim.__version__


@pytest.mark.slow
def test_cli_text_digits_and_plots(capsys, tmp_path):
    assert main(["invariance", "--digits", "20", "--corpus-steps", "150", "--corpus-random", "1",
                 "--plot", str(tmp_path / "inv.png")]) == 0
    out = capsys.readouterr().out
    assert "Before" in out and "After" in out and "Size = 40" in out
    assert (tmp_path / "inv.png").stat().st_size > 1000
    for argv in (
        ["slope", "--angle-deg", "45.2", "--seconds", "0.1", "--solver", "classic"],
        ["push", "--force", "9.83", "--seconds", "0.1"],
        ["critical-scale", "--angle-deg", "45.2", "--seconds", "0.1", "--lo", "1e-2", "--solver", "classic"],
        ["failure-rate", "--scales", "none,1e-6", "--corpus-steps", "80", "--corpus-random", "0", "--solver", "classic"],
        ["patterns", "--corpus-steps", "80", "--corpus-random", "0"],
    ):
        png = tmp_path / f"{argv[0]}.png"
        out_json = tmp_path / f"{argv[0]}.json"
        assert main(argv + ["--plot", str(png), "--out", str(out_json)]) == 0, argv
        text = capsys.readouterr().out
        assert argv[0] in text and str(png) in text
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert json.loads(out_json.read_text())["experiment"] == argv[0]


@pytest.mark.parametrize(
    "argv, words",
    [
        (["slope", "--solver", "simplex"], ["simplex"]),
        (["slope", "--solver", "lemke:pivoting=bland"], ["bland"]),
        (["push", "--solver", "lemke:warp=1"], ["warp"]),
        (["invariance", "--digits", "99"], ["digits"]),
        (["critical-scale", "--lo", "1", "--hi", "0.1"], ["lo"]),
    ],
)
def test_cli_errors_are_one_line(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lcpsim: error:") and "\n" not in err
    for w in words:
        assert w in err


def test_cli_bad_scale_is_usage_error(capsys):
    with pytest.raises(SystemExit) as e:
        main(["slope", "--scale", "-1"])
    assert e.value.code == 2


@pytest.mark.slow
def test_report_quick(tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["report", "--out", str(out), "--quick", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    html = (out / "index.html").read_text()
    md = (out / "report.md").read_text()
    assert summary["index_html"].endswith("index.html")
    for text in (html, md):
        assert "3.9 %" in text and "4e-3" in text and "0.004895" in text and "1e-16" in text
        for name in ("Failure rate", "Slope test", "Critical scale", "Scaling invariance", "Contact patterns", "Pushed cube",
                     "Solver comparison"):
            assert name in text
    for fig in summary["figures"].values():
        p = out / fig
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", fig
        assert fig in md and fig in html
    # Viewer pages: every slope test, the pushed cube, a stack and a heap, each linked
    # from its section of both documents.
    views = summary["views"]
    assert sum(v.startswith("view_slope_") for v in views) == len(slope.REPORT_SCALES) * len(slope.REPORT_ANGLES) * 2
    assert any(v.startswith("view_push_") for v in views) and {"view_stack.html", "view_heap.html"} <= set(views)
    for v in views:
        page = (out / v).read_text()
        assert page.startswith("<!DOCTYPE html>") and 'id="lcpsim-data"' in page and len(page) < 2_000_000
        assert f'href="{v}"' in html and f"]({v})" in md
    sections = html.split("<h2>")
    for v in views:
        head = next(s for s in sections if f'href="{v}"' in s).split("</h2>")[0]
        want = "Slope test" if "slope" in v else "Pushed cube" if "push" in v else "Many bodies"
        assert head.startswith(want), (v, head)
    results = json.loads((out / "results.json").read_text())
    assert results["lcpsim_version"] == lcpsim.__version__ and results["seed"] == 0
    assert os.path.getsize(out / "results.json") > 1000
