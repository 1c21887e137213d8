"""Accelerations agree with an independent engine (Pinocchio's ABA) on random trees and deep
chains, by both forward-dynamics paths."""
import numpy as np
import pytest

import mbs
from trees import depth, random_chain, random_state, random_tree, spring_forces

pin_ref = pytest.importorskip("mbs.bench.pinocchio_ref")
pytest.importorskip("pinocchio")

PATHS = ("composite", "articulated")


def _agree_with_pinocchio(model, path, seed, states=3, tol=1e-11):
    system = mbs.build(model, "vm", path=path)
    assert system.info.extra["dynamics"] == path
    for k in range(states):
        x = random_state(system, 100 * seed + k)
        ours = system.rhs(x)[system.info.nq:]
        theirs = pin_ref.pinocchio_accelerations(model, x, spring_forces(model, system, x))
        assert np.abs(ours - theirs).max() <= tol * np.abs(theirs).max()


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_accelerations_match_pinocchio(seed, free_base, path):
    model = random_tree(seed, n_bodies=12, free_base=free_base)
    assert len(model.bodies) >= 10 and depth(model) >= 4
    _agree_with_pinocchio(model, path, seed)


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("links", [20, 60])
def test_chains_match_pinocchio(links, free_base, path):
    model = random_chain(links, links, free_base)
    assert depth(model) == links
    _agree_with_pinocchio(model, path, links, states=2)
