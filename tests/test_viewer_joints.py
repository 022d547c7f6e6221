"""The viewer draws joints: the page's data holds each joint's kind and, for every
kept state, its anchor and axis, moving with its bodies (checked against the other
side's pose and against the world's own anchor). The page in a browser:
test_viewer_browser.py."""

from __future__ import annotations

import numpy as np

from lcpsim import Trajectory, World
from lcpsim.trajectory_data import quat_rotate
from lcpsim.viewer import render_html
from test_viewer import decode, page_data


def double_pendulum() -> World:
    """Two bars: the first on a hinge at the world point (0, 0, 2), the second hanging from
    its far end on a ball joint; released horizontal, a slider and a weld beside them."""
    w = World()
    a = w.add_box(half_extents=(0.25, 0.03, 0.03), mass=1.0, position=(0.25, 0, 2))
    b = w.add_box(half_extents=(0.25, 0.03, 0.03), mass=1.0, position=(0.75, 0, 2))
    w.add_hinge(None, a, (0, 0, 2), (0, 1, 0))
    w.add_ball(a, b, (0.5, 0, 2))
    c = w.add_box(size=0.1, mass=0.5, position=(3, 0, 1))
    w.add_slider(None, c, (3, 0, 1), (0, 0, 1))
    d = w.add_box(size=0.1, mass=0.5, position=(3.3, 0, 1))
    w.add_fixed(c, d)
    return w


def test_the_page_holds_each_joint_at_its_anchor_moving_with_its_bodies(tmp_path):
    traj = double_pendulum().run(400)
    # Through a file too: the joints' geometry travels in the config.
    traj = Trajectory.load(traj.save(tmp_path / "p.h5"))
    joints = traj.config["joints"]
    d = page_data(render_html(traj))
    assert [j["kind"] for j in d["joints"]] == ["hinge", "ball", "slider", "fixed"]
    assert [j["bodies"] for j in d["joints"]] == [[None, 0], [0, 1], [None, 2], [2, 3]]
    anchor, axis = decode(d["arrays"]["j_anchor"]), decode(d["arrays"]["j_axis"])
    steps = decode(d["arrays"]["frame_step"])
    assert anchor.shape == axis.shape == (d["frames"], 4, 3)
    pos = np.concatenate([traj.initial_positions[None], traj.positions])[steps]
    quat = np.concatenate([traj.initial_orientations[None], traj.orientations])[steps]
    # The hinge stays at its world point, about y, while its bar swings down.
    np.testing.assert_allclose(anchor[:, 0], np.tile([0, 0, 2], (len(steps), 1)), atol=1e-6)
    np.testing.assert_allclose(axis[:, 0], np.tile([0, 1, 0], (len(steps), 1)), atol=1e-6)
    # The ball joint, drawn where bar B carries it, is where bar A carries it: the bar's far end.
    carried_by_a = pos[:, 0] + quat_rotate(quat[:, 0], joints[1]["anchor"][0])
    np.testing.assert_allclose(anchor[:, 1], carried_by_a, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(anchor[:, 1] - [0, 0, 2], axis=1), 0.5, atol=1e-5)
    assert anchor[0, 1, 0] == np.float32(0.5) and anchor[-1, 1, 2] < 1.7  # it swung down
    # The slider's anchor falls with its block along the world's z, the weld's rides on it.
    np.testing.assert_allclose(anchor[:, 2], pos[:, 2], atol=1e-5)
    np.testing.assert_allclose(axis[:, 2], np.tile([0, 0, 1], (len(steps), 1)), atol=1e-6)
    np.testing.assert_allclose(anchor[:, 3], pos[:, 3], atol=1e-5)
    assert anchor[-1, 2, 2] < 0.5


def test_a_trajectory_without_joint_geometry_draws_none():
    traj = double_pendulum().run(5)
    bare = Trajectory(**{**traj.__dict__, "config": None})
    d = page_data(render_html(bare))
    assert d["joints"] == [] and "j_anchor" not in d["arrays"]
