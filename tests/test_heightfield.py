"""Height fields: ``World.add_heightfield`` (a box rests on a flat one as on
the plane), MJCF ``hfield`` from elevation data and from a PNG (a ball rolls
down the ramp at 5/7 g sin θ, the way MuJoCo rolls it), the viewer's page,
and bad grids refused naming the field."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

from lcpsim import World

from conftest import raises_naming

G = 9.81


def test_box_rests_on_a_flat_heightfield_as_on_the_plane():
    ends = []
    for ground in ("plane", "hfield"):
        w = World(dt=1e-3)
        if ground == "plane":
            w.add_ground(mu=0.5)
        else:
            w.add_heightfield(np.zeros((6, 9)), size=(3.0, 2.0), mu=0.5)
        i = w.add_box(half_extents=(0.5, 0.4, 0.25), mass=2.0, position=(0.3, -0.2, 0.25))
        traj = w.run(1000)
        assert traj.lcp_stats().failures == 0
        ends.append(traj.positions[-1, i])
    np.testing.assert_allclose(ends[1], [0.3, -0.2, 0.25], atol=1e-9)
    np.testing.assert_allclose(ends[1], ends[0], atol=1e-12)


def test_heightfield_is_read_back_and_drawn(tmp_path):
    w = World()
    h = np.arange(12.0).reshape(3, 4) / 10
    i = w.add_heightfield(h, size=(2.0, 1.0), position=(0, 0, -1))
    b = w.body(i)
    assert b.kind == "hfield" and b.is_static
    np.testing.assert_array_equal(b.heights, h)
    np.testing.assert_array_equal(b.half_extents, [2.0, 1.0])
    w.add_sphere(0.2, position=(0, 0, 0.5))
    html = open(w.run(20).to_html(tmp_path / "hf.html"), encoding="utf-8").read()
    assert '"hfield"' in html and '"heights"' in html


@pytest.mark.parametrize(
    "heights, size, words",
    [
        (np.zeros(4), (1, 1), ["heights", "2-D"]),
        (np.zeros((1, 3)), (1, 1), ["heights", "nrow, ncol >= 2", "(1, 3)"]),
        ([[0, 0], [0, np.nan]], (1, 1), ["heights must be finite", "NaN"]),
        (np.zeros((2, 2)), (1, 1, 1), ["size", "2 real numbers"]),
        (np.zeros((2, 2)), (1, -2), ["half_y must be > 0", "-2"]),
        (np.zeros((2, 2)), (np.inf, 1), ["size must be finite"]),
    ],
)
def test_bad_heightfields_are_refused_naming_the_field(heights, size, words):
    w = World()
    raises_naming(ValueError, lambda: w.add_heightfield(heights, size=size), words)
    assert w.body_count == 0


mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

#: A ramp falling 1 m over 6 m towards +y (MuJoCo's elevation rows run from +y down to −y).
RAMP = """
<mujoco>
  <option timestep="0.001"/>
  <asset>{hfield}</asset>
  <worldbody>
    <geom type="hfield" hfield="ramp"/>
    <body name="ball" pos="{pos}"><freejoint/><geom type="sphere" size="0.2" friction="1"/></body>
  </worldbody>
</mujoco>"""
ELEVATION = '<hfield name="ramp" nrow="5" ncol="3" size="2 3 1.0 0.1" elevation="0 0 0  1 1 1  2 2 2  3 3 3  4 4 4"/>'


def _png(path, rows: list[list[int]]) -> None:
    """An 8-bit greyscale PNG of ``rows`` (top row first)."""
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    chunk = lambda kind, data: (struct.pack(">I", len(data)) + kind + data  # noqa: E731
                                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    head = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def _ball_on_ramp(hfield: str) -> str:
    th = np.arctan(1 / 6)
    pos = np.array([0.2, 0.0, 0.5]) + 0.2 * np.array([0.0, np.sin(th), np.cos(th)])
    return RAMP.format(hfield=hfield, pos=" ".join(f"{x:.17g}" for x in pos))


@pytest.mark.parametrize("source", ["elevation", "png"])
def test_mjcf_hfield_ramp_rolls_a_ball_as_theory_and_mujoco(tmp_path, source):
    if source == "png":
        _png(tmp_path / "ramp.png", [[v, v, v] for v in (0, 64, 128, 191, 255)])
        xml = _ball_on_ramp('<hfield name="ramp" file="ramp.png" size="2 3 1.0 0.1"/>')
        (tmp_path / "scene.xml").write_text(xml)
        source_arg = tmp_path / "scene.xml"
    else:
        xml = source_arg = _ball_on_ramp(ELEVATION)
    w = World.from_mjcf(source_arg)
    ground = w.body(0)
    assert ground.kind == "hfield" and ground.heights.shape == (5, 3)
    assert ground.heights[0, 0] == pytest.approx(1.0) and ground.heights[-1, 0] == pytest.approx(0.0)
    ball = w.body_id("ball")
    traj = w.run(500)
    assert traj.lcp_stats().failures == 0
    th = np.arctan(1 / 6) if source == "elevation" else None
    v = traj.velocities[-1, ball, :3]
    if th is not None:
        down = np.array([0.0, np.cos(th), -np.sin(th)])
        assert v @ down / 0.5 == pytest.approx(5 / 7 * G * np.sin(th), rel=1e-2)
    m = mujoco.MjModel.from_xml_path(str(source_arg)) if source == "png" else mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(500):
        mujoco.mj_step(m, d)
    # The same way down, at a speed within MuJoCo's soft-contact difference.
    assert v[1] > 0.3 and d.qvel[1] > 0.3
    assert v[1] == pytest.approx(d.qvel[1], rel=0.15)


def test_mjcf_hfield_problems_are_refused_naming_them(tmp_path):
    from lcpsim.mjcf import MjcfError

    with pytest.raises(MjcfError, match="missing.png"):
        World.from_mjcf(_ball_on_ramp('<hfield name="ramp" file="missing.png" size="2 3 1.0 0.1"/>'))
    moving = ('<mujoco><asset>' + ELEVATION + '</asset><worldbody><body name="b"><freejoint/>'
              '<geom name="rug" type="hfield" hfield="ramp"/></body></worldbody></mujoco>')
    with pytest.raises(MjcfError, match="geom 'rug' is an hfield on a moving body"):
        World.from_mjcf(moving)
