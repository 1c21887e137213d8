"""Measured stability limits against those predicted from the AD Jacobian's eigenvalues
(``heli bench stability`` on small models; the full table is the benchmark)."""
import json
import math

import pytest

from mbs.bench import stability as st
from mbs.models.demo import spinning_rotor
from mbs.models.stability_cases import stiff_damper_rotor
from mbs.solvers import Problem

OMEGA = 44.4
REV = 2 * math.pi / OMEGA


@pytest.fixture(scope="module")
def rotor():
    """Conservative 2-blade rotor on a free hub (hub on the ground), blades at rest in the
    rotating frame: its fastest mode (blades lagging against the hub, 102 rad/s) starts quiet."""
    m = spinning_rotor(n_blades=2, free_fuselage=False, omega=OMEGA)
    m.set_initial(**{"blade1.flap": 0.0, "blade2.flap": 0.0, "blade2.lag": 0.0})
    problem = Problem(m, "vm")
    return problem, st.predict(problem, 20 * REV)


def test_predicted_rk4_limit_is_the_imaginary_axis_bound_of_the_fastest_mode(rotor):
    _, pred = rotor
    lim = pred.limits["rk4"]
    assert abs(lim.eigenvalue.imag) > 100 and abs(lim.eigenvalue.real) < 1e-3 * abs(lim.eigenvalue)
    assert lim.h == pytest.approx(2 * math.sqrt(2) / abs(lim.eigenvalue), rel=1e-9)
    assert pred.limits["euler"].h == 0 and pred.limits["midpoint"].h == math.inf


@pytest.mark.parametrize("method", ["rk4", "rk8"])
def test_explicit_measured_limit_within_10_percent_of_predicted(rotor, method):
    problem, pred = rotor
    h_pred = pred.limits[method].h
    h_meas, probes = st.measure_explicit(problem, method, h_pred, 20 * REV, pred.judge)
    assert 0.9 <= h_meas / h_pred <= 1.1, (h_meas, h_pred)
    assert all(p.stable for p in probes if p.h <= 0.95 * h_pred)
    assert not any(p.stable for p in probes if p.h >= 1.05 * h_pred)


@pytest.mark.parametrize("reach", [0.4, 0.2])
def test_explicit_euler_grows_the_fastest_mode_by_one_plus_h_omega_squared_per_step(rotor, reach):
    """No stable step on the imaginary axis: the measured energy factor per step of the
    fastest mode is 1 + (hω)² (a factor 1 would be neutral stability)."""
    problem, pred = rotor
    g = st.euler_growth(problem, pred.judge.x0, reach / abs(pred.lam_max), pred.lam_max)
    assert g["predicted_energy_factor"] == pytest.approx(1 + reach**2, rel=1e-4)
    assert g["measured_energy_factor"] > 1
    assert abs(g["ratio"] - 1) < 0.05, g


def test_implicit_midpoint_stays_bounded_at_ten_times_the_rk4_limit(rotor):
    problem, pred = rotor
    h_meas, probes = st.measure_implicit(problem, "midpoint", pred.limits["rk4"].h, 20 * REV, pred.judge)
    by_multiple = {round(p.h / pred.limits["rk4"].h): p for p in probes}
    assert by_multiple[10].stable and by_multiple[10].status == "success"
    assert 0 <= by_multiple[10].growth < st.ENERGY_RISE
    assert h_meas is None  # no instability: only the Newton iteration may give up


def test_energy_judge_separates_bounded_error_from_growth(rotor):
    problem, pred = rotor
    h = pred.limits["rk4"].h
    assert st.probe(problem, "rk4", 0.9 * h, 20 * REV, pred.judge).stable
    beyond = st.probe(problem, "rk4", 1.1 * h, 20 * REV, pred.judge)
    assert not beyond.stable and beyond.growth > 1e3 * st.ENERGY_RISE


@pytest.fixture(scope="module")
def damper():
    problem = Problem(stiff_damper_rotor(10.0), "compiled")
    return problem, st.predict(problem, 0.5 * REV)


def test_stiff_damper_sets_a_real_axis_limit_that_rk4_obeys_and_midpoint_ignores(damper):
    problem, pred = damper
    lim = pred.limits["rk4"]
    assert lim.eigenvalue.real < -1e4 and abs(lim.eigenvalue.imag) < 1e-6 * abs(lim.eigenvalue)
    assert lim.reach == pytest.approx(2.785293563405282, rel=1e-9)
    h_meas, _ = st.measure_explicit(problem, "rk4", lim.h, 0.5 * REV, pred.judge)
    assert 0.9 <= h_meas / lim.h <= 1.1
    far = st.probe(problem, "midpoint", 20 * lim.h, 0.5 * REV, pred.judge)
    assert far.stable and far.status == "success" and far.growth <= 0  # energy only decays


def test_tumbling_quaternion_keeps_energy_at_rk4_order_through_90_deg_pitch():
    """Pitching over the vertical: the energy error falls at least like h^4 (RK4) between
    h and h/2 and h/4, the attitude follows the finer run to 1e-6 rad, while RK4 on Euler
    angles (same body, same step) is off by more than 0.01 rad near the singularity."""
    r = st.tumbling(h=0.02, span=10.0, backend="vm")
    assert r["nose_from_vertical_min_deg"] < 0.5 and r["pitch_max_deg"] > 89 and r["pitch_min_deg"] < -89
    assert 3.7 <= r["energy_order"] <= 5.5 and 3.7 <= r["energy_order_half"] <= 5.5, r
    assert r["energy_error"]["1"] < 1e-6
    assert r["quaternion_attitude_error_rad"] < 1e-6
    assert r["euler_angle_attitude_error_rad"] > 1e4 * r["quaternion_attitude_error_rad"]


def test_euler_angle_kinematics_agree_with_quaternion_away_from_the_singularity():
    """The comparison is fair: a body that stays far from ±90° pitch gives the same attitude."""
    r = st.tumbling(h=0.02, span=2.0, backend="vm", rates=(2.0, 0.0, 0.1))
    assert abs(r["pitch_max_deg"]) < 30
    assert r["euler_angle_attitude_error_rad"] < 1e-6


def test_unknown_case_and_bad_damper_factor_are_named():
    with pytest.raises(ValueError, match="warp"):
        st.run("structural", cases=("warp",))
    with pytest.raises(ValueError, match="-1"):
        stiff_damper_rotor(-1.0)


def test_cli_prints_the_table_and_one_json_object(capsys):
    from mbs.cli import main

    assert main(["bench", "stability", "--scene", "demo-rotor", "--revs", "5", "--case", "none", "--json"]) == 0
    captured = capsys.readouterr()
    res, out = json.loads(captured.out), captured.err.splitlines()  # --json: the table on stderr
    rk4 = res["table"]["methods"]["rk4"]
    assert 0.9 <= rk4["ratio"] <= 1.1 and res["cases"] == {}
    assert any(line.lstrip().startswith("rk4") and f"{rk4['ratio']:.3f}" in line for line in out)
