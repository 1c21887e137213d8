"""Floquet analysis at the periodic solution: the single blade's exponents against the closed
forms, and the Bo105 in hover (neutral heading, rotor modes named and placed, in the rotating
and the fixed frame; the chart and table of ``heli floquet --out``)."""
import csv
import json

import numpy as np
import pytest

import mbs
from mbs import scenes
from mbs.analysis import flap_lag_frequencies
from mbs.analysis.floquet import analyse, floquet
from mbs.analysis.monodromy import TangentStepper
from mbs.analysis.trim import periodic_solution
from mbs.cli import main
from mbs import aircraft


def _closed_form(system):
    b, mr = system.info.bodies[system.info.body_names.index("blade1")], aircraft.load().data["main_rotor"]
    return flap_lag_frequencies(b["mass"], b["com"], b["inertia"], mr["flap_hinge_offset"], mr["flap_stiffness"],
                                mr["lag_stiffness"], mr["omega"])


def _single_blade_modes(gravity: bool):
    sc = scenes.get("single-blade")
    model = sc.model()
    if not gravity:
        model.gravity = np.zeros(3)
    system, stepper = mbs.build(model, "compiled"), TangentStepper(model, "rk4")
    sol = periodic_solution(sc, steps_per_rev=200, system=system, stepper=stepper)
    return {m.name: m for m in analyse(sol, system, stepper).modes}, _closed_form(system)


def test_single_blade_exponents_equal_the_closed_forms():
    """Without gravity the periodic solution is the undeflected blade, about which the closed
    forms linearise: frequencies to 1e-6 (measured 1e-8, 2e-9), no damping (RK4 at 200 steps
    per revolution: |Re λ| < 1e-7 |λ|). With gravity the blade droops by 1.2 mrad and the
    frequencies move by 3e-6."""
    modes, (nu_flap, nu_lag) = _single_blade_modes(gravity=False)
    assert set(modes) == {"flap", "lag"}
    assert modes["flap"].per_rev == pytest.approx(nu_flap, rel=1e-6)
    assert modes["lag"].per_rev == pytest.approx(nu_lag, rel=1e-6)
    for m in modes.values():
        assert abs(m.exponent.real) < 1e-7 * abs(m.exponent) and abs(abs(m.multiplier) - 1) < 1e-6
    drooped, _ = _single_blade_modes(gravity=True)
    assert drooped["flap"].per_rev == pytest.approx(nu_flap, rel=1e-5)
    assert drooped["lag"].per_rev == pytest.approx(nu_lag, rel=1e-5)


def test_hover_modes(capsys):
    """Hover trim: the heading mode is neutral, the lag modes sit near the blade's 0.68/rev
    with the damper's few per cent (the cyclic and collective ones raised to 0.78-0.89/rev by
    the airframe's roll, pitch and yaw, light as the whole aircraft's inertia less the rotors'), the flap modes near 1/rev are well damped (Lock number 5;
    one more flap mode, the regressing one in the fixed frame, couples with the body's pitch and
    roll and is damped less), the teeter near the tail rotor's 1/rev (5.25/rev of the main rotor)."""
    assert main(["floquet", "hover", "--frame", "rotating", "--json"]) == 0
    res = json.loads(capsys.readouterr().out)  # stdout is the JSON object alone
    modes = res["modes"]
    assert res["frame"] == "rotating" and "files" not in res
    assert min(abs(np.hypot(*m["multiplier"]) - 1) for m in modes) < 1e-9  # heading
    lag = [m for m in modes if m["name"] == "lag"]
    flap = [m for m in modes if m["name"] == "flap" and 0.95 < m["per_rev"] < 1.1]
    teeter = [m for m in modes if m["name"] == "tail rotor" and m["per_rev"] > 1]
    assert len(lag) == 4 and all(0.6 < m["per_rev"] < 0.95 and 0.02 < m["damping_ratio"] < 0.1 for m in lag)
    assert min(m["per_rev"] for m in lag) == pytest.approx(0.68, abs=0.01)  # the blade's own, uncoupled
    assert len(flap) >= 3 and all(m["damping_ratio"] > 0.2 for m in flap)
    assert len(teeter) == 1 and teeter[0]["per_rev"] == pytest.approx(5.25, rel=0.02)
    assert res["period_revs"] == 4 and res["interval_revs"] == 2


def test_floquet_rejects_scenes_without_a_periodic_solution():
    with pytest.raises(ValueError, match="no periodic solution"):
        floquet("structural")


def test_hover_chart_and_table_in_the_fixed_frame(tmp_path, capsys):
    """``heli floquet hover --out DIR`` (fixed frame by default) writes ``floquet_hover.png``
    and ``floquet_hover.csv``, whose rows are the JSON output's modes; in the fixed frame the
    lag modes split into regressing (near 1 - 0.68/rev), advancing (1 + its rotating-frame
    frequency, raised to 0.89/rev by the airframe's roll and pitch), collective and differential
    (near 0.68/rev, the collective raised by the yaw), and the multipliers do not change."""
    assert main(["floquet", "hover", "--out", str(tmp_path), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)  # stdout is the JSON object alone
    assert res["frame"] == "fixed (multi-blade)"
    png, table = tmp_path / "floquet_hover.png", tmp_path / "floquet_hover.csv"
    assert res["files"] == [str(table), str(png)]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(res["modes"])
    for row, m in zip(rows, res["modes"]):
        assert row["mode"] == m["name"]
        assert [float(row[k]) if row[k] else None for k in ("real_per_s", "imag_rad_s", "frequency_hz", "per_rev",
                                                            "damping_ratio")] \
            == [*m["exponent"], m["frequency_hz"], m["per_rev"], m["damping_ratio"]]
        assert float(row["multiplier_modulus"]) == pytest.approx(np.hypot(*m["multiplier"]), rel=1e-15)
    lag = {m["name"]: m["per_rev"] for m in res["modes"] if m["name"].endswith(" lag")}
    assert set(lag) == {"regressing lag", "advancing lag", "collective lag", "differential lag"}
    assert lag["regressing lag"] == pytest.approx(1 - lag["differential lag"], abs=0.05)
    assert 1 + lag["differential lag"] - 0.05 < lag["advancing lag"] < 1.95


def test_rk8_tableau_equals_scipys_dop853():
    """The rk8 coefficients are kept as data (no SciPy import for the integrators); they are
    SciPy's DOP853 numbers exactly."""
    from scipy.integrate._ivp import dop853_coefficients as dp

    from mbs.integrators import RK8

    s = dp.N_STAGES
    assert RK8.a == tuple(tuple(float(v) for v in row[:s]) for row in dp.A[:s])
    assert RK8.b == tuple(float(v) for v in dp.B) and RK8.c == tuple(float(v) for v in dp.C[:s])
