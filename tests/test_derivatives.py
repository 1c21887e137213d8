"""Stability and control derivatives at trim (quasi-static rotor, implicit-function theorem)
against central finite differences of the period-mean accelerations with the rotor re-trimmed;
the A matrix's modes named and the classical signs; ``heli derivatives``."""
import json

import numpy as np
import pytest

from mbs import scenes
from mbs.analysis.derivatives import COLUMN, derivatives
from mbs.analysis.held import HELD, HeldStepper
from mbs.analysis.monodromy import TangentStepper
from mbs.cli import main

FD_STEPS = {"u": 0.02, "w": 0.02, "p": 2e-3, "q": 2e-3, "collective": 2e-4}
"""Central-difference steps (m/s, rad/s, rad): truncation error below 1e-6 relative."""
STEPS_PER_REV = 50
"""RK4 steps per revolution of the trims here (the derivatives differ from those at the default
100 by 2e-6 relative; the check is of the discrete map, whatever its step)."""


@pytest.fixture(scope="module")
def lin():
    """Derivatives of the forward-flight model by speed (m/s), shared evaluators."""
    sc = scenes.get("forward-flight")
    system, stepper, held, cache = sc.system("compiled"), TangentStepper(sc.model(), "rk4"), HeldStepper(sc.model()), {}

    def get(speed: float):
        if speed not in cache:
            cache[speed] = derivatives("forward-flight", speed, steps_per_rev=STEPS_PER_REV, system=system,
                                       stepper=stepper, held_stepper=held)
        return cache[speed]
    return get


def _mean_fd(res, column: int, step: float) -> np.ndarray:
    """``(ā(y + δ e_k) − ā(y − δ e_k)) / 2δ`` (6,), the rotor's periodic response solved afresh
    (Newton) at each perturbed held motion or control ``y = (b, c)``."""
    b, c, nb = res.held.b, res.held.c, len(HELD)
    means = []
    for sign in (1, -1):
        y = np.r_[b, c]
        y[column] += sign * step
        sol = res.rotor.solve(y[:nb], y[nb:], res.held.x_r)
        assert sol.converged and sol.residual < 1e-12
        means.append(sol.mean)
    return (means[0] - means[1]) / (2 * step)


@pytest.mark.parametrize("variable", sorted(FD_STEPS))
def test_derivatives_equal_finite_differences_with_the_rotor_retrimmed(lin, variable):
    """At 30 m/s: the column of ``dā/d(b, c)`` of one body velocity, rate or control equals
    central differences of re-solved periodic responses to 1e-4 relative (of the column's
    largest entry; measured 2.4e-7 for u, 4e-8 for w, 3e-9 .. 9e-9 for p, q, collective)."""
    res = lin(30.0)
    lay = res.rotor.lay
    k = HELD.index(variable) if variable in HELD else len(HELD) + lay.control_names.index(variable)
    fd, ad = _mean_fd(res, k, FD_STEPS[variable]), res.held.dmean[:, k]
    assert np.abs(fd - ad).max() <= 1e-4 * np.abs(ad).max(), (variable, fd, ad)
    if variable in HELD:
        rows = [i for i, s in enumerate(res.states) if s in ("u", "v", "w", "p", "q", "r")]
        assert np.allclose(res.A[rows, res.states.index(variable)], ad[[0, 2, 4, 1, 3, 5]], rtol=0, atol=1e-15)


def test_a_matrix_has_the_padfield_kinematics_and_gravity(lin):
    """θ̇ = q cos Φ − r sin Φ, φ̇ = p + ... (Euler kinematics by AD), −g cos Θ_e in ∂u̇/∂θ,
    U_e in ∂ẇ/∂q, and the named derivatives with the kinematic terms removed."""
    res, g = lin(30.0), 9.80665
    ref, a, s = res.reference, res.A, res.states.index
    assert a[s("theta"), s("q")] == pytest.approx(np.cos(ref["Phi_e"]), rel=1e-12)
    assert a[s("phi"), s("p")] == pytest.approx(1.0, rel=1e-12)
    assert a[s("u"), s("theta")] == pytest.approx(-g * np.cos(ref["Theta_e"]), rel=1e-3)
    assert a[s("w"), s("q")] == pytest.approx(res.table["Z_q"] + ref["U_e"], rel=1e-12)
    assert res.table["Z_q"] == pytest.approx(a[s("w"), s("q")] - ref["U_e"])
    assert np.abs(res.mean_acceleration_at_reference).max() < 1e-4  # measured 2e-6 rad/s²
    assert COLUMN["theta"] == HELD.index("pitch")


@pytest.mark.parametrize("speed", [0.0, 30.0])
def test_classical_signs_and_named_modes(lin, speed, capsys):
    """Damping in pitch, heave and roll (M_q, Z_w, L_p < 0), collective lifts (Z_θ0 < 0), aft
    cyclic pitches up (M_θ1s > 0), left lateral cyclic rolls left (L_θ1c < 0); the modes are
    named, the fastest a roll subsidence (in hover coupled with pitch through the rotor)."""
    res = lin(speed)
    t = res.table
    assert t["M_q"] < 0 and t["Z_w"] < 0 and t["L_p"] < 0 and t["N_r"] < 0
    assert t["Z_θ0"] < 0 and t["M_θ1s"] > 0 and t["L_θ1c"] < 0
    names = [m.name for m in res.modes]
    print(f"\n{speed:g} m/s: " + "; ".join(f"{m.name} {m.eigenvalue.real:+.4f}{m.eigenvalue.imag:+.4f}j"
                                          for m in res.modes))
    fastest = min(res.modes, key=lambda m: m.eigenvalue.real).name
    assert "roll" in fastest and fastest.endswith("subsidence")
    assert any("heave" in n and "subsidence" in n for n in names) and "phugoid" in names
    assert sum(1 if m.eigenvalue.imag == 0 else 2 for m in res.modes) == 8


def test_heli_derivatives_prints_the_table_and_writes_matlab(tmp_path, capsys):
    """With --json, stdout is the JSON object alone and the labelled tables go to stderr; an
    upper-case ``.MAT`` is a MATLAB file of exactly that name."""
    from scipy.io import loadmat

    path = tmp_path / "bo105_hover.MAT"
    assert main(["derivatives", "hover", "--steps-per-rev", "50", "--json", "--mat", str(path)]) == 0
    captured = capsys.readouterr()
    res, out = json.loads(captured.out), captured.err.splitlines()
    assert res["states"] == ["u", "w", "q", "theta", "v", "p", "phi", "r"]
    assert np.array(res["A"]).shape == (8, 8) and np.array(res["B"]).shape == (8, 4)
    assert {"X_u", "Z_w", "M_q", "L_p", "N_r", "Z_θ0", "M_θ1s", "L_θ1c", "N_θ0T"} <= set(res["derivatives"])
    assert any("roll subsidence" in line or "pitch-roll subsidence" in line for line in out)
    assert any(line.startswith("  M ") for line in out)
    header = out.index("  A (row: time derivative of the state; column: per unit of the state or control):")
    assert out[header + 1].split() == ["u", "w", "q", "θ", "v", "p", "φ", "r"]
    assert [line.split()[0] for line in out[header + 2:header + 10]] == [
        "du/dt", "dw/dt", "dq/dt", "dθ/dt", "dv/dt", "dp/dt", "dφ/dt", "dr/dt"]
    assert [float(x) for x in out[header + 4].split()[1:]] == pytest.approx(np.array(res["A"])[2], abs=5e-5)
    assert out[header + 11].split() == ["θ0", "θ1s", "θ1c", "θ0T"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bo105_hover.MAT"]
    mat = loadmat(path)
    assert np.allclose(mat["A"], res["A"]) and np.allclose(mat["B"], res["B"])


def test_heli_derivatives_refuses_a_clamped_scene(capsys):
    assert main(["derivatives", "ground-run"]) == 2
    assert "free-flying" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["A.MAT", "a.mat", "B.NPZ", "b.npz"])
def test_matrix_files_keep_the_given_name_in_any_case(name, tmp_path):
    """``--mat A.MAT`` was accepted and then refused after the whole computation ('unknown matrix
    file type'), and ``B.NPZ`` became ``B.NPZ.npz``: the file is written under its own name."""
    from types import SimpleNamespace

    from scipy.io import loadmat

    from mbs import arguments
    from mbs.analysis.derivatives import write_matrices

    path = arguments.matrix_file(str(tmp_path / name))
    res = SimpleNamespace(A=np.eye(8), B=np.ones((8, 4)), states=["u", "w", "q", "theta", "v", "p", "phi", "r"],
                          controls=["collective", "longitudinal_cyclic", "lateral_cyclic", "tail_collective"],
                          speed=0.0, modes=[])
    assert write_matrices(res, path) == str(tmp_path / name)
    assert [p.name for p in tmp_path.iterdir()] == [name]
    data = loadmat(path) if name.lower().endswith(".mat") else np.load(path)
    assert np.array_equal(data["A"], np.eye(8)) and np.array_equal(data["B"], np.ones((8, 4)))


def test_a_complex_pair_named_as_a_subsidence_is_explained_in_the_table():
    """A new user read 'roll-pitch subsidence' beside a period of 8.9 s as a contradiction: the
    table says why a pair damped at 90 % of critical or more is named so; without one, no note."""
    from mbs.analysis.flight_modes import FlightMode
    from mbs.commands import mode_lines

    pair = FlightMode(complex(-3.7282, 0.7048), {}, "roll-pitch subsidence")
    lines = mode_lines([pair])
    assert "8.91" in lines[1] and "+0.983" in lines[1]
    assert lines[2] == "  (a complex pair damped at 90 % of critical or more is named as a subsidence: it dies out " \
                       "within one swing)"
    assert len(mode_lines([FlightMode(complex(-3.0, 0.0), {}, "roll subsidence")])) == 2


R22_60KT = np.array([  # a new user's Robinson R22 at 60 kt (teetering rotor): its A in Padfield's order
    [-0.0505765, -0.0363662, 2.84279, -9.7807, 0.000197777, -0.264717, -0.000390072, 0.0524987],
    [-0.0570486, -0.805017, 30.7878, 0.717767, -0.0120929, 0.259896, 0.149445, 0.385093],
    [0.0186492, 0.00144741, -1.19555, 0.00545466, 0.000141225, 0.332414, 0.000544331, -0.0345808],
    [0, 0, 0.999883, 0, 0, 0, -1.41266e-07, 0.0152782],
    [0.00253752, -0.00268341, -0.263789, -0.0113896, -0.13634, -2.77368, 9.77952, -30.522],
    [0.00351662, -0.0151352, -1.01414, -0.00143975, -0.124138, -1.67076, 0.0123419, 0.320402],
    [0, 0, 0.00112272, 1.42029e-07, 0, 1, 4.27023e-10, -0.0734765],
    [-0.0410637, -0.114115, 0.399284, -0.000318787, 0.0678443, -0.077814, -0.000365801, -1.32861]])


def test_of_two_lateral_oscillations_the_dutch_roll_is_the_sideslip_and_yaw_one():
    """Two new users' R22 at 60 kt named its lightly damped 5 s sideslip-yaw oscillation the
    lateral phugoid (yaw 0.165 of it, under a quarter) and a well-damped pair with 0.39 of pitch
    and heave in it the Dutch roll (yaw 0.28). The Dutch roll is the one with the largest v + r
    share; the other is named after its axes."""
    from mbs.analysis.flight_modes import flight_modes

    modes = {m.name: m for m in flight_modes(R22_60KT)}
    assert sorted(modes) == ["Dutch roll", "phugoid", "pitch subsidence", "roll subsidence", "yaw-pitch oscillation"]
    dutch, other = modes["Dutch roll"], modes["yaw-pitch oscillation"]
    assert dutch.eigenvalue == pytest.approx(-0.0604 + 1.2136j, abs=2e-3) and 0.04 < dutch.damping_ratio < 0.06
    assert other.eigenvalue == pytest.approx(-1.268 + 1.253j, abs=2e-3)
    share = lambda m, *k: sum(m.participation[s] for s in k)  # noqa: E731
    assert share(dutch, "v", "r") > share(other, "v", "r") and dutch.participation["r"] < 0.25


def test_a_neutral_root_has_no_damping_ratio():
    """A new user's Floquet table printed the neutral heading root (+0.0000, multiplier 1.000) with
    ζ −1.000, its sign that of round-off: it reads as a strong instability. A root below 1e-6 1/s
    prints "neutral", is NaN in the mode, empty in the CSV and null in the JSON."""
    from mbs.analysis.flight_modes import FlightMode, damping_ratio
    from mbs.commands import mode_lines

    assert np.isnan(damping_ratio(complex(3e-10, 0.0))) and damping_ratio(complex(-2e-6, 0.0)) == 1.0
    neutral = FlightMode(complex(3e-10, 0.0), {}, "yaw subsidence")
    assert "neutral" in mode_lines([neutral])[1] and neutral.summary()["damping_ratio"] is None
    assert json.loads(json.dumps(neutral.summary()))["damping_ratio"] is None


XCELL_HOVER = np.array([  # a new user's X-Cell 60 (8.2 kg) in hover: its A in Padfield's order
    [-0.028873, -0.000162025, 0.190967, -9.80625, 0.000311455, 0.0752532, 0.000643837, 0.00130747],
    [-0.00204137, -0.615651, -0.00479859, 0.0108351, 0.0115863, 0.00776745, -0.850843, -0.121266],
    [0.423051, -0.102224, -8.29766, -0.112588, -0.0126007, -0.80095, 0.00159017, -0.0509568],
    [0, 0, 0.996228, -1.1631e-26, 0, 0, 1.587e-07, -0.0867712],
    [-0.000321254, 0.00506075, 0.0722037, 0.00158886, -0.0561499, -0.190368, 9.7693, 0.0296729],
    [0.070639, 0.0540361, 1.6449, -0.00304482, -0.893069, -15.4354, -0.211245, 0.633094],
    [0, 0, -9.59938e-05, -1.587e-07, 0, 1, -1.89679e-11, -0.00110211],
    [-0.000556131, -0.0871562, 0.0536462, -0.0009663, 0.829698, -0.262569, 0.000277056, -1.07049]])


def test_two_real_modes_led_by_one_axis_have_two_names():
    """A new user's X-Cell 60 in hover printed 'yaw subsidence' twice and no heave mode: the heave
    couples to the yaw through the torque. The one with the larger yaw share keeps the name, the
    other is named after its two largest axes."""
    from mbs.analysis.flight_modes import flight_modes

    modes = flight_modes(XCELL_HOVER)
    names = [m.name for m in modes]
    assert len(set(names)) == len(names) and "yaw subsidence" in names and "yaw-heave subsidence" in names, names
    yaw, coupled = (next(m for m in modes if m.name == n) for n in ("yaw subsidence", "yaw-heave subsidence"))
    assert yaw.participation["r"] > coupled.participation["r"] and coupled.participation["w"] > 0.15
    assert {m.name for m in flight_modes(R22_60KT)} == {"Dutch roll", "phugoid", "pitch subsidence", "roll subsidence",
                                                         "yaw-pitch oscillation"}  # one of each: unchanged


BELL412_140KT = np.array([  # a new user's Bell 412 at 140 kt (its tail the Bo105's): A in Padfield's order
    [-0.0586773, -0.0190448, 9.86811, -9.7175, 0.00413204, -0.339454, -0.00705784, 0.490147],
    [-0.00304554, -0.801159, 71.005, 1.26866, -0.0179433, -0.569351, 0.490981, 0.697776],
    [0.00458116, 0.104575, -1.55483, -0.0287946, -0.00161988, 0.406873, 0.00054875, 0.0294109],
    [0, 0, 0.998873, 2.16537e-26, 0, -2.1684e-19, -8.54184e-08, 0.0474648],
    [0.00410938, -0.0177181, -0.354071, -0.0662605, -0.140537, -9.71989, 9.70777, -70.96],
    [0.00690252, 0.0815507, -1.55487, -0.0142129, -0.130546, -3.18582, -0.0882283, 0.91955],
    [0, 0, 0.00624681, 8.68979e-08, 0, 1, -5.17194e-09, -0.131461],
    [-0.00740261, 0.00519479, 0.273209, 0.00085542, 0.0236421, -0.118148, 0.00345065, -1.02948]])


def test_a_divergence_from_static_instability_in_angle_of_attack_is_explained():
    """A new user's Bell 412 with the Bo105's tail had a heave divergence at 140 kt and M_w > 0,
    with no word on why. Where Padfield's short-period condition Z_w M_q - M_w U_e > 0 fails and
    a longitudinal mode grows, the derivatives say so with the figures; not where it holds."""
    from types import SimpleNamespace

    from mbs.analysis.derivatives import static_stability_warning
    from mbs.analysis.flight_modes import flight_modes

    a = BELL412_140KT
    table = {"Z_w": a[1, 1], "M_q": a[2, 2], "M_w": a[2, 1]}
    res = SimpleNamespace(table=table, reference={"U_e": 71.4064}, modes=flight_modes(a), units={"M_w": "rad/(m s)"})
    (words,) = static_stability_warning(res)
    margin = a[1, 1] * a[2, 2] - a[2, 1] * 71.4064
    assert margin == pytest.approx(-6.22, abs=0.01)
    assert f"M_w = +0.1046 rad/(m s), and Z_w M_q - M_w U_e = {margin:+.3g} 1/s^2 < 0" in words
    assert "heave divergence +1.65 1/s" in words, words
    stable = SimpleNamespace(**{**vars(res), "table": {**table, "M_w": -0.01}})
    assert static_stability_warning(stable) == []  # the condition holds: no word, whatever grows
    calm = SimpleNamespace(**{**vars(res), "modes": [m for m in res.modes if m.eigenvalue.real < 0]})
    assert static_stability_warning(calm) == []  # nothing grows: no word
