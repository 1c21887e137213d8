"""Accelerations agree with an independent engine (Pinocchio's ABA) on random trees."""
import numpy as np
import pytest

import mbs
from trees import depth, random_state, random_tree, spring_forces

pin_ref = pytest.importorskip("mbs.bench.pinocchio_ref")
pytest.importorskip("pinocchio")


@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_accelerations_match_pinocchio(seed, free_base):
    model = random_tree(seed, n_bodies=12, free_base=free_base)
    assert len(model.bodies) >= 10 and depth(model) >= 4
    system = mbs.build(model, "vm")
    for k in range(3):
        x = random_state(system, 100 * seed + k)
        ours = system.rhs(x)[system.info.nq:]
        theirs = pin_ref.pinocchio_accelerations(model, x, spring_forces(model, system, x))
        assert np.abs(ours - theirs).max() <= 1e-10 * np.abs(theirs).max()
