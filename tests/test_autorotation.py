"""Autorotation: the rotor speed a state, no engine torque; the steady autorotation as a periodic
trim with the descent rate solved for (:mod:`mbs.analysis.rotor_speed_trim`), and the engine
failure scenes."""
from __future__ import annotations

import numpy as np
import pytest

from mbs import scenes
from mbs.analysis.rotor_speed_trim import descent_estimate, rotor_speed_trim
from mbs.analysis.trim import evaluators

SPEEDS = (20.0, 30.0, 40.0)


@pytest.fixture(scope="module")
def autorotation():
    sc = scenes.get("autorotation")
    system, stepper = evaluators(sc)
    return sc, system, stepper, {v: rotor_speed_trim(sc, v, system=system, stepper=stepper) for v in SPEEDS}


@pytest.mark.parametrize("speed", SPEEDS)
def test_steady_autorotation_trims_in_at_most_8_iterations_with_the_torque_balanced(autorotation, speed):
    """The rotor at its nominal speed, no drive torque: Newton from the level-flight estimate
    converges to 1e-10 in at most 8 iterations; the drive train's angular momentum returns after
    the period (its mean torque, all forces on the drive train, zero to 1e-10 of the hover torque);
    the aerodynamic torque alone averages within 1e-4 of the hover torque (the rest: the blades'
    weight about the tilted shaft and their pitch motion's inertia)."""
    sc, _, _, trims = autorotation
    res = trims[speed]
    assert res.converged, res.reason
    assert res.iterations <= 8
    assert abs(res.torque_balance) < 1e-10
    hover_torque = 8000.0  # N m, the Bo105 model's hover torque
    assert abs(res.mean_torque) < 1e-4 * hover_torque
    assert res.climb_rate < 0


@pytest.mark.parametrize("speed", SPEEDS)
def test_autorotation_descent_rate_against_the_energy_method(autorotation, speed):
    """Momentum theory's energy balance: in a steady autorotation the descent supplies the power of
    level flight at the same speed, ``V_d ≈ P_level / W`` (Gessow & Myers, Aerodynamics of the
    Helicopter, ch. 7; the closed-form level power of :func:`mbs.models.helicopter.estimate_trim`):
    within 10 %, the model descending a little faster (its induced and profile power are larger in
    the autorotating flow)."""
    sc, _, _, trims = autorotation
    estimate = descent_estimate(sc, speed)
    assert trims[speed].climb_rate == pytest.approx(estimate, rel=0.10)
    assert trims[speed].climb_rate < estimate  # faster down


def test_the_descent_rate_has_its_minimum_between_the_slow_and_the_fast_speed(autorotation):
    """The power curve's bucket: slowest descent at the middle speed (30 m/s, 58 kt)."""
    trims = autorotation[3]
    sink = {v: -t.climb_rate for v, t in trims.items()}
    assert sink[30.0] < sink[20.0] and sink[30.0] < sink[40.0]


def test_the_trimmed_autorotation_runs_periodic_in_the_simulation(autorotation):
    sc, system, _, trims = autorotation
    res = trims[30.0]
    h = 2 * np.pi / res.omega / 100
    traj = system.run(res.x0, 0.0, h, 800, every=200, p=res.params)  # the period is 2 revolutions
    speed = traj.column("main_hub.azimuth_rate")
    assert np.abs(speed - speed[0]).max() < 1e-8 * res.omega
    assert np.abs(speed[0] - res.omega) < 1e-3 * res.omega


def test_the_constant_speed_trim_points_a_free_rotor_scene_to_the_rotor_speed_trim():
    from mbs.analysis.trim import trim

    with pytest.raises(ValueError, match="at a speed that is a state"):
        trim("autorotation")


def test_engine_failure_in_hover_with_the_collective_lowered_the_rotor_recovers():
    """Both engines fail at 1 s in hover; the pilot lowers the collective to 0.15 rad from 1.5 s to
    2 s: the rotor speed falls to a minimum and recovers, the aircraft sinks; the run reports the
    minimum, the time to it and the sink rate (run.json's ``rotor_speed``)."""
    from mbs.inputs import InputTable
    from mbs.simulate import simulate

    sc = scenes.get("engine-failure")
    hover = sc.model().parameters["collective"].default
    table = InputTable(np.array([0.0, 1.5, 2.0]), ["collective"], np.array([[hover], [hover], [0.15]]))
    sim = simulate(sc, revs=60, inputs=table)
    figures = sim.summary()["rotor_speed"]
    print(figures)
    assert 0.3 < figures["time_to_min_rotor_speed"] < 6.0
    assert 0.6 * 44.4 < figures["rotor_speed_min"] < 0.95 * 44.4
    assert sim.columns()["main_rotor.speed"][-1] > figures["rotor_speed_min"] + 1.0  # recovering
    assert figures["sink_rate_end"] > 3.0 and figures["height_lost"] > 5.0
    columns = sim.columns()
    after = np.asarray(columns["time"]) >= 1.0  # both engines failed: no rating left, no margin shown
    for k in (1, 2):
        assert np.all(np.asarray(columns[f"engine{k}.takeoff_margin"])[after] == 0.0)


def test_the_pilot_line_says_when_the_rotor_speed_is_still_falling_at_the_end():
    """A new user's R22 run ended 2 s after the failure with the rotor still slowing, and the
    summary called its last value the lowest."""
    from mbs.drivetrain.report import pilot_figures, pilot_line

    t = np.linspace(0.0, 3.0, 31)
    falling = pilot_figures({"time": t, "main_rotor.speed": 44.4 - 2.0 * np.maximum(t - 1.0, 0.0)}, 1.0)
    assert pilot_line(falling).startswith("rotor speed: still falling at the end of the run, 91.0 % of 44.4 rad/s "
                                          "2.00 s after the failure and falling at 2 rad/s^2")
    turned = pilot_figures({"time": t, "main_rotor.speed": 40.0 + (t - 2.0) ** 2}, None)
    assert pilot_line(turned) == "rotor speed: lowest 90.9 % of 44.0 rad/s, 2.00 s after the start"


def test_autorotation_takes_a_gear_ratio_that_does_not_repeat_as_trim_does(tmp_path, capsys):
    """A new user's R22 (tail-rotor gear ratio 6.409) trimmed, but 'heli autorotation' refused the
    same file after compiling, naming an internal function: it now turns the tail rotor at the
    nearest ratio that repeats, as the trims do, and says so; its speeds take a unit as trim's."""
    import json

    from mbs import aircraft, cli

    text = aircraft.resolve("bo105").read_text().replace('gear_ratio = { value = 5.25,', 'gear_ratio = { value = 5.2513,')
    path = tmp_path / "odd_gear.toml"
    path.write_text(text)
    assert cli.main(["autorotation", "--aircraft", str(path), "--speeds", "60kt", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "5.2513 repeats the rotors only every" in out["approximation"], out["approximation"]
    trim, = out["trims"]
    assert trim["converged"] and trim["speed"] == pytest.approx(60 * 1852 / 3600)


@pytest.mark.parametrize("text, want", [("20,30", [20.0, 30.0]), ("50kt, 70kt", [50 * 1852 / 3600, 70 * 1852 / 3600]),
                                        ("100km/h", [100 / 3.6])])
def test_autorotation_speeds_carry_a_unit(text, want):
    from mbs.drivetrain.commands import speed_list

    assert speed_list(text) == pytest.approx(want)
    with pytest.raises(ValueError, match="outside the speeds of a steady autorotation"):
        speed_list("200kt")


def test_an_engine_failure_starts_from_its_governed_trim(tmp_path, capsys):
    """A new user's one-engine failure began with a start-up transient (rotor speed -2.8 %, 23
    deg/s of yaw before the failure) and '--start trim' refused with the wrong reason. A scene
    whose engines govern its rotor speed starts from its trim with the governor's reference
    solved for: until the failure at 1 s the rotor turns at its nominal speed to 1e-9 and the
    aircraft does not yaw; a rotor speed that no engine governs names heli autorotation."""
    import json

    from mbs.cli import main

    out = tmp_path / "ef"
    assert main(["simulate", "engine-failure", "--revs", "8", "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "trimming it now" in err or "starting from the periodic trim" in err, err
    run = json.loads((out / "run.json").read_text())
    assert run["initial_state"]["from"] == "periodic trim"
    import csv

    rows = [r for r in csv.DictReader(open(out / "results.csv")) if float(r["time"]) < 1.0]
    speed = np.array([float(r["main_rotor.speed"]) for r in rows])
    assert np.abs(speed - 44.4).max() < 1e-9 * 44.4
    assert max(abs(float(r["fuselage.r"])) for r in rows) < 1e-6
    assert main(["simulate", "autorotation", "--revs", "1", "--start", "trim", "--out", str(tmp_path / "a")]) == 2
    assert "without an engine governing it" in capsys.readouterr().err


def test_autorotation_at_a_rotor_speed_of_its_own():
    """An R22 flight manual gives its glide at 90 % rotor speed; heli autorotation held only the
    nominal one. --rotor-speed takes rad/s, rpm or a percentage, within the rotor's range."""
    from mbs.drivetrain.commands import rotor_speed

    mr = {"omega": 44.4, "omega_min": 22.2, "omega_max": 53.3}
    assert rotor_speed(None, mr) is None
    assert rotor_speed("90%", mr) == pytest.approx(39.96)
    assert rotor_speed("400rpm", mr) == pytest.approx(400 * np.pi / 30)
    assert rotor_speed("40", mr) == 40.0
    with pytest.raises(ValueError, match="outside the rotor's omega_min..omega_max"):
        rotor_speed("10%", mr)
    with pytest.raises(ValueError, match="give rad/s, rpm"):
        rotor_speed("fast", mr)


def test_a_slower_rotor_autorotates_as_the_trim_at_that_speed(autorotation):
    """At 95 % rotor speed the autorotation's torque balances there: the descent differs from the
    nominal speed's, the trim converges."""
    sc, system, stepper, trims = autorotation
    slow = rotor_speed_trim(sc, 30.0, system=system, stepper=stepper, omega=0.95 * 44.4)
    assert slow.converged and abs(slow.torque_balance) < 1e-10
    assert slow.climb_rate != pytest.approx(trims[30.0].climb_rate, abs=1e-3)
