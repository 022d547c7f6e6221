"""The peers' many-body scenes written once as MJCF (``benchmarks/scenes/<scene>.xml``, read by
lcpsim and MuJoCo in ``benchmarks/peers/many_bodies.py``): each file is what
``many_bodies.py --write-scenes`` writes from ``lcpsim.scenes`` now, gives lcpsim the world
``lcpsim.scenes`` builds bit for bit, and gives MuJoCo the same masses, poses and friction."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="MJCF needs MuJoCo (pip install 'lcpsim[mjcf]')")

from lcpsim import World  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks" / "peers"))
import many_scenes  # noqa: E402


def _split(world: World) -> tuple[list[int], list[int]]:
    """The world's dynamic and static boxes, in body order."""
    boxes = [i for i in range(world.body_count) if world.body(i).kind == "box"]
    return [i for i in boxes if not world.body(i).is_static], [i for i in boxes if world.body(i).is_static]


@pytest.mark.parametrize("key", list(many_scenes.SCENE_BY_KEY))
def test_a_scene_file_is_lcpsims_scene_bit_for_bit_and_mujoco_reads_it_alike(key):
    path = many_scenes.mjcf_path(key)
    built, how = many_scenes.SCENE_BY_KEY[key].build()
    desc = many_scenes.describe(built, how)
    assert path.read_text() == many_scenes.scene_mjcf(desc, key), "rewrite it: many_bodies.py --write-scenes"

    w = World.from_mjcf(path)
    assert (w.dt, w.body_count) == (built.dt, built.body_count)
    ours_dyn, ours_static = _split(w)
    theirs_dyn, theirs_static = _split(built)
    assert len(ours_dyn) == len(theirs_dyn) and len(ours_static) == len(theirs_static)
    for i, j in [*zip(ours_dyn, theirs_dyn), *zip(ours_static, theirs_static)]:
        a, b = w.body(i), built.body(j)
        for field in ("position", "orientation", "half_extents", "inertia"):
            assert np.array_equal(getattr(a, field), getattr(b, field)), (key, i, field)
        assert (a.mass, a.mu, a.is_static) == (b.mass, b.mu, b.is_static), (key, i)

    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    assert m.opt.timestep == w.dt and m.nbody == len(ours_dyn) + 1
    np.testing.assert_array_equal(m.opt.gravity, [0, 0, -many_scenes.G])
    for k, i in enumerate(ours_dyn):  # MuJoCo's bodies 1..n are the dynamic boxes in order
        a = w.body(i)
        assert m.body_mass[k + 1] == a.mass
        assert np.array_equal(d.xipos[k + 1], a.position) and np.array_equal(d.xquat[k + 1], a.orientation)
        np.testing.assert_allclose(m.body_inertia[k + 1], np.diag(a.inertia), rtol=1e-15)
    assert set(m.geom_friction[:, 0]) == {a.mu for a in map(w.body, range(w.body_count))} == {many_scenes.MU}
