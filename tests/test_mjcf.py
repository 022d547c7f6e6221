"""MJCF through MuJoCo's compiler: a scene of free bodies at rest where
MuJoCo puts them, names, and every unsupported element refused in one line
(``lcpsim simulate FILE.xml``: exit 2)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

from lcpsim import World  # noqa: E402
from lcpsim.mjcf import MjcfError  # noqa: E402

from conftest import raises_naming  # noqa: E402

SCENE_TEMPLATE = """
<mujoco model="shapes">
  <option timestep="0.002" gravity="0 0 -9.81"/>
  <asset>
    <mesh name="tetra" vertex="0 0 0  0.3 0 0  0 0.3 0  0 0 0.3"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" friction="0.8"/>
    <geom name="block" type="box" size="0.2 0.2 0.1" pos="3 3 0.1"/>
    <geom name="ramp" type="mesh" mesh="tetra" pos="-3 -3 0"/>
    <geom name="ghost" type="sphere" size="0.5" pos="0 0 0.25" contype="0" conaffinity="0"/>
    <body name="post" pos="3 -3 0.5">
      <geom name="post" type="cylinder" size="0.1 0.5"/>
      <geom name="rail" type="capsule" size="0.05 0.4" pos="0 0 0.6" euler="90 0 0"/>
    </body>
{free_bodies}  </worldbody>
</mujoco>
"""

#: The scene's free bodies: name, pos, euler (or ""), geom type, size, mass.
FREE_BODIES = [
    ("box", "0 0 0.25", "", "box", "0.3 0.2 0.25", "2"),
    ("ball", "1 0 0.2", "", "sphere", "0.2", "1"),
    ("pill", "-1 0 0.1", "0 90 0", "capsule", "0.1 0.3", "1"),
    ("can", "0 1 0.15", "", "cylinder", "0.2 0.15", "1"),
    ("rock", "0 -1 0.0", "", "mesh", "", "0.5"),
]


def _free_body(name: str, pos: str, euler: str, kind: str, size: str, mass: str) -> str:
    turn = f' euler="{euler}"' if euler else ""
    shape = 'mesh="tetra"' if kind == "mesh" else f'size="{size}"'
    return (f'    <body name="{name}" pos="{pos}"{turn}>\n      <freejoint/>\n'
            f'      <geom type="{kind}" {shape} mass="{mass}"/>\n    </body>\n')


SCENE = SCENE_TEMPLATE.format(free_bodies="".join(_free_body(*b) for b in FREE_BODIES))


def _mujoco_rest(xml: str, seconds: float) -> tuple[dict[str, np.ndarray], float]:
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    deepest = 0.0
    for _ in range(int(round(seconds / m.opt.timestep))):
        mujoco.mj_step(m, d)
        if d.ncon:
            deepest = max(deepest, float(-min(d.contact.dist[: d.ncon].min(), 0.0)))
    names = {
        mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b): d.xipos[b].copy()
        for b in range(1, m.nbody)
        if m.body_jntnum[b] > 0  # the moving bodies
    }
    return names, deepest


def test_mjcf_scene_rests_where_mujoco_puts_it():
    w = World.from_mjcf(SCENE)
    assert w.dt == 0.002
    assert [w.body(w.body_id(n)).kind for n in ("box", "ball", "pill", "can", "rock")] == [
        "box", "sphere", "capsule", "cylinder", "convex",
    ]
    assert w.body(w.body_id("floor")).kind == "plane" and w.body(w.body_id("block")).is_static
    statics = {n: w.body(w.body_id(n)) for n in ("ramp", "post", "rail")}
    assert [b.kind for b in statics.values()] == ["convex", "cylinder", "capsule"]
    assert all(b.is_static for b in statics.values())
    np.testing.assert_allclose(statics["rail"].position, [3, -3, 1.1], atol=1e-12)
    assert w.body(w.body_id("box")).mass == pytest.approx(2.0)
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    theirs, penetration = _mujoco_rest(SCENE, 1.0)
    for name, p in theirs.items():
        ours = traj.positions[-1, w.body_id(name)]
        # Within MuJoCo's own penetration (its soft contacts sink a little), plus round-off.
        assert np.abs(ours - p).max() <= penetration + 1e-6, (name, ours, p, penetration)
        assert np.abs(traj.velocities[-1, w.body_id(name)]).max() < 1e-6, name


def test_mjcf_from_a_file_and_names(tmp_path):
    path = tmp_path / "scene.xml"
    path.write_text(SCENE)
    w = World.from_mjcf(path)
    assert w.body_count == 10  # the visual-only geom is skipped
    with pytest.raises(KeyError, match="no body named 'nope'"):
        w.body_id("nope")
    assert w.copy().body_id("ball") == w.body_id("ball")


BODY = '<body name="{name}" pos="0 0 1">{inner}</body>'


@pytest.mark.parametrize(
    "xml, words",
    [
        (BODY.format(name="arm", inner='<joint name="elbow" type="hinge" stiffness="5"/><geom type="box" size=".1 .1 .1"/>'),
         ["joint 'elbow'", "hinge", "stiffness"]),
        (BODY.format(name="egg", inner='<freejoint/><geom name="shell" type="ellipsoid" size=".1 .2 .3"/>'),
         ["geom 'shell'", "ellipsoid"]),
        (BODY.format(name="two", inner='<freejoint/><geom type="box" size=".1 .1 .1"/>'
                     '<geom type="sphere" size=".1" pos=".2 0 0" friction="0.3"/>'),
         ["body 'two'", "different friction", "1.0, 0.3"]),
        (BODY.format(name="car", inner='<freejoint/><geom type="box" size=".1 .1 .1"/>'
         '<body name="wheel"><geom type="sphere" size=".1" pos=".2 0 0" contype="0" conaffinity="0"/></body>'),
         ["body 'wheel'", "no colliding geom"]),
        (BODY.format(name="top", inner='<freejoint/><geom name="tip" type="sphere" size=".1" condim="6"/>'),
         ["geom 'tip'", "condim=6", "rolling"]),
        ('<geom name="floor" type="plane" size="1 1 1"/>'
         + BODY.format(name="p", inner='<freejoint/><geom name="first" type="sphere" size=".1" priority="1"/>'),
         ["geom 'first'", "priority=1", "geom 'floor'", "priority=0"]),
        ('<geom name="floor" type="plane" size="1 1 1" friction="0.5"/>'
         + BODY.format(name="p", inner='<freejoint/><geom name="ice" type="box" size=".1 .1 .1" condim="1" friction="0.9"/>'),
         ["geom 'ice'", "condim 1, friction 0.9", "geom 'floor'", "condim 3, friction 0.5", "<= 0.5"]),
        ('<geom name="floor" type="plane" size="1 1 1" friction="1 0.03 0"/>'
         + BODY.format(name="p", inner='<freejoint/><geom name="pad" type="box" size=".1 .1 .1" condim="4" friction="1 0.01 0"/>'),
         ["geom 'floor'", "condim 3, torsional friction 0.03", "geom 'pad'", "condim 4, torsional friction 0.01",
          "<= 0.01"]),
    ],
)
def test_unsupported_elements_are_refused_naming_them(xml, words):
    raises_naming(MjcfError, lambda: World.from_mjcf(f"<mujoco><worldbody>{xml}</worldbody></mujoco>"), words,
                  one_line=True)


SLOPE = """
<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <geom name="slope" type="plane" size="5 5 .1" euler="0 20 0" condim="{floor}" friction="{mu}"/>
    <body name="block" pos="0 0 0.1" euler="0 20 0">
      <freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1" condim="{block}" friction="{mu}"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("floor, block, frictionless", [(1, 1, True), (3, 1, False), (3, 3, False)])
def test_condim_1_pairs_slide_without_friction_as_in_mujoco(floor, block, frictionless):
    """A block on a 20° slope, μ = 0.5 > tan 20°: it slides down at g sin θ when both geoms are
    frictionless (condim 1; MuJoCo's pair takes the larger condim) and stays put otherwise."""
    xml = SLOPE.format(floor=floor, block=block, mu=0.5)
    w = World.from_mjcf(xml)
    b = w.body_id("block")
    assert w.body(b).mu == (0.0 if block == 1 else 0.5)
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(500):
        mujoco.mj_step(m, d)
    theta = np.radians(20)
    ours, theirs = np.linalg.norm(w.velocities[b]), np.linalg.norm(d.qvel[:3])
    if frictionless:
        assert ours == pytest.approx(9.81 * np.sin(theta) * 0.5, rel=1e-9)  # v = g sin θ t exactly
        assert theirs == pytest.approx(ours, rel=0.02)
    else:
        assert ours < 1e-9 and theirs < 1e-2


SPIN = """
<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <geom type="plane" size="5 5 .1" friction="0 0.005 0"/>
    <body name="block" pos="0 0 0.1">
      <freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1" condim="4" friction="0 0.01 0"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_condim_4_spins_a_box_down_at_its_torsional_bound():
    """A frictionless box spun at 2 rad/s on the ground, torsional friction 0.01 m (condim 4):
    the patch's torque μ_t m g slows it by h μ_t g / I a step, I = m (0.2 m)² / 6."""
    w = World.from_mjcf(SPIN)
    b = w.body_id("block")
    w.set_angular_velocity(b, (0.0, 0.0, 2.0))
    traj = w.run(50)
    assert traj.lcp_stats().failures == 0
    assert w.velocities[b][5] == pytest.approx(2.0 - 50 * 1e-3 * 0.01 * 9.81 / (0.04 / 6), abs=1e-9)
    with pytest.raises(ValueError, match="torsional_friction"):
        w.set_torsional_friction(b, -1.0)


def test_a_geom_margin_is_refused_as_mujoco_rests_bodies_that_far_apart():
    cube = ('<mujoco><worldbody><geom type="plane" size="1 1 1"/><body pos="0 0 0.2"><freejoint/>'
            '<geom name="shell" type="box" size=".1 .1 .1" margin="{margin}"/></body></worldbody></mujoco>')
    rest = []
    for margin in (0.0, 0.01):
        m = mujoco.MjModel.from_xml_string(cube.format(margin=margin))
        d = mujoco.MjData(m)
        mujoco.mj_step(m, d, nstep=3000)
        rest.append(float(d.qpos[2]))
    assert rest[1] - rest[0] == pytest.approx(0.01, abs=1e-4)  # MuJoCo: 1 cm higher
    with pytest.raises(MjcfError, match="geom 'shell' has margin=0.01.*apart"):
        World.from_mjcf(cube.format(margin=0.01))


# A ball 0.5 m above the floor and a bead on a vertical slide with a damper and a range that
# holds it 0.1 m below its start; option flags turn parts off.
FLAGS = """
<mujoco>
  <option timestep="0.001"><flag {flags}/></option>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 .1"/>
    <body name="ball" pos="0 0 0.6"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body>
    <body name="bead" pos="1 0 2">
      <joint name="rail" type="slide" axis="0 0 1" range="-0.1 0.1" damping="50"/>
      <geom type="sphere" size="0.05" mass="1"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("flags, ball_falls, ball_through, bead_free", [
    ('gravity="disable"', False, False, False),
    ('contact="disable"', True, True, False),
    ('limit="disable" damper="disable"', True, False, True),
    ('constraint="disable" damper="disable"', True, True, True),
])
def test_option_flags_turn_off_what_they_turn_off_in_mujoco(flags, ball_falls, ball_through, bead_free):
    """0.5 s: the ball stays (no gravity), lands on the floor, or falls through it (no contact);
    the bead is held by its damped, limited rail, or falls freely once limit and damper are off."""
    xml = FLAGS.format(flags=flags)
    w = World.from_mjcf(xml)
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, nstep=500)
    n = 500
    free_fall = 9.81 * 1e-6 * n * (n + 1) / 2  # semi-implicit Euler, exactly
    ball, bead = traj.positions[-1, w.body_id("ball")], traj.positions[-1, w.body_id("bead")]
    theirs_ball, theirs_bead = d.xipos[1], d.xipos[2]
    if not ball_falls:
        assert ball[2] == 0.6 and abs(theirs_ball[2] - 0.6) < 1e-9
    elif ball_through:
        assert ball[2] == pytest.approx(0.6 - free_fall, abs=1e-9) and theirs_ball[2] < 0.6 - 1.0
    else:
        assert ball[2] == pytest.approx(0.1, abs=1e-6) and theirs_ball[2] == pytest.approx(0.1, abs=2e-3)
    if bead_free:
        assert bead[2] == pytest.approx(2 - free_fall, abs=1e-6) and theirs_bead[2] == pytest.approx(2 - free_fall, abs=5e-3)
    else:
        assert bead[2] >= 2 - 0.1 - 1e-6 and theirs_bead[2] > 2 - 0.1 - 5e-3


@pytest.mark.parametrize("xml, words", [
    ('<mujoco><option><flag actuation="disable"/></option><worldbody><body name="b"><joint name="j" type="hinge"/>'
     '<geom type="box" size=".1 .1 .1"/></body></worldbody><actuator><velocity joint="j" kv="1" forcerange="-1 1"/>'
     '</actuator></mujoco>', ["actuation is disabled"]),
    ('<mujoco><option><flag override="enable"/></option><worldbody/></mujoco>', ["override", "o_friction"]),
    ('<mujoco><option density="1.2"/><worldbody/></mujoco>', ["option density=1.2", "fluid"]),
    ('<mujoco><worldbody><body name="balloon" gravcomp="1"><freejoint/><geom size=".1"/></body></worldbody></mujoco>',
     ["body 'balloon'", "gravcomp=1"]),
])
def test_options_lcpsim_cannot_follow_are_refused(xml, words):
    raises_naming(MjcfError, lambda: World.from_mjcf(xml), words)


def test_a_zero_timestep_is_refused_naming_the_option():
    xml = '<mujoco><option timestep="0"/><worldbody><geom type="plane" size="1 1 1"/></worldbody></mujoco>'
    with pytest.raises(MjcfError, match="timestep must be > 0.*got 0.0"):
        World.from_mjcf(xml)
    assert World.from_mjcf(xml, dt=1e-3).dt == 1e-3  # a dt given replaces the file's


def test_actuators_are_refused():
    xml = ('<mujoco><worldbody><body name="b"><joint name="j" type="slide"/><geom type="box" size=".1 .1 .1"/>'
           '</body></worldbody><actuator><motor name="push" joint="j"/></actuator></mujoco>')
    with pytest.raises(MjcfError, match="actuator 'push'"):
        World.from_mjcf(xml)


def test_cli_simulates_an_mjcf_file_and_refuses_with_exit_2(tmp_path):
    good = tmp_path / "good.xml"
    good.write_text(SCENE)
    p = subprocess.run([sys.executable, "-m", "lcpsim", "simulate", str(good), "--steps", "50"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "mjcf" in p.stdout
    bad = tmp_path / "bad.xml"
    bad.write_text("<mujoco><worldbody>" + BODY.format(name="arm", inner='<joint name="elbow" armature="1"/><geom size=".1"/>')
                   + "</worldbody></mujoco>")
    p = subprocess.run([sys.executable, "-m", "lcpsim", "simulate", str(bad)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1 and "joint 'elbow'" in p.stderr


def test_cli_view_draws_an_mjcf_file(tmp_path):
    path = tmp_path / "scene.xml"
    path.write_text(SCENE)
    out = tmp_path / "scene.html"
    p = subprocess.run([sys.executable, "-m", "lcpsim", "view", str(path), "--steps", "20", "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 0 and "20 steps" in p.stdout


FILTER_SCENE = """
<mujoco model="filter">
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" contype="1" conaffinity="3"/>
    <geom name="shelf" type="box" size="0.5 0.5 0.05" pos="0 0 0.6"/>
    <body name="ghost" pos="0 0 1"><freejoint/><geom type="sphere" size="0.1" contype="2" conaffinity="2"/></body>
    <body name="crate" pos="1.2 0 1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body name="lid" pos="0.3 0.3 0.8"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
</mujoco>
"""


def test_mjcf_contype_conaffinity_filter_agrees_with_mujoco():
    # The ghost ball (2/2) shares no bit with the shelf (1/1): it falls through the shelf onto
    # the floor, whose affinity 3 takes its type 2; the lid (1/1) lands on the shelf.
    w = World.from_mjcf(FILTER_SCENE)
    assert w.collision_filter(w.body_id("ghost")) == (2, 2)
    assert w.collision_filter(w.body_id("floor")) == (1, 3)
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    theirs, penetration = _mujoco_rest(FILTER_SCENE, 1.0)
    assert theirs["ghost"][2] < 0.2 and theirs["lid"][2] > 0.6  # MuJoCo filters the same way
    for name, p in theirs.items():
        ours = traj.positions[-1, w.body_id(name)]
        assert np.abs(ours - p).max() <= penetration + 1e-6, (name, ours, p, penetration)
    np.testing.assert_allclose(traj.positions[-1, w.body_id("ghost")], [0, 0, 0.1], atol=1e-6)
    np.testing.assert_allclose(traj.positions[-1, w.body_id("lid")], [0.3, 0.3, 0.75], atol=1e-6)


@pytest.mark.parametrize(
    "source, words",
    [
        ("<mujoco><worldbody><geom type='box' size='.1 .1 .1'></worldbody></mujoco>", ["could not compile"]),
        ("<mujoco><worldbody><geom type='box' size='.1 .1 .1'/></worldbody>", ["could not compile"]),
        ('<mujoco><asset><mesh name="rock" file="no_such_rock.stl"/></asset><worldbody>'
         '<geom type="mesh" mesh="rock"/></worldbody></mujoco>', ["no_such_rock.stl"]),
        ('<mujoco><asset><mesh name="flat" vertex="0 0 0 1 0 0 0 1 0 1 1 0"/></asset><worldbody>'
         '<body name="f"><freejoint/><geom type="mesh" mesh="flat"/></body></worldbody></mujoco>', ["flat"]),
        ('<mujoco><worldbody><body name="b"><freejoint/><geom type="sphere" size="-1"/></body></worldbody></mujoco>',
         ["could not compile", "must be positive"]),
    ],
)
def test_bad_mjcf_raises_one_line_naming_what_is_wrong(source, words):
    raises_naming(MjcfError, lambda: World.from_mjcf(source), words, one_line=True)


def test_missing_mjcf_file_is_named(tmp_path):
    with pytest.raises(MjcfError, match="nowhere.xml"):
        World.from_mjcf(tmp_path / "nowhere.xml")


def test_the_benchmark_bin_file_loads_alike_in_both_engines():
    """benchmarks/scenes/mixed_bin.xml (benchmarks/mjcf_bin.py): every free body where MuJoCo
    puts its centre of mass, with MuJoCo's mass; the bin's static geoms; the file's time step."""
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "mixed_bin.xml"
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    w = World.from_mjcf(path)
    assert w.dt == m.opt.timestep and w.body_count == m.ngeom  # one lcpsim body per colliding geom
    kinds = {"box": "box", "sphere": "sphere", "capsule": "capsule", "cylinder": "cylinder", "mesh": "convex"}
    for b in range(1, m.nbody):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)
        body = w.body(w.body_id(name))
        assert body.kind == kinds[name.rstrip("0123456789")]
        assert body.mass == pytest.approx(float(m.body_mass[b]), rel=1e-12)
        np.testing.assert_allclose(body.position, d.xipos[b], atol=1e-9, err_msg=name)
    assert sum(w.body(i).is_static for i in range(w.body_count)) == 5  # floor and four walls


def _sliding_block(cone: str) -> str:
    return (f'<mujoco><option timestep="0.002" cone="{cone}"/><worldbody>'
            '<geom type="plane" size="5 5 .1" friction="0.5"/><body name="b" pos="0 0 0.1"><freejoint/>'
            '<geom type="box" size=".1 .1 .1" friction="0.5"/></body></worldbody></mujoco>')


@pytest.mark.parametrize("cone, dirs, diagonal", [("pyramidal", 4, 1 / np.sqrt(2)), ("elliptic", 8, 1.0)])
def test_the_model_cone_sets_friction_dirs_and_a_callers_value_wins(cone, dirs, diagonal):
    """MuJoCo's pyramidal cone (edges n ± μ t1, n ± μ t2) is lcpsim's 4-direction cone: a block
    sliding along the diagonal of x and y decelerates at μg/√2 in both engines; under the elliptic
    cone lcpsim's 8 directions include the diagonal, which then slows at μg as on the round cone."""
    xml = _sliding_block(cone)
    assert World.from_mjcf(xml).params["friction_dirs"] == dirs
    assert World.from_mjcf(xml, friction_dirs=6).params["friction_dirs"] == 6
    v0, steps, dt, mu_g = 2.0, 100, 0.002, 0.5 * 9.81
    w = World.from_mjcf(xml)
    b = w.body_id("b")
    w.set_velocity(b, [v0 / np.sqrt(2), v0 / np.sqrt(2), 0.0])
    w.run(steps)
    slowing = (v0 - np.linalg.norm(np.asarray(w.velocities)[b][:3])) / (steps * dt) / mu_g
    assert slowing == pytest.approx(diagonal, rel=1e-9)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    d.qvel[:2] = v0 / np.sqrt(2)
    mujoco.mj_step(m, d, steps)
    assert (v0 - np.linalg.norm(d.qvel[:2])) / (steps * dt) / mu_g == pytest.approx(diagonal, rel=0.05)
