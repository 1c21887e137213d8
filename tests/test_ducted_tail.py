"""A fan-in-fin tail rotor (Fenestron, fantail): ``tail_rotor.duct_exit_ratio`` σ_d makes the tail
rotor a ducted fan, whose inflow follows the ideal axial momentum theory of a shrouded rotor and
whose duct carries the rest of the thrust (Pereira, PhD thesis, Maryland 2008, ch. 2; Jardin et
al., AIAA 2015). Checked against that theory's closed forms, alone and in the Bo105's hover and
forward-flight trims with its tail rotor given a duct; no Fenestron measurement was found to
compare with."""
import json

import casadi as ca
import numpy as np
import pytest

from mbs.aero import inflow as inf
from mbs.cli import main

RHO, RADIUS = 1.225, 0.35
AREA = np.pi * RADIUS**2


@pytest.mark.parametrize("ratio", [0.5, 0.8, 1.0, 1.3, 2.0])
def test_hover_shares_the_thrust_and_needs_the_closed_form_power(ratio):
    """At the hover equilibrium of ``ducted_rate`` for the fan's thrust T/(2 σ_d): the duct carries
    (2 σ_d − 1) of the fan's thrust and the fan's ideal power T_fan v is T^1.5 / sqrt(4 σ_d ρ A),
    to 1e-12; at σ_d = ½ the rate is the open rotor's (``uniform_rate``) at every inflow."""
    total = 1500.0
    fan_thrust = total / (2 * ratio)
    v = ratio * np.sqrt(2 * fan_thrust / (RHO * AREA))
    assert abs(float(inf.ducted_rate(v, fan_thrust, 0.0, RHO, RADIUS, ratio))) < 1e-9
    fan, duct = (float(x) for x in inf.ducted_fan_thrust(v, 0.0, RHO, RADIUS, ratio))
    assert fan == pytest.approx(fan_thrust, rel=1e-12)
    assert duct == pytest.approx((2 * ratio - 1) * fan_thrust, rel=1e-12, abs=1e-9)
    assert fan * v == pytest.approx(total**1.5 / np.sqrt(4 * ratio * RHO * AREA), rel=1e-12)
    if ratio == 0.5:
        for v0 in (1.0, 7.5, 20.0):
            open_rate = float(inf.uniform_rate(v0, 900.0, 0.0, 0.0, RHO, RADIUS))
            assert float(inf.ducted_rate(v0, 900.0, 0.0, RHO, RADIUS, 0.5)) == pytest.approx(open_rate, rel=1e-12)


def test_an_unloaded_duct_in_axial_flow_makes_no_thrust_and_the_in_plane_flow_does_not_enter():
    """With the hub moving along its axis at V, the unloaded fan's induced velocity is (σ_d − 1) V
    (the duct sets the flow through it): fan and duct thrust are zero there. The in-plane speed
    is not an argument: a ducted fan has no translational lift in this model."""
    for ratio, speed in ((1.2, 5.0), (0.8, -3.0), (1.0, 10.0)):
        fan, duct = (float(x) for x in inf.ducted_fan_thrust((ratio - 1) * speed, speed, RHO, RADIUS, ratio))
        assert abs(fan) < 1e-9 and abs(duct) < 1e-9


def test_the_ad_derivatives_of_the_ducted_inflow_equal_central_differences():
    """d(rate)/d(v, T, V_normal) by CasADi's AD against central differences (step 1e-5), 1e-7."""
    v, t, vn = ca.SX.sym("v"), ca.SX.sym("t"), ca.SX.sym("vn")
    rate = inf.ducted_rate(v, t, vn, RHO, RADIUS, 1.1)
    f = ca.Function("f", [ca.vertcat(v, t, vn)], [rate, ca.jacobian(rate, ca.vertcat(v, t, vn))])
    x = np.array([14.0, 700.0, 1.5])
    jac = np.array(f(x)[1]).ravel()
    for k in range(3):
        step = np.zeros(3)
        step[k] = 1e-5 * max(1.0, abs(x[k]))
        diff = (float(f(x + step)[0]) - float(f(x - step)[0])) / (2 * step[k])
        assert jac[k] == pytest.approx(diff, rel=1e-7, abs=1e-9)


def test_a_ducted_fan_takes_uniform_inflow_only():
    from mbs.aero import RotorModel

    with pytest.raises(ValueError, match="duct exit ratio 0.3 outside"):
        RotorModel(duct_exit_ratio=0.3)
    with pytest.raises(ValueError, match="a ducted fan takes uniform inflow"):
        RotorModel(inflow="pitt-peters", duct_exit_ratio=1.0)


def _bo105_duct(tmp_path, ratio: float) -> str:
    from mbs import aircraft

    head, sep, rest = aircraft.resolve("bo105").read_text().partition("[tail_rotor]\n")
    path = tmp_path / f"bo105_duct_{ratio}.toml"
    path.write_text(head + sep + f'duct_exit_ratio = {{ value = {ratio}, unit = "-", source = "EST" }}\n' + rest)
    return str(path)


def test_the_check_refuses_a_duct_below_half_and_lists_the_ducts_thrust(tmp_path):
    from mbs import aircraft

    report = aircraft.check(_bo105_duct(tmp_path, 0.3))
    assert any("tail_rotor.duct_exit_ratio: 0.3 below 0.5" in p for p in report.problems), report.problems
    report = aircraft.check(_bo105_duct(tmp_path, 1.0))
    assert report.ok, report.problems
    rows = {name: value for name, value, _ in report.figures}
    fan = rows["hover tail-rotor thrust, the fan's blades"]  # the duct carries as much at sigma_d = 1
    assert rows["hover tail-rotor duct thrust"] == pytest.approx(fan, rel=1e-12)
    assert rows["hover tail-rotor thrust, fan and duct together"] == pytest.approx(2 * fan, rel=1e-12)
    plain = {n: v for n, v, _ in aircraft.check("bo105").figures}  # a new user's Gazelle read the fan's as the whole
    assert "hover tail-rotor duct thrust" not in plain and plain["hover tail-rotor thrust"] == pytest.approx(
        rows["hover tail-rotor thrust, fan and duct together"], rel=1e-9)


def _trim(capsys, scene: str, speed: float, path: str | None = None) -> dict:
    args = ["trim", scene, "--speed", str(speed), "--json", "--quiet"] + (["--aircraft", path] if path else [])
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def test_the_bo105_hovers_with_a_ducted_tail_rotor_as_momentum_theory_says(tmp_path, capsys):
    """The Bo105 with its tail rotor in a duct of σ_d = 1, in its hover trim (period means):
    duct thrust = (2 σ_d − 1) fan thrust to 1e-6 (measured 2e-9); the inflow state the closed form
    σ_d sqrt(2 T_fan / (ρ B² A)) to 1e-6 (1e-9); the anti-torque thrust, fan plus duct, the open
    tail rotor's to 1e-4 (3e-6: the same main-rotor torque); the tail rotor's power over the open
    one's the closed forms' (``mbs.aircraft.performance``) to 2 % (measured 0.7577 against
    0.7558). At 30 m/s the trim converges, the duct still carries its hover share (axial flow)."""
    from mbs import aircraft
    from mbs.aircraft import performance

    path = _bo105_duct(tmp_path, 1.0)
    ducted, plain = _trim(capsys, "hover", 0.0, path)["outputs"], _trim(capsys, "hover", 0.0)["outputs"]
    d = aircraft.load(path).data
    tr, rho = d["tail_rotor"], d["environment"]["rho"]
    tip = tr["gear_ratio"] * d["main_rotor"]["omega"] * tr["radius"]
    fan = ducted["tail_rotor.thrust"]
    assert ducted["tail_rotor.duct_thrust"] == pytest.approx(fan, rel=1e-6)
    closed = np.sqrt(2 * fan / (rho * tr["tip_loss"] ** 2 * np.pi * tr["radius"] ** 2))
    assert ducted["tail_rotor.inflow_ratio"] * tip == pytest.approx(closed, rel=1e-6)
    assert fan + ducted["tail_rotor.duct_thrust"] == pytest.approx(plain["tail_rotor.thrust"], rel=1e-4)
    ratio = performance.hover(d).tail.power / performance.hover(aircraft.load("bo105").data).tail.power
    assert ducted["tail_rotor.power"] / plain["tail_rotor.power"] == pytest.approx(ratio, rel=0.02)
    assert "tail_rotor.duct_thrust" not in plain
    cruise = _trim(capsys, "forward-flight", 30.0, path)
    assert cruise["converged"]
    out = cruise["outputs"]
    assert out["tail_rotor.duct_thrust"] == pytest.approx(out["tail_rotor.thrust"], rel=0.01)


def test_a_duct_in_more_cross_flow_than_flows_through_it_is_warned_of(tmp_path):
    """A new user's Gazelle trimmed at 140 kt with its duct still carrying its hover share (881 N
    against the fan's 897 N) and no word: the duct model is axial. A trim whose flight speed
    exceeds the flow through the fan says so; below it, or with an open rotor, nothing is said."""
    from mbs import aircraft
    from mbs.models.helicopter.airframe_warnings import airframe_warnings

    ducted, open_rotor = aircraft.load(_bo105_duct(tmp_path, 1.0)).data, aircraft.load("bo105").data
    cruise = {"fuselage.u": 72.0, "tail_rotor.inflow": 31.0, "tail_rotor.duct_thrust": 881.0}
    (line,) = [w for w in airframe_warnings(cruise, ducted) if w.startswith("tail rotor: its fan in a duct")]
    assert "meets 72 m/s of cross-flow, more than the 31 m/s through it" in line and "881 N" in line
    assert not [w for w in airframe_warnings({**cruise, "fuselage.u": 25.0}, ducted) if "duct" in w]
    assert not [w for w in airframe_warnings(cruise, open_rotor) if "duct" in w]
