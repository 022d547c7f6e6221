"""MJCF's explicit contact pairs (``<contact><pair>``) read as ``World.add_contact_pair``: the
pair's two geoms touch whatever their bits, with the pair's friction, not the geoms'. Each
scene is run by both engines from the same file: a box on a plane tilted by gravity."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

from lcpsim import World  # noqa: E402
from lcpsim.mjcf import MjcfError  # noqa: E402

from conftest import raises_naming  # noqa: E402

G, TILT = 9.81, np.radians(20.0)  # tan 20° = 0.36: μ = 1 holds the box, μ = 0.1 lets it slide
STEPS, DT = 250, 0.002  # 0.5 s


def _slope(geom_friction: float, pair: str, bits: str = "", box_bits: str | None = None) -> str:
    """A 0.2 m box of 1 kg on the floor plane, gravity tilted by TILT towards +x; ``bits``
    of the floor's geom (and the box's, unless ``box_bits``)."""
    return f"""<mujoco><option timestep="{DT}" gravity="{G * np.sin(TILT):.9f} 0 {-G * np.cos(TILT):.9f}"/>
      <worldbody><geom name="floor" type="plane" size="5 5 .1" friction="{geom_friction}" {bits}/>
        <body name="box" pos="0 0 0.1"><freejoint/>
          <geom name="box" type="box" size="0.1 0.1 0.1" mass="1" friction="{geom_friction}" {bits if box_bits is None else box_bits}/></body>
      </worldbody><contact>{pair}</contact></mujoco>"""


def _both(xml: str) -> tuple[np.ndarray, np.ndarray]:
    """The box's centre after STEPS steps in MuJoCo and in lcpsim."""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, nstep=STEPS)
    w = World.from_mjcf(xml)
    traj = w.run(STEPS)
    assert traj.lcp_stats().failures == 0
    return np.array(d.qpos[:3]), np.asarray(w.positions[w.body_id("box")])


def _slide(mu: float) -> float:
    """How far a box slides from rest in STEPS steps down the slope with friction ``mu``
    (semi-implicit Euler: ``a h² n(n+1)/2``)."""
    return G * max(0.0, np.sin(TILT) - mu * np.cos(TILT)) * DT * DT * STEPS * (STEPS + 1) / 2


@pytest.mark.parametrize(
    "geom_friction, pair, mu",
    [
        (1.0, '<pair name="slick" geom1="box" geom2="floor" friction="0.1 0.1"/>', 0.1),  # the geoms would hold
        (0.1, '<pair name="grip" geom1="floor" geom2="box" friction="1 1"/>', 1.0),  # the geoms would slide
        (1.0, '<pair name="ice" geom1="box" geom2="floor" condim="1"/>', 0.0),  # frictionless
    ],
)
def test_a_pair_slides_or_holds_with_its_own_friction_as_in_mujoco(geom_friction, pair, mu):
    ours_mj, ours = _both(_slope(geom_friction, pair))
    expected = _slide(mu)
    # Both rest on the plane (centre 0.1 m up) and have moved along x as the pair's μ says.
    assert abs(ours[2] - 0.1) < 1e-3 and abs(ours_mj[2] - 0.1) < 1e-3
    assert abs(ours[0] - expected) < 1e-6, (ours[0], expected)
    assert abs(ours_mj[0] - expected) < 0.01, (ours_mj[0], expected)
    w = World.from_mjcf(_slope(geom_friction, pair))
    box, floor = w.body_id("box"), w.body_id("floor")
    assert w.contact_pairs() == [(min(box, floor), max(box, floor), mu)]


def test_geoms_that_collide_with_nothing_touch_through_their_pair():
    bits = 'contype="0" conaffinity="0"'
    pair = '<pair name="slick" geom1="box" geom2="floor" friction="0.1 0.1"/>'
    ours_mj, ours = _both(_slope(1.0, pair, bits))
    assert abs(ours[2] - 0.1) < 1e-3 and abs(ours_mj[2] - 0.1) < 1e-3
    assert abs(ours[0] - _slide(0.1)) < 1e-6 and abs(ours_mj[0] - _slide(0.1)) < 0.01
    # Without the pair the box (which lcpsim needs to collide by its bits) falls through the floor.
    fall_mj, fall = _both(_slope(1.0, "", bits, box_bits=""))
    assert fall[2] < -0.5 and fall_mj[2] < -0.5


def test_a_pair_touches_past_an_exclude_as_in_mujoco():
    pair = '<exclude body1="world" body2="box"/><pair name="slick" geom1="box" geom2="floor" friction="0.1 0.1"/>'
    ours_mj, ours = _both(_slope(1.0, pair))
    assert abs(ours[2] - 0.1) < 1e-3 and abs(ours_mj[2] - 0.1) < 1e-3


ARM = """<mujoco><worldbody><geom name="floor" type="plane" size="5 5 .1"/>
  <body name="base" pos="0 0 1"><freejoint/><geom name="base" type="box" size=".1 .1 .1"/>
    <body name="arm" pos="0 0 .3"><joint type="hinge"/><geom name="arm" type="box" size=".1 .1 .1" {arm}/></body>
  </body>
  <body name="dumbbell" pos="1 0 1"><freejoint/><geom name="bell" type="sphere" size=".05"/>
    <geom name="other_bell" type="sphere" size=".05" pos=".2 0 0"/></body></worldbody><contact>{pair}</contact></mujoco>"""


@pytest.mark.parametrize(
    "pair, words, arm",
    [
        ('<pair name="p" geom1="arm" geom2="floor" condim="4"/>', ["contact pair 'p'", "condim=4"], ""),
        ('<pair name="p" geom1="arm" geom2="floor" condim="6"/>', ["contact pair 'p'", "condim=6"], ""),
        ('<pair name="p" geom1="arm" geom2="floor" margin="0.01"/>', ["contact pair 'p'", "margin=0.01"], ""),
        ('<pair name="p" geom1="arm" geom2="floor" gap="0.01"/>', ["contact pair 'p'", "gap=0.01"], ""),
        ('<pair name="p" geom1="arm" geom2="floor" friction="0.2 0.7"/>', ["contact pair 'p'", "0.2 and 0.7"], ""),
        ('<pair name="p" geom1="arm" geom2="base"/>', ["contact pair 'p'", "joined by a joint"], ""),
        ('<pair name="p" geom1="arm" geom2="floor"/>', ["contact pair 'p'", "geom 'arm'", "condim=4"], 'condim="4"'),
        ('<pair name="p" geom1="bell" geom2="floor"/>', ["contact pair 'p'", "geom 'bell'", "body 'dumbbell'"], ""),
    ],
)
def test_pairs_lcpsim_cannot_express_are_refused_naming_the_pair(pair, words, arm):
    raises_naming(MjcfError, lambda: World.from_mjcf(ARM.format(pair=pair, arm=arm)), words, one_line=True)
