"""The viewer without a browser: trajectories with their contacts, saved to HDF5
and loaded back; the viewer page's data, size cap and downsampling; `lcpsim
view` and its one-line errors. The page in a real browser: test_viewer_browser.py."""

from __future__ import annotations

import base64
import json
import math
import re

import h5py
import numpy as np
import pytest

from lcpsim import Trajectory, scenes
from lcpsim.cli import main
from lcpsim.io import save_lcp
from lcpsim.io.trajectory_file import TrajectoryFileError
from lcpsim.viewer import render_html
from lcpsim.viewer.encode import choose_frames

CLASSIC = {"pivoting": "classic", "piv_tol": 1e-12, "zero_tol": 1e-6}
G = 9.81


@pytest.fixture(scope="module")
def failing():
    """The source note's classic Lemke on the 45.0001° slope, unscaled: a few LCPs cycle (real failures)."""
    s = scenes.cube_on_slope(45.0001, 1.0, **CLASSIC)
    traj = s.world.run(300, record_contacts=True)
    assert traj.failures > 0, "this scene no longer fails: pick another for the failed-step tests"
    return s, traj


def page_data(page: str) -> dict:
    m = re.search(r'<script type="application/json" id="lcpsim-data">(.*?)</script>', page, re.S)
    assert m is not None
    return json.loads(m.group(1))


def decode(a: dict) -> np.ndarray:
    dt = {"f4": "<f4", "f8": "<f8", "i4": "<i4", "u1": "u1"}[a["dtype"]]
    return np.frombuffer(base64.b64decode(a["b64"]), dtype=dt).reshape(a["shape"])


# ---------------------------------------------------------------- recording contacts


def test_recording_contacts_changes_nothing_and_matches_the_step_records():
    a = scenes.cube_on_slope(45.2, 1.0).world
    b = a.copy()
    c = a.copy()
    plain = a.run(300)
    rec = b.run(300, record_contacts=True)
    for name in ("positions", "orientations", "velocities", "status", "pivots", "residual", "normal_impulse"):
        assert np.array_equal(getattr(plain, name), getattr(rec, name)), name
    log = rec.contact_log
    assert plain.contact_log is None and log is not None and len(log) == 300
    assert np.array_equal(log.counts, rec.contacts)
    records = [c.step() for _ in range(300)]
    for t in (0, 1, 150, 299):
        r = records[t]
        got = log.at(t)
        for f in ("points", "normals", "fn", "friction", "lam", "body_a", "body_b"):
            assert np.array_equal(got[f], getattr(r, f)), (t, f)
    # Σ over contacts equals the trajectory's per-step totals.
    fn_sum = np.add.reduceat(log.fn, log.offsets[:-1])
    assert np.allclose(fn_sum, rec.normal_impulse, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="record_contacts"):
        a.run(1, capture="x.h5", record_contacts=True)


def test_config_travels_with_the_trajectory():
    s = scenes.box_stack(2)
    traj = s.world.run(3)
    assert traj.config["scene"] == "box_stack"
    kinds = [b["kind"] for b in traj.config["bodies"]]
    assert kinds == [s.world.body(i).kind for i in range(s.world.body_count)]


# ---------------------------------------------------------------- HDF5


def test_save_and_load_round_trip(tmp_path, failing):
    _, traj = failing
    path = traj.save(tmp_path / "t.h5")
    back = Trajectory.load(path)
    for name in ("time", "positions", "orientations", "velocities", "pivots", "residual", "solver_residual",
                 "lcp_size", "contacts", "normal_impulse", "friction_impulse", "max_lambda", "islands",
                 "max_island_size", "initial_positions", "initial_orientations", "initial_velocities"):
        assert np.array_equal(getattr(back, name), getattr(traj, name)), name
    assert list(back.status) == list(traj.status) and back.failures == traj.failures > 0
    assert back.dt == traj.dt and back.config == json.loads(json.dumps(traj.config))
    for f in ("offsets", "points", "normals", "fn", "friction", "lam", "body_a", "body_b"):
        assert np.array_equal(getattr(back.contact_log, f), getattr(traj.contact_log, f)), f
    # Without a contact log, and empty.
    plain = scenes.resting_cube().world.run(0)
    back = Trajectory.load(plain.save(tmp_path / "empty.h5"))
    assert len(back) == 0 and back.contact_log is None and back.bodies == plain.bodies


@pytest.mark.slow
def test_bad_files_raise_one_clear_error(tmp_path, failing):
    _, traj = failing
    good = traj.save(tmp_path / "good.h5")
    with pytest.raises(FileNotFoundError):
        Trajectory.load(tmp_path / "missing.h5")
    data = open(good, "rb").read()
    (tmp_path / "trunc.h5").write_bytes(data[: len(data) // 3])
    with pytest.raises(TrajectoryFileError, match="not a readable HDF5 file"):
        Trajectory.load(tmp_path / "trunc.h5")
    (tmp_path / "text.h5").write_text("hello")
    with pytest.raises(TrajectoryFileError, match="not a readable HDF5 file"):
        Trajectory.load(tmp_path / "text.h5")
    save_lcp(tmp_path / "lcp.h5", np.eye(2), -np.ones(2))
    with pytest.raises(TrajectoryFileError, match="not an lcpsim trajectory .it holds M, q"):
        Trajectory.load(tmp_path / "lcp.h5")
    scenes.resting_cube().world.run(2, capture=tmp_path / "cap.h5")
    with pytest.raises(TrajectoryFileError, match="not an lcpsim trajectory .its format is 'lcpsim-corpus'"):
        Trajectory.load(tmp_path / "cap.h5")
    with h5py.File(good, "a") as f:
        del f["positions"]
    with pytest.raises(TrajectoryFileError, match="damaged trajectory file"):
        Trajectory.load(good)


# ---------------------------------------------------------------- the page


def test_page_holds_the_run_and_fits_the_cap():
    s = scenes.cube_on_slope(45.2, 1.0)
    traj = s.world.run(2000, record_contacts=True)
    page = render_html(traj, body=s.body, direction=s.direction)
    assert len(page.encode()) <= 2_000_000
    d = page_data(page)
    assert d["steps"] == 2000 and d["frames"] == 2001 and d["stride"] == 1 and "downsampled-notice" not in page
    steps = decode(d["arrays"]["frame_step"])
    assert np.array_equal(steps, np.arange(2001))
    # The down-slope distance read out equals the analytic slide, ½ g (sin θ − μ cos θ) t².
    th = math.radians(45.2)
    along = decode(d["arrays"]["focus_along"])
    assert along[0] == 0 and along[-1] == pytest.approx(0.5 * G * (math.sin(th) - math.cos(th)) * 4, rel=0.01)
    pose = decode(d["arrays"]["pose"])
    assert pose.shape == (2001, 1, 7)
    assert np.allclose(pose[-1, 0, :3], traj.positions[-1, s.body], atol=1e-6)
    assert d["failed_runs"] == []
    # No address of any server: everything the page needs is inside it.
    assert not re.search(r"<script[^>]+src=|<link[^>]+href=|@import", page)


def test_downsampling_keeps_every_failed_step_and_says_so(failing):
    _, traj = failing
    full = page_data(render_html(traj))
    assert full["frames"] == 301
    failed = np.nonzero(~traj.ok)[0] + 1
    page = render_html(traj, max_bytes=800_000)  # three.js alone is ~720 kB
    d = page_data(page)
    assert len(page.encode()) <= 800_000 and d["stride"] > 1 and d["frames"] < 301
    assert "downsampled-notice" in page and f"(one step in {d['stride']}," in page
    kept = decode(d["arrays"]["frame_step"])
    assert set(failed) <= set(kept) and kept[0] == 0 and kept[-1] == 300
    assert [r[0] for r in d["failed_runs"]] == [int(s) for s in failed]
    # Every step's status is kept, whatever the stride.
    codes = decode(d["arrays"]["step_status"])
    assert [d["status_names"][c] for c in codes] == list(traj.status)
    with pytest.raises(ValueError, match="max_bytes"):
        render_html(traj, max_bytes=100_000)


def test_a_long_run_is_downsampled_under_the_default_cap():
    traj = scenes.cube_on_slope(45.2, 1.0).world.run(8000, record_contacts=True)
    page = render_html(traj)
    d = page_data(page)
    assert len(page.encode()) <= 2_000_000 and d["stride"] >= 2 and "downsampled-notice" in page
    kept = decode(d["arrays"]["frame_step"])
    assert kept[-1] == 8000 and np.all(np.diff(kept) <= d["stride"])  # never truncated: evenly thinned to the end
    assert decode(d["arrays"]["step_status"]).size == 8000


def test_choose_frames_is_the_smallest_stride_that_fits():
    cost = np.full(101, 10.0)
    idx, stride = choose_frames(cost, np.array([37], np.int64), budget=10.0 * 30)
    assert stride == 4 and 37 in idx and idx[-1] == 100 and cost[idx].sum() <= 300
    idx, stride = choose_frames(cost, np.array([], np.int64), budget=1e9)
    assert stride == 1 and idx.size == 101


def test_empty_trajectory_page_says_so():
    traj = scenes.cube_on_slope(30, 1.0).world.run(0, record_contacts=True)
    page = render_html(traj)
    assert 'id="empty-notice"' in page and "This trajectory is empty" in page
    assert page_data(page)["frames"] == 1


# ---------------------------------------------------------------- lcpsim view


def test_view_scene_and_file(tmp_path, capsys):
    out, h5 = tmp_path / "v.html", tmp_path / "v.h5"
    rc = main(["view", "cube_on_slope", "--angle-deg", "45.2", "--mu", "1", "--out", str(out), "--save", str(h5)])
    assert rc == 0 and "wrote" in capsys.readouterr().out
    assert out.stat().st_size < 2_000_000
    d = page_data(out.read_text())
    assert d["direction_label"] == "down-slope distance" and d["steps"] == 2000
    rc = main(["view", str(h5), "--out", str(tmp_path / "w.html")])
    assert rc == 0
    assert page_data((tmp_path / "w.html").read_text())["arrays"]["pose"] == d["arrays"]["pose"]


@pytest.mark.parametrize("case", ["missing", "truncated", "foreign", "not_a_scene", "scene_option_on_file"])
def test_view_bad_input_exits_2_with_one_line(tmp_path, capsys, case, failing):
    _, traj = failing
    good = traj.save(tmp_path / "good.h5")
    if case == "truncated":
        (tmp_path / "bad.h5").write_bytes(open(good, "rb").read()[:2000])
    elif case == "foreign":
        save_lcp(tmp_path / "bad.h5", np.eye(2), -np.ones(2))
    args = {"missing": [str(tmp_path / "bad.h5")], "truncated": [str(tmp_path / "bad.h5")],
            "foreign": [str(tmp_path / "bad.h5")], "not_a_scene": ["cube_on_slop"],
            "scene_option_on_file": [good, "--angle-deg", "30"]}[case]
    rc = main(["view", *args, "--out", str(tmp_path / "x.html")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("lcpsim: error: ")
    assert not (tmp_path / "x.html").exists()


def test_report_pages_rerun_the_experiments_runs():
    """A report page's run is the experiment's: same scene, same steps, same motion."""
    from lcpsim.experiments import push, slope

    r = slope.run({"solver": "classic", "angle_deg": 45.0001, "scale": "none", "seconds": 0.3})
    s = slope.make_scene(r["config"])
    traj = s.world.run(r["steps"], record_contacts=True)
    assert traj.displacement(s.body) @ s.direction == r["slide_distance_m"]
    assert traj.failures == r["lcp_failures"] > 0
    r = push.run({"force": 9.83, "seconds": 0.3})
    s = push.make_scene(r["config"])
    traj = s.world.run(300, record_contacts=True)
    assert traj.displacement(s.body) @ s.direction == r["displacement_m"]
