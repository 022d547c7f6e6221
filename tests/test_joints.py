"""Joints from Python (World.add_hinge, add_slider, add_ball, add_fixed):
a pendulum's period and length, a chain that stays closed on the ground with
every LCP solved, the reactions, and bad input as ValueError naming the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lcpsim import World

G = 9.81


def hinge_pendulum(length: float = 1.0, radius: float = 0.05, theta0: float = 0.05) -> tuple[World, int]:
    w = World()
    anchor = np.array([0.0, 0.0, 2.0])
    p = anchor + length * np.array([math.sin(theta0), 0.0, -math.cos(theta0)])
    ball = w.add_sphere(radius, mass=1.0, position=p)
    w.add_hinge(None, ball, anchor, (0, 1, 0))
    return w, ball


def test_hinge_pendulum_period_and_length():
    length, radius, theta0 = 1.0, 0.05, 0.05
    w, ball = hinge_pendulum(length, radius, theta0)
    traj = w.run(10_000)
    x = traj.positions[:, ball, 0]
    ups = [i - 1 + x[i - 1] / (x[i - 1] - x[i]) for i in range(1, len(x)) if x[i - 1] < 0 <= x[i]]
    period = (ups[-1] - ups[0]) / (len(ups) - 1) * w.dt
    expect = 2 * math.pi * math.sqrt((0.4 * radius**2 + length**2) / (G * length)) * (1 + theta0**2 / 16)
    assert abs(period - expect) / expect < 5e-3, (period, expect)
    arm = np.linalg.norm(traj.positions[:, ball] - np.array([0.0, 0.0, 2.0]), axis=1)
    assert np.max(np.abs(arm - length)) <= 1e-6
    # The hinge holds the ball's weight and its centripetal pull: about m g at the bottom.
    force, _ = w.joint_reactions()
    assert force.shape == (1, 3) and 0.9 * G < force[0, 2] < 1.1 * G


def test_ball_chain_on_the_ground_stays_closed_with_every_lcp_solved():
    w = World()
    w.add_ground(mu=0.5)
    links = []
    for i in range(8):
        links.append(w.add_box(half_extents=(0.1, 0.02, 0.02), mass=0.5, position=(0.2 * i + 0.1, 0, 1.2)))
        w.add_ball(links[i - 1] if i else None, links[i], (0.2 * i, 0, 1.2))
    worst = 0.0
    for _ in range(1500):
        rec = w.step()
        assert rec.ok
        worst = max(worst, max(w.joint_error(j)[0] for j in range(w.joint_count)))
    assert worst <= 1e-6
    assert w.positions[links[-1], 2] < 0.1  # the far end lies on the ground


@pytest.mark.parametrize("anchor_x", [-0.5, 0.0])
def test_a_hinged_bar_on_the_ground_rests_with_every_lcp_solved(anchor_x):
    # A 1 m, 1 kg bar lying on the ground, hinged to the world at one end or at
    # its centre: the contacts under the axle are the hinge's (its normal is
    # the joint's), the others carry what statics says.
    w = World()
    w.add_ground(mu=0.5)
    bar = w.add_box(half_extents=(0.5, 0.05, 0.05), mass=1.0, position=(0, 0, 0.05), mu=0.5)
    w.add_hinge(None, bar, anchor=(anchor_x, 0, 0.05), axis=(0, 1, 0))
    traj = w.run(2000)
    assert traj.lcp_stats().failures == 0
    assert np.max(np.abs(traj.positions[:, bar] - np.array([0.0, 0.0, 0.05]))) <= 1e-9
    rec = w.last_record
    force, _ = w.joint_reactions()
    ground = rec.fn / w.dt
    if anchor_x < 0:  # moments about the axle: the far end carries m g / 2
        assert np.all(rec.points[:, 0] > 0)
        assert ground.sum() == pytest.approx(G / 2, rel=1e-9) and force[0, 2] == pytest.approx(G / 2, rel=1e-9)
    else:  # the split with the hinge is indeterminate; the total and the balance are not
        assert ground.sum() + force[0, 2] == pytest.approx(G, rel=1e-9)
        left, right = ground[rec.points[:, 0] < 0].sum(), ground[rec.points[:, 0] > 0].sum()
        assert abs(left - right) <= 1e-9 * G


def test_fixed_joint_and_copy():
    w = World()
    box = w.add_box(size=0.2, mass=2.0, position=(0.5, 0, 1))
    w.add_fixed(None, box)
    twin = w.copy()
    w.run(200)
    twin.run(200)
    for world in (w, twin):
        assert np.allclose(world.positions[box], (0.5, 0, 1), atol=1e-9)
        force, torque = world.joint_reactions()
        assert np.allclose(force[0], (0, 0, 2 * G), atol=1e-9) and np.allclose(torque[0], 0, atol=1e-9)


def test_step_record_holds_each_joints_reaction():
    w = World()
    box = w.add_box(size=0.2, mass=2.0, position=(0.5, 0, 1))
    w.add_fixed(None, box)
    for _ in range(50):
        rec = w.step()
    force, torque = w.joint_reactions()
    assert rec.joint_force.shape == rec.joint_torque.shape == (1, 3)
    assert np.array_equal(rec.joint_force, force) and np.array_equal(rec.joint_torque, torque)
    assert np.allclose(rec.joint_force[0], (0, 0, 2 * G), atol=1e-9)  # the weld holds the box's weight
    free = World()
    free.add_sphere(0.1, position=(0, 0, 1))
    assert free.step().joint_force.shape == (0, 3)


def test_hinge_limit_stops_a_falling_bar_at_the_limit():
    w = World()
    bar = w.add_box(half_extents=(0.5, 0.03, 0.03), mass=1.0, position=(0.5, 0, 2))
    j = w.add_hinge(None, bar, (0, 0, 2), (0, 1, 0), limits=(-0.2, 0.6))
    angles = []
    for _ in range(1500):
        assert w.step().ok
        angles.append(w.joint_position(j))
    step = np.max(np.abs(np.diff(angles)))
    assert max(angles) <= 0.6 + step and abs(angles[-1] - 0.6) < 1e-6


def test_slider_displacement_follows_gravity_along_its_axis():
    w = World()
    box = w.add_box(size=0.2, mass=1.0, position=(0, 0, 1))
    j = w.add_slider(None, box, (0, 0, 1), (0, 0, 2))
    w.run(1000)
    assert w.joint_position(j) == pytest.approx(-0.5 * G * 1.0 * (1.0 + 1e-3), rel=2e-3)
    assert np.allclose(w.positions[box, :2], 0, atol=1e-9)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda w, b: w.add_hinge(None, b, (math.nan, 0, 0), (0, 1, 0)), "anchor must be finite, got nan"),
        (lambda w, b: w.add_hinge(None, b, (0, 0, 0), (0, 0, 0)), r"axis must be a non-zero vector, got \(0, 0, 0\)"),
        (lambda w, b: w.add_ball(None, 7, (0, 0, 0)), r"body_b must be a body index in \[0, 1\), got 7"),
        (lambda w, b: w.add_ball(5, b, (0, 0, 0)), r"body_a must be None \(the world\) or a body index"),
        (lambda w, b: w.add_slider(None, b, (0, 0, 0), (1, 0, 0), limits=(1.0, -1.0)), "lower <= upper"),
        (lambda w, b: w.set_motor(w.add_hinge(None, b, (0, 0, 0), (0, 1, 0)), 1.0, -2.0),
         "max_force must be finite and >= 0, got -2.0"),
        (lambda w, b: w.set_motor(w.add_ball(None, b, (0, 0, 0)), 1.0, 2.0), "motor is for hinges and sliders"),
        (lambda w, b: w.add_hinge(None, b, (0, 0, 0), (0, 1, 0), motor=(math.inf, 1.0)), "speed must be finite"),
        (lambda w, b: w.joint_error(3), r"joint must be a joint index in \[0, 0\), got 3"),
        (lambda w, b: w.set_joint_params(drift=2.0), r"joint_drift must be in \[0, 1\], got 2"),
    ],
)
def test_bad_joint_input_is_a_value_error_naming_the_field(call, match):
    w = World()
    b = w.add_box(size=0.2, position=(0, 0, 1))
    with pytest.raises(ValueError, match=match):
        call(w, b)


def test_two_finger_gripper_lifts_a_cube_and_holds_it():
    # Round fingertips: one contact each, on a line through the cube's centre, so
    # no LCP answer lets the cube turn. Flat pads give four corners a side, and an
    # answer loading one corner per pad, the two on a line along the grip, is as
    # exact as a spread one: with no torsional friction the cube then pivots
    # about that line (docs/joints.md, "Beside MuJoCo").
    w = World()
    w.add_ground(mu=1.0)
    cube = w.add_box(size=0.1, mass=1.0, position=(0, 0, 0.05), mu=1.0)
    palm = w.add_box(half_extents=(0.15, 0.05, 0.02), mass=1.0, position=(0, 0, 0.2), mu=1.0)
    fingers = [w.add_sphere(radius=0.02, mass=0.2, position=(x, 0, 0.05), mu=1.0) for x in (-0.1, 0.1)]
    lift = w.add_slider(None, palm, (0, 0, 0.2), (0, 0, 1), motor=(0.0, 200.0))
    for f, x in zip(fingers, (-0.1, 0.1)):
        w.add_slider(palm, f, (x, 0, 0.05), (-x, 0, 0), motor=(0.1, 20.0))  # towards the cube
    grip = lambda: w.positions[cube, 2] - w.positions[fingers[0], 2]
    for _ in range(1000):  # the fingers close
        assert w.step().ok
    start = grip()
    for s in range(2200):  # up 0.2 m at 0.1 m/s, reached and left over 0.2 s
        w.set_motor(lift, 0.1 * min(1.0, s / 200, (2200 - s) / 200), 200.0)
        assert w.step().ok
    lifted = grip()
    for _ in range(2000):  # held
        assert w.step().ok
    assert abs(lifted - start) <= 1e-3 and abs(grip() - lifted) <= 1e-3  # no slip
    assert w.positions[cube, 2] == pytest.approx(0.25, abs=2e-3)
    assert max(w.joint_error(j)[0] for j in range(w.joint_count)) <= 1e-6


def test_a_damped_slider_decays_as_implicit_euler():
    # m v' = -d v; implicit Euler: v <- v / (1 + dt d / m) each step, stable for any d.
    for d in (4.0, 2e4):
        w = World()
        b = w.add_box(size=0.2, mass=2.0, position=(0, 0, 1))
        w.set_velocity(b, (1.0, 0, 0))
        w.add_slider(None, b, (0, 0, 1), (1, 0, 0), damping=d)
        factor = 1.0 / (1.0 + w.dt * d / 2.0)
        for k in range(1, 6):
            assert w.step().ok
            assert w.velocities[b, 0] == pytest.approx(factor**k, rel=1e-9)
    w = World()
    b = w.add_box(size=0.2, mass=2.0, position=(0, 0, 1))
    w.set_velocity(b, (1.0, 0, 0))
    w.add_slider(None, b, (0, 0, 1), (1, 0, 0), damping=4.0)
    for _ in range(1000):
        w.step()
    assert w.velocities[b, 0] == pytest.approx(math.exp(-4.0 * 1.0 / 2.0), rel=3e-3)  # exp(-d t / m) within dt


def test_mjcf_hinge_damping_slows_a_wheel_as_implicit_euler():
    xml = ('<mujoco><option timestep="0.001" gravity="0 0 0"/><worldbody><body pos="0 0 1">'
           '<joint type="hinge" axis="0 1 0" damping="0.008"/><geom type="sphere" size="0.1" mass="1"/>'
           '</body></worldbody></mujoco>').replace('<body ', '<body name="wheel" ')
    w = World.from_mjcf(xml)
    b = w.body_id("wheel")
    w.set_angular_velocity(b, (0, 3.0, 0))
    for _ in range(100):
        assert w.step().ok
    inertia = 0.4 * 0.1**2  # a solid sphere's, 1 kg, r = 0.1 m
    assert w.body(b).velocity[4] == pytest.approx(3.0 / (1 + 0.001 * 0.008 / inertia) ** 100, rel=1e-9)


@pytest.mark.parametrize("damping, match", [(-1.0, "damping must be finite and >= 0, got -1.0"),
                                            ("x", "damping must be a real number")])
def test_bad_damping_is_a_value_error(damping, match):
    w = World()
    b = w.add_box(size=0.2, position=(0, 0, 1))
    with pytest.raises(ValueError, match=match):
        w.add_hinge(None, b, (0, 0, 1), (0, 1, 0), damping=damping)
    j = w.add_ball(None, b, (0, 0, 1))
    with pytest.raises(ValueError, match="damping is for hinges and sliders"):
        w.set_joint_damping(j, 1.0)
