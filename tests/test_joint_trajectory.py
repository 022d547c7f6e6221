"""Joints in the trajectory (World.run): each step's joint reactions, coordinates
and errors, equal to what the step records and the world say step by step; a
weld's reaction against the weight it holds; the arrays through save and load
(and files written before them read with no joints)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lcpsim import World
from lcpsim.trajectory import Trajectory

G = 9.81


def pendulum() -> tuple[World, int]:
    """A ball on a hinge released at 60° and a slider beside it, so the run has two kinds of joint."""
    w = World()
    ball = w.add_sphere(0.05, mass=1.0, position=(math.sin(1.0), 0.0, 2.0 - math.cos(1.0)))
    w.add_hinge(None, ball, (0, 0, 2), (0, 1, 0))
    block = w.add_box(size=0.1, mass=0.5, position=(3, 0, 1))
    w.add_slider(None, block, (3, 0, 1), (1, 0, 1))
    return w, ball


def test_the_trajectory_holds_each_steps_joint_reactions_positions_and_errors():
    w, _ = pendulum()
    stepped = w.copy()
    traj = w.run(300)
    assert traj.joints == 2
    assert traj.joint_force.shape == traj.joint_torque.shape == (300, 2, 3)
    assert traj.joint_position.shape == (300, 2) and traj.joint_error.shape == (300, 2, 2)
    for t in range(300):
        rec = stepped.step()
        np.testing.assert_array_equal(traj.joint_force[t], rec.joint_force)
        np.testing.assert_array_equal(traj.joint_torque[t], rec.joint_torque)
        for j in range(2):
            assert traj.joint_position[t, j] == stepped.joint_position(j)
            assert tuple(traj.joint_error[t, j]) == stepped.joint_error(j)
    # The pendulum swings (its angle changes, its hinge pulls) and the slider slides down its axis.
    assert np.ptp(traj.joint_position[:, 0]) > 0.3 and np.all(np.linalg.norm(traj.joint_force[:, 0], axis=1) > 1)
    assert traj.joint_position[-1, 1] < -0.1


def test_a_welds_reaction_in_the_trajectory_holds_the_weight():
    # A 2 kg box welded to the world 0.5 m beside the anchor: the weld pushes up with m g
    # and twists with the weight's moment about the anchor, r × (m g ẑ) = (0, −0.5 m g, 0).
    w = World()
    box = w.add_box(size=0.2, mass=2.0, position=(0.5, 0, 1))
    w.add_fixed(None, box, anchor=(0, 0, 1))
    traj = w.run(50)
    np.testing.assert_allclose(traj.joint_force[:, 0], np.tile([0, 0, 2 * G], (50, 1)), atol=1e-9)
    np.testing.assert_allclose(traj.joint_torque[:, 0], np.tile([0, -0.5 * 2 * G, 0], (50, 1)), atol=1e-9)
    assert np.all(traj.joint_error <= 1e-12)


def test_a_world_without_joints_records_none_and_record_contacts_keeps_them():
    w = World()
    w.add_ground()
    w.add_box(size=1.0, position=(0, 0, 0.5))
    traj = w.run(3)
    assert traj.joints == 0 and traj.joint_force.shape == (3, 0, 3) and traj.joint_position.shape == (3, 0)
    a, _ = pendulum()
    b = a.copy()
    plain, logged = a.run(20), b.run(20, record_contacts=True)
    for name in ("joint_force", "joint_torque", "joint_position", "joint_error"):
        np.testing.assert_array_equal(getattr(plain, name), getattr(logged, name))


def test_joint_arrays_survive_save_and_load(tmp_path):
    w, _ = pendulum()
    traj = w.run(40)
    again = Trajectory.load(traj.save(tmp_path / "p.h5"))
    for name in ("joint_force", "joint_torque", "joint_position", "joint_error"):
        np.testing.assert_array_equal(getattr(again, name), getattr(traj, name))
    assert again.joints == 2


def test_a_version_3_trajectory_file_reads_with_no_joints(tmp_path):
    import h5py

    w, _ = pendulum()
    path = w.run(5).save(tmp_path / "v3.h5")
    with h5py.File(path, "r+") as f:
        for name in ("joint_force", "joint_torque", "joint_position", "joint_error"):
            del f[name]
        f.attrs["format_version"] = 3
    old = Trajectory.load(path)
    assert old.joints == 0 and old.joint_force.shape == (5, 0, 3) and old.joint_error.shape == (5, 0, 2)


def test_a_damaged_joint_array_is_refused_by_name(tmp_path):
    import h5py

    from lcpsim.io.trajectory_file import TrajectoryFileError

    w, _ = pendulum()
    path = w.run(5).save(tmp_path / "bad.h5")
    with h5py.File(path, "r+") as f:
        del f["joint_torque"]
        f.create_dataset("joint_torque", data=np.zeros((5, 3)))
    with pytest.raises(TrajectoryFileError, match="joint_torque"):
        Trajectory.load(path)
