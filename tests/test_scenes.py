"""Every test scene through Python, with its analytic pass criterion
(g = 9.81, h = 1e-3, default solver unless stated), built by lcpsim.scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lcpsim import scenes

G = 9.81
H = 1e-3


def slide_and_tilt(s: scenes.Scene, steps: int):
    traj = s.world.run(steps)
    return float(traj.displacement(s.body) @ s.direction), float(traj.tilt(s.body)[-1]), traj


# ----------------------------------------------------------------- scene objects


def test_scene_metadata():
    s = scenes.cube_on_slope(30.0, 0.5)
    th = math.radians(30)
    assert s.name == "cube_on_slope" and s.world.scene == "cube_on_slope" and s.body == 1 and s.ground == 0
    assert s.bodies == (1,) and s.params["angle_deg"] == 30.0
    np.testing.assert_allclose(s.direction, [math.cos(th), 0, -math.sin(th)], atol=1e-15)
    np.testing.assert_allclose(s.normal, [math.sin(th), 0, math.cos(th)], atol=1e-15)
    # The cube sits on the slope, face down, touching.
    np.testing.assert_allclose(s.world.positions[s.body], 0.5 * s.normal, atol=1e-15)
    assert s.world.step().contacts == 4
    # World arguments pass through.
    s = scenes.box_stack(4, dt=2e-3, cone_scale="dt", pivoting="classic", friction_dirs=4)
    p = s.world.params
    assert p["dt"] == 2e-3 and p["scale"] == 2e-3 and p["friction_dirs"] == 4
    assert s.world.solver_options == {"pivoting": "classic"}
    assert s.bodies == (1, 2, 3, 4) and s.body == 4 and s.direction is None
    assert s.world.config()["scene_params"]["n"] == 4
    assert scenes.pushed_cube(1.0, 0.5).direction.tolist() == [1.0, 0.0, 0.0]
    assert scenes.ball_on_incline(20, 0.3).world.body(1).kind == "sphere"
    assert scenes.box_pile(2, 2, 2, yaw=0.3, seed=5).world.body_count == 9
    assert set(scenes.scene_parameters("box_pile")) == {"nx", "ny", "nz", "size", "mass", "mu", "spacing", "yaw", "seed"}
    assert scenes.make_scene("cube_drop", height=0.5).params["height"] == 0.5


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: scenes.cube_on_slope(95.0, 0.5), ["angle_deg", "95"]),
        (lambda: scenes.cube_on_slope(30.0, -0.5), ["mu", "-0.5"]),
        (lambda: scenes.cube_on_slope(30.0, 0.5, size=0.0), ["size", "0"]),
        (lambda: scenes.cube_on_slope(30.0, 0.5, mass=-1.0), ["mass", "-1"]),
        (lambda: scenes.cube_on_slope(30.0, 0.5, downhill="north"), ["downhill", "north"]),
        (lambda: scenes.pushed_cube(float("nan"), 0.5), ["force", "nan"]),
        (lambda: scenes.box_stack(0), ["n", "0"]),
        (lambda: scenes.box_pile(0, 3, 3), ["nx*ny*nz"]),
        (lambda: scenes.ball_on_incline(30.0, 0.3, radius=0.0), ["radius", "0"]),
        (lambda: scenes.cube_drop(-1.0), ["height", "-1"]),
        (lambda: scenes.cube_on_slope(30.0, 0.5, dt=0.0), ["dt", "0"]),
        (lambda: scenes.make_scene("pendulum"), ["pendulum"]),
    ],
)
def test_bad_scene_parameters(call, words):
    with pytest.raises(ValueError) as e:
        call()
    for w in words:
        assert w.lower() in str(e.value).lower(), (w, str(e.value))


# ----------------------------------------------------------------- §3 scenes


def test_resting_cube_carries_m_g_h_and_does_not_drift():
    for mass in (1.0, 3.5):
        s = scenes.resting_cube(0.5, mass=mass)
        e0 = s.world.energy()
        traj = s.world.run(1000)
        assert s.world.energy() <= e0 + 1e-12
        assert traj.failures == 0
        np.testing.assert_allclose(traj.normal_impulse, mass * G * H, rtol=1e-12)
        assert np.abs(traj.velocities[:, s.body]).max() < 1e-9
        assert np.abs(traj.positions[:, s.body] - traj.initial_positions[s.body]).max() < 1e-9


@pytest.mark.parametrize("mu", [0.3, 0.6])
def test_block_on_incline_sticks_at_098_mu_and_slides_at_102_mu(mu):
    # Sticks: tan θ = 0.98 μ.
    th = math.degrees(math.atan(0.98 * mu))
    s = scenes.cube_on_slope(th, mu)
    traj = s.world.run(1000)
    assert traj.failures == 0
    assert np.linalg.norm(traj.velocities[-1, s.body, :3]) < 1e-6
    # Slides: tan θ = 1.02 μ, a = g (sin θ − μ cos θ) within 1 %.
    th = math.atan(1.02 * mu)
    s = scenes.cube_on_slope(math.degrees(th), mu)
    traj = s.world.run(1000)
    a = traj.velocities[-1, s.body, :3] @ s.direction / 1.0
    expect = G * (math.sin(th) - mu * math.cos(th))
    assert traj.failures == 0 and a == pytest.approx(expect, rel=0.01)
    assert traj.tilt(s.body).max() < 1e-6


def test_block_along_a_bisector_sticks_below_mu_cos_pi_over_k():
    mu, k = 0.5, 8
    threshold = mu * math.cos(math.pi / k)
    for factor, moves in ((0.98, False), (1.02, True)):
        th = math.degrees(math.atan(factor * threshold))
        s = scenes.cube_on_slope(th, mu, tangent_angle=math.pi / k)
        traj = s.world.run(1000)
        v = np.linalg.norm(traj.velocities[-1, s.body, :3])
        assert traj.failures == 0
        assert (v > 1e-3) if moves else (v < 1e-6), (factor, v)


def test_sliding_to_rest_from_v0():
    for v0, mu in ((1.0, 0.5), (2.0, 0.3)):
        s = scenes.cube_on_slope(0.0, mu, speed=v0)
        traj = s.world.run(int(1.5 * v0 / (mu * G) / H))
        d = traj.displacement(s.body) @ s.direction
        assert traj.failures == 0
        assert d == pytest.approx(v0 * v0 / (2 * mu * G), rel=0.005)
        assert np.linalg.norm(traj.velocities[-1, s.body]) < 1e-9
        assert s.expected_slide(traj.time[-1]) == pytest.approx(v0 * v0 / (2 * mu * G))


def test_pushed_cube_stays_at_979_newton_with_friction_equal_to_the_push():
    s = scenes.pushed_cube(9.79, 1.0)
    traj = s.world.run(1000)
    assert traj.failures == 0
    np.testing.assert_allclose(traj.friction_impulse[:, 0], -9.79 * H, rtol=1e-10)
    np.testing.assert_allclose(traj.normal_impulse, G * H, rtol=1e-12)
    assert np.abs(traj.max_lambda).max() < 1e-9
    assert np.linalg.norm(traj.velocities[-1, s.body]) < 1e-9
    # The load moves onto the leading edge (x = +0.5).
    r = s.world.step()
    assert r.fn[r.points[:, 0] > 0].sum() > 0.5 * G * H


def test_pushed_cube_slides_at_983_newton():
    s = scenes.pushed_cube(9.83, 1.0)
    traj = s.world.run(1000)
    a = traj.velocities[-1, s.body, 0] / 1.0
    assert traj.failures == 0
    assert a == pytest.approx(9.83 - G, rel=0.01)
    np.testing.assert_allclose(traj.friction_impulse[5:, 0], -G * H, rtol=1e-9)  # μ N once sliding
    assert np.abs(traj.velocities[-1, s.body, 3:]).max() < 1e-9  # no tipping


@pytest.mark.parametrize("mu, force", [(0.5, 8.0), (0.2, 15.0)])
def test_pushed_box_slides_with_f_minus_mu_m_g(mu, force):
    s = scenes.pushed_cube(force, mu)
    traj = s.world.run(1000)
    assert traj.failures == 0
    assert traj.velocities[-1, s.body, 0] == pytest.approx(force - mu * G, rel=0.01)


def test_cube_on_slope_rests_tips_or_slides():
    # Rests iff tan θ ≤ min(μ, 1).
    for angle, mu in ((30.0, 0.7), (40.0, 1.5)):
        d, tilt, traj = slide_and_tilt(scenes.cube_on_slope(angle, mu), 2000)
        assert traj.failures == 0 and abs(d) < 1e-6 and tilt < 1e-6, (angle, mu, d, tilt)
    # Tips iff tan θ > 1 and μ > 1.
    d, tilt, traj = slide_and_tilt(scenes.cube_on_slope(50.0, 1.5), 2000)
    assert traj.failures == 0 and tilt > 0.5
    # Slides without tipping if μ ≤ 1.
    for angle, mu in ((40.0, 0.5), (60.0, 1.0)):
        s = scenes.cube_on_slope(angle, mu)
        d, tilt, traj = slide_and_tilt(s, 1000)
        assert traj.failures == 0 and tilt < 1e-6
        assert d == pytest.approx(s.expected_slide(1.0), rel=0.01)


@pytest.mark.parametrize("scale", [None, 0.1, "dt", 1e-6])
def test_knife_edge_45_2_degrees_slides_at_every_scale(scale):
    th = math.radians(45.2)
    expect = 0.5 * G * (math.sin(th) - math.cos(th)) * 4.0  # 0.097 m in 2 s
    d, tilt, traj = slide_and_tilt(scenes.cube_on_slope(45.2, 1.0, cone_scale=scale), 2000)
    assert traj.failures == 0
    assert d == pytest.approx(expect, rel=0.01) and tilt < 1e-3


@pytest.mark.parametrize("scale", [None, 4e-3, "dt", 1e-6])
def test_knife_edge_45_plus_1e4_degrees_slides_with_the_default_solver(scale):
    angle = 45.0 + 1e-4
    th = math.radians(angle)
    expect = 0.5 * G * (math.sin(th) - math.cos(th)) * 4.0
    d, tilt, traj = slide_and_tilt(scenes.cube_on_slope(angle, 1.0, cone_scale=scale), 2000)
    assert traj.failures == 0
    assert d == pytest.approx(expect, rel=0.05) and tilt < 1e-6


def test_ball_rolls_with_five_sevenths_g_sin_theta():
    for angle, mu in ((30.0, 0.3), (20.0, 0.2)):
        th = math.radians(angle)
        assert mu >= 2 / 7 * math.tan(th)
        s = scenes.ball_on_incline(angle, mu)
        traj = s.world.run(1000)
        a = traj.velocities[-1, s.body, :3] @ s.direction / 1.0
        assert traj.failures == 0
        assert a == pytest.approx(5 / 7 * G * math.sin(th), rel=1e-3)
        # Rolling: the contact point does not slip.
        v, w = traj.velocities[-1, s.body, :3], traj.velocities[-1, s.body, 3:]
        assert np.linalg.norm(v + np.cross(w, -0.5 * s.normal)) < 1e-9


def test_ball_slips_below_two_sevenths_tan_theta():
    th = math.radians(30.0)
    s = scenes.ball_on_incline(30.0, 0.1)
    traj = s.world.run(1000)
    a = traj.velocities[-1, s.body, :3] @ s.direction
    assert a == pytest.approx(G * (math.sin(th) - 0.1 * math.cos(th)), rel=1e-3)


@pytest.mark.parametrize("n", [3, 6])
def test_stack_interface_forces(n):
    s = scenes.box_stack(n)
    traj = s.world.run(300)
    assert traj.failures == 0
    r = s.world.step()
    below = (s.ground, *s.bodies)
    for j in range(n):
        f = r.fn[r.between(below[j], below[j + 1])].sum()
        assert f == pytest.approx((n - j) * 1.0 * G * H, rel=1e-3), (j, f)
    assert np.abs(traj.positions[-1, list(s.bodies)] - traj.initial_positions[list(s.bodies)]).max() < 1e-6


def test_ball_drop_impact_time():
    for height, e in ((1.0, 0.0), (0.3, 0.9)):
        s = scenes.ball_drop(height, restitution=e)
        traj = s.world.run(int(1.2 * math.sqrt(2 * height / G) / H))
        i = int(np.argmax(traj.normal_impulse > 0))
        assert traj.normal_impulse[i] > 0
        t_impact = traj.time[i] - H  # the step's start
        assert abs(t_impact - math.sqrt(2 * height / G)) <= 2 * H
        if e > 0:
            assert traj.velocities[i, s.body, 2] == pytest.approx(e * math.sqrt(2 * G * height), rel=0.02)


def test_cube_drop_lands_flat_and_stays():
    s = scenes.cube_drop(0.5)
    traj = s.world.run(1500)
    assert traj.failures == 0
    i = int(np.argmax(traj.normal_impulse > 0))
    assert abs(traj.time[i] - H - math.sqrt(1.0 / G)) <= 2 * H
    assert traj.positions[-1, s.body, 2] == pytest.approx(0.5, abs=1e-6)
    assert np.linalg.norm(traj.velocities[-1, s.body]) < 1e-9 and traj.tilt(s.body).max() < 1e-9


def test_box_pile_runs():
    s = scenes.box_pile()
    traj = s.world.run(3)
    assert traj.contacts[0] == 27 * 4 and traj.lcp_size[0] == 27 * 4 * 10
    assert traj.failures == 0, traj.lcp_stats()
