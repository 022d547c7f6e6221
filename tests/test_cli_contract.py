"""The command line's contract. Every user error exits 2
with one line on stderr (argparse: one line plus a hint), exit 1 means only
"ran, but not solved / a case failed", a lcpsim bug exits 3; a sweep checks its
whole config before it starts and fails when a case fails; the CLI refuses the
option combinations the API refuses."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lcpsim.cli import EXIT_INTERNAL, Command, main
from lcpsim.io import save_lcp

REPROS = Path(__file__).parent / "data" / "repros"


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "lcpsim", *args], capture_output=True, text=True, timeout=300)


def assert_user_error(p: subprocess.CompletedProcess, *parts: str, hint: bool = False) -> str:
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    assert "Traceback" not in p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == (2 if hint else 1), p.stderr
    assert ": error: " in lines[0]
    if hint:
        assert lines[1].startswith("hint: ") and "--help" in lines[1]
    for part in parts:
        assert part in lines[0], (part, lines[0])
    return lines[0]


@pytest.fixture
def lcp_file(tmp_path):
    return str(save_lcp(tmp_path / "p.npz", np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, -1.0])))


@pytest.mark.parametrize(
    "args",
    [
        ("solve",),
        ("solve", "x.npz", "--bogus"),
        ("solve", "x.npz", "--max-pivots", "many"),
        ("simulate", "no_such_scene"),
        ("failure-rate", "--scales", "1e-3", "--nope"),
    ],
)
def test_argparse_errors_are_one_line_and_a_hint(args):
    line = assert_user_error(run(*args), hint=True)
    assert line.startswith(("lcpsim: error: ", f"lcpsim {args[0]}: error: "))


@pytest.mark.parametrize(
    "name, needle",
    [
        ("hugehdr.npz", "claims shape (1000000, 1000000)"),
        ("huge2.h5", "needs 298 GiB"),
        ("ext.h5", "external link"),
        ("dump_trace_garbage.h5", "'/trace' must be a group"),
        ("dump_opt_list.h5", "options attribute must be a JSON object"),
    ],
)
def test_damaged_files_exit_2(name, needle):
    assert_user_error(run("solve", str(REPROS / name)), needle)


@pytest.mark.parametrize(
    "extra",
    [("--method", "pgs", "--piv-tol", "1e-3"), ("--method", "newton_fb", "--pivoting", "classic"), ("--method", "pgs", "--max-pivots", "5")],
)
def test_cli_refuses_what_the_api_refuses(lcp_file, extra):
    import lcpsim

    with pytest.raises(ValueError):
        opt = extra[2].lstrip("-").replace("-", "_")
        lcpsim.solve_lcp(np.eye(2), -np.ones(2), method=extra[1], **{opt: float(extra[3]) if opt != "pivoting" else extra[3]})
    assert_user_error(run("solve", lcp_file, *extra), "applies only to --method lemke")


def test_not_solved_is_exit_1_and_distinct_from_errors(tmp_path):
    # q < 0 with M = −I: no solution; Lemke ray-terminates.
    path = save_lcp(tmp_path / "infeasible.npz", -np.eye(2), np.array([-1.0, -1.0]))
    p = run("solve", str(path))
    assert p.returncode == 1 and p.stderr == "" and "not solved" in p.stdout


def test_simulate_sizes_exit_2():
    assert_user_error(run("simulate", "box_stack", "--n", "100000", "--steps", "1"), "needs", "TiB")
    assert_user_error(run("simulate", "cube_on_slope", "--angle-deg", "30", "--mu", "0.5", "--friction-dirs", "1000000"), "friction_dirs")


def test_simulate_capture_refuses_an_existing_file(tmp_path):
    out = tmp_path / "c.h5"
    args = ("simulate", "resting_cube", "--steps", "5", "--capture", str(out))
    assert run(*args).returncode == 0
    assert_user_error(run(*args), "already exists", "--overwrite")
    assert run(*args, "--overwrite").returncode == 0


def test_a_bug_is_exit_3_not_1(capsys, monkeypatch):
    from lcpsim.cli import command

    def boom(_args):
        raise RuntimeError("a bug")

    # Registered for this test only (the registry is global).
    monkeypatch.setitem(command._COMMANDS, "__boom", Command("__boom", "test only", lambda p: None, boom))
    assert main(["__boom"]) == EXIT_INTERNAL == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("lcpsim: internal error") and "RuntimeError: a bug" in err[0]


def test_sweep_malformed_yaml_exits_2(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("experiment: push\ngrid: {force: [1, 2\n")
    assert_user_error(run("sweep", str(cfg)), "not valid YAML")


@pytest.mark.slow
def test_sweep_checks_the_whole_config_before_starting(tmp_path):
    # The second solver of the grid is invalid: refused before the first case runs.
    grid = {"force": [9.79, 9.83], "solver": ["robust", "lemke:bogus_option=1"]}
    cfg = tmp_path / "s.json"
    cfg.write_text(json.dumps({"experiment": "push", "base": {"seconds": 0.05}, "grid": grid, "output": "out.h5"}))
    assert_user_error(run("sweep", str(cfg), "--workers", "1", "--no-progress"), "sweep: push: solver")
    assert not (tmp_path / "out.h5").exists()
    cfg.write_text(json.dumps({"experiment": "push", "base": {"seconds": "fast"}, "output": "out.h5"}))
    assert_user_error(run("sweep", str(cfg), "--workers", "1", "--no-progress"), "seconds", "must be a finite number")


@pytest.mark.slow
def test_sweep_whose_cases_fail_exits_1(tmp_path):
    cfg = tmp_path / "s.yaml"
    # friction_dirs = 3 passes the config check (an integer) but every world refuses it.
    cfg.write_text("experiment: push\nbase: {seconds: 0.05, friction_dirs: 3}\ngrid: {force: [1.0, 2.0]}\noutput: out.h5\n")
    p = run("sweep", str(cfg), "--workers", "1", "--no-progress")
    assert p.returncode == 1, (p.stdout, p.stderr)
    assert "2 failed" in p.stdout
