"""MuJoCo's body filter read from MJCF: a body never touches its own weld group, nor its
parent's weld group unless that is the world's (``filterparent``), nor a body it is
``<contact><exclude>``-d from. Each scene is run by both engines from the same file."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

from lcpsim import World  # noqa: E402
from lcpsim.mjcf import MjcfError  # noqa: E402

def _model(bodies: str, flag: str = "", after: str = "") -> str:
    """A model of ``bodies`` in the world at dt = 2 ms; ``flag``: an <option> flag; ``after``: after the world."""
    return f'<mujoco><option timestep="0.002">{flag}</option><worldbody>{bodies}</worldbody>{after}</mujoco>'


# A free base with a mount welded on it (no joint), an arm hinged to the mount whose box sinks
# 2 cm into the base's top, and two welded spheres that overlap each other by 4 cm. The hinge
# axis is y and the arm's centre of mass lies below it in x: it hangs at rest.
WELDED = """
    <geom name="floor" type="plane" size="2 2 .1"/>
    <body name="base" pos="0 0 0.1">
      <freejoint/>
      <geom name="base" type="box" size="0.3 0.3 0.1" mass="4"/>
      <body name="mount" pos="0 0 0.15">
        <geom name="mount" type="box" size="0.05 0.05 0.05" mass="0.5"/>
        <body name="arm">
          <joint name="pivot" type="hinge" axis="0 1 0"/>
          <geom name="arm" type="box" size="0.2 0.05 0.05" pos="0 0.15 -0.02" mass="0.2"/>
        </body>
      </body>
      <body name="left" pos="-0.2 0 0.15"><geom name="left" type="sphere" size="0.06" mass="0.1"/></body>
      <body name="right" pos="-0.12 0 0.15"><geom name="right" type="sphere" size="0.06" mass="0.1"/></body>
    </body>
"""

# A static post (a body welded to the world) and a flap hinged at one end 0.15 m beside the
# post's top: the flap's weight turns it onto the top face, which holds it level. The flap's parent
# is the world's weld group, so MuJoCo does not filter the pair.
ON_THE_WORLD = _model("""
    <body name="post" pos="0 0 0.5">
      <geom name="post" type="box" size="0.05 0.05 0.5"/>
      <body name="flap" pos="-0.2 0 0.52">
        <joint name="hinge" type="hinge" axis="0 1 0"/>
        <geom name="flap" type="box" size="0.2 0.05 0.02" pos="0.2 0 0" mass="0.3"/>
      </body>
    </body>
""")

# A ball resting on a box resting on the floor; the ball excluded from the box (or from the
# world: the floor).
EXCLUDED = """
    <geom name="floor" type="plane" size="2 2 .1"/>
    <body name="box" pos="0 0 0.2"><freejoint/><geom name="box" type="box" size="0.3 0.3 0.2" mass="2"/></body>
    <body name="ball" pos="0.1 0 0.5"><freejoint/><geom name="ball" type="sphere" size="0.1" mass="0.5"/></body>
"""


def _mujoco_pairs(m, d) -> set[frozenset[str]]:
    """The pairs of bodies MuJoCo has contacts between (after mj_forward or a step)."""
    name = lambda g: mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[g]))  # noqa: E731
    return {frozenset((name(c.geom1), name(c.geom2))) for c in d.contact[: d.ncon]}


def _lcpsim_pairs(w: World, names: list[str]) -> set[frozenset[str]]:
    by_index = {w.body_id(n): n for n in names}
    rec = w.last_record
    out = set()
    for a, b in zip(rec.body_a, rec.body_b):
        out.add(frozenset((by_index.get(int(a), "world"), by_index.get(int(b), "world"))))
    return out


def test_a_body_touches_neither_its_weld_group_nor_its_parents_in_either_engine():
    xml = _model(WELDED)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    names = ["base", "mount", "arm", "left", "right"]
    w = World.from_mjcf(xml)
    ids = {n: w.body_id(n) for n in names}
    # Weld group {base, mount, left, right}; the arm's parent group is the same. Pairs a
    # joint or weld joins (base-mount, base-left, base-right, mount-arm) need no exclusion.
    expected = {("mount", "left"), ("mount", "right"), ("left", "right"), ("arm", "base"), ("arm", "left"), ("arm", "right")}
    assert w.excluded_pairs() == sorted(tuple(sorted((ids[a], ids[b]))) for a, b in expected)
    w.step()
    ours = _lcpsim_pairs(w, names)
    theirs = _mujoco_pairs(m, d)
    filtered = [frozenset(p) for p in (("arm", "base"), ("left", "right"))]
    for pair in filtered:  # they overlap by 2 and 4 cm, and neither engine sees it
        assert pair not in ours and pair not in theirs, (pair, ours, theirs)
    assert ours == theirs == {frozenset(("world", "base"))}, (ours, theirs)  # the floor only
    # Left alone, the base rests and the arm hangs still in both.
    traj = w.run(250)
    assert traj.lcp_stats().failures == 0
    for _ in range(251):
        mujoco.mj_step(m, d)
    for n in names:
        b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n)
        np.testing.assert_allclose(traj.positions[-1, ids[n]], d.xipos[b], atol=2e-3, err_msg=n)


def test_with_filterparent_disabled_a_hinged_child_of_a_moving_body_is_refused():
    xml = _model(WELDED, flag='<flag filterparent="disable"/>')
    with pytest.raises(MjcfError) as e:
        World.from_mjcf(xml)
    msg = str(e.value)
    assert "'mount'" in msg and "'arm'" in msg and "filterparent" in msg and "\n" not in msg


def test_a_body_hinged_on_a_body_of_the_world_rests_on_it_in_both_engines():
    m = mujoco.MjModel.from_xml_string(ON_THE_WORLD)
    d = mujoco.MjData(m)
    flap = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "flap")
    for _ in range(250):
        mujoco.mj_step(m, d)
    assert frozenset(("post", "flap")) in _mujoco_pairs(m, d)
    w = World.from_mjcf(ON_THE_WORLD)
    assert w.excluded_pairs() == []
    traj = w.run(250)
    assert traj.lcp_stats().failures == 0
    rec = w.last_record
    post, ours = w.body_id("post"), w.body_id("flap")
    assert any({int(a), int(b)} == {post, ours} for a, b in zip(rec.body_a, rec.body_b))
    # Level on the post (unsupported, it would have swung down about its hinge in 0.5 s).
    np.testing.assert_allclose(traj.positions[-1, ours], [0, 0, 1.02], atol=1e-6)
    np.testing.assert_allclose(d.xipos[flap], [0, 0, 1.02], atol=2e-3)


@pytest.mark.parametrize("body1, rest_z", [("box", 0.1), ("world", 0.5)])
def test_an_excluded_pair_passes_through_in_both_engines(body1, rest_z):
    """Excluded from the box, the ball falls through it onto the floor (z = 0.1); excluded from
    the world (the floor), it stays on the box (z = 0.5)."""
    xml = _model(EXCLUDED, after=f'<contact><exclude body1="{body1}" body2="ball"/></contact>')
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    ball = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")
    for _ in range(500):
        mujoco.mj_step(m, d)
    w = World.from_mjcf(xml)
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    ours = traj.positions[-1, w.body_id("ball")]
    assert abs(ours[2] - rest_z) < 1e-4 and abs(d.xipos[ball][2] - rest_z) < 5e-3, (ours, d.xipos[ball])
