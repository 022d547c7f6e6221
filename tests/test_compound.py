"""Compound bodies (several solid parts in one body): ``World.add_compound``,
MJCF bodies of several geoms, what a run records and draws of them, and bad
parts refused naming the field."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lcpsim import World
from lcpsim.io.capture import open_capture

from conftest import raises_naming

G = 9.81
TURN_Y = (np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0)  # a quarter turn about y: body z onto x


def dumbbell() -> list[dict]:
    """Two spheres of radius 0.2 at x = ±0.5 and a bar between them."""
    return [
        {"kind": "sphere", "radius": 0.2, "position": (-0.5, 0, 0)},
        {"kind": "capsule", "radius": 0.05, "half_length": 0.4, "orientation": TURN_Y},
        {"kind": "sphere", "radius": 0.2, "position": (0.5, 0, 0)},
    ]


def test_dumbbell_rests_on_its_spheres_each_carrying_half():
    w = World(dt=1e-3)
    w.add_ground(mu=0.5)
    i = w.add_compound(dumbbell(), mass=3.0, position=(0, 0, 0.2))
    traj = w.run(1000)
    assert traj.lcp_stats().failures == 0
    np.testing.assert_allclose(traj.positions[-1, i], [0, 0, 0.2], atol=1e-6)
    rec = w.step()
    assert rec.ok and len(rec.fn) == 2
    np.testing.assert_allclose(rec.fn, 0.5 * 3.0 * G * 1e-3, rtol=1e-6)


def test_compound_parts_and_mass_properties_come_back():
    w = World()
    # Two unit cubes side by side, given 3 m off the origin: a 2 × 1 × 1 box.
    parts = [{"kind": "box", "half_extents": (0.5, 0.5, 0.5), "position": (3 + dx, 0, 0)} for dx in (0, 1)]
    i = w.add_compound(parts, mass=6.0, position=(0, 0, 2))
    b = w.body(i)
    assert b.kind == "compound"
    np.testing.assert_allclose(b.com_offset, [3.5, 0, 0])
    np.testing.assert_allclose([p["position"] for p in b.parts], [[-0.5, 0, 0], [0.5, 0, 0]])
    box = w.body(w.add_box(half_extents=(1.0, 0.5, 0.5), mass=6.0, position=(5, 5, 5)))
    np.testing.assert_allclose(b.inertia, box.inertia, atol=1e-12)
    # The parts given back make the same body again (now about their centre of mass).
    again = w.body(w.add_compound(b.parts, mass=6.0, position=(0, 3, 2)))
    np.testing.assert_allclose(again.inertia, b.inertia, atol=1e-12)
    np.testing.assert_allclose(again.com_offset, 0, atol=1e-15)
    # A non-uniform density: the centre of mass given, with the inertia.
    heavy = w.body(w.add_compound(parts, mass=6.0, com=(3.2, 0, 0), inertia=np.eye(3), position=(0, 6, 2)))
    np.testing.assert_allclose([p["position"] for p in heavy.parts], [[-0.2, 0, 0], [0.8, 0, 0]], atol=1e-15)
    np.testing.assert_allclose(heavy.inertia, np.eye(3))


def test_compound_of_one_box_moves_exactly_like_the_box():
    def run(add):
        w = World(dt=1e-3)
        w.add_slope(30.0, mu=0.3)
        n = np.array([np.sin(np.radians(30)), 0, np.cos(np.radians(30))])
        q = (np.cos(np.radians(15)), 0, np.sin(np.radians(15)), 0)
        i = add(w, dict(mass=2.0, position=tuple(0.25 * n), orientation=q, mu=0.3))
        return w.run(500).positions[-1, i]

    half = (0.5, 0.4, 0.25)
    box = run(lambda w, kw: w.add_box(half_extents=half, **kw))
    one = run(lambda w, kw: w.add_compound([{"kind": "box", "half_extents": half}], **kw))
    assert np.linalg.norm(box - run(lambda w, kw: w.add_box(half_extents=half, **kw))) == 0
    np.testing.assert_allclose(one, box, atol=1e-9)
    assert box[0] > 0.3  # it slid down the slope


def test_a_compound_run_is_recorded_captured_and_drawn(tmp_path):
    w = World(dt=1e-3)
    w.add_ground()
    w.add_compound(dumbbell(), position=(0, 0, 0.3))
    cfg = json.loads(json.dumps(w.config()))
    assert cfg["bodies"][1]["kind"] == "compound" and len(cfg["bodies"][1]["parts"]) == 3
    traj = w.run(200, capture=tmp_path / "run.h5", fclib=tmp_path / "fclib")
    assert traj.lcp_stats().failures == 0
    html = open(traj.to_html(tmp_path / "run.html"), encoding="utf-8").read()
    for word in ('"compound"', '"parts"', "solidObject"):
        assert word in html, word
    cap = open_capture(tmp_path / "run.h5")
    assert len(cap) > 0 and cap.runs[0]["bodies"][1]["parts"][0]["kind"] == "sphere"
    assert any((tmp_path / "fclib").iterdir())


@pytest.mark.parametrize(
    "parts, words",
    [
        ([], ["parts", "at least one part"]),
        ("sphere", ["parts must be a list"]),
        ([{"kind": "mesh"}], ["parts[0].kind", "'mesh'"]),
        ([{"kind": "sphere"}], ["parts[0]", "needs radius"]),
        ([{"kind": "sphere", "radius": 1, "colour": 3}], ["parts[0]", "colour"]),
        ([{"kind": "sphere", "radius": 0.1}, {"kind": "sphere", "radius": -1.0}], ["parts", "[1]", "radius", "-1"]),
        ([{"kind": "sphere", "radius": 0.1, "position": (np.nan, 0, 0)}], ["parts[0].position", "nan"]),
        ([{"kind": "box", "half_extents": (1, 1)}], ["parts[0].half_extents", "3 real numbers"]),
        ([{"kind": "sphere", "radius": 0.1, "orientation": (0, 0, 0, 0)}], ["parts", "[0]", "orientation"]),
        ([{"kind": "convex", "vertices": [[0, 0, 0], [1, 0, 0]]}], ["parts", "[0]", "vertices", "at least 4"]),
    ],
)
def test_bad_parts_are_refused_naming_the_field(parts, words):
    w = World()
    raises_naming(ValueError, lambda: w.add_compound(parts), words)
    assert w.body_count == 0


mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

TABLE = """
<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <body name="table" pos="0 0 0">
      <freejoint/>
      <geom name="top" type="box" size="0.5 0.3 0.025" pos="0 0 0.5" mass="4"/>
      <geom type="capsule" size="0.025 0.225" pos=" 0.45  0.25 0.25" mass="1"/>
      <geom type="capsule" size="0.025 0.225" pos="-0.45  0.25 0.25" mass="1"/>
      <geom type="capsule" size="0.025 0.225" pos="-0.45 -0.25 0.25" mass="1"/>
      <geom type="capsule" size="0.025 0.225" pos=" 0.45 -0.25 0.25" mass="1"/>
    </body>
    <body name="dumbbell" pos="2 0 0.2">
      <freejoint/>
      <geom type="sphere" size="0.2" pos="-0.5 0 0" mass="1"/>
      <geom type="capsule" size="0.05 0.4" euler="0 90 0" mass="1"/>
      <geom type="sphere" size="0.2" pos="0.5 0 0" mass="3"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_mjcf_bodies_of_several_geoms_are_compounds_with_mujocos_mass():
    w = World.from_mjcf(TABLE)
    m = mujoco.MjModel.from_xml_string(TABLE)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for name in ("table", "dumbbell"):
        b = w.body(w.body_id(name))
        k = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)
        assert b.kind == "compound" and b.mass == pytest.approx(m.body_mass[k])
        np.testing.assert_allclose(b.position, d.xipos[k], atol=1e-12)
        np.testing.assert_allclose(np.sort(np.linalg.eigvalsh(b.inertia)), np.sort(m.body_inertia[k]), rtol=1e-9)
    # The dumbbell's right sphere is heavier: its centre of mass is off the middle, its parts too.
    db = w.body(w.body_id("dumbbell"))
    assert db.position[0] > 2.0
    traj = w.run(1000)
    assert traj.lcp_stats().failures == 0
    # Both rest where they were put: the table on its feet, the dumbbell on its spheres.
    for name in ("table", "dumbbell"):
        i = w.body_id(name)
        np.testing.assert_allclose(traj.positions[-1, i], traj.positions[0, i], atol=1e-6)
