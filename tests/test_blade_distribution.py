"""Blade distributions along the span: chord, twist, mass and section inertias per length; the
rigid blade's mass, first moment and flap inertia each integrated from the data."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aircraft_files import entries, write
from test_cli_errors import run_main
from mbs import aircraft, scenes
from mbs.aircraft.blade import Distribution
from mbs.aircraft.report import check
from mbs.models.helicopter.tree import box_inertia

BO105 = aircraft.load().data["main_rotor"]


def _file(tmp_path, name="tables.toml", drop=(), **tables):
    """The Bo105's file with ``tables`` (key -> (rows, unit)) in [main_rotor] and ``drop`` removed."""
    raw = entries("bo105")
    for key in drop:
        raw["main_rotor"].pop(key)
    for key, (rows, unit) in tables.items():
        section, _, entry = key.rpartition("__") if "__" in key else ("main_rotor", "", key)
        raw[section][entry] = {"value": rows, "unit": unit, "source": "test"}
    return write(raw, tmp_path / name)


def _uniform(mu: float, hinge_r: float = 0.0):
    return [[hinge_r, mu], [1.0, mu]]


def test_a_uniform_mass_table_gives_the_uniform_blades_closed_forms_and_its_box():
    R, e, t, c = 5.0, 0.25, 0.03, 0.3
    mu = 6.0
    blade = Distribution({"radius": R, "flap_hinge_offset": e, "chord": c, "blade_thickness": t,
                          "mass_table": [[e / R, mu], [1.0, mu]]})
    m, span = mu * (R - e), R - e
    assert blade.mass == pytest.approx(m, rel=1e-13)
    assert blade.first_moment == pytest.approx(m * span / 2, rel=1e-13)
    assert blade.flap_inertia == pytest.approx(m * span**2 / 3 + m * t**2 / 12, rel=1e-13)
    mass, com, inertia = blade.body()
    assert np.allclose(com, [span / 2, 0, 0], rtol=1e-13) and np.allclose(inertia, box_inertia(m, span, c, t),
                                                                          rtol=1e-12, atol=0)


def test_a_linear_mass_table_integrates_exactly_and_its_flap_inertia_is_not_three_s_over_two():
    """mu = a + b r between the hinge and the tip: m, S and I in closed form; the three are
    independent (a uniform blade of this mass would have another first moment and flap inertia)."""
    R, e, a, b = 6.0, 0.3, 20.0, -2.5
    blade = Distribution({"radius": R, "flap_hinge_offset": e, "chord": 0.4, "blade_thickness": 0.0,
                          "mass_table": [[e / R, a + b * e], [1.0, a + b * R]],
                          "section_inertia_table": [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]})
    mu = lambda r: a + b * r  # noqa: E731
    x, w = np.polynomial.legendre.leggauss(8)
    r = 0.5 * (R - e) * x + 0.5 * (R + e)
    integral = lambda f: 0.5 * (R - e) * np.dot(w, f(r))  # noqa: E731
    assert blade.mass == pytest.approx(integral(mu), rel=1e-13)
    assert blade.first_moment == pytest.approx(integral(lambda r: mu(r) * (r - e)), rel=1e-13)
    assert blade.flap_inertia == pytest.approx(integral(lambda r: mu(r) * (r - e) ** 2), rel=1e-13)
    assert abs(blade.flap_inertia / (blade.mass * (R - e) ** 2 / 3) - 1) > 0.05


def test_the_file_with_a_mass_table_reports_mass_first_moment_flap_inertia_and_lock_number_from_it(tmp_path):
    rows = [[0.0, 40.0], [0.1, 12.0], [0.2, 6.0], [0.95, 5.5], [1.0, 9.0]]  # a root fitting and a tip weight
    path = _file(tmp_path, drop=("I_flap", "blade_mass"), mass_table=(rows, "-, kg/m"))
    craft = aircraft.load(path)
    mr = craft.data["main_rotor"]
    blade = Distribution(mr)
    assert mr["blade_mass"] == blade.mass and mr["first_moment"] == blade.first_moment
    assert mr["I_flap"] == blade.flap_inertia
    report = check(path)
    derived = {e: (v, how) for e, v, _, how in report.derived}
    for entry in ("main_rotor.blade_mass", "main_rotor.first_moment", "main_rotor.I_flap"):
        assert "mass_table" in derived[entry][1], derived[entry]
    figures = {n: v for n, v, _ in report.figures}
    rho = craft.data["environment"]["rho"]
    assert figures["Lock number"] == pytest.approx(rho * mr["lift_slope"] * mr["chord"] * mr["radius"] ** 4
                                                   / mr["I_flap"], rel=1e-12)
    assert figures["Lock number"] != pytest.approx(5.2, rel=1e-3)  # not the uniform Bo105's


def test_the_rigid_blade_body_is_the_integrated_one(tmp_path):
    rows = [[0.0, 30.0], [0.2, 6.0], [1.0, 6.0]]
    craft = aircraft.load(_file(tmp_path, drop=("I_flap", "blade_mass"), mass_table=(rows, "-, kg/m")))
    model = scenes.get("hover").with_aircraft(craft).model()
    body = model.bodies["blade1"]
    mass, com, inertia = Distribution(craft.data["main_rotor"]).body()
    assert body.mass == mass and np.allclose(body.com, com, rtol=0, atol=0) and np.array_equal(body.inertia, inertia)


def _rhs(craft, scene="hover"):
    """The right-hand side at the packaged Bo105's initial state and parameters (its stored trim)."""
    reference = scenes.get(scene).system("vm")
    system = scenes.get(scene).with_aircraft(craft).system("vm")
    return np.asarray(system.rhs(reference.x0(), p=reference.params()))


def test_chord_and_twist_tables_equal_to_the_constant_chord_and_linear_twist_give_the_same_loads(tmp_path):
    mr = BO105
    twist = [[0.0, 0.0], [1.0, mr["twist"]]]
    chord = [[0.0, mr["chord"]], [1.0, mr["chord"]]]
    plain = _rhs(aircraft.load("bo105"))
    tabled = _rhs(aircraft.load(_file(tmp_path, drop=("twist", "chord"), twist_table=(twist, "-, rad"),
                                      chord_table=(chord, "-, m"))))
    assert np.abs(tabled - plain).max() <= 1e-12 * np.abs(plain).max()


def test_a_twist_table_turns_each_element_by_its_own_angle(tmp_path):
    """A nonlinear twist (zero inboard, washout beyond 0.7 R) gives a different lift than its
    straight-line equivalent, and the equivalent is reported as derived."""
    rows = [[0.0, 0.0], [0.7, 0.0], [1.0, -0.1]]
    craft = aircraft.load(_file(tmp_path, drop=("twist",), twist_table=(rows, "-, rad")))
    assert craft.data.meta["main_rotor"]["twist"]["origin"] == "derived"
    rotor = __import__("mbs.models.helicopter.aero", fromlist=["main_rotor"]).main_rotor(
        craft.data, scenes.get("hover").builder.config, "fuselage")
    radius = rotor.radius
    for r_over, expected in ((0.35, 0.0), (0.85, -0.05), (1.0, -0.1)):
        assert rotor.twist_at(r_over * radius) == pytest.approx(expected, abs=1e-15)


BROKEN = {  # what -> (tables, drop, words of the one line)
    "chord and chord_table": ({"chord_table": ([[0.0, 0.27], [1.0, 0.27]], "-, m")}, (),
                              "main_rotor.chord_table: replaces main_rotor.chord"),
    "I_flap and mass_table": ({"mass_table": ([[0.0, 6.0], [1.0, 6.0]], "-, kg/m")}, ("blade_mass",),
                              "main_rotor.mass_table: replaces main_rotor.I_flap"),
    "stations beyond the tip": ({"twist_table": ([[0.0, 0.0], [1.2, 0.1]], "-, rad")}, ("twist",),
                                "main_rotor.twist_table: the stations r/R (0, 1.2) must be"),
    "negative mass": ({"mass_table": ([[0.0, 6.0], [1.0, -1.0]], "-, kg/m")}, ("I_flap", "blade_mass"),
                      "main_rotor.mass_table: the mass per length -1 at r/R = 1 is not positive"),
    "mass short of the tip": ({"mass_table": ([[0.0, 6.0], [0.9, 6.0]], "-, kg/m")}, ("I_flap", "blade_mass"),
                              "main_rotor.mass_table: the last station is r/R = 0.9"),
    "section inertias alone": ({"section_inertia_table": ([[0.0, 0.1, 0.2, 0.3], [1.0, 0.1, 0.2, 0.3]],
                                                          "-, kg m, kg m, kg m")}, (),
                               "main_rotor.section_inertia_table: applies with main_rotor.mass_table only"),
    "wrong column unit": ({"chord_table": ([[0.0, 0.27], [1.0, 0.27]], "-, kg")}, ("chord",),
                          "main_rotor.chord_table: unit 'kg' is a mass, not a length"),
    "twist missing": ({}, ("twist",), "main_rotor.twist: missing"),
    "tail chord and chord_table": ({"tail_rotor__chord_table": ([[0.0, 0.18], [1.0, 0.18]], "-, m")}, (),
                                   "tail_rotor.chord_table: replaces tail_rotor.chord"),
    "sweep beyond 45 deg": ({"tip_sweep": (60.0, "deg")}, (), "main_rotor.tip_sweep: 1.0472 rad (60 deg) is outside"),
    "sweep starting inboard of half the radius": ({"tip_sweep": (20.0, "deg"), "sweep_start": (0.3, "-")}, (),
                                                  "main_rotor.sweep_start: 0.3 is outside [0.5, 1]"),
}


@pytest.mark.parametrize("what", list(BROKEN))
def test_a_broken_distribution_is_one_line_naming_its_entry(what, tmp_path, capsys):
    tables, drop, words = BROKEN[what]
    path = _file(tmp_path, drop=drop, **tables)
    code, err = run_main(["aircraft", "check", str(path)], capsys)
    assert code == 2 and words in err.splitlines()[0] and "Traceback" not in err, err
    code, err = run_main(["simulate", "hover", "--aircraft", str(path), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err


def test_an_elastic_blade_refuses_a_mass_table_or_mass_override_it_would_ignore(tmp_path, capsys):
    path = _file(tmp_path, drop=("I_flap", "blade_mass"), mass_table=([[0.0, 6.0], [1.0, 6.0]], "-, kg/m"))
    code, err = run_main(["simulate", "elastic-rotor", "--aircraft", str(path), "--revs", "0.1",
                          "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and "main_rotor.mass_table: the segmented elastic blade is a uniform beam" in err, err
    code, err = run_main(["simulate", "elastic-rotor-modal", "--aircraft", str(path), "--revs", "0.1",
                          "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and "main_rotor.mass_table: the modal blade is a uniform beam" in err, err
    path = _printed(tmp_path, "printed.toml", 34.0, first=70.0)
    code, err = run_main(["simulate", "elastic-rotor-modal", "--aircraft", str(path), "--revs", "0.1",
                          "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and "main_rotor.blade_mass: the modal blade is a uniform beam" in err, err


# -- tip sweep ----------------------------------------------------------------------------------

def _swept_rotor(angle: float, sense: int = 1):
    import casadi as ca

    from mbs.aero import Airfoil, Rotor, RotorAero

    frame = np.eye(3) if sense > 0 else np.diag([1.0, -1.0, 1.0])
    rotor = Rotor("r", "hub", ["b"], 5.0, 0.3, -0.1, 0.2, 8, shaft_frame=frame, sweep_start=0.9, sweep_angle=angle)
    aero = RotorAero(rotor, Airfoil(5.7, 0.01, 0.3), 1.2, 1.0)

    class Body:
        omega = ca.DM([0.0, 0.0, 0.0])

    def element(w, r=4.8):
        f, torque, _ = aero._swept_element(Body, ca.DM(-np.asarray(w)), ca.DM.zeros(3), ca.DM([0, 0, 1.0]),
                                           ca.DM(np.eye(3)[:, :2]), [ca.DM(0.0)], r, r, 0.1, 1.0)
        return np.array(ca.evalf(f)).ravel(), np.array(ca.evalf(torque)).ravel()
    return rotor, aero, element


@pytest.mark.parametrize("sense", [1, -1])
def test_a_swept_tip_element_is_loaded_by_the_velocity_normal_to_its_quarter_chord_only(sense):
    """Simple sweep theory: flow along the swept quarter-chord line adds no load; the flow turned
    with the sweep gives the unswept element's force turned with it; the force acts at the
    quarter chord, offset aft by (r - r_s) tan(sweep)."""
    angle = np.radians(20.0)
    rotor, _, element = _swept_rotor(angle, sense)
    w = np.array([-3.0, -sense * 180.0, 12.0])  # air from ahead, from below, with some radial flow
    span = np.array([np.cos(angle), -sense * np.sin(angle), 0.0])
    f, torque = element(w)
    f_spanwise, _ = element(w + 40.0 * span)
    assert np.abs(f_spanwise - f).max() <= 1e-12 * np.abs(f).max()
    turn = np.array([[np.cos(angle), sense * np.sin(angle), 0], [-sense * np.sin(angle), np.cos(angle), 0], [0, 0, 1]])
    _, _, straight = _swept_rotor(1e-300, sense)
    f_straight, _ = straight(turn.T @ w)
    assert np.abs(turn @ f_straight - f).max() <= 1e-12 * np.abs(f).max()
    offset = (4.8 - 0.9 * 5.0) * np.tan(angle)
    point = np.array([4.8, -sense * offset, 0.0])
    assert np.allclose(torque, np.cross(point, f), rtol=0, atol=1e-12 * np.abs(torque).max())


def test_a_tip_sweep_entry_sweeps_the_model_and_sweep_start_alone_is_refused(tmp_path, capsys):
    raw = entries("bo105")
    raw["main_rotor"]["tip_sweep"] = {"value": 20.0, "unit": "deg", "source": "test"}
    raw["main_rotor"]["sweep_start"] = {"value": 0.93, "unit": "-", "source": "test"}
    craft = aircraft.load(write(raw, tmp_path / "swept.toml"))
    rotor = __import__("mbs.models.helicopter.aero", fromlist=["main_rotor"]).main_rotor(
        craft.data, scenes.get("hover").builder.config, "fuselage")
    assert rotor.sweep_angle == pytest.approx(math.radians(20.0)) and rotor.swept(0.95 * rotor.radius)
    assert not rotor.swept(0.9 * rotor.radius)
    plain = _rhs(aircraft.load("bo105"))
    assert np.abs(_rhs(craft) - plain).max() > 1e-3 * np.abs(plain).max()  # the tip's loads moved
    raw["main_rotor"].pop("tip_sweep")
    code, err = run_main(["aircraft", "check", str(write(raw, tmp_path / "half.toml"))], capsys)
    assert code == 2 and "main_rotor.sweep_start: 0.93 starts a tip sweep of 0 deg" in err, err


def test_a_long_table_in_degrees_is_listed_by_column_not_a_traceback(tmp_path, capsys):
    """An 8-row twist table in deg: ``aircraft check`` (text and JSON) lists it converted, each
    column's range on one line, and exits 0."""
    rows = [[0.2, 0.0], [0.3, -0.7], [0.4, -1.5], [0.5, -2.2], [0.6, -2.9], [0.7, -3.7], [0.8, -4.4], [1.0, -5.9]]
    path = _file(tmp_path, drop=("twist",), twist_table=(rows, "-, deg"))
    from mbs.aircraft.report import lines

    code, err = run_main(["aircraft", "check", str(path)], capsys)
    assert code == 0 and "Traceback" not in err, err
    line = next(x for x in lines(check(path)) if "main_rotor.twist_table" in x)
    assert f"columns 0.2 .. 1, {math.radians(-5.9):.6g} .. 0 (8 rows; --json lists them)" in line, line
    assert run_main(["aircraft", "check", str(path), "--json"], capsys)[0] == 0


def _printed(tmp_path, name: str, mass_kg: float, lock: float | None = None, first: float | None = None):
    """The Bo105's file with a blade mass given beside its flap inertia (or a Lock number), as
    reports print them, and optionally its first moment about the hinge."""
    raw = entries("bo105")
    raw["main_rotor"]["blade_mass"] = {"value": mass_kg, "unit": "kg", "source": "test", "override": True}
    if lock is not None:
        raw["main_rotor"].pop("I_flap")
        raw["main_rotor"]["lock_number"] = {"value": lock, "unit": "-", "source": "test"}
    if first is not None:
        raw["main_rotor"]["first_moment"] = {"value": first, "unit": "kg m", "source": "test", "override": True}
    return write(raw, tmp_path / name)


def test_a_blade_mass_given_beside_its_flap_inertia_keeps_all_three_in_the_model(tmp_path):
    """A blade of 34 kg and first moment 70 kg m beside the Bo105's I_flap 231.7 kg m^2: the
    model's blade body (the tree's) has that mass, first moment and flap inertia about the hinge,
    to 1e-12, where the uniform box would have had 273 kg m^2 (the flap inertia 18 % high, the Lock
    number 15 % low). The flap frequency is sqrt(1 + e S / I + K / (I Omega^2)); the shipped files
    keep their box."""
    from mbs.aircraft import derived, mass

    path = _printed(tmp_path, "printed.toml", 34.0, first=70.0)
    report = check(path)
    assert report.ok, report.problems
    mr = aircraft.load(path).data["main_rotor"]
    body = scenes.get("hover").with_aircraft(aircraft.load(path)).model().bodies["blade1"]
    span = mr["radius"] - mr["flap_hinge_offset"]
    assert body.mass == pytest.approx(34.0, rel=1e-12)
    assert body.mass * body.com[0] == pytest.approx(70.0, rel=1e-12)
    assert np.asarray(body.inertia)[1, 1] + body.mass * body.com[0] ** 2 == pytest.approx(231.7, rel=1e-12)
    assert 34.0 * span**2 / 3 > 1.15 * 231.7
    nu2 = 1 + mr["flap_hinge_offset"] * 70.0 / 231.7 + mr["flap_stiffness"] / (231.7 * mr["omega"] ** 2)
    assert derived.flap_frequency(mr) == pytest.approx(math.sqrt(nu2), rel=1e-14)
    for name in ("bo105", "lynx", "puma"):
        d = aircraft.load(name).data["main_rotor"]
        assert mass.is_uniform_blade(d) and not d.get("mass_table")


def test_a_blade_with_negative_inertia_about_its_own_centre_of_mass_is_refused(tmp_path):
    """A report's blade weight (93.9 kg) beside its Lock number (I_flap 975 kg m^2 from it)
    cannot be one uniform-mass blade: S^2/m exceeds I_flap; the check names the three values."""
    report = check(_printed(tmp_path, "impossible.toml", 93.9, lock=2.2))
    assert any(p.startswith("main_rotor.blade_mass: 93.9 kg with the first moment") and
               "negative inertia about its own centre of mass" in p and "from lock_number" in p
               for p in report.problems), report.problems
    report = check(_printed(tmp_path, "off.toml", 30.0, first=200.0))
    assert any("main_rotor.first_moment: 200 kg m puts the blade's centre of mass" in p for p in report.problems)


@pytest.mark.parametrize("unit, scale", [("-, R", 1.0), ("%R, %R", 100.0)])
def test_a_chord_table_as_fractions_of_the_radius_is_the_same_table_in_metres(tmp_path, unit, scale):
    """A chord printed as c/R (a new user's blade was refused: "unknown symbol 'R'"), or both columns
    in percent of R: the table in metres, to 1e-15, listed with the column times the radius."""
    radius = BO105["radius"]
    rows = [[0.2, 0.27], [0.7, 0.27], [1.0, 0.2]]
    given = [[scale * r, scale * c / radius] for r, c in rows]
    plain = aircraft.load(_file(tmp_path, drop=("chord",), chord_table=(rows, "-, m"))).data["main_rotor"]
    path = _file(tmp_path, drop=("chord",), chord_table=(given, unit))
    read = aircraft.load(path).data["main_rotor"]
    assert np.allclose(read["chord_table"], plain["chord_table"], rtol=1e-15, atol=1e-15)
    assert read["chord"] == pytest.approx(plain["chord"], rel=1e-14)
    how = {r[0]: r[3] for r in check(path).converted}["main_rotor.chord_table"]
    assert f"column 2 times main_rotor.radius {radius:.6g} m" in how
