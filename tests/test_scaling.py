"""Scaling benchmark pieces: model families, the growth-exponent fit, MuJoCo agreement."""
import csv

import numpy as np
import pytest

import mbs
from mbs import Fixed, Hinge, Model, Serial
from mbs.bench import mujoco_ref as mj_ref
from mbs.bench import scaling
from mbs.dynamics import Layout
from mbs.forces import UserForce
from trees import random_state, random_tree


@pytest.mark.parametrize("n", [1, 7, 100])
def test_chain_has_one_dof_per_link_in_one_branch(n):
    model = scaling.chain(n)
    assert Layout.of(model).nv == n
    assert max(model.depth(b) for b in model.bodies) == n


@pytest.mark.parametrize("blades", [2, 3, 16])
def test_rotor_has_seven_plus_two_dof_per_blade(blades):
    assert Layout.of(scaling.rotor(blades)).nv == 7 + 2 * blades


def test_family_builders_reject_empty_models():
    with pytest.raises(ValueError, match="n = 0"):
        scaling.chain(0)
    with pytest.raises(ValueError, match="n_blades = 0"):
        scaling.rotor(0)


def test_fit_recovers_known_exponent_from_noisy_data():
    rng = np.random.default_rng(3)
    n = np.array([5, 10, 20, 40, 70, 100])
    t = 3.0 * n**2.5 * np.exp(rng.normal(scale=0.02, size=n.size))
    assert scaling.fit_exponent(n, t) == pytest.approx(2.5, abs=0.05)


def test_upper_half_fit_sees_the_asymptotic_exponent():
    n = np.array([5, 10, 20, 40, 70, 100])
    t = 1000.0 * n + n**3  # linear at small sizes, cubic at large ones
    all_k, upper_k = scaling.fit_exponent(n, t), scaling.fit_exponent(*scaling.upper_half(n, t))
    assert upper_k > all_k + 0.3
    assert 2.5 < upper_k < 3.0
    assert list(scaling.upper_half(n, t)[0]) == [40, 70, 100]


@pytest.mark.parametrize("n, t", [([10], [1.0]), ([10, 20], [1.0, 0.0]), ([10, 10], [1.0, 2.0])])
def test_fit_rejects_degenerate_data(n, t):
    with pytest.raises(ValueError, match="need >= 2"):
        scaling.fit_exponent(n, t)


def test_verdict_uses_the_widest_timing_and_the_n_squared_target():
    fit = {"rhs_us": {"all": 1.3, "upper_half": 1.8, "dof_range": [5, 20]},
           "vm_rhs_us": {"all": 1.8, "upper_half": 2.8, "dof_range": [5, 100]}}
    v = scaling.verdict(fit)
    assert (v["measure"], v["met"], v["dof_range"]) == ("vm_rhs_us", False, [5, 100])
    fit["rhs_us"]["dof_range"] = [5, 100]
    assert scaling.verdict(fit)["met"] is True


def test_run_without_compiling_writes_table_csv_and_chart(tmp_path):
    res = scaling.run((2,), (2, 3), max_instructions=0, out=tmp_path, batches=1)
    assert [(r["family"], r["dof"]) for r in res["rows"]] == [("rotor", 11), ("chain", 2), ("chain", 3)]
    assert all(r["rhs_us"] is None and r["vm_rhs_us"] > 0 and r["codegen_s"] > 0 for r in res["rows"])
    assert res["rows"][2]["instructions"] > res["rows"][1]["instructions"]
    assert res["fits"]["rotor"] == {} and "vm_rhs_us" in res["fits"]["chain"] and list(res["target"]) == ["chain"]
    with open(tmp_path / "scaling.csv") as f:
        rows = list(csv.DictReader(f))
    assert [int(r["dof"]) for r in rows] == [11, 2, 3] and rows[0]["rhs_us"] == ""
    assert (tmp_path / "scaling.png").stat().st_size > 10_000
    assert any("growth exponents, chain" in line for line in scaling.table(res))



@pytest.mark.parametrize("free_base", [False, True])
@pytest.mark.parametrize("seed", [4, 5])
def test_mujoco_accelerations_equal_ours(seed, free_base):
    pytest.importorskip("mujoco", reason="MuJoCo not installed (pip install mujoco)")
    model = random_tree(seed, n_bodies=10, free_base=free_base, serial=False)
    system = mbs.build(model, "vm")
    tree = mj_ref.MujocoTree(model)
    for k in range(3):
        x = random_state(system, 10 * seed + k)
        ours, theirs = system.rhs(x)[system.info.nq:], tree.accelerations(x)
        assert np.abs(ours - theirs).max() <= 1e-10 * np.abs(theirs).max()


def test_mjcf_refuses_what_mujoco_cannot_express():
    pytest.importorskip("mujoco", reason="MuJoCo not installed (pip install mujoco)")
    m = Model("offset")
    m.add_body("a", "world", Serial(Hinge((1, 0, 0), name="p"), Fixed(at=(0.1, 0, 0)), Hinge(name="q")), 1.0)
    with pytest.raises(NotImplementedError, match="'a'"):
        mj_ref.to_mjcf(m)
    m = Model("pushed")
    m.add_body("a", "world", Hinge(), 1.0)
    m.add_force(UserForce("push", lambda state, loads: None))
    with pytest.raises(NotImplementedError, match="'push'"):
        mj_ref.to_mjcf(m)


def test_the_bo105_benchmark_tree_runs_in_mujoco_with_our_accelerations():
    """'heli bench speed' stopped at MuJoCo's 'inertia must satisfy A + B >= C' once the Bo105's
    inertias were read whole-aircraft (the airframe left after the rotors breaks the triangle
    inequality): the benchmark tree's fuselage carries the published inertia, and MuJoCo's
    accelerations equal ours."""
    pytest.importorskip("mujoco", reason="MuJoCo not installed (pip install mujoco)")
    from mbs.bench.speed import bo105_tree

    model = bo105_tree()
    system = mbs.build(model, "vm")
    tree = mj_ref.MujocoTree(model)
    x = random_state(system, 3)
    ours, theirs = system.rhs(x)[system.info.nq:], tree.accelerations(x)
    assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
