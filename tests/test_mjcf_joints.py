"""MJCF joints through ``World.from_mjcf``: hinge, slide and ball joints,
bodies nested in bodies (welded when they have no joint), ``<velocity>``
actuators driven by ``World.set_control``, checked against theory and against
MuJoCo running the same file; everything else refused naming the element."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

from lcpsim import World  # noqa: E402
from lcpsim.mjcf import MjcfError  # noqa: E402

from conftest import raises_naming  # noqa: E402

DATA = Path(__file__).parent / "data" / "mjcf"
G = 9.81


def _mujoco(name: str) -> tuple:
    m = mujoco.MjModel.from_xml_path(str(DATA / name))
    return m, mujoco.MjData(m)


def _period(x: np.ndarray, dt: float) -> float:
    """Mean period from the upward zero crossings of ``x`` (linear interpolation)."""
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    t = (i + x[i] / (x[i] - x[i + 1])) * dt
    return float((t[-1] - t[0]) / (len(t) - 1))


def test_hinge_pendulum_period_matches_theory_and_mujoco():
    # 1 kg sphere (r = 0.05 m) 1 m below a hinge, released at 0.05 rad.
    w = World.from_mjcf(DATA / "hinge_pendulum_joint.xml")
    assert (w.body_count, w.joint_count) == (1, 1)
    bob = w.body_id("bob")
    pivot = np.array([0.0, 0.0, 2.0])
    xs, worst_length = [], 0.0
    for _ in range(10_000):  # 10 s, about 5 periods
        assert w.step().ok
        xs.append(w.positions[bob, 0])
        worst_length = max(worst_length, abs(np.linalg.norm(w.positions[bob] - pivot) - 1.0))
    period = _period(np.array(xs), w.dt)
    i_pivot = 1.0 + 0.4 * 0.05**2
    theory = 2 * math.pi * math.sqrt(i_pivot / G) * (1 + 0.05**2 / 16)
    assert period == pytest.approx(theory, rel=5e-3)
    assert worst_length < 1e-6
    m, d = _mujoco("hinge_pendulum_joint.xml")
    mx = []
    for _ in range(10_000):
        mujoco.mj_step(m, d)
        mx.append(d.geom_xpos[0][0])
    # MuJoCo's hinge is exact (reduced coordinates): the two differ by their integrators only.
    assert period == pytest.approx(_period(np.array(mx), m.opt.timestep), rel=1e-4)


def test_slider_range_stops_the_body_at_its_limit():
    w = World.from_mjcf(DATA / "slider_limit_joint.xml")
    one_step = math.sqrt(2 * G * 0.3) * w.dt  # the motion of one step at the limit
    lowest = 0.0
    for _ in range(1000):
        assert w.step().ok
        lowest = min(lowest, w.joint_position(0))
    assert lowest >= -0.3 - one_step
    assert w.joint_position(0) == pytest.approx(-0.3, abs=1e-6)
    assert w.positions[w.body_id("carriage"), 2] == pytest.approx(0.7, abs=1e-6)
    assert abs(w.velocities[0, 2]) < 1e-6
    # MuJoCo's limit is soft: it rests past -0.3 m (0.37 mm measured); lcpsim is within that of it.
    m, d = _mujoco("slider_limit_joint.xml")
    for _ in range(1000):
        mujoco.mj_step(m, d)
    assert abs(w.joint_position(0) - float(d.qpos[0])) <= abs(float(d.qpos[0]) + 0.3) + 1e-6


@pytest.mark.parametrize("ref", [0, 20])
def test_hinge_range_in_degrees_stops_the_bar_at_its_limit(ref):
    # range="-10 30" (degrees, compiled to radians by MuJoCo): the bar swings down onto +30°.
    # With ref="20" the file's pose is qpos = 20°: lcpsim's angle (0 there) stops at 10°.
    xml = (DATA / "hinge_limit_joint.xml").read_text().replace('range="-10 30"', f'range="-10 30" ref="{ref}"')
    w = World.from_mjcf(xml)
    limit = math.radians(30 - ref)
    highest = 0.0
    for _ in range(2000):
        assert w.step().ok
        highest = max(highest, w.joint_position(0))
    # At most one step's motion past the limit (ω ≤ √(3 g sin 30° / L) for a bar hinged at its end).
    assert highest <= limit + math.sqrt(3 * G * 0.5 / 1.0) * w.dt
    assert w.joint_position(0) == pytest.approx(limit, abs=1e-6)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(2000):
        mujoco.mj_step(m, d)
    q = float(d.qpos[0]) - math.radians(ref)
    assert abs(w.joint_position(0) - q) <= abs(q - limit) + 1e-6


def test_ball_chain_of_nested_bodies_stays_closed():
    w = World.from_mjcf(DATA / "ball_chain_joint.xml")
    assert (w.body_count, w.joint_count) == (5, 5)
    m, d = _mujoco("ball_chain_joint.xml")
    worst = 0.0
    for i in range(2000):
        assert w.step().ok
        worst = max(worst, max(w.joint_error(j)[0] for j in range(w.joint_count)))
        if i < 200:
            mujoco.mj_step(m, d)
        if i == 199:  # the tip where MuJoCo's is at 0.2 s: 2.1 mm apart measured, 0.53 mm at dt/4
            assert np.linalg.norm(w.positions[w.body_id("link5")] - d.xipos[m.body("link5").id]) < 5e-3
    assert worst < 1e-6
    # It fell: the tip is well below the release height, at most 1 m from the pivot.
    tip = w.positions[w.body_id("link5")]
    assert tip[2] < 1.9 and np.linalg.norm(tip - [0, 0, 2]) < 1.0


def _relative_pose(w: World, a: int, b: int) -> tuple[np.ndarray, np.ndarray]:
    from scipy.spatial.transform import Rotation

    ra = Rotation.from_quat(w.orientations[a][[1, 2, 3, 0]])
    rb = Rotation.from_quat(w.orientations[b][[1, 2, 3, 0]])
    return ra.inv().apply(w.positions[b] - w.positions[a]), (ra.inv() * rb).as_rotvec()


def test_welded_child_moves_with_its_parent_without_colliding():
    w = World.from_mjcf(DATA / "welded_child_joint.xml")
    arm, hand, post = w.body_id("arm"), w.body_id("hand"), w.body_id("post")
    assert w.body(post).is_static and not w.body(hand).is_static
    assert w.joint_count == 2  # the shoulder and the hand's weld
    p0, r0 = _relative_pose(w, arm, hand)
    m, d = _mujoco("welded_child_joint.xml")
    worst = 0.0
    for i in range(1000):
        rec = w.step()
        mujoco.mj_step(m, d)
        assert rec.ok and not rec.between(arm, hand).any()
        p, r = _relative_pose(w, arm, hand)
        worst = max(worst, float(np.linalg.norm(p - p0)), float(np.linalg.norm(r - r0)))
        if i == 199:  # the arm (with its hand) swings as MuJoCo's does
            assert w.joint_position(0) == pytest.approx(float(d.qpos[0]), abs=1e-3)
    assert worst < 1e-6
    assert w.joint_position(0) > 1.0  # it swung down


def test_a_massless_frame_between_arm_and_hand_is_skipped():
    # The hand hangs on the arm through a "mount" body with no joint, no geom and no mass.
    xml = (DATA / "welded_child_joint.xml").read_text().replace(
        '<body name="hand" pos="0.5 0 0">', '<body name="mount" pos="0.5 0 0"><body name="hand">'
    ).replace("</body>\n    </body>\n  </worldbody>", "</body></body>\n    </body>\n  </worldbody>")
    assert mujoco.MjModel.from_xml_string(xml).nbody == 5  # world, post, arm, mount, hand
    w = World.from_mjcf(xml)
    assert (w.body_count, w.joint_count) == (3, 2)
    arm, hand = w.body_id("arm"), w.body_id("hand")
    p0, _ = _relative_pose(w, arm, hand)
    for _ in range(300):
        assert w.step().ok
    assert np.linalg.norm(_relative_pose(w, arm, hand)[0] - p0) < 1e-6
    assert w.joint_position(0) > 0.5


def test_parent_and_child_on_a_hinge_do_not_collide():
    # The two links' boxes overlap by 0.04 m around the elbow.
    w = World.from_mjcf(DATA / "two_link_joint.xml")
    upper, lower = w.body_id("upper"), w.body_id("lower")
    m, d = _mujoco("two_link_joint.xml")
    for _ in range(200):
        rec = w.step()
        mujoco.mj_step(m, d)
        assert rec.ok and not rec.between(upper, lower).any()
        assert max(w.joint_error(j)[0] for j in range(2)) < 1e-6
    assert d.ncon == 0
    # The same motion as MuJoCo's at 0.2 s (they differ by their integrators: 7e-4 rad measured).
    assert w.joint_position(0) == pytest.approx(float(d.qpos[0]), abs=2e-3)
    assert w.joint_position(1) == pytest.approx(float(d.qpos[1]), abs=2e-3)


def test_velocity_actuator_drives_a_hinge_at_its_target_speed():
    # Disc I = 0.005 kg·m², forcerange ±0.05 N·m: 10 rad/s² up to 2 rad/s at 0.2 s.
    w = World.from_mjcf(DATA / "turntable_joint.xml")
    disc = w.body_id("disc")
    for _ in range(100):
        assert w.step().ok
    assert w.velocities[disc, 5] == pytest.approx(0.0, abs=1e-9)  # ctrl starts at 0: held still
    w.set_control("spin", 2.0)
    m, d = _mujoco("turntable_joint.xml")
    d.ctrl[0] = 2.0
    for i in range(500):
        assert w.step().ok
        mujoco.mj_step(m, d)
        if i == 99:  # saturated in both engines: the bound's acceleration
            assert w.velocities[disc, 5] == pytest.approx(1.0, abs=1e-6)
            assert float(d.qvel[0]) == pytest.approx(1.0, abs=1e-6)
    assert w.velocities[disc, 5] == pytest.approx(2.0, abs=1e-9)
    assert float(d.qvel[0]) == pytest.approx(2.0, abs=1e-4)
    w.set_control(0, -1.0)  # by index
    for _ in range(400):
        w.step()
    assert w.velocities[disc, 5] == pytest.approx(-1.0, abs=1e-9)
    assert w.copy().velocities[disc, 5] == pytest.approx(-1.0)


def test_velocity_actuator_gear_scales_speed_and_force_as_mujoco():
    # gear 2: the joint turns at ctrl / 2 = 1 rad/s, with up to 2 × 0.05 N·m (20 rad/s²).
    xml = (DATA / "turntable_joint.xml").read_text().replace('kv="1"', 'kv="1" gear="2"')
    w = World.from_mjcf(xml)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    w.set_control("spin", 2.0)
    d.ctrl[0] = 2.0
    for i in range(300):
        w.step()
        mujoco.mj_step(m, d)
        if i == 24:
            assert w.velocities[0, 5] == pytest.approx(0.5, abs=1e-9)
            assert float(d.qvel[0]) == pytest.approx(0.5, abs=1e-6)
    assert w.velocities[0, 5] == pytest.approx(1.0, abs=1e-9)
    assert float(d.qvel[0]) == pytest.approx(1.0, abs=1e-4)


@pytest.mark.parametrize(
    "actuator, value, words",
    [("spun", 1.0, ["actuator", "'spun'", "spin"]), (3, 1.0, ["actuator", "3"]), ("spin", float("nan"), ["value", "nan"])],
)
def test_set_control_bad_input_names_the_field(actuator, value, words):
    w = World.from_mjcf(DATA / "turntable_joint.xml")
    raises_naming(ValueError, lambda: w.set_control(actuator, value), words)


BOX = '<geom type="box" size=".1 .1 .1"/>'


@pytest.mark.parametrize(
    "body, actuator, words",
    [
        (f'<joint name="j1" type="hinge"/><joint name="j2" type="slide"/>{BOX}', "", ["body 'b'", "2 joints", "hinge+slide"]),
        (f'<joint name="j" type="ball" range="0 30"/>{BOX}', "", ["joint 'j'", "ball", "range"]),
        (f'<joint name="j" type="ball" damping="0.1"/>{BOX}', "", ["joint 'j'", "damping"]),
        (f'<joint name="j" type="hinge"/>{BOX}', '<motor name="push" joint="j"/>', ["actuator 'push'", "velocity"]),
        (f'<joint name="j" type="hinge"/>{BOX}', '<position name="servo" joint="j" kp="10"/>', ["actuator 'servo'"]),
        (f'<joint name="j" type="hinge"/>{BOX}', '<velocity name="v" joint="j" kv="1"/>', ["actuator 'v'", "forcerange"]),
        (f'<joint name="j" type="ball"/>{BOX}', '<velocity name="v" joint="j" kv="1" forcerange="-1 1"/>',
         ["actuator 'v'", "ball"]),
        (f'<joint name="j" type="hinge"/><geom type="box" size=".1 .1 .1"/><geom type="sphere" size=".1" contype="2"/>',
         "", ["body 'b'", "different contype"]),
        (f'<joint name="j" type="hinge"/>{BOX}<body name="weight"><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'
         '</body>', "", ["body 'weight'", "no colliding geom"]),
    ],
)
def test_unsupported_joint_models_are_refused_naming_the_element(body, actuator, words):
    xml = f'<mujoco><worldbody><body name="b" pos="0 0 1">{body}</body></worldbody><actuator>{actuator}</actuator></mujoco>'
    raises_naming(MjcfError, lambda: World.from_mjcf(xml), words, one_line=True)


def test_cli_refuses_two_joints_on_a_body_with_exit_2(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text(f'<mujoco><worldbody><body name="arm"><joint name="a" type="hinge"/><joint name="b" type="slide"/>'
                   f'{BOX}</body></worldbody></mujoco>')
    p = subprocess.run([sys.executable, "-m", "lcpsim", "simulate", str(bad)], capture_output=True, text=True, timeout=120,
                       cwd=tmp_path)
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1 and "body 'arm'" in p.stderr
    good = subprocess.run([sys.executable, "-m", "lcpsim", "simulate", str(DATA / "two_link_joint.xml"), "--steps", "50"],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert good.returncode == 0, good.stderr
