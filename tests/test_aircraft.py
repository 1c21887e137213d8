"""Aircraft files: units, validation (every broken file named by its entry), derived values, the
Bo105 from its file unchanged, a rotor of another blade count, the sense of rotation (a
mirrored aircraft flies the mirrored motion), and the packaged Lynx and Puma."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from aircraft_files import edited, entries, mirrored, with_tail_rotor, write
from test_cli_errors import run_main
from mbs import aircraft, cli, scenes
from mbs.aircraft import derived, performance, units
from mbs.aircraft.schema import ENTRIES
from mbs.simulate import simulate

DATA = Path(__file__).with_name("data")


# -- units ------------------------------------------------------------------------------------

@pytest.mark.parametrize("value, unit, si, target", [
    (10.0, "ft", 3.048, "m"), (100.0, "lb", 45.359237, "kg"), (1.0, "slug ft^2", 1.3558179483314004, "kg m^2"),
    (424.0, "rpm", 44.40117617, "rad/s"), (3.0, "deg", 0.05235987756, "rad"), (1.0, "ft lbf/rad", 1.3558179483, "N m/rad"),
    (1.0, "lbf", 4.4482216152605, "N"), (1.0, "hp", 745.69987158227, "W"), (100.0, "kt", 51.444444444, "m/s"),
    (0.002377, "slug/ft^3", 0.002377 * 515.378818, "kg/m^3"), (6.0, "1/deg", 343.77467708, "1/rad"), (2.0, "ft^2", 0.18580608, "m^2"),
])
def test_units_convert_to_si_and_back(value, unit, si, target):
    assert units.convert(value, unit, target) == pytest.approx(si, rel=1e-8)
    assert units.convert(units.convert(value, unit, target), target, unit) == pytest.approx(value, rel=1e-14)


@pytest.mark.parametrize("unit, target, words", [("kg", "m", "a mass, not a length"), ("deg", "-", "an angle"),
                                                 ("rad/s", "1/rev", "per revolution"), ("furlong", "m", "unknown symbol")])
def test_units_of_another_kind_are_refused(unit, target, words):
    with pytest.raises(units.UnitError, match=words):
        units.convert(1.0, unit, target)


# -- the Bo105 from its file --------------------------------------------------------------------

def test_bo105_from_its_file_equals_the_scenes_before_the_file():
    """Every scene, one revolution from its own initial state at the recorded step, equals the run
    recorded before the aircraft became a file (``tests/data/scenes_before_aircraft_files.json``)
    to 1e-12."""
    for name, ref in json.loads((DATA / "scenes_before_aircraft_files.json").read_text()).items():
        sim = simulate(name, 1.0, steps_per_rev=ref["steps"])
        info = sim.system.info
        assert list(info.state_names) == ref["state_names"], name
        then = [info.output_names.index(n) for n in ref["output_names"]]  # the outputs of then (loads came later)
        np.testing.assert_array_equal(sim.params, ref["params"], err_msg=name)
        np.testing.assert_array_equal(sim.traj.x[0], ref["x0"], err_msg=name)
        for got, want in ((sim.traj.x[-1], ref["x_1rev"]), (sim.outputs[-1][then], ref["y_1rev"])):
            assert np.all(np.abs(got - want) <= 1e-12 * (1 + np.abs(want))), name


# -- broken files ---------------------------------------------------------------------------------

def _raw_with(change):
    raw = entries("bo105")
    change(raw)
    return raw


def _set(section, key, **fields):
    return lambda raw: raw[section][key].update(fields)


def _drop(section, key):
    return lambda raw: raw[section].pop(key)


def _add(section, key, entry):
    return lambda raw: raw.setdefault(section, {}).__setitem__(key, entry)


BROKEN = {  # what is wrong -> (the change, the words of the one line)
    "missing entry": (_drop("main_rotor", "radius"), "main_rotor.radius: missing"),
    "typo in an entry": (_add("main_rotor", "raduis", {"value": 4.9, "unit": "m", "source": "S1"}),
                         "main_rotor.raduis: unknown entry (did you mean 'radius'?)"),
    "unknown section": (_add("main_rotr", "radius", {"value": 4.9, "unit": "m", "source": "S1"}),
                        "[main_rotr]: unknown section (did you mean 'main_rotor'?)"),
    "unknown field": (lambda raw: raw["aircraft"]["mass"].update(vlaue=2.0), "aircraft.mass: unknown field 'vlaue'"),
    "no source": (lambda raw: raw["aircraft"]["mass"].pop("source"), "aircraft.mass: no source"),
    "wrong unit": (_set("main_rotor", "radius", unit="kg"), "main_rotor.radius: unit 'kg' is a mass, not a length"),
    "missing unit": (lambda raw: raw["main_rotor"]["chord"].pop("unit"), "main_rotor.chord: no unit"),
    "unknown unit": (_set("main_rotor", "chord", unit="cubit"), "main_rotor.chord: unit 'cubit': unknown symbol"),
    "not a number": (_set("main_rotor", "chord", value="0.27 m"), "main_rotor.chord: '0.27 m' is not a number"),
    "negative mass": (_set("aircraft", "mass", value=-2200.0), "aircraft.mass: -2200 kg must be > 0"),
    "triangle inequality": (_set("aircraft", "Izz", value=9000.0), "aircraft.Izz: principal moments"),
    "hinge outside the blade": (_set("main_rotor", "flap_hinge_offset", value=5.2),
                                "main_rotor.flap_hinge_offset: 5.2 m puts the hinge outside the blade"),
    "twist beyond 45 deg": (_set("main_rotor", "twist", value=-50.0, unit="deg"), "main_rotor.twist: -0.872665 rad"),
    "fractional blade count": (_set("main_rotor", "n_blades", value=4.5), "main_rotor.n_blades: 4.5 must be a whole"),
    "unknown rotation": (_set("main_rotor", "rotation", value="cw"), "main_rotor.rotation: 'cw' is not one of"),
    "derived without override": (_add("main_rotor", "blade_mass", {"value": 30.0, "unit": "kg", "source": "EST"}),
                                 "main_rotor.blade_mass: is derived"),
    "override of plain data": (_set("main_rotor", "chord", override=True), "main_rotor.chord: override applies to "
                                                                          "derived entries only"),
    "teetering with three blades": (_set("tail_rotor", "n_blades", value=3),
                                    "tail_rotor.n_blades: a teetering tail rotor has 2 blades"),
    "seesaw on a rigid hub": (_set("tail_rotor", "hub_type", value="rigid"),
                              "tail_rotor.seesaw_mass, seesaw_size, teeter_stiffness: apply only when "
                              "tail_rotor.hub_type = 'teetering'"),
    "control range reversed": (_set("main_rotor", "collective_min", value=0.5),
                               "main_rotor.collective_min: 28.65 deg is not below collective_max"),
    "vector of the wrong length": (_set("fuselage_aero", "X", value=[1.0, 2.0]),
                                   "fuselage_aero.X: must be a list of 4 numbers"),
    "entry not a table": (lambda raw: raw["main_rotor"].__setitem__("radius", 4.91),
                          "main_rotor.radius: write it as { value = ..."),
    "rotor heavier than the aircraft": (_set("aircraft", "mass", value=150.0), "aircraft.mass: 150 kg leaves"),
    "supersonic tip": (_set("environment", "speed_of_sound", value=200.0), "main_rotor.radius: tip Mach number 1.090"),
    "delta3 beyond 70 deg": (_set("tail_rotor", "delta3", value=80.0, unit="deg"), "tail_rotor.delta3: 1.39626 rad"),
    "delta3 on a rigid hub": (lambda raw: with_tail_rotor(raw, hub_type=("rigid", "-"), delta3=(30.0, "deg")),
                              "tail_rotor.delta3: 30 deg on a rigid hub, which does not flap"),
    "flap hinge outboard of the root": (lambda raw: with_tail_rotor(raw, hub_type=("flapping", "-"),
                                                                    flap_hinge_offset=(0.3, "m")),
                                        "tail_rotor.flap_hinge_offset: 0.3 m lies outboard of the aerodynamic root"),
    "flap spring on a teetering hub": (_add("tail_rotor", "flap_stiffness", {"value": 10.0, "unit": "N m/rad",
                                                                            "source": "EST"}),
                                       "tail_rotor.flap_stiffness: applies only when tail_rotor.hub_type = 'flapping'"),
}


@pytest.mark.parametrize("what", list(BROKEN))
def test_a_broken_aircraft_file_is_one_line_naming_its_entry(what, tmp_path, capsys):
    change, words = BROKEN[what]
    path = write(_raw_with(change), tmp_path / "broken.toml")
    code, err = run_main(["simulate", "hover", "--aircraft", str(path), "--out", str(tmp_path / "out")], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and words in lines[0] and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()
    code, err = run_main(["aircraft", "check", str(path)], capsys)  # every problem, one line each
    assert code == 2 and words in err.splitlines()[0] and "Traceback" not in err, err


def test_entries_left_from_the_other_model_are_one_line_naming_them_all(tmp_path):
    """The template's seven polynomial entries kept after switching to tables: one problem that
    names them all and what they need, not seven."""
    tables = _add("fuselage_aero", "model", {"value": "tables", "unit": "-", "source": "R1"})
    path = write(_raw_with(tables), tmp_path / "tables.toml")
    lines = [p for p in aircraft.check(path).problems if "only when" in p]
    assert lines == ["fuselage_aero.v_ref, X, Y, Z, M, N, angle_limit: apply only when fuselage_aero.model = "
                     "'polynomials' (7 entries); leave them out"]


def test_a_toml_syntax_error_names_its_line(tmp_path, capsys):
    path = tmp_path / "syntax.toml"
    path.write_text("[aircraft]\nmass = { value = 2200.0, unit = \"kg\"\n")
    code, err = run_main(["aircraft", "check", str(path)], capsys)
    assert code == 2 and "line 2" in err


def test_check_lists_every_problem_of_a_file(tmp_path, capsys):
    raw = _raw_with(lambda r: (r["main_rotor"].pop("radius"), r["aircraft"]["mass"].update(unit="m")))
    code, err = run_main(["aircraft", "check", str(write(raw, tmp_path / "two.toml"))], capsys)
    assert code == 2
    assert "main_rotor.radius: missing" in err and "aircraft.mass: unit 'm'" in err


# -- each fact in one place ---------------------------------------------------------------------

def test_a_five_blade_rotor_has_five_blades_72_degrees_apart_and_trims(tmp_path):
    path = edited(tmp_path / "five.toml", drop_overrides=True,
                  **{"main_rotor.n_blades": 5, "main_rotor.radius": 5.5, "tail_rotor.hub_x": -6.8})
    craft = aircraft.load(path)
    mr = craft.data["main_rotor"]
    model = scenes.get("hover", craft).model()
    blades = [model.bodies[f"blade{k}"] for k in range(1, 6)]
    assert "blade6" not in model.bodies
    for k, b in enumerate(blades):
        angle = math.atan2(b.frame[1, 0], b.frame[0, 0])
        assert angle == pytest.approx(math.remainder(2 * math.pi * k / 5, 2 * math.pi), abs=1e-12)
        assert b.mass == pytest.approx(3 * mr["I_flap"] / 5.5**2, rel=1e-14)
        inertia_about_hinge = b.inertia[2, 2] + b.mass * b.com[0] ** 2
        assert inertia_about_hinge == pytest.approx(mr["I_flap"] + b.mass * mr["chord"] ** 2 / 12, rel=1e-12)
    from mbs.analysis.trim import trim

    res = trim(scenes.get("hover", craft))
    assert res.converged, res.reason
    assert res.thrust == pytest.approx(craft.data["aircraft"]["mass"] * 9.80665, rel=0.02)


def test_blades_of_a_config_beyond_the_aircraft_are_refused():
    from dataclasses import replace

    from mbs.models import helicopter

    with pytest.raises(ValueError, match="has 4 blades"):
        helicopter.build(replace(helicopter.Config(), blades=5))


def test_changing_the_radius_recomputes_every_derived_value(tmp_path):
    base = aircraft.load(edited(tmp_path / "a.toml", drop_overrides=True)).data
    new = aircraft.load(edited(tmp_path / "b.toml", drop_overrides=True,
                               **{"main_rotor.radius": 5.5, "tail_rotor.hub_x": -6.8})).data
    mr, env = new["main_rotor"], new["environment"]
    assert mr["blade_mass"] == pytest.approx(3 * mr["I_flap"] / 5.5**2, rel=1e-14) != base["main_rotor"]["blade_mass"]
    lag_inertia = mr["I_flap"] + mr["blade_mass"] * mr["chord"] ** 2 / 12  # the box blade about its lag hinge
    assert mr["lag_stiffness"] == pytest.approx(mr["lag_frequency"] ** 2 * lag_inertia * mr["omega"] ** 2, rel=1e-14)
    ct = new["aircraft"]["mass"] * env["g"] / (env["rho"] * math.pi * 5.5**2 * (mr["omega"] * 5.5) ** 2)
    assert mr["tip_loss"] == pytest.approx(1 - math.sqrt(2 * ct) / 4, rel=1e-14) != base["main_rotor"]["tip_loss"]
    hover = performance.hover(new)
    tr = new["tail_rotor"]
    tail_ct = hover.main.torque / abs(mr["hub_x"] - tr["hub_x"]) / (
        env["rho"] * math.pi * tr["radius"] ** 2 * (tr["gear_ratio"] * mr["omega"] * tr["radius"]) ** 2)
    assert tr["tip_loss"] == pytest.approx(1 - math.sqrt(2 * tail_ct) / 2, rel=1e-12) != base["tail_rotor"]["tip_loss"]
    assert new["wake"]["core"] == mr["root_cutout"]
    eb = new["elastic_blade"]
    assert eb["flap_frequency"] == pytest.approx(math.sqrt(1 + mr["flap_stiffness"] / (mr["I_flap"] * mr["omega"] ** 2)))
    from mbs.flexible.uniform_blade import beam_frequencies, blade_from_data

    beam = beam_frequencies(blade_from_data(new), mr["omega"])
    for k in ("flap", "lag", "torsion"):
        assert beam[k] / mr["omega"] == pytest.approx(eb[f"{k}_frequency"], rel=1e-9)


def test_lag_stiffness_with_a_hinge_offset_gives_the_lag_frequency(tmp_path):
    """An offset hinge with the derived spring: the single blade's lag frequency from the AD
    Jacobian equals the file's."""
    craft = aircraft.load(edited(tmp_path / "e.toml", drop_overrides=True, **{"main_rotor.flap_hinge_offset": 0.4}))
    assert derived.lag_stiffness(craft.data["main_rotor"]) > 0
    from mbs.linearize import rhs_jacobian
    from mbs.dynamics import symbolic

    model = scenes.get("single-blade", craft).model()
    model.gravity = np.zeros(3)
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    lam = np.linalg.eigvals(np.array(rhs_jacobian(sym["rhs"])(np.zeros(sym.layout.nx), 0.0, p)))
    omega = craft.data["main_rotor"]["omega"]
    assert min(abs(lam)) / omega == pytest.approx(craft.data["main_rotor"]["lag_frequency"], rel=1e-9)


def test_an_override_is_used_and_reported_when_it_differs(tmp_path):
    raw = entries("bo105")
    raw["main_rotor"]["blade_mass"].update(value=34.0)
    report = aircraft.check(write(raw, tmp_path / "o.toml"))
    assert report.ok and aircraft.load(tmp_path / "o.toml").data["main_rotor"]["blade_mass"] == 34.0
    assert any(w.startswith("main_rotor.blade_mass: the override 34 kg differs by +17.9 %") for w in report.warnings)


def test_a_new_aircraft_from_the_template_loads_and_warns_until_filled_in(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    assert run_main(["aircraft", "new", "My Heli", "--out", str(path)], capsys)[0] == 0
    craft = aircraft.load(path)
    assert craft.name == "My Heli"
    bo105 = aircraft.load()
    written = 0
    for section in ("main_rotor", "tail_rotor", "aircraft"):
        for key, value in bo105.data[section].items():
            if bo105.data.meta[section][key]["origin"] == "file" and ENTRIES[section][key].default is None:
                written += key != "name" and craft.data[section][key] == value
    applies = lambda s, e: not e.only_if or bo105.data[s][e.only_if[0]] == e.only_if[1]  # noqa: E731
    assert written == sum(e.default is None and applies(s, e) for s in ("main_rotor", "tail_rotor", "aircraft")
                          for e in ENTRIES[s].values()) - 1  # all but the name
    assert cli.main(["aircraft", "check", str(path)]) == 0
    assert "still carry the template's Bo105 values" in capsys.readouterr().out
    text = path.read_text()  # the CG's stations are offered once, in [aircraft]
    assert text.count("cg_station = ") == 1 and "reference_station" not in text
    # the Bo105's inertias are its whole aircraft's: the template says so, where it read them as the
    # airframe's and added the rotors (Ixx +62 %)
    assert craft.data["aircraft"]["inertia"] == "whole-aircraft" and '\ninertia = { value = "whole-aircraft"' in text
    # an entry needed once its switch is set says so, one with a default says it only applies: a
    # Bell 206 trial read the engine's commented ratings as defaults
    line = next(x for x in text.splitlines() if x.startswith("# takeoff_power = "))
    assert line.endswith('# required with model = "turboshaft" or "piston"'), line
    line = next(x for x in text.splitlines() if x.startswith("# oei_power = "))
    assert line.endswith('# required with model = "turboshaft" or "piston", unless one engine'), line
    line = next(x for x in text.splitlines() if x.startswith("# flap_stiffness = "))
    assert line.endswith('# only with hub_type = "flapping"'), line


def test_inertias_read_as_the_airframes_by_default_are_warned_of(tmp_path):
    """A new user's CH-53D, its report's inertias written without aircraft.inertia, had the rotors
    added to them (Ixx +59 %) with no word. Left out, the reading is warned of with what the
    rotors add; given either way, it is not."""
    from mbs.aircraft import mass

    raw = entries("bo105")
    del raw["aircraft"]["inertia"]
    report = aircraft.check(write(raw, tmp_path / "default.toml"))
    d = aircraft.load(tmp_path / "default.toml").data
    added = np.diag(mass.whole_aircraft(d).inertia) / np.array([d["aircraft"][k] for k in ("Ixx", "Iyy", "Izz")]) - 1
    words = [w for w in report.warnings if w.startswith("aircraft.inertia: not given")]
    assert len(words) == 1 and f"Ixx {100 * added[0]:+.0f} %" in words[0] and added[0] > 0.5, words
    assert 'give inertia = "whole-aircraft"' in words[0]
    for reading in ("airframe", "whole-aircraft"):
        raw["aircraft"]["inertia"] = {"value": reading, "unit": "-", "source": "report"}
        warnings = aircraft.check(write(raw, tmp_path / f"{reading}.toml")).warnings
        assert not any(w.startswith("aircraft.inertia: not given") for w in warnings), reading


def test_the_templates_optional_blocks_load_when_uncommented(tmp_path, capsys):
    """Removing one '# ' from each line of the commented [swashplate] and [elastic_blade] blocks
    gives a file that loads (it was invalid TOML: value = None), with the Bo105's swashplate; a
    file without the block is refused by the swashplate scenes with that way out."""
    path = tmp_path / "mine.toml"
    assert run_main(["aircraft", "new", "My Heli", "--out", str(path)], capsys)[0] == 0
    code, err = run_main(["simulate", "forward-flight-swashplate", "--aircraft", str(path), "--out", str(tmp_path / "o")],
                         capsys)
    assert code == 2 and "has no [swashplate] section" in err and "uncomment the [swashplate] block" in err
    lines, block = [], False
    for line in path.read_text().splitlines():
        block = line.startswith(("# [swashplate]", "# [elastic_blade]")) or (block and not line.startswith("["))
        lines.append(line[2:] if block and line.startswith("# ") else line)
    (tmp_path / "full.toml").write_text("\n".join(lines))
    craft = aircraft.load(tmp_path / "full.toml")
    assert craft.data["swashplate"] == aircraft.load().data["swashplate"]
    assert craft.data["elastic_blade"]["torsion_frequency"] == aircraft.load().data["elastic_blade"]["torsion_frequency"]


# -- the sense of rotation ------------------------------------------------------------------------

MIRROR = {"fuselage.y": -1, "fuselage.qx": -1, "fuselage.qz": -1, "fuselage.v": -1, "fuselage.p": -1,
          "fuselage.r": -1}


def test_a_mirrored_aircraft_flies_the_mirrored_motion(tmp_path):
    """The Bo105 mirrored in its x-z plane turns clockwise with its tail rotor on the other side.
    From the mirrored state, one revolution of forward flight (every aerodynamics switch on) is
    the mirror of the Bo105's: the same flap, lag, teeter and inflow; lateral motion reversed;
    the same thrust, powers, shaft torques and blade root loads (whose components read as a
    counter-clockwise rotor's); hub loads in body axes with their lateral parts reversed."""
    craft = aircraft.load(mirrored(tmp_path / "mirror.toml"))
    assert craft.data["main_rotor"]["rotation"] == "clockwise"
    plain, mirror = scenes.get("forward-flight"), scenes.get("forward-flight", craft)
    sys_a, sys_b = plain.system(), mirror.system()
    names = sys_a.info.state_names
    assert list(sys_b.info.state_names) == list(names)
    flip = np.array([MIRROR.get(n, 1) for n in names])
    x0, p = sys_a.x0(), sys_a.params()
    h = plain.revolution(sys_a, p) / 100
    a = sys_a.run(x0, 0.0, h, 100, every=100, p=p).x[-1]
    b = sys_b.run(flip * x0, 0.0, h, 100, every=100, p=p).x[-1]
    np.testing.assert_allclose(flip * b, a, rtol=1e-10, atol=1e-10)
    assert abs(a[names.index("fuselage.v")]) > 1e-3  # there is lateral motion to reverse
    ya = sys_a.history("outputs", sys_a.run(x0, 0.0, h, 10, p=p), p)
    yb = sys_b.history("outputs", sys_b.run(flip * x0, 0.0, h, 10, p=p), p)
    lateral = ("fin.sidewash", ".hub.force_y", ".hub.moment_x", ".hub.moment_z")  # body axes: y reversed
    sideways = np.array([-1.0 if n.endswith(lateral) else 1.0 for n in sys_a.info.output_names])
    assert sum(sideways < 0) == 7 and any(n.startswith("blade1.root") for n in sys_a.info.output_names)
    scale = np.maximum(1.0, np.abs(ya).max(axis=0))  # loads of kN: round-off relative to each output's size
    np.testing.assert_allclose(sideways * yb / scale, ya / scale, rtol=0, atol=1e-10)


# -- the packaged aircraft ------------------------------------------------------------------------

@pytest.mark.parametrize("name, lock, flap_per_rev", [("lynx", 7.12, math.sqrt(1.193)), ("puma", 9.374, 1.026)])
def test_packaged_aircraft_have_their_published_lock_number_and_flap_frequency(name, lock, flap_per_rev):
    """Padfield, Helicopter Flight Dynamics, Tables 4B.1 and 4B.2: the Lynx's Lock number 7.12 and
    lambda_beta^2 = 1.193; the Puma's Lock number 9.374 and lambda_beta = 1.026 (both derived from
    the tables' I_beta, K_beta, a, c, R)."""
    report = aircraft.check(name)
    assert report.ok and not [w for w in report.warnings if "TEMPLATE" in w]
    figures = {n: v for n, v, _ in report.figures}
    assert figures["Lock number"] == pytest.approx(lock, abs=0.02)
    assert figures["flap frequency"] == pytest.approx(flap_per_rev, abs=2e-3)


def test_a_fan_in_fin_tail_rotor_of_13_blades_is_taken_and_19_refused(tmp_path):
    """The Gazelle's Fenestron has 13 blades (NASA TM-88370); a rigid tail rotor of 13 reads, 19 is named."""
    for n, ok in ((13, True), (19, False)):
        raw = with_tail_rotor(entries("bo105"), hub_type=("rigid", "-"), n_blades=(n, "-"))
        problems = aircraft.check(write(raw, tmp_path / f"fan{n}.toml")).problems
        assert (not any("n_blades" in p for p in problems)) == ok, problems
        assert ok or any("tail_rotor.n_blades: 19 is outside [2, 18]" in p for p in problems), problems


def test_a_tail_rotor_overlapping_the_main_disc_in_plan_view_is_warned_and_one_under_it_refused(tmp_path):
    """The UH-1H's tail disc overlaps its main rotor's by about 0.03 m in plan view (the blades
    clear by coning and height): a warning giving the overlap at the hub plane, sqrt(R_t² − Δz²)
    wide there; a tail hub under the main disc is refused, named."""
    d = aircraft.load("bo105").data
    mr, tr = d["main_rotor"], d["tail_rotor"]
    half = math.sqrt(tr["radius"] ** 2 - (tr["hub_z"] - mr["hub_z"]) ** 2)
    near = mr["hub_x"] - (mr["radius"] + half - 0.05)
    report = aircraft.check(write(with_tail_rotor(entries("bo105"), hub_x=(near, "m")), tmp_path / "near.toml"))
    assert report.ok, report.problems
    assert any(w.startswith("tail_rotor.hub_x: the tail-rotor disc overlaps the main rotor's by 0.05 m")
               for w in report.warnings), report.warnings
    assert not any("overlaps" in w for w in aircraft.check("bo105").warnings)
    report = aircraft.check(write(with_tail_rotor(entries("bo105"), hub_x=(-3.0, "m")), tmp_path / "under.toml"))
    assert any(p.startswith("tail_rotor.hub_x: -3 m puts the tail-rotor hub under the main rotor's disc")
               for p in report.problems), report.problems


def test_a_number_printed_in_parts_is_read_as_printed(tmp_path):
    """A new user's R22 flight manual prints the rotor diameter as 25 ft 2 in and the tail precone as
    1 deg 11 min; both had to be converted by hand. A list of parts with a unit each is read
    as their sum and listed as printed; text in parts, parts of two signs and a list without a
    unit per part are refused saying how to write them."""
    from aircraft_files import entries, write

    raw = entries("bo105")
    raw["main_rotor"].pop("radius")
    raw["main_rotor"]["diameter"] = {"value": [32, 2.5], "unit": "ft, in", "source": "POH"}
    raw["tail_rotor"]["precone"] = {"value": [1, 11], "unit": "deg, arcmin", "source": "POH"}
    report = aircraft.check(write(raw, tmp_path / "parts.toml"))
    assert report.ok, report.problems
    d = aircraft.load(tmp_path / "parts.toml").data
    assert d["main_rotor"]["radius"] == pytest.approx((32 * 0.3048 + 2.5 * 0.0254) / 2, rel=1e-15)
    assert d["tail_rotor"]["precone"] == pytest.approx(np.radians(1 + 11 / 60), rel=1e-15)
    listed = "\n".join(f"{row[0]} {row[3]}" for row in report.converted)
    assert "main_rotor.diameter from 32 ft 2.5 in" in listed and "tail_rotor.precone from 1 deg 11 arcmin" in listed
    assert "main_rotor.radius half the diameter 32 ft 2.5 in (main_rotor.diameter)" in listed
    from mbs.aircraft.reader import printed  # a mixing row's units differ in kind: listed as a list, not in parts

    assert printed({"value": [2.0, 0.5, 0, 0, 0], "unit": "deg, deg/in, deg/in, deg/in, deg/in"}) == \
        "[2.0, 0.5, 0, 0, 0] deg, deg/in, deg/in, deg/in, deg/in"
    hint = 'value = [25, 2], unit = "ft, in"'
    for value, unit, words in (("25 ft 2 in", "ft", hint), ([25, 2], "ft", hint), ([1, -11], "deg, arcmin", "one sign"),
                               ([25, 2, 1], "ft, in", hint)):
        raw["main_rotor"]["diameter"] = {"value": value, "unit": unit, "source": "POH"}
        problems = aircraft.check(write(raw, tmp_path / "bad.toml")).problems
        assert any(p.startswith("main_rotor.diameter: ") and words in p for p in problems), (value, problems)


def test_a_figure_of_zero_prints_without_a_sign():
    """A Bell 412 trial's check printed 'whole-aircraft Ixz (about the CG) -0 kg m^2' for an Ixz
    left out (its sign times zero)."""
    from mbs.aircraft.report import _fmt

    assert _fmt(-0.0) == "0" and _fmt(-473.08) == "-473.08" and _fmt(3) == "3"


def test_a_small_helicopters_drag_area_and_the_templates_hub_and_accessories_are_checked_for_size(tmp_path):
    """A new user's X-Cell 60 (8.2 kg, R 0.775 m): its published 0.1 m^2 drag area (0.053 of the
    disc) was called no helicopter's, while the template's Bo105 hub drag (0.25 m^2, 2.5 times its
    fuselage's) and accessory power (7.5 kW, six times its hover power) passed without a word."""
    import copy

    from mbs.aircraft.report import _drag_area_note

    d = copy.deepcopy(aircraft.load().data)  # the loaded aircraft is shared: change a copy
    f = 1.02  # m^2: the Bo105's drag area at zero angles
    for radius, warned in ((1.9, False), (1.5, True), (2.0, True), (4.91, False)):  # shares 0.090, 0.14, 0.081, 0.013
        d["main_rotor"]["radius"] = radius
        words = _drag_area_note(d)
        assert bool(words) == warned, (radius, words)
        assert not words or f"{f / (math.pi * radius**2):.3g} of the main rotor's disc area" in words[0]
    raw = entries("bo105")
    raw["hub_drag"]["flat_plate_area"].update(value=1.5)
    raw["engine"]["accessory_power"].update(value=400e3)
    warnings = aircraft.check(write(raw, tmp_path / "big.toml")).warnings
    assert any(w.startswith("hub_drag.flat_plate_area: 1.5 m^2, more than the fuselage's drag area at zero angles "
                            "(1.02 m^2)") for w in warnings), warnings
    assert any(w.startswith("engine.accessory_power: 4e+05 W, more than both rotors' hover power (3.622e+05 W)")
               for w in warnings), warnings
    assert not any(w.startswith(("hub_drag", "engine.accessory")) for w in aircraft.check("bo105").warnings)
