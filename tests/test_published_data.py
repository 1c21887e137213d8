"""Published data as printed: whole-aircraft inertias, pilot controls through a rigging, the
tail-rotor pitch and collective conventions, and trims at zero bank and in steady turns."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from aircraft_files import edited, entries, write
from mbs import aircraft, scenes
from mbs.aircraft import mass, rigging
from mbs.analysis.trim import evaluators, trim
from mbs.models.helicopter import build
from mbs.models.helicopter.config import Config

RIG = {  # a utility helicopter's kind of rigging: inches of travel, blade angles per inch, mixing, phase
    "collective_lever": {"value": [0.0, 10.0], "unit": "in", "source": "test"},
    "longitudinal_stick": {"value": [-5.0, 5.0], "unit": "in", "source": "test"},
    "lateral_stick": {"value": [-4.0, 4.0], "unit": "in", "source": "test"},
    "pedals": {"value": [-2.7, 2.7], "unit": "in", "source": "test"},
    "collective": {"value": [3.0, 1.6, 0.0, 0.0, 0.0], "unit": "deg, deg/in, deg/in, deg/in, deg/in", "source": "t"},
    "longitudinal_cyclic": {"value": [0.0, 0.1, -1.6, 0.0, 0.0], "unit": "deg, deg/in, deg/in, deg/in, deg/in",
                            "source": "t"},
    "lateral_cyclic": {"value": [0.0, 0.0, 0.0, -1.0, 0.0], "unit": "deg, deg/in, deg/in, deg/in, deg/in",
                       "source": "t"},
    "tail_collective": {"value": [5.0, 0.3, 0.0, 0.0, 3.0], "unit": "deg, deg/in, deg/in, deg/in, deg/in",
                        "source": "t"},
    "phase": {"value": -10.0, "unit": "deg", "source": "t"},
}


def _rigged(tmp_path, **conventions):
    raw = entries("bo105")
    raw["controls"] = dict(RIG)
    if conventions:
        raw["conventions"] = {k: {"value": v, "unit": "-", "source": "t"} for k, v in conventions.items()}
    return aircraft.load(write(raw, tmp_path / "rigged.toml"))


def _whole(tmp_path, name: str):
    raw = entries(name)
    raw["aircraft"]["inertia"] = {"value": "whole-aircraft", "unit": "-", "source": "test"}
    return aircraft.load(write(raw, tmp_path / f"{name}_whole.toml"))


def _pose(model, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Body ``name``'s frame (rotation, origin) in the world at zero joint coordinates and azimuths,
    composed from the model's own ``at``/``frame`` data (independent of :mod:`mbs.aircraft.mass`)."""
    body = model.bodies[name]
    if body.parent == "world":
        return body.frame, body.at
    rot, origin = _pose(model, body.parent)
    return rot @ body.frame, origin + rot @ body.at


def _model_inertia(model, turn: float) -> np.ndarray:
    """The model's inertia about the origin (the CG) with both rotors turned by ``turn`` rad about
    their shafts (zero flap, lag, pitch and teeter)."""
    total = np.zeros((3, 3))
    for name, body in model.bodies.items():
        rot, origin = _pose(model, name)
        for hub in ("main_hub", "tail_hub"):  # turn a rotor's bodies about its hub's axis
            if name == hub or _descends(model, name, hub):
                h_rot, h_at = _pose(model, hub)
                spin = h_rot @ _rz(turn) @ h_rot.T
                rot, origin = spin @ rot, h_at + spin @ (origin - h_at)
        com = origin + rot @ body.com
        total += rot @ body.inertia @ rot.T + body.mass * (com @ com * np.eye(3) - np.outer(com, com))
    return total


def _descends(model, name: str, ancestor: str) -> bool:
    while name != "world":
        name = model.bodies[name].parent
        if name == ancestor:
            return True
    return False


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


@pytest.mark.parametrize("name", ["puma", "bo105", "lynx"])
def test_a_whole_aircraft_inertia_is_the_models_total_over_a_revolution(tmp_path, name):
    """With ``inertia = "whole-aircraft"`` the model's bodies (airframe, hubs, blades, seesaw),
    averaged over the rotors' revolution, carry exactly the published inertia about the CG."""
    craft = _whole(tmp_path, name)
    model = build(Config(fuselage="clamped", rotor_aero=False, airframe_aero=False), craft)
    turns = 2 * np.pi * np.arange(36) / 36
    average = sum(_model_inertia(model, a) for a in turns) / len(turns)
    assert np.abs(average - mass.published_inertia(craft.data)).max() <= 1e-9 * np.abs(average).max()


def test_the_puma_as_whole_aircraft_warns_that_no_airframe_has_what_is_left(tmp_path):
    """Padfield's Puma inertias less four 68.3 kg blades of I_beta = 1280 kg m^2 leave an airframe
    whose pitch inertia exceeds roll plus yaw: a warning in check and the trim, not a refusal."""
    craft = _whole(tmp_path, "puma")
    report = aircraft.check(craft.path)
    assert report.ok and any("triangle inequality" in w for w in report.warnings), report.warnings
    frame = mass.airframe(craft.data).inertia
    assert np.linalg.eigvalsh(frame)[0] > 0  # positive definite: the model runs


def test_a_whole_aircraft_inertia_smaller_than_the_rotors_is_refused(tmp_path):
    path = edited(tmp_path / "tiny.toml", "puma", **{"aircraft.inertia": "whole-aircraft", "aircraft.Ixx": 4500.0,
                                                      "aircraft.Iyy": 6000.0, "aircraft.Izz": 5000.0})
    report = aircraft.check(path)
    assert not report.ok and report.problems[0].startswith("aircraft.Ixx:") and "not positive definite" in \
        report.problems[0]


def test_the_airframe_basis_puts_the_published_inertia_on_the_airframe(tmp_path):
    """``inertia = "airframe"``: the file's tensor is the airframe body's, unchanged."""
    craft = aircraft.load(edited(tmp_path / "frame.toml", "bo105", **{"aircraft.inertia": "airframe"}))
    body = build(Config(), craft).bodies["fuselage"]
    assert np.array_equal(body.inertia, mass.published_inertia(craft.data))


def test_rigging_maps_pilot_controls_to_blade_angles_and_back(tmp_path):
    craft = _rigged(tmp_path, tail_collective_positive="port", collective_radius=0.75)
    rig = rigging.rigging(craft.data)
    pilot = {"collective_lever": 0.127, "longitudinal_stick": 0.0254, "lateral_stick": -0.02, "pedals": 0.01}
    blade = rig.blade(pilot)
    back = rig.pilot(blade)
    assert all(back[k] == pytest.approx(v, abs=1e-15) for k, v in pilot.items())
    # by hand: 5 in of collective lever is 3 + 1.6 * 5 = 11 deg at 0.75 R; the Bo105's twist -0.14 rad
    # makes the root 0.105 rad more; a thrust to port is against the Bo105's anti-torque (starboard) thrust
    deg, inch = math.radians(1.0), 0.0254
    assert blade["collective"] == pytest.approx(11 * deg + 0.75 * 0.14, abs=1e-14)
    tail = 5 * deg + 0.3 * deg * 5 + 3 * deg * pilot["pedals"] / inch
    assert blade["tail_collective"] == pytest.approx(-tail, abs=1e-14)
    s, c = (0.1 * 5 - 1.6 * 1.0) * deg, -1.0 * deg * pilot["lateral_stick"] / inch  # the mixing's theta_1s, theta_1c
    phase = math.radians(-10.0)
    assert blade["longitudinal_cyclic"] == pytest.approx(s * math.cos(phase) - c * math.sin(phase), abs=1e-14)
    assert blade["lateral_cyclic"] == pytest.approx(c * math.cos(phase) + s * math.sin(phase), abs=1e-14)
    jac = np.array([[(rig.blade({**pilot, p: pilot[p] + 1e-6})[b] - rig.blade({**pilot, p: pilot[p] - 1e-6})[b])
                     / 2e-6 for p in rigging.PILOT] for b in rigging.BLADE])
    assert np.abs(jac - rig.matrix()).max() <= 1e-8


def test_a_mixing_as_printed_with_a_common_gain_and_a1_b1_cyclic_is_the_same_rigging(tmp_path):
    """A report's ``B1 = K (k1 x1 + ... )`` with pitch ``theta_0 - A1 cos psi - B1 sin psi``,
    written with ``gain`` and ``cyclic_pitch = "A1, B1"``, gives the rigging of the hand-multiplied,
    sign-turned rows to round-off; trims report their cyclic in A1, B1."""
    plain = rigging.rigging(_rigged(tmp_path).data)
    raw = entries("bo105")
    raw["controls"] = {k: dict(v) for k, v in RIG.items()}
    for row, gain in (("longitudinal_cyclic", -1.6), ("lateral_cyclic", -1.0)):  # the rows negated: B1, A1
        value = RIG[row]["value"]
        raw["controls"][row] = {**RIG[row], "value": [-value[0], *(-v / gain for v in value[1:])], "gain": gain}
    raw["conventions"] = {"cyclic_pitch": {"value": "A1, B1", "unit": "-", "source": "t"}}
    printed = aircraft.load(write(raw, tmp_path / "printed.toml"))
    rig = rigging.rigging(printed.data)
    assert np.abs(rig.matrix() - plain.matrix()).max() <= 1e-15
    pilot = {"collective_lever": 0.127, "longitudinal_stick": 0.0254, "lateral_stick": -0.02, "pedals": 0.01}
    assert all(rig.blade(pilot)[k] == pytest.approx(v, abs=1e-15) for k, v in plain.blade(pilot).items())
    conv = rigging.conventions(printed.data)
    published = conv.to_published({"collective": 0.1, "longitudinal_cyclic": 0.02, "lateral_cyclic": -0.03,
                                    "tail_collective": 0.2})
    assert (published["longitudinal_cyclic"], published["lateral_cyclic"]) == (-0.02, 0.03)  # B1, A1
    assert list(conv.scale()) == [1.0, -1.0, -1.0, 1.0]
    listed = {r[0]: r for r in aircraft.check(printed.path).converted}
    assert listed["controls.longitudinal_cyclic"][3].startswith("the offset, and the gain -1.6 times each factor")


@pytest.mark.parametrize("where, gain, words", [
    ("main_rotor.radius", 2.0, "gain applies to the mixing rows of [controls] only"),
    ("controls.collective", "x", "gain: 'x' is not a number"),
])
def test_a_gain_off_a_mixing_row_or_not_a_number_is_refused(tmp_path, where, gain, words):
    raw = entries("bo105")
    raw["controls"] = {k: dict(v) for k, v in RIG.items()}
    section, key = where.split(".")
    raw[section][key] = {**raw[section][key], "gain": gain}
    report = aircraft.check(write(raw, tmp_path / "bad.toml"))
    assert any(p.startswith(f"{where}: {words}") for p in report.problems), report.problems


@pytest.mark.parametrize("row, unit, words", [
    ("collective", "deg, deg/%, deg/in, deg/in, deg/in", "give it in deg/in"),
    ("pedals", "kg", "a control's position is a length"),
    ("collective", "deg, deg/in", "give 5 units"),
])
def test_a_rigging_in_the_wrong_units_is_refused_naming_the_entry(tmp_path, row, unit, words):
    raw = entries("bo105")
    raw["controls"] = {k: dict(v) for k, v in RIG.items()}
    raw["controls"][row]["unit"] = unit
    report = aircraft.check(write(raw, tmp_path / "bad.toml"))
    assert not report.ok and report.problems[0].startswith(f"controls.{row}:") and words in report.problems[0], \
        report.problems


@pytest.fixture(scope="module")
def forward_flight():
    sc = scenes.get("forward-flight")
    return sc, evaluators(sc)


def test_a_zero_bank_trim_holds_the_wings_level_and_trims_the_sideslip(forward_flight):
    sc, (system, stepper) = forward_flight
    level = trim(sc, speed=30.0, system=system, stepper=stepper, bank=0.0)
    assert level.converged and level.iterations <= 8, level.reason
    assert level.roll == 0.0 and level.flight.constraint == "zero bank"
    x = dict(zip(level.state_names, level.x0))
    u, v, w = (x[f"fuselage.{k}"] for k in "uvw")
    # the track is turned by the sideslip from the nose: the body velocity's side component is V sin(beta)
    assert v / math.sqrt(u * u + v * v + w * w) == pytest.approx(math.sin(level.sideslip), abs=2e-3)
    zero_sideslip = trim(sc, speed=30.0, system=system, stepper=stepper)
    assert abs(zero_sideslip.roll) > math.radians(0.5) and abs(level.sideslip) > math.radians(1.0)


def test_a_steady_turn_banks_as_the_centripetal_force_asks(forward_flight):
    """At 30 m/s turning at 0.1 rad/s the bank exceeds the straight flight's by atan(V psi_dot / g)
    (the rotor's tilt to hold the turn) within 0.2 deg, and the body rates are the heading rate's
    components."""
    sc, (system, stepper) = forward_flight
    straight = trim(sc, speed=30.0, system=system, stepper=stepper)
    turn = trim(sc, speed=30.0, system=system, stepper=stepper, turn_rate=0.1)
    assert turn.converged and turn.iterations <= 8, turn.reason
    g = sc.aircraft.data["environment"]["g"]
    assert math.degrees(turn.roll - straight.roll) == pytest.approx(math.degrees(math.atan(30.0 * 0.1 / g)), abs=0.2)
    x = dict(zip(turn.state_names, turn.x0))
    phi, theta = turn.roll, turn.pitch
    expected = 0.1 * np.array([-math.sin(theta), math.sin(phi) * math.cos(theta), math.cos(phi) * math.cos(theta)])
    rates = np.array([x[f"fuselage.{k}"] for k in "pqr"])
    assert np.abs(rates - expected).max() <= 0.02 * 0.1  # the rotor's vibration moves them a little within a period
    left = trim(sc, speed=30.0, system=system, stepper=stepper, turn_rate=-0.1)
    assert left.roll - straight.roll == pytest.approx(-(turn.roll - straight.roll), abs=math.radians(0.2))


def test_a_rigged_aircraft_trims_in_pilot_controls_and_warns_at_a_stop(tmp_path):
    craft = _rigged(tmp_path)
    sc = scenes.get("hover", craft)
    res = trim(sc)
    assert res.converged and set(res.pilot) == set(rigging.PILOT) and res.pilot_units["pedals"] == "in"
    rig = rigging.rigging(craft.data)
    si = {k: v * 0.0254 for k, v in res.pilot.items()}
    assert all(rig.blade(si)[k] == pytest.approx(res.controls[k], abs=1e-12) for k in rigging.BLADE)
    stops = [w for w in res.warnings if "position (travel" in w]
    beyond = [k for k, (lo, hi) in zip(rigging.PILOT, np.array([RIG[k]["value"] for k in rigging.PILOT]))
              if not lo + 0.01 * (hi - lo) < res.pilot[k] < hi - 0.01 * (hi - lo)]
    assert [w.split(" =")[0] for w in stops] == beyond


def test_derivatives_come_per_published_control_and_per_pilot_position(tmp_path):
    """The control derivatives in the published tail-pitch convention flip the tail column; per
    pilot position they are B times the rigging's d(blade)/d(pilot)."""
    from mbs.analysis.derivatives import derivatives

    craft = _rigged(tmp_path, tail_collective_positive="port")
    res = derivatives(scenes.get("forward-flight", craft), speed=20.0)
    assert res.published["N_θ0T"] == -res.table["N_θ0T"] and res.published["L_θ1c"] == res.table["L_θ1c"]
    g = rigging.rigging(craft.data).matrix()
    assert np.abs(res.B_pilot - res.B @ g).max() <= 1e-12 * np.abs(res.B).max()
    assert res.pilot["N_pedals"] == pytest.approx(sum(res.table[f"N_{s}"] * g[i, 3] for i, s in
                                                       enumerate(("θ0", "θ1s", "θ1c", "θ0T"))), rel=1e-12)


def _rot(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` (rad) about the unit ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


@pytest.mark.parametrize("curve", [[[-2.0, -6000.0], [0.0, 0.0], [2.0, 6000.0]],
                                   [[-1.0, -5200.0], [-0.2, -2500.0], [0.0, 0.0], [0.2, 2500.0], [1.0, 5200.0]]])
def test_a_lag_damper_strut_loads_flap_and_lag_by_virtual_work(tmp_path, curve):
    """Hub end and blade end of a published damper geometry; its tension from the force curve at the
    rate of extension (and a stiffness about the neutral length): the generalized forces on blade 1's
    flap and lag are -T dL/dβ and -T dL/dζ, with L from an independent composition of the hinges."""
    from scipy.interpolate import CubicSpline

    from mbs.dynamics import symbolic

    raw = entries("bo105")
    raw["main_rotor"]["lag_damping"]["value"] = 0.0
    raw["lag_damper"] = {"hub_point": {"value": [0.25, 0.20, 0.02], "unit": "m", "source": "t"},
                         "blade_point": {"value": [0.75, 0.06, 0.0], "unit": "m", "source": "t"},
                         "force_curve": {"value": curve, "unit": "m/s, N", "source": "t"},
                         "stiffness": {"value": 2.0e5, "unit": "N/m", "source": "t"}}
    craft = aircraft.load(write(raw, tmp_path / "damped.toml"))
    cfg = Config(fuselage="none", tail_rotor=False, rotor_aero=False, airframe_aero=False)
    with_damper, without = (symbolic(build(replace_cfg(cfg, dampers=on), craft)) for on in (True, False))
    model = with_damper.model
    x = np.zeros(len(_state_names(with_damper)))
    idx = {n: i for i, n in enumerate(_state_names(with_damper))}
    beta, zeta, beta_dot, zeta_dot = 0.03, 0.05, 0.4, -0.6
    x[idx["blade1.flap"]], x[idx["blade1.lag"]] = beta, zeta
    x[idx["blade1.flap_rate"]], x[idx["blade1.lag_rate"]] = beta_dot, zeta_dot
    p = np.array([q.default for q in model.parameters.values()])
    ht = [np.asarray(s["parts"](x, 0.0, p)[2]).ravel() for s in (with_damper, without)]
    q_damper = ht[0] - ht[1]
    rates = [n for n in _state_names(with_damper) if n.endswith("_rate")]
    d = craft.data
    e = d["main_rotor"]["flap_hinge_offset"]
    prm = {k: q.default for k, q in model.parameters.items()}
    theta = prm["collective"] + prm["lateral_cyclic"]  # blade 1 at ψ = 0: the pitch and its rate (driven)
    theta_dot = prm["omega"] * prm["longitudinal_cyclic"]

    def length(b, z, th=None):
        rot = _rot((0, -1, 0), b) @ _rot((0, 0, -1), z) @ _rot((1, 0, 0), theta if th is None else th)
        point = np.array([e, 0, 0]) + rot @ (np.array([0.75, 0.06, 0.0]) - [e, 0, 0])
        return np.linalg.norm(point - [0.25, 0.20, 0.02])
    h = 1e-6
    dl_db = (length(beta + h, zeta) - length(beta - h, zeta)) / (2 * h)
    dl_dz = (length(beta, zeta + h) - length(beta, zeta - h)) / (2 * h)
    rows = np.array(curve)
    dl_dt = (length(beta, zeta, theta + h) - length(beta, zeta, theta - h)) / (2 * h)
    rate = dl_db * beta_dot + dl_dz * zeta_dot + dl_dt * theta_dot
    neutral = np.linalg.norm(np.array([0.75, 0.06, 0.0]) - [0.25, 0.20, 0.02])
    tension = float(CubicSpline(rows[:, 0], rows[:, 1], bc_type="natural")(rate)) + 2.0e5 * (length(beta, zeta) - neutral)
    assert q_damper[rates.index("blade1.flap_rate")] == pytest.approx(-tension * dl_db, rel=1e-7, abs=1e-6)
    assert q_damper[rates.index("blade1.lag_rate")] == pytest.approx(-tension * dl_dz, rel=1e-7, abs=1e-6)


def replace_cfg(cfg, **changes):
    from dataclasses import replace

    return replace(cfg, **changes)


def _state_names(sym) -> list[str]:
    from mbs.backends.info import info_of

    return info_of(sym, {}).state_names


def test_a_banked_trim_is_not_written_where_simulate_would_start_from_it(tmp_path, capsys):
    """``heli trim --bank 0 --write``: refused before trimming, in one line (stored trims are of
    straight flight at zero sideslip, which ``heli simulate`` starts from)."""
    from test_cli_errors import run_main

    code, err = run_main(["trim", "forward-flight", "--bank", "0", "--write", str(tmp_path / "t.toml"), "--quiet"],
                         capsys)
    assert code == 2 and "a trim with --bank or --turn-rate is not stored" in err
    assert not (tmp_path / "t.toml").exists()



def test_a_lock_number_as_published_gives_the_flap_inertia(tmp_path):
    """``lock_number`` in place of ``I_flap``: I_flap = rho a c R^4 / gamma, listed as derived;
    the Bo105's own gamma gives back its I_flap to round-off, and with a mass table it is a problem."""
    from mbs.aircraft import performance

    d = aircraft.load("bo105").data
    gamma = performance.lock_number(d["main_rotor"], d["environment"]["rho"])
    raw = entries("bo105")
    del raw["main_rotor"]["I_flap"]
    raw["main_rotor"]["lock_number"] = {"value": gamma, "unit": "-", "source": "report"}
    report = aircraft.check(write(raw, tmp_path / "lock.toml"))
    assert report.ok, report.problems
    derived = {e: (v, how) for e, v, _, how in report.derived}
    assert derived["main_rotor.I_flap"][0] == pytest.approx(d["main_rotor"]["I_flap"], rel=1e-12)
    assert "from lock_number" in derived["main_rotor.I_flap"][1]
    raw["main_rotor"]["I_flap"] = {"value": 231.7, "unit": "kg m^2", "source": "report"}
    both = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert "main_rotor.lock_number: replaces main_rotor.I_flap, which is computed from it; leave I_flap out" \
        in both.problems


def test_a_blade_weight_alone_gives_the_uniform_blade_s_flap_inertia(tmp_path):
    """A report that prints the blade's weight and no flap inertia or Lock number (a new user's
    UH-60: 116.5 kg, refused for want of I_flap even with override): I_flap = m (R - e)^2 / 3, listed
    as derived; beside I_flap the weight stays the override it was (a non-uniform blade)."""
    raw = entries("bo105")
    del raw["main_rotor"]["I_flap"]
    raw["main_rotor"]["blade_mass"] = {"value": 30.0, "unit": "kg", "source": "report", "override": True}
    path = write(raw, tmp_path / "weight.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    mr = aircraft.load(path).data["main_rotor"]
    assert mr["I_flap"] == pytest.approx(30.0 * (mr["radius"] - mr["flap_hinge_offset"]) ** 2 / 3, rel=1e-12)
    assert mr["first_moment"] == pytest.approx(30.0 * (mr["radius"] - mr["flap_hinge_offset"]) / 2, rel=1e-12)
    assert any(e == "main_rotor.I_flap" and "from blade_mass alone" in how for e, _, _, how in report.derived)
    raw["main_rotor"]["I_flap"] = {"value": 231.7, "unit": "kg m^2", "source": "report"}
    raw["main_rotor"]["blade_mass"]["value"] = 28.0
    both = aircraft.load(write(raw, tmp_path / "both.toml")).data["main_rotor"]
    assert both["I_flap"] == 231.7 and both["blade_mass"] == 28.0


@pytest.mark.parametrize("hub", ["teetering", "flapping"])
def test_a_tail_rotor_lock_number_as_published_gives_the_blade_mass(tmp_path, hub):
    """``tail_rotor.lock_number`` (a report that prints gamma = 4 and no blade mass: a new user's
    Prouty helicopter had to work out 6.6 kg by hand) replaces ``blade_mass``: the uniform blade
    from the flap hinge (the axis but on a flapping hub) has that Lock number, to 1e-12."""
    raw = entries("bo105")
    del raw["tail_rotor"]["blade_mass"]
    raw["tail_rotor"]["lock_number"] = {"value": 4.0, "unit": "-", "source": "report"}
    if hub == "flapping":
        raw["tail_rotor"]["hub_type"]["value"] = "flapping"
        for key in ("seesaw_mass", "seesaw_size", "teeter_stiffness"):
            raw["tail_rotor"].pop(key, None)
        raw["tail_rotor"]["flap_hinge_offset"] = {"value": 0.05, "unit": "m", "source": "report"}
        raw["tail_rotor"]["flap_stiffness"] = {"value": 0.0, "unit": "N m/rad", "source": "report"}
    path = write(raw, tmp_path / "tail_lock.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    tr, rho = aircraft.load(path).data["tail_rotor"], aircraft.load(path).data["environment"]["rho"]
    span = tr["radius"] - (0.05 if hub == "flapping" else 0.0)
    assert rho * tr["lift_slope"] * tr["chord"] * tr["radius"] ** 4 / (tr["blade_mass"] * span**2 / 3) == \
        pytest.approx(4.0, rel=1e-12)
    assert any(e == "tail_rotor.blade_mass" for e, *_ in report.derived)
    raw["tail_rotor"]["blade_mass"] = {"value": 1.0, "unit": "kg", "source": "report"}
    both = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert any(p.startswith("tail_rotor.lock_number: replaces tail_rotor.blade_mass") for p in both.problems), \
        both.problems


@pytest.mark.parametrize("hinge, hub, unit, fraction, listed", [
    (0.14, 0.2, "R", 1.0, "0.14 R"),
    (3.0, 20.0, "% R", 0.01, "3.0 % R"),  # "3 % of R": a new user's OH-6A was told "unknown symbol 'R'"
    (3.0, 20.0, "%R", 0.01, "3.0 %R")])
def test_a_length_as_a_fraction_of_the_radius(tmp_path, hinge, hub, unit, fraction, listed):
    """``unit = "R"`` on a rotor's length (a hinge offset printed as e/R) is that fraction of its
    rotor's radius, ``"%R"`` that percentage, listed with the unit as written; on the radius itself
    or outside the rotors it is a problem."""
    raw = entries("bo105")
    raw["main_rotor"]["flap_hinge_offset"] = {"value": hinge, "unit": unit, "source": "report", "note": "e/R"}
    raw["tail_rotor"]["hub_size"] = {"value": hub, "unit": unit, "source": "report"}
    craft = aircraft.load(write(raw, tmp_path / "fractions.toml"))
    d = craft.data
    assert d["main_rotor"]["flap_hinge_offset"] == pytest.approx(fraction * hinge * d["main_rotor"]["radius"], rel=1e-15)
    assert d["tail_rotor"]["hub_size"] == pytest.approx(fraction * hub * d["tail_rotor"]["radius"], rel=1e-15)
    converted = {r[0]: r[3] for r in aircraft.check(craft.path).converted}
    assert converted["main_rotor.flap_hinge_offset"] == f"times main_rotor.radius 4.91 m: from {listed}"
    for section, key in (("main_rotor", "radius"), ("horizontal_tail", "x")):
        bad = entries("bo105")
        bad[section][key] = {"value": 0.5, "unit": unit, "source": "report"}
        report = aircraft.check(write(bad, tmp_path / "bad.toml"))
        assert f"{section}.{key}: unit {unit!r} (a fraction of the rotor's radius) applies to the lengths of " \
               "[main_rotor] and [tail_rotor] only" in report.problems


# -- units as reports print them -------------------------------------------------------------------

LBF, FT = 4.4482216152605, 0.3048


@pytest.mark.parametrize("printed, plain", [
    ("ft-lb", "ft lbf"), ("FT-LB/RAD", "ft lbf/rad"), ("slug-ft2", "slug ft^2"), ("SLUG-FT2", "slug ft^2"),
    ("in.", "in"), ("kn", "kt"), ("KTS", "kt"), ("knots", "kt"), ("deg/sec", "deg/s"), ("DEG", "deg"),
    ("lb", "lbf"), ("lbs", "lbf"), ("lb/ft^2", "lbf/ft^2"), ("psf", "lbf/ft^2"), ("s-1", "s^-1"), ("feet", "ft"),
    # copied from a typeset report
    ("slug·ft²", "slug ft^2"), ("kg·m²", "kg m^2"), ("kg.m2", "kg m^2"), ("N.m", "N m"), ("lb·ft", "ft lbf"),
    ("ft²", "ft^2"), ("ft**2", "ft^2"), ("sq ft", "ft^2"), ("SQ. FT.", "ft^2"), ("cu ft", "ft^3"), ("kg/m³", "kg/m^3"),
    ("s⁻¹", "s^-1"), ("°", "deg"), ("°/s", "deg/s"), ("SHP", "hp"), ("kgf", "kg m/s^2"),
    # successive slashes and parentheses
    ("ft/sec²/in", "ft/s^2 in"), ("(ft/sec^2)/in", "ft/s^2 in"), ("ft/(sec^2 in)", "ft/s^2 in"), ("deg/(s/ft)", "deg ft/s"),
    # abbreviation stops, 'per', a leading slash
    ("in.-lb", "ft lbf"), ("FT.-LB.", "ft lbf"), ("in.²", "ft^2"), ("deg./sec.", "deg/s"), ("/deg", "s^-1"),
    ("per deg", "s^-1"), ("ft per sec", "kt"), ("psi", "lbf/ft^2"), ("fpm", "kt"), ("KTAS", "kt"), ("mph", "kt"),
    ("slugs/ft3", "slug/ft^3"), ("N-D", "-"), ("n.d.", "-"), ("Dimensionless", "-"),
])
def test_a_unit_as_a_report_prints_it_reads_as_its_plain_form(printed, plain):
    """Hyphens, powers without ``^``, capitals, trailing periods and common spellings, the forms of
    a typeset report (superscripts, ``°``, a middle or full stop between symbols, ``sq ft``);
    ``lb`` a pound-force where a force, moment or pressure is wanted."""
    from mbs.aircraft import units

    si = {"/deg": "1/rad", "per deg": "1/rad", "in.-lb": "N m", "in.²": "m^2", "ft per sec": "m/s", "psi": "Pa",
          "fpm": "m/s", "mph": "m/s", "slugs/ft3": "kg/m^3"}.get(printed) or {
        "-": "-", "slug/ft^3": "kg/m^3", "ft lbf": "N m", "ft lbf/rad": "N m/rad", "slug ft^2": "kg m^2", "in": "m",
        "kt": "m/s", "deg/s": "rad/s",
          "deg": "rad", "lbf": "N", "lbf/ft^2": "Pa", "s^-1": "1/s", "ft": "m", "kg m^2": "kg m^2", "N m": "N m",
          "ft^2": "m^2", "ft^3": "m^3", "kg/m^3": "kg/m^3", "hp": "W", "kg m/s^2": "N", "ft/s^2 in": "1/s^2",
          "deg ft/s": "rad m/s"}[plain]
    want = {"kgf": 9.80665, "in.-lb": LBF * 0.0254, "in.²": 0.0254**2, "/deg": 180 / np.pi, "per deg": 180 / np.pi,
            "ft per sec": FT, "psi": LBF / 0.0254**2, "fpm": FT / 60, "mph": 0.44704}.get(printed) \
        or units.factor_to(plain, si)
    assert units.factor_to(printed, si) == pytest.approx(want, rel=1e-15)
    assert units.pound_force(printed, si) == (printed in ("ft-lb", "FT-LB/RAD", "lb", "lbs", "lb/ft^2", "lb·ft",
                                                           "in.-lb", "FT.-LB."))


@pytest.mark.parametrize("printed, target, factor, how", [
    ("ft-lb/rad/sec", "N m s/rad", LBF * FT, " (lb as pound-force; read as ft-lb/(rad/sec))"),
    ("IN.-LB./RAD/SEC", "N m s/rad", LBF * 0.0254, " (lb as pound-force; read as IN.-LB./(RAD/SEC))"),
    ("1/rad/s", "s/rad", 1.0, " (read as 1/(rad/s))"),
    ("ft/sec/sec", "m/s^2", FT, ""),  # the left-to-right reading is of the kind: kept
    ("deg/sec/in", "rad/(s m)", np.pi / 180 / 0.0254, ""),
])
def test_a_rate_printed_after_a_second_slash_is_read_per_that_rate_only_where_the_kind_asks(printed, target, factor,
                                                                                             how):
    """``A/B/C`` is ``(A/B)/C``; only where that is of the wrong kind and ``A/(B/C)`` of the right
    one (a damper in ft-lb per rad/sec) is it read so, and the conversion says it."""
    from mbs.aircraft import units

    assert units.factor_to(printed, target) == pytest.approx(factor, rel=1e-15)
    assert units.how_read(printed, target) == how


def test_a_damping_per_radian_per_second_as_printed_is_listed_as_read(tmp_path):
    raw = entries("bo105")
    raw["main_rotor"]["lag_damping"] = {**raw["main_rotor"]["lag_damping"], "unit": "ft-lb/rad/sec",
                                        "value": raw["main_rotor"]["lag_damping"]["value"] / (LBF * FT)}
    printed = aircraft.load(write(raw, tmp_path / "damper.toml"))
    assert printed.data["main_rotor"]["lag_damping"] == pytest.approx(aircraft.load().data["main_rotor"]["lag_damping"],
                                                                      rel=1e-14)
    listed = {r[0]: r[3] for r in aircraft.check(printed.path).converted}
    assert listed["main_rotor.lag_damping"].endswith("ft-lb/rad/sec (lb as pound-force; read as ft-lb/(rad/sec))")


def test_pounds_are_a_mass_where_a_mass_is_wanted():
    from mbs.aircraft import units

    assert units.factor_to("lb", "kg") == 0.45359237 and not units.pound_force("lb", "kg")
    assert units.factor_to("lb/ft", "kg/m") == pytest.approx(0.45359237 / FT, rel=1e-15)  # a blade's mass per length
    assert units.factor_to("lb ft^2", "kg m^2") == pytest.approx(0.45359237 * FT**2, rel=1e-15)


@pytest.mark.parametrize("unit, target, words", [
    ("KN", "N", "'KN' could be kN or kn; write the symbol in its own case"),
    ("lbm", "N", "unit 'lbm' is a mass, not a force"),  # the pound-mass said so: never a force
    ("ft--lb", "N m", "cannot read 'ft--lb'"),
    ("cubits", "m", "unknown symbol 'cubits'"),
    ("KIAS", "m/s", "unit 'KIAS': an indicated airspeed, which the air's density turns into the true airspeed"),
    ("°F", "rad", "unknown symbol 'F'"),
    ("ft³", "m^2", "unit 'ft³' is a volume, not an area"),
    ("ft3/rad", "m^3", "unit 'ft3/rad' is a quantity in m\\^3/rad, not a volume"),
    ("(ft/s", "m/s", "unit '\\(ft/s': unbalanced parentheses"),
    ("ft/", "m", "a symbol is missing around '/'"),
    # neither reading a damping
    ("ft-lb/rad/sec/in", "N m s/rad", "unit 'ft-lb/rad/sec/in' is a quantity in kg/\\(s rad\\), not a damping"),
])
def test_a_printed_unit_that_is_ambiguous_or_unreadable_is_refused(unit, target, words):
    from mbs.aircraft import units

    with pytest.raises(units.UnitError, match=words):
        units.factor_to(unit, target)


def test_loads_and_a_mass_in_pounds_as_printed_load_as_in_si_and_the_check_says_how(tmp_path):
    """The Bo105's fuselage polynomials (N, N m) written in lb and ft-lb and its mass in LB give
    the same aircraft to round-off; the check lists them as read with lb a pound-force."""
    raw = entries("bo105")
    fa = raw["fuselage_aero"]
    fa["X"] = {**fa["X"], "value": [v / LBF for v in fa["X"]["value"]], "unit": "lb"}
    fa["M"] = {**fa["M"], "value": [v / (LBF * FT) for v in fa["M"]["value"]], "unit": "ft-lb"}
    raw["aircraft"]["mass"] = {**raw["aircraft"]["mass"], "value": raw["aircraft"]["mass"]["value"] / 0.45359237,
                               "unit": "LB"}
    printed, plain = aircraft.load(write(raw, tmp_path / "pounds.toml")), aircraft.load()
    for section, key in (("fuselage_aero", "X"), ("fuselage_aero", "M")):
        assert np.allclose(printed.data[section][key], plain.data[section][key], rtol=1e-14, atol=0)
    assert printed.data["aircraft"]["mass"] == pytest.approx(plain.data["aircraft"]["mass"], rel=1e-15)
    listed = {r[0]: r[3] for r in aircraft.check(printed.path).converted}
    assert listed["fuselage_aero.X"].endswith("lb (lb as pound-force)")
    assert listed["fuselage_aero.M"].endswith("ft-lb (lb as pound-force)")
    assert "pound-force" not in listed["aircraft.mass"]


def test_a_diameter_tip_speeds_and_minutes_of_arc_as_a_flight_manual_prints_them(tmp_path):
    """A new user's R22 and AH-1: '25 ft 2 in' diameters, tail-rotor speeds printed as tip speeds
    and a precone of 1 deg 11 min had to be converted by hand. A diameter gives the radius, a main
    rotor's tip speed its speed, a tail rotor's its gear ratio, each listed as converted with its
    source; arcmin is an angle (and 'min' for one says so); a diameter beside a radius, a tip speed
    beside a rotor speed (a flight manual prints both) are taken when they agree within 0.5 %."""
    from mbs.aircraft import units

    d = aircraft.load("bo105").data
    mr, tr = d["main_rotor"], d["tail_rotor"]
    raw = entries("bo105")
    del raw["main_rotor"]["radius"], raw["main_rotor"]["omega"], raw["tail_rotor"]["gear_ratio"]
    raw["main_rotor"]["diameter"] = {"value": 2 * mr["radius"] / 0.3048, "unit": "ft", "source": "POH"}
    raw["main_rotor"]["tip_speed"] = {"value": mr["omega"] * mr["radius"] / 0.3048, "unit": "ft/s", "source": "POH"}
    raw["tail_rotor"]["tip_speed"] = {"value": tr["gear_ratio"] * mr["omega"] * tr["radius"], "unit": "m/s",
                                      "source": "POH"}
    report = aircraft.check(write(raw, tmp_path / "printed.toml"))
    assert report.ok, report.problems
    got = aircraft.load(tmp_path / "printed.toml").data
    for section, key in (("main_rotor", "radius"), ("main_rotor", "omega"), ("tail_rotor", "gear_ratio")):
        assert got[section][key] == pytest.approx(d[section][key], rel=1e-12), key
    listed = {e: (how, source) for e, _, _, how, source in report.converted}
    assert listed["main_rotor.radius"] == ("half the diameter " + f"{2 * mr['radius'] / 0.3048!r} ft "
                                           "(main_rotor.diameter)", "POH")
    assert listed["main_rotor.omega"][0].startswith("main_rotor.tip_speed") and "main_rotor.radius 4.91 m" in \
        listed["main_rotor.omega"][0]
    assert listed["tail_rotor.gear_ratio"][0].startswith("tail_rotor.tip_speed")
    raw["main_rotor"]["radius"] = {"value": 4.91, "unit": "m", "source": "S1"}  # both as printed, agreeing
    raw["main_rotor"]["omega"] = {"value": 424, "unit": "rpm", "source": "POH"}  # 44.40 rad/s against 44.4
    both = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert both.ok  # and each printed check says what it gave and which value the model flies
    listed = {e: how for e, _, _, how, _ in both.converted}
    assert listed["main_rotor.diameter"].endswith("ft, checked against main_rotor.radius: it gives 4.91 against 4.91 "
                                                  "(+0 %); the model flies main_rotor.radius")
    assert "checked against main_rotor.omega" in listed["main_rotor.tip_speed"]
    raw["main_rotor"]["radius"]["value"] = 5.0
    radius, omega = aircraft.check(write(raw, tmp_path / "differ.toml")).problems  # the tip speed over it too
    assert radius.startswith("main_rotor.diameter: gives main_rotor.radius = 4.91, against the file's 5 (-1.8 %)")
    assert omega.startswith("main_rotor.tip_speed: gives main_rotor.omega = 43.6")
    assert units.convert(71.0, "arcmin", "rad") == pytest.approx(math.radians(1 + 11 / 60), rel=1e-15)
    with pytest.raises(units.UnitError, match="minutes of arc are arcmin"):
        units.convert(71.0, "min", "rad")


def test_the_control_ranges_are_shown_in_the_file_s_conventions_where_those_differ(tmp_path):
    """A new user's EC135 gave collective_radius 0.75 and its collective range at 0.75 R, which the
    model reads at the root, without a word. The check now shows each range the file's conventions
    turn, as those conventions state it."""
    from mbs.aircraft import checks

    assert checks.control_range_notes(aircraft.load("bo105").data) == []
    path = edited(tmp_path / "c75.toml", "bo105", **{"conventions.collective_radius": 0.75})
    d = aircraft.load(path).data
    (line,) = checks.control_range_notes(d)
    low = math.degrees(d["main_rotor"]["collective_min"] + 0.75 * d["main_rotor"]["twist"])
    assert line.startswith("main_rotor.collective_min, _max: the model's collective range 7.62 to 23.61 deg is "
                           f"{low:.4g} to ")
    assert any("tail_collective range" in w for w in checks.control_range_notes(aircraft.load("puma").data))


def test_a_main_rotor_delta3_couples_pitch_to_flapping_by_its_tangent(tmp_path, capsys):
    """A new user's EC135 (a bearingless rotor with delta3 = 7.5 deg, as its paper prints it) could
    not be given it: main_rotor.delta3 skews the flap hinge as the tail rotor's is. In hover, the
    blades coned by beta0 lose tan(delta3) beta0 of pitch, which the trim's collective makes up:
    for 30 deg on the Bo105, within 1 % (measured 1.0798 against 1.0805 deg); the flapping reported
    is the blades' (the hinge's angle times cos delta3); with the swashplate's own delta3 it is
    refused as the same coupling given twice."""
    from mbs.cli import main

    path = tmp_path / "d3.toml"
    raw = entries("bo105")
    raw["main_rotor"]["delta3"] = {"value": 30.0, "unit": "deg", "source": "test"}
    write(raw, path)
    trims = {}
    for name, file in (("plain", "bo105"), ("skewed", str(path))):
        assert main(["trim", "forward-flight", "--aircraft", file, "--speed", "0", "--json", "--quiet"]) == 0
        trims[name] = json.loads(capsys.readouterr().out)
    gained = trims["skewed"]["controls"]["collective"] - trims["plain"]["controls"]["collective"]
    beta0 = trims["skewed"]["flapping"]["beta0"]
    assert gained == pytest.approx(math.tan(math.radians(30.0)) * beta0, rel=0.01), (gained, beta0)
    assert beta0 == pytest.approx(trims["plain"]["flapping"]["beta0"], rel=0.1)
    raw["swashplate"]["horn"]["value"] = "blade"  # a horn on the blade, whose delta3 is the coupling
    raw["swashplate"].pop("ball_radius")
    raw["swashplate"]["delta3"] = {"value": 10.0, "unit": "deg", "source": "test"}
    both = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert any(p.startswith("main_rotor.delta3: the swashplate's delta3 is the same coupling") for p in both.problems)


def test_an_elastic_blade_frequency_no_uniform_blade_has_is_the_entry_s_problem(tmp_path):
    """A new user's Mi-8 kept the Puma's [elastic_blade] section: every command stopped with
    SciPy's 'f(a) and f(b) must have different signs'. It is the entry's problem, naming the
    frequencies the rotor's uniform blade can have and the ways out."""
    path = edited(tmp_path / "low.toml", "bo105", **{"elastic_blade.flap_frequency": 0.9, "elastic_blade.flap_stiffness": None})
    report = aircraft.check(path)
    assert not report.ok
    (line,) = report.problems
    assert line.startswith("elastic_blade.flap_frequency: 0.9/rev is beyond what this rotor's uniform blade gives (")
    assert "give elastic_blade.flap_stiffness" in line and "leave [elastic_blade] out" in line
