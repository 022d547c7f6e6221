"""Pours of cubes (``lcpsim.scenes.cube_pour``): contact that changes every
step, every island answered by a named stage of the solve chain."""

import numpy as np
import pytest

import lcpsim
from lcpsim.trajectory import STAGES


def test_a_pour_is_seeded():
    a, b, c = (lcpsim.scenes.cube_pour(12, seed=s) for s in (1, 1, 2))
    assert np.array_equal(a.world.positions, b.world.positions)
    assert np.array_equal(a.world.orientations, b.world.orientations)
    assert not np.array_equal(a.world.positions, c.world.positions)


def test_a_pour_has_uniformly_turned_cubes_and_a_bin():
    s = lcpsim.scenes.cube_pour(40, seed=3)
    q = s.world.orientations[list(s.bodies)]
    # Orientations spread over the sphere of unit quaternions: no axis-aligned start.
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0)
    assert np.abs(q[:, 0]).min() < 0.9
    static = [i for i in range(s.world.body_count) if i not in s.bodies]
    assert len(static) == 5  # the ground and four walls
    bare = lcpsim.scenes.cube_pour(40, seed=3, walls=False)
    assert bare.world.body_count == 41


def test_every_island_of_a_pour_is_answered_by_a_stage_of_the_chain():
    s = lcpsim.scenes.cube_pour(12, seed=1)
    tr = s.world.run(1500)
    stats = tr.lcp_stats()
    assert stats.failures == 0
    assert tr.stage_counts.shape == (1500, len(STAGES))
    assert np.array_equal(tr.stage_counts.sum(axis=1), tr.islands)
    assert set(stats.stages) == set(STAGES)
    assert sum(stats.stages.values()) == int(tr.islands.sum())
    # The cubes land on one another: the body-space stages answer some coupled islands.
    assert stats.stages["previous_basis"] > 0
    assert 0.0 < stats.backstop_fraction < 1.0
    rec = s.world.step()
    assert len(rec.island_stage) == rec.islands
    assert set(rec.island_stage) <= set(STAGES)


def test_stage_counts_survive_a_trajectory_file(tmp_path):
    tr = lcpsim.scenes.cube_pour(6, seed=2).world.run(700)
    back = lcpsim.Trajectory.load(tr.save(tmp_path / "pour.h5"))
    assert np.array_equal(back.stage_counts, tr.stage_counts)


@pytest.mark.parametrize("bad", [dict(n=0), dict(n=5, spacing=1.0), dict(n=5, jitter=0.5), dict(n=5, mu=-1.0)])
def test_a_pour_with_bad_parameters_is_refused(bad):
    with pytest.raises(ValueError):
        lcpsim.scenes.cube_pour(**bad)
