"""A converged trim that is still no trim of a helicopter is warned of: the disc tilted from its
shaft beyond what rotors flap in trim, and attitudes beyond what helicopters trim at."""
import json
from types import SimpleNamespace

import numpy as np
import pytest

from mbs.analysis import trim_checks
from mbs.cli import main


def _trim(beta1c_deg: float, beta1s_deg: float = 0.0, pitch_deg: float = 0.0):
    return SimpleNamespace(converged=True, flapping={"beta0": 0.05, "beta1c": np.radians(beta1c_deg),
                                                     "beta1s": np.radians(beta1s_deg)},
                           pitch=np.radians(pitch_deg), roll=0.0, sideslip=0.0)


def test_a_disc_tilted_beyond_ten_degrees_from_the_shaft_is_named():
    """A new user's OH-6A with the template's Bo105 fuselage left unscaled trimmed at 80 kt with
    15.5 deg of flapping and -19.9 deg of pitch, and only a tail-stall warning."""
    (line,) = trim_checks.flapping(_trim(-15.5, 1.0))
    assert line.startswith("main-rotor flapping 15.5 deg (beta1c -15.5, beta1s +1.0 deg) tilts the disc")
    assert trim_checks.flapping(_trim(-7.0, 7.0)) == []  # 9.9 deg
    assert trim_checks.flapping(SimpleNamespace(flapping={})) == []  # a scene without main-rotor flapping


def test_attitudes_beyond_what_helicopters_trim_at_are_named():
    d = {"envelope": {}}
    assert trim_checks.attitude(_trim(0.0, pitch_deg=-19.9), d) == []
    (line,) = trim_checks.attitude(_trim(0.0, pitch_deg=-31.0), d)
    assert line.startswith("pitch -31.00 deg is outside what a helicopter trims at (-30.0 to +30.0 deg)")


def test_the_shipped_bo105_trims_without_a_flapping_warning(capsys):
    """Its disc tilts 1-3 deg from the shaft at 0-150 kn; at 70 m/s no flapping line."""
    assert main(["trim", "forward-flight", "--speed", "70", "--json", "--quiet"]) == 0
    res = json.loads(capsys.readouterr().out)
    tilt = np.degrees(np.hypot(res["flapping"]["beta1c"], res["flapping"]["beta1s"]))
    assert res["converged"] and 0.5 < tilt < 5.0
    assert not [w for w in res["warnings"] if "flapping" in w], res["warnings"]


def test_a_failed_trim_says_what_stays_unbalanced_and_warns_where_it_stopped():
    """A new user's R22 with a fuselage moment its teetering rotor could not hold, and an AH-1
    whose tail sat square in the hover's downwash, gave 'the line search found no decrease' and
    nothing else: the reason names the fuselage's largest residual, the warnings are those of
    the last iterate."""
    from mbs.analysis.trim import _unbalanced

    lay = SimpleNamespace(residual_names=["blade1.flap", "fuselage.u", "fuselage.q", "fuselage.w"])
    note = _unbalanced(lay, np.array([1e-3, 2e-3, 0.05, 0.01]))
    assert note.startswith("; at the last iterate the pitching moment stays unbalanced (scaled residual of "
                           "fuselage.q 0.05)")
    assert _unbalanced(lay, np.array([1.0, 2e-3, 0.05, 0.01])) == ""  # the rotor's own periodicity dominates
    # a Bell 206 trial's teetering rotor failed naming the rolling moment, its fuselage's pitching
    # moment the cause: the note says what the rotor holds per degree of teeter (W h + K)
    data = {"main_rotor": {"hub_type": "teetering", "hub_z": -1.58, "flap_stiffness": 0.0},
            "aircraft": {"mass": 1451.0}, "environment": {"g": 9.80665}}
    note = _unbalanced(lay, np.array([1e-3, 2e-3, 0.05, 0.01]), SimpleNamespace(data=data))
    assert f"a teetering rotor holds {np.radians(1) * 1451.0 * 9.80665 * 1.58:.4g} N m per degree of teeter" in note
    from mbs.analysis.trim import _teeter_note  # a failure with no other reason found says it too

    assert _teeter_note(SimpleNamespace(data=data)).startswith("; a teetering rotor cannot hold every fuselage "
                                                               "moment: a teetering rotor holds")
    data["main_rotor"]["hub_type"] = "flapping"
    assert "teeter" not in _unbalanced(lay, np.array([1e-3, 2e-3, 0.05, 0.01]), SimpleNamespace(data=data))
    assert _teeter_note(SimpleNamespace(data=data)) == ""
    d = {"envelope": {}, "wake": {"width": 0.34}, "horizontal_tail": {"alpha_stall": 0.26}, "vertical_fin": {"alpha_stall": 0.26},
         "fuselage_aero": {"model": "polynomials"}}
    failed = SimpleNamespace(converged=False, pitch=np.radians(-35.0), roll=0.0, sideslip=0.0, x0=np.zeros(0),
                             state_names=[], last_iterate_means={"horizontal_tail.wake_immersion": 0.88})
    failed.state = {}
    lines = trim_checks.warnings(failed, d)
    assert lines[0].startswith("at the last iterate (no trim): pitch -35.00 deg is outside"), lines
    assert lines[1].startswith("at the last iterate (no trim): horizontal tail: at the edge of the main rotor's "
                               "wake (immersion 0.88"), lines
    assert trim_checks.warnings(SimpleNamespace(converged=False, last_iterate_means={}), d) == []


def test_a_trim_with_its_blades_past_their_stall_angle_says_so(tmp_path):
    """The analytic section only bounds its lift beyond alpha_stall (no stall): a trim whose blades
    carry more than 1 % of their dynamic pressure there is past the model, and says so. The Bo105
    at 60 m/s has 0.016 % there; with its stall angle at 7 deg, 60 m/s puts a large share past it."""
    from aircraft_files import entries, write

    from mbs import aircraft, scenes
    from mbs.analysis.trim import trim

    plain = trim("forward-flight", 60.0)
    assert plain.output_means["main_rotor.stalled_share"] < 1e-3
    assert not any(w.startswith("main rotor:") for w in plain.warnings)
    raw = entries("bo105")
    raw["main_rotor"]["alpha_stall"].update(value=0.12)
    low = trim(scenes.get("forward-flight").with_aircraft(aircraft.load(write(raw, tmp_path / "low.toml"))), 60.0)
    share = low.output_means["main_rotor.stalled_share"]
    assert share > 0.05, share
    assert any(w.startswith(f"main rotor: {100 * share:.1f} % of its blades' dynamic pressure over the revolution is "
                            "beyond the stall angle 6.9 deg") for w in low.warnings), low.warnings


def test_the_trims_thrust_coefficient_is_of_the_air_it_flew_in():
    """An acceptance test's trim at 3000 m printed the sea-level C_T and C_T/sigma (26 % low): the
    coefficients use the ISA's density when the trim flew in it."""
    from mbs import aircraft
    from mbs.analysis.trim import rotor_coefficients
    from mbs.environment import atmosphere

    d = aircraft.load().data
    sea, high = (rotor_coefficients(d, 21800.0, 30.0, air) for air in ({}, {"altitude": 3000.0}))
    assert high["C_T"] / sea["C_T"] == pytest.approx(d["environment"]["rho"] / atmosphere.density(3000.0), rel=1e-12)
    assert high["C_T/sigma"] / high["C_T"] == pytest.approx(sea["C_T/sigma"] / sea["C_T"], rel=1e-12)


def test_the_stall_share_is_a_share_whatever_the_stall_angle():
    """An acceptance test's stall angle of 50 deg gave a stall share of -4.6e-5: between 0 and 1 at
    every angle, and 0 beyond 45 deg and short of the stall angle."""
    import casadi as ca

    from mbs.aero.rotor import stalled_share
    from mbs.aero.sections import Airfoil

    for stall in (0.26, 0.87):
        share = [float(ca.evalf(stalled_share(Airfoil(5.7, 0.01, 0.0, stall), -np.cos(a), np.sin(a))))
                 for a in np.radians(np.linspace(-89, 89, 357))]
        assert min(share) >= 0 and max(share) <= 1
    inside = float(ca.evalf(stalled_share(Airfoil(5.7, 0.01, 0.0, 0.26), -np.cos(0.35), np.sin(0.35))))
    assert inside == pytest.approx(1.0, abs=1e-6)  # 20 deg: past a 15 deg stall, short of 45
