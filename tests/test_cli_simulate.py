"""`lcpsim simulate SCENE`: summary text and JSON keys, scene parameters,
capture, exit codes and one-line errors."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from lcpsim.cli import main
from lcpsim.io.capture import open_capture

G = 9.81

JSON_KEYS = {
    "scene", "params", "world", "steps", "time", "body", "bodies", "final_position", "final_orientation",
    "final_velocity", "displacement", "distance", "tilt_deg", "max_tilt_deg", "direction", "slide",
    "expected_slide", "lcp", "islands", "wall_time", "steps_per_second", "capture", "captured",
}
LCP_KEYS = {"steps", "lcps", "failures", "by_status", "max_residual", "pivots_median", "pivots_max",
            "max_lcp_size", "max_contacts", "retaken", "stages", "backstop_fraction"}


def simulate_json(capsys, *args: str) -> tuple[int, dict]:
    rc = main(["simulate", *args, "--json"])
    out = capsys.readouterr().out
    return rc, json.loads(out)


def test_json_keys_and_knife_edge_slide(capsys):
    rc, d = simulate_json(capsys, "cube_on_slope", "--angle-deg", "45.2", "--mu", "1", "--steps", "2000")
    assert rc == 0
    assert set(d) == JSON_KEYS and set(d["lcp"]) == LCP_KEYS
    th = math.radians(45.2)
    assert d["slide"] == pytest.approx(0.5 * G * (math.sin(th) - math.cos(th)) * 4, rel=0.01)
    assert d["expected_slide"] == pytest.approx(d["slide"], rel=0.01)
    assert d["tilt_deg"] < 0.06 and d["steps"] == 2000 and d["time"] == pytest.approx(2.0)
    assert d["lcp"]["lcps"] == 2000 and d["lcp"]["failures"] == 0 and d["lcp"]["by_status"] == {"solved": 2000}
    assert d["lcp"]["max_lcp_size"] == 40 and d["params"]["angle_deg"] == 45.2
    assert d["world"]["cone_scale"] == "none" and d["capture"] is None and d["captured"] == 0


def test_options_reach_the_world(capsys):
    rc, d = simulate_json(
        capsys, "pushed_cube", "--force", "9.79", "--mu", "1", "--steps", "300", "--scale", "dt",
        "--pivoting", "lexicographic", "--zero-tol", "1e-7", "--dt", "0.002", "--friction-dirs", "4", "--set", "erp=0.1",
    )
    assert rc == 0
    w = d["world"]
    assert w["dt"] == 0.002 and w["scale"] == 0.002 and w["friction_dirs"] == 4 and w["erp"] == 0.1
    assert w["solver_options"] == {"pivoting": "lexicographic", "zero_tol": 1e-7}
    assert d["lcp"]["max_lcp_size"] == 4 * 6 and d["slide"] == pytest.approx(0.0, abs=1e-9)
    rc, d = simulate_json(capsys, "box_stack", "--n", "4", "--steps", "50", "--scale", "1e-3")
    assert rc == 0 and d["bodies"] == 4 and d["slide"] is None and d["world"]["scale"] == 1e-3
    rc, d = simulate_json(capsys, "box_pile", "--nx", "2", "--ny", "1", "--nz", "2", "--yaw", "0.3", "--seed", "3",
                          "--steps", "0")
    assert rc == 0 and d["steps"] == 0 and d["lcp"]["lcps"] == 0 and d["params"]["seed"] == 3


def test_text_summary(capsys):
    assert main(["simulate", "pushed_cube", "--force", "9.83", "--mu", "1", "--steps", "500"]) == 0
    out = capsys.readouterr().out
    for word in ("scene:", "pushed_cube", "final position", "displacement:", "tilt:", "slide:", "analytic",
                 "LCPs:", "failures 0", "residual:", "pivots:", "median", "LCP size:", "steps/s"):
        assert word in out, (word, out)


def test_capture_then_solve_an_index(tmp_path, capsys):
    path = tmp_path / "drop.h5"
    rc, d = simulate_json(capsys, "ball_drop", "--height", "0.05", "--steps", "200", "--capture", str(path))
    assert rc == 0 and d["capture"] == str(path)
    with open_capture(path) as c:
        assert len(c) == d["captured"] == d["lcp"]["lcps"] > 0
        assert c.metadata["scene"] == "ball_drop"
    assert main(["solve", str(path), "--index", "3"]) == 0
    assert "[3]" in capsys.readouterr().out


@pytest.mark.parametrize(
    "args, words",
    [
        (["box_stack", "--angle", "3"], ["box_stack", "--angle-deg"]),
        (["cube_on_slope", "--mu", "-1"], ["mu", "-1"]),
        (["cube_on_slope", "--angle-deg", "91"], ["angle_deg", "91"]),
        (["cube_on_slope", "--set", "warp=2"], ["warp"]),
        (["cube_on_slope", "--set", "erp"], ["NAME=VALUE"]),
        (["cube_on_slope", "--method", "pgs", "--pivoting", "classic"], ["--pivoting", "lemke"]),
        (["cube_on_slope", "--steps", "-5"], ["--steps"]),
        (["cube_on_slope", "--dt", "0"], ["dt", "0"]),
    ],
)
def test_invalid_input_is_one_line_on_stderr(capsys, args, words):
    assert main(["simulate", *args, "--steps", "10"] if "--steps" not in args else ["simulate", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("lcpsim: error: ")
    for w in words:
        assert w in err[0], (w, err[0])


def test_bad_scale_and_scene_via_argparse(capsys):
    with pytest.raises(SystemExit) as e:
        main(["simulate", "cube_on_slope", "--scale", "-1"])
    assert e.value.code == 2
    with pytest.raises(SystemExit):
        main(["simulate", "teapot"])
    capsys.readouterr()


def test_subprocess_help_lists_scenes_and_params():
    p = subprocess.run([sys.executable, "-m", "lcpsim", "simulate", "--help"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0
    for word in ("cube_on_slope", "pushed_cube", "box_pile", "--angle-deg", "--force", "--capture", "--scale",
                 "--json", "--set"):
        assert word in p.stdout, word
    p = subprocess.run([sys.executable, "-m", "lcpsim", "--help"], capture_output=True, text=True, timeout=120)
    assert "simulate" in p.stdout


def test_cube_heap_from_the_command_line(capsys):
    """`lcpsim simulate cube_heap --n N --seed S [--walls]`."""
    rc, d = simulate_json(capsys, "cube_heap", "--n", "5", "--seed", "3", "--walls", "--steps", "150")
    assert rc == 0 and d["bodies"] == 5
    assert {k: d["params"][k] for k in ("n", "seed", "walls")} == {"n": 5, "seed": 3, "walls": True}
    # Five cubes (four over one) fall together: one island once they have landed.
    assert d["islands"]["max"] >= 1 and d["islands"]["max_lcp_size"] > 0
    assert d["world"]["threads"] == 1


def test_a_pour_from_the_command_line(capsys):
    """`lcpsim simulate cube_pour --n N --seed S [--no-walls]`: the islands per stage in the JSON."""
    rc, d = simulate_json(capsys, "cube_pour", "--n", "6", "--seed", "2", "--no-walls", "--steps", "600")
    assert rc == 0
    assert d["lcp"]["failures"] == 0
    assert set(d["lcp"]["stages"]) == {"previous_basis", "guessed_basis", "structured_lemke", "dense"}
