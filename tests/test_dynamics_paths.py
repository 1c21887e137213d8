"""The two forward-dynamics paths (composite: Mt by subtree sums and LDL; articulated: the
articulated-body recursion) give the same accelerations; the builder takes the cheaper one."""
import numpy as np
import pytest

import mbs
from mbs.bench.scaling import chain
from mbs.dynamics import PATHS, symbolic
from mbs.models.demo import driven_rotor
from trees import random_chain, random_state, random_tree


def _both(model):
    return [mbs.build(model, "vm", path=p) for p in PATHS]


def _max_rel_diff(model, seed: int, states: int = 3) -> float:
    comp, art = _both(model)
    worst = 0.0
    for k in range(states):
        x = random_state(comp, 10 * seed + k)
        a, b = comp.rhs(x, 0.3), art.rhs(x, 0.3)
        worst = max(worst, np.abs(a - b).max() / np.abs(a).max())
    return worst


@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [4, 5, 6])
def test_paths_agree_on_random_trees(seed, free_base):
    assert _max_rel_diff(random_tree(seed, n_bodies=14, free_base=free_base), seed) <= 1e-12


@pytest.mark.parametrize("free_base", [False, True])
def test_paths_agree_on_a_60_link_chain(free_base):
    assert _max_rel_diff(random_chain(7, 60, free_base), 7, states=2) <= 1e-12


def test_paths_agree_with_driven_joints_and_springs():
    """Bodies without rates (the driven hub) pass their whole inertia to their parent."""
    model = driven_rotor()
    assert any(not b.joint.nv for b in model.bodies.values()) and model.forces
    assert _max_rel_diff(model, 8) <= 1e-12


def test_builder_takes_the_path_with_fewer_operations():
    deep, shallow = symbolic(chain(40)), symbolic(random_tree(2, n_bodies=12, free_base=False))
    for sym in (deep, shallow):
        assert sym.path == min(sym.operations, key=sym.operations.get)
    assert deep.path == "articulated" and deep.operations["composite"] > 2 * deep.operations["articulated"]
    assert shallow.path == "composite"
    system = mbs.build(chain(3), "vm", path="composite")
    assert system.info.extra["dynamics"] == "composite" and system.info.extra["operations"]["articulated"] > 0


def test_articulated_operations_grow_linearly_on_chains():
    ops = {n: symbolic(chain(n), "articulated").operations["articulated"] for n in (10, 20, 40)}
    per_link = [(ops[b] - ops[a]) / (b - a) for a, b in ((10, 20), (20, 40))]
    assert abs(per_link[1] / per_link[0] - 1) < 0.02
    composite = [symbolic(chain(n)).operations["composite"] for n in (20, 40)]
    assert composite[1] / composite[0] > 3  # subtree sums O(n²), LDL of the dense Mt O(n³)


def test_unknown_path_is_refused():
    with pytest.raises(ValueError, match="unknown dynamics path 'crba'; choose one of composite, articulated"):
        mbs.build(chain(2), "vm", path="crba")


def test_100_link_chain_builds_and_runs_compiled():
    """The deep chain compiles in a few translation units at -O1 where large (cached after the
    first build) and equals the virtual machine; a short run keeps its energy."""
    model = chain(100)
    compiled, vm = mbs.build(model, "compiled"), mbs.build(model, "vm")
    assert compiled.info.extra["dynamics"] == "articulated"
    x = random_state(vm, 1, scale=0.3)
    assert np.abs(compiled.rhs(x) - vm.rhs(x)).max() <= 1e-12 * np.abs(vm.rhs(x)).max()
    traj = compiled.run(x, 0.0, 2e-4, 500, every=100)
    e = np.array([vm.energy(xi)[-1] for xi in traj.x])
    assert traj.ok and np.abs(e - e[0]).max() <= 1e-6 * np.abs(vm.energy(x)[:3]).max()
