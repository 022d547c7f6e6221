"""Sweeps on Dask — case grid, stable ids, resumable output; an
interrupted sweep (stopped, or killed with SIGKILL) resumed gives the same
results as an uninterrupted one; a killed worker loses no finished case."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from lcpsim.cli import main
from lcpsim.experiments import sweep

GRID = {
    "experiment": "slope",
    "base": {"seconds": 0.05, "mu": 1.0},
    "grid": {"angle_deg": [45.0001, 45.2], "scale": ["none", "1e-3"], "solver": ["classic", "robust"]},
}


def comparable(records):
    """Records keyed by id, without what legitimately differs between runs (timing, worker)."""
    out = {}
    for r in records:
        res = {k: v for k, v in r["result"].items() if k != "wall_time_s"}
        out[r["id"]] = {"experiment": r["experiment"], "config": r["config"], "result": res}
    return out


def test_expand_cases_ids_are_stable():
    a = sweep.expand_cases(GRID)
    b = sweep.expand_cases(json.loads(json.dumps(GRID)))
    assert len(a) == 8 and [c["id"] for c in a] == [c["id"] for c in b]
    assert len({c["id"] for c in a}) == 8
    assert all(c["id"].startswith("slope-") for c in a)
    # YAML-style "1e-3" strings are numbers; defaults are filled in.
    c = next(c for c in a if c["config"]["scale"] != "none")
    assert c["config"]["scale"] == 1e-3 and c["config"]["dt"] == 1e-3 and c["config"]["seed"] == 0
    multi = {"cases": [GRID, {"experiment": "push", "grid": {"force": [9.79, 9.83]}, "seeds": [0, 1]}]}
    assert len(sweep.expand_cases(multi)) == 12
    with pytest.raises(ValueError, match="unknown config key"):
        sweep.expand_cases({"experiment": "slope", "grid": {"angel": [1]}})
    with pytest.raises(ValueError, match="unknown experiment"):
        sweep.expand_cases({"experiment": "nope", "grid": {}})
    with pytest.raises(ValueError, match="non-empty list"):
        sweep.expand_cases({"experiment": "slope", "grid": {"mu": 1}})


@pytest.mark.slow
def test_interrupted_and_resumed_equals_uninterrupted(tmp_path):
    full = tmp_path / "full.h5"
    s = sweep.run_sweep(GRID, output=full, workers=2, processes=False, progress=None)
    assert s["complete"] and s["ran"] == 8 and s["failed"] == 0
    part = tmp_path / "part.h5"
    s1 = sweep.run_sweep(GRID, output=part, workers=2, processes=False, progress=None, stop_after=3)
    assert s1["ran"] == 3 and not s1["complete"]
    assert len(sweep.load_results(part)) == 3
    s2 = sweep.run_sweep(GRID, output=part, workers=2, processes=False, progress=None)
    assert s2["done_before"] == 3 and s2["ran"] == 5 and s2["complete"]
    assert comparable(sweep.load_results(part)) == comparable(sweep.load_results(full))
    # Nothing left to do: no cluster is even started.
    s3 = sweep.run_sweep(GRID, output=part, progress=None)
    assert s3["ran"] == 0 and s3["done_before"] == 8
    # Every record carries config, seed and version.
    for r in sweep.load_results(part):
        assert r["result"]["lcpsim_version"] and r["result"]["seed"] == 0 and r["config"]["seed"] == 0


@pytest.mark.slow
def test_killed_sweep_resumes(tmp_path):
    """SIGKILL the whole `lcpsim sweep` process group mid-run, then resume."""
    cfg = {**GRID, "base": {"seconds": 2.0, "mu": 1.0}, "seeds": [0, 1, 2]}
    cfg_path = tmp_path / "sweep.json"
    out = tmp_path / "killed.h5"
    cfg_path.write_text(json.dumps({**cfg, "output": "killed.h5"}))
    proc = subprocess.Popen(
        [sys.executable, "-m", "lcpsim", "sweep", str(cfg_path), "--workers", "1", "--no-progress"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )
    try:
        deadline = time.time() + 120
        while time.time() < deadline:
            if out.exists():
                try:
                    if len(sweep.load_results(out)) >= 2:
                        break
                except Exception:
                    pass
            if proc.poll() is not None:
                break
            time.sleep(0.05)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    done = len(sweep.load_results(out))
    assert 2 <= done < 24, done  # killed mid-sweep
    s = sweep.run_sweep(cfg, output=out, workers=2, processes=False, progress=None)
    assert s["complete"] and s["done_before"] == done and s["ran"] == 24 - done
    ref = tmp_path / "ref.h5"
    sweep.run_sweep(cfg, output=ref, workers=2, processes=False, progress=None)
    assert comparable(sweep.load_results(out)) == comparable(sweep.load_results(ref))


@pytest.mark.slow
def test_killed_worker_loses_no_finished_case(tmp_path):
    """Kill a worker process after the first result: every case still finishes once."""
    killed = []

    def kill_one(record, client):
        if not killed:
            pids = client.run(os.getpid)
            addr, pid = sorted(pids.items())[0]
            killed.append(pid)
            os.kill(pid, signal.SIGKILL)

    cfg = {**GRID, "base": {"seconds": 0.3, "mu": 1.0}}
    out = tmp_path / "workers.h5"
    s = sweep.run_sweep(cfg, output=out, workers=2, processes=True, progress=None, on_result=kill_one)
    assert killed and s["complete"] and s["failed"] == 0
    recs = sweep.load_results(out)
    assert len(recs) == 8 and len({r["id"] for r in recs}) == 8


def test_parquet_output(tmp_path):
    pytest.importorskip("pyarrow")
    out = tmp_path / "res.parquet"
    s = sweep.run_sweep(GRID, output=out, workers=1, processes=False, progress=None, stop_after=2)
    assert s["ran"] == 2
    s = sweep.run_sweep(GRID, output=out, workers=2, processes=False, progress=None)
    assert s["complete"] and s["done_before"] == 2
    assert len(sweep.load_results(out)) == 8


def test_cli_sweep_yaml(tmp_path, capsys):
    cfg = tmp_path / "s.yaml"
    cfg.write_text(
        "experiment: push\n"
        "base: {seconds: 0.05}\n"
        "grid:\n"
        "  force: [9.79, 9.83]\n"
        "  scale: [none, dt]\n"
        "output: push.h5\n"
    )
    assert main(["sweep", str(cfg), "--workers", "1", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "4/4 cases" in text and "outcome=rest" in text and "outcome=slide" in text
    assert (tmp_path / "push.h5").exists()
    assert main(["sweep", str(cfg), "--no-progress", "--json"]) == 0
    lines = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert len(lines) == 4 and {r["result"]["outcome"] for r in lines} == {"rest", "slide"}
    assert main(["sweep", str(tmp_path / "missing.yaml")]) == 2
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"experiment": "slope", "grid": {"angle": [1]}, "output": "x.h5"}))
    assert main(["sweep", str(bad)]) == 2
    assert "angle" in capsys.readouterr().err
