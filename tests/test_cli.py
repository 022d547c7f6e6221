"""The lcpsim command line, run as a subprocess like a user would."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import lcpsim
from lcpsim.io import save_lcp

M = np.array([[2.0, 1.0], [1.0, 2.0]])
Q = np.array([-1.0, -1.0])


def run(*args: str, check_rc: int | None = None) -> subprocess.CompletedProcess:
    p = subprocess.run([sys.executable, "-m", "lcpsim", *args], capture_output=True, text=True, timeout=120)
    if check_rc is not None:
        assert p.returncode == check_rc, (p.returncode, p.stdout, p.stderr)
    return p


def assert_one_line_error(p: subprocess.CompletedProcess, *parts: str) -> None:
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("lcpsim: error: "), lines[0]
    assert "Traceback" not in p.stderr
    for part in parts:
        assert part in lines[0], (part, lines[0])


def test_version():
    p = run("--version", check_rc=0)
    assert p.stdout.strip() == f"lcpsim {lcpsim.__version__}"


def test_console_script_version():
    # The script installed beside this interpreter first: one found on PATH
    # may be another Python's (a pyenv shim of a version without lcpsim).
    beside = os.path.join(os.path.dirname(sys.executable), "lcpsim")
    exe = beside if os.path.exists(beside) else shutil.which("lcpsim")
    if exe is None:
        pytest.skip("lcpsim console script not on PATH")
    p = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and lcpsim.__version__ in p.stdout


def test_help_lists_subcommands():
    p = run("--help", check_rc=0)
    for word in ("solve", "demo", "--version"):
        assert word in p.stdout
    p = run("solve", "--help", check_rc=0)
    for word in ("--method", "--pivoting", "--json", "FILE".lower()):
        assert word in p.stdout.lower()


def test_no_command_prints_help_and_fails():
    p = run()
    assert p.returncode == 2
    assert "usage" in p.stderr.lower()


@pytest.mark.parametrize("suffix", [".npz", ".h5"])
def test_solve_human(tmp_path, suffix):
    path = save_lcp(tmp_path / f"p{suffix}", M, Q)
    p = run("solve", str(path), check_rc=0)
    assert "status:    solved" in p.stdout
    assert "residual" in p.stdout and "pivots" in p.stdout
    assert "n = 2" in p.stdout


@pytest.mark.parametrize("suffix", [".npz", ".h5"])
@pytest.mark.parametrize("pivoting", ["lexicographic", "classic"])
def test_solve_json(tmp_path, suffix, pivoting):
    path = save_lcp(tmp_path / f"p{suffix}", M, Q)
    p = run("solve", str(path), "--json", "--pivoting", pivoting, check_rc=0)
    out = json.loads(p.stdout)
    assert out["status"] == "solved" and out["ok"] is True
    assert out["pivoting"] == pivoting and out["method"] == "lemke"
    assert isinstance(out["pivots"], int)
    z = np.array(out["z"])
    w = np.array(out["w"])
    np.testing.assert_allclose(z, [1 / 3, 1 / 3], atol=1e-9)
    np.testing.assert_allclose(w, M @ z + Q, atol=1e-12)
    assert out["residual"] <= 1e-9


@pytest.mark.parametrize("method", ["pgs", "newton_fb"])
def test_solve_other_methods(tmp_path, method):
    path = save_lcp(tmp_path / "p.npz", M, Q)
    p = run("solve", str(path), "--method", method, "--json")
    out = json.loads(p.stdout)
    assert out["method"] == method
    assert p.returncode == (0 if out["ok"] else 1)


def test_unsolved_exit_code(tmp_path):
    path = save_lcp(tmp_path / "inf.npz", [[-1.0]], [-1.0])
    p = run("solve", str(path), "--json")
    out = json.loads(p.stdout)
    assert out["ok"] is False and out["status"] != "solved"
    assert p.returncode == 1


def test_missing_file(tmp_path):
    assert_one_line_error(run("solve", str(tmp_path / "missing.npz")), "missing.npz", "no such file")


@pytest.mark.parametrize(
    "name, content, parts",
    [
        ("bad.npz", b"not a zip", ["bad.npz", "npz"]),
        ("bad.h5", b"not hdf5", ["bad.h5", "HDF5"]),
        ("bad.txt", b"1 2 3", ["bad.txt", "format"]),
    ],
)
def test_malformed_file(tmp_path, name, content, parts):
    (tmp_path / name).write_bytes(content)
    assert_one_line_error(run("solve", str(tmp_path / name)), *parts)


def test_missing_array(tmp_path):
    np.savez(tmp_path / "noq.npz", M=M)
    assert_one_line_error(run("solve", str(tmp_path / "noq.npz")), "noq.npz", "'q'")


def test_wrong_shapes(tmp_path):
    np.savez(tmp_path / "shape.npz", M=np.ones((2, 3)), q=Q)
    assert_one_line_error(run("solve", str(tmp_path / "shape.npz")), "square", "(2, 3)")


def test_non_finite(tmp_path):
    np.savez(tmp_path / "nan.npz", M=np.array([[1.0, np.nan], [0.0, 1.0]]), q=Q)
    assert_one_line_error(run("solve", str(tmp_path / "nan.npz")), "M[0, 1]", "nan")


def test_bad_option_value(tmp_path):
    path = save_lcp(tmp_path / "p.npz", M, Q)
    assert_one_line_error(run("solve", str(path), "--piv-tol", "-1"), "piv_tol", "-1")
    p = run("solve", str(path), "--method", "simplex")
    assert p.returncode == 2 and "invalid choice" in p.stderr


def test_demo():
    p = run("demo", check_rc=0)
    for word in ("lemke lexicographic", "lemke classic", "pgs", "newton_fb", "status", "residual"):
        assert word in p.stdout
    # 4 scenes × 4 solvers
    rows = [line for line in p.stdout.splitlines() if any(s in line.split() for s in lcpsim.STATUSES)]
    assert len(rows) == 16, p.stdout


def test_main_in_process(capsys, tmp_path):
    from lcpsim.cli import main

    path = save_lcp(tmp_path / "p.npz", M, Q)
    assert main(["solve", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] is True
    assert main(["solve", str(tmp_path / "missing.h5")]) == 2
    assert "no such file" in capsys.readouterr().err
