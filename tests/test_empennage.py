"""A stabilator with its schedule and stops, interference tables in place of the wake, and the
airframe warnings of a trim."""
import re

import casadi as ca
import numpy as np
import pytest

from mbs import aircraft, scenes
from mbs.aero.empennage import CLAMP_SMOOTHING, smooth_clamp
from mbs.aero.interpolation import Spline
from mbs.aero.sections import EPS
from mbs.models.helicopter.airframe_warnings import airframe_warnings, trim_warnings

KT = 1852 / 3600
SCHEDULE_KT = [0, 20, 40, 60, 80, 120]
SCHEDULE_DEG = [30, 30, 15, 5, 0, -5]
DOWNWASH_ALPHA_DEG = [-30, -10, 0, 10, 30]
DOWNWASH_DEG = [1.0, 2.5, 3.0, 3.5, 4.0]
Q_RATIO = [0.8, 0.85, 0.9, 0.85, 0.8]


def _file(tmp_path, collective_gain: float, cyclic_gain: float = 0.0) -> str:
    """The Bo105 with a stabilator (schedule, collective gain about 10 deg, stops -10/+35 deg) and
    published-style downwash and dynamic-pressure tables at the horizontal tail (test data)."""
    text = aircraft.resolve("bo105").read_text()
    tables = "\n".join([
        f'interference_alpha = {{ value = {DOWNWASH_ALPHA_DEG}, unit = "deg", source = "TEST" }}',
        f'q_ratio = {{ value = {Q_RATIO}, unit = "-", source = "TEST" }}',
        f'downwash = {{ value = {DOWNWASH_DEG}, unit = "deg", source = "TEST" }}', "", "[vertical_fin]"])
    text = text.replace("\n[vertical_fin]", "\n" + tables, 1)
    text += "\n".join(["", "[stabilator]",
                       f'airspeed = {{ value = {SCHEDULE_KT}, unit = "kt", source = "TEST" }}',
                       f'incidence = {{ value = {SCHEDULE_DEG}, unit = "deg", source = "TEST" }}',
                       f'collective_gain = {{ value = {collective_gain}, unit = "-", source = "TEST" }}',
                       'collective_reference = { value = 10.0, unit = "deg", source = "TEST" }',
                       'incidence_min = { value = -10.0, unit = "deg", source = "TEST" }',
                       'incidence_max = { value = 35.0, unit = "deg", source = "TEST" }',
                       *([f'cyclic_gain = {{ value = {cyclic_gain}, unit = "-", source = "TEST" }}'] if cyclic_gain
                         else []), ""])
    path = tmp_path / f"bo105_stabilator_{collective_gain:g}_{cyclic_gain:g}.toml"
    path.write_text(text)
    return str(path)


def test_smooth_clamp_holds_the_stops_without_a_kink():
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [smooth_clamp(x, -0.2, 0.6), ca.jacobian(smooth_clamp(x, -0.2, 0.6), x)])
    assert float(f(0.3)[0]) == pytest.approx(0.3, abs=CLAMP_SMOOTHING**2 / (4 * 0.3) * 1.01)
    assert float(f(0.6)[0]) == pytest.approx(0.6 - CLAMP_SMOOTHING / 2, abs=1e-5)
    assert float(f(5.0)[0]) == pytest.approx(0.6, abs=1e-5) and float(f(-5.0)[0]) == pytest.approx(-0.2, abs=1e-5)
    slopes = [float(f(v)[1]) for v in np.linspace(0.55, 0.65, 201)]
    assert max(abs(np.diff(slopes))) < 0.05  # continuous slope through the stop


def test_aircraft_check_takes_the_stabilator_and_names_bad_schedules(tmp_path):
    path = _file(tmp_path, 0.0)
    assert aircraft.check(path).ok, aircraft.check(path).problems
    bad = path.replace(".toml", "_bad.toml")
    text = open(path).read().replace("incidence_max = { value = 35.0", "incidence_max = { value = 25.0")
    open(bad, "w").write(text)
    assert any("30 deg lies beyond the stops" in p for p in aircraft.check(bad).problems)
    short = text.replace('q_ratio = { value = [0.8, 0.85, 0.9, 0.85, 0.8]', 'q_ratio = { value = [0.8, 0.85]')
    open(bad, "w").write(short)
    assert any("horizontal_tail.q_ratio: 2 values for 5 breakpoints" in p for p in aircraft.check(bad).problems)


def test_trimmed_stabilator_follows_its_schedule_and_interference_tables(tmp_path):
    """Forward flight at 50 kt with the stabilator file (collective gain 0.5 about 10 deg): the
    trimmed incidence is the schedule's spline at the airspeed plus the gain term, within the
    smoothed stops (to 1e-6 rad: the period mean against the trim's initial airspeed); the
    horizontal tail's downwash is the tables' ``sqrt(η)``-scaled air turned down by ``ε`` at the
    fuselage angle of attack (to 1e-5 m/s, the period mean against the trim's initial state); with a collective gain of 20 the schedule runs
    into the +35 deg stop and the trim's airframe warnings say so."""
    from mbs.analysis.trim import periodic_solution

    d = aircraft.load(_file(tmp_path, 0.5)).data
    res = periodic_solution(scenes.get("forward-flight").with_aircraft(_file(tmp_path, 0.5)), 50 * KT)
    assert res.converged
    x, out = res.state, res.output_means
    speed = np.sqrt(x["fuselage.u"] ** 2 + x["fuselage.v"] ** 2 + x["fuselage.w"] ** 2)
    raw = Spline(np.array(SCHEDULE_KT) * KT, np.radians(SCHEDULE_DEG))(speed) + 0.5 * (
        res.controls["collective"] - np.radians(10))
    assert out["stabilator.incidence"] == pytest.approx(float(smooth_clamp(raw, np.radians(-10), np.radians(35))),
                                                        abs=1e-6)
    alpha = np.arctan2(x["fuselage.w"], x["fuselage.u"] + EPS)
    eps = Spline(np.radians(DOWNWASH_ALPHA_DEG), np.radians(DOWNWASH_DEG))(alpha)
    eta = Spline(np.radians(DOWNWASH_ALPHA_DEG), Q_RATIO)(alpha)
    air = -np.array([x["fuselage.u"], x["fuselage.w"]])
    turned_z = -np.sin(eps) * air[0] + np.cos(eps) * air[1]
    assert out["horizontal_tail.downwash"] == pytest.approx(np.sqrt(eta) * turned_z - air[1], abs=1e-5)
    assert not [w for w in trim_warnings(res, d) if "stabilator" in w]
    stop = periodic_solution(scenes.get("forward-flight").with_aircraft(_file(tmp_path, 20.0)), 50 * KT)
    assert stop.converged and stop.output_means["stabilator.incidence"] == pytest.approx(np.radians(35), abs=0.01)
    d5 = aircraft.load(_file(tmp_path, 20.0)).data
    assert any("stabilator: at its stop +35.0 deg" in w for w in trim_warnings(stop, d5))


def test_an_elevator_linked_to_the_cyclic_follows_it(tmp_path):
    """The stabilator file with an elevator gain of -2 rad per rad of longitudinal cyclic (and no
    collective gain), trimmed at 50 kt: its incidence is the schedule plus -2 theta_1s of the
    trim, within the stops (1e-6 rad, as above); without the gain the schedule alone."""
    from mbs.analysis.trim import periodic_solution

    res = periodic_solution(scenes.get("forward-flight").with_aircraft(_file(tmp_path, 0.0, -2.0)), 50 * KT)
    assert res.converged
    x = res.state
    speed = np.sqrt(x["fuselage.u"] ** 2 + x["fuselage.v"] ** 2 + x["fuselage.w"] ** 2)
    raw = Spline(np.array(SCHEDULE_KT) * KT, np.radians(SCHEDULE_DEG))(speed) \
        - 2.0 * res.controls["longitudinal_cyclic"]
    assert abs(res.controls["longitudinal_cyclic"]) > 0.005
    assert res.output_means["stabilator.incidence"] == pytest.approx(
        float(smooth_clamp(raw, np.radians(-10), np.radians(35))), abs=1e-6)
    actuators = scenes.get("forward-flight-actuators").with_aircraft(_file(tmp_path, 0.0, -2.0))
    with pytest.raises(ValueError, match="stabilator.cyclic_gain: the schedule reads the longitudinal_cyclic"):
        actuators.system("vm")


def test_airframe_warnings_fire_where_they_should(tmp_path):
    d = aircraft.load("bo105").data
    calm = {"main_rotor.inflow": 8.0, "horizontal_tail.downwash": 2.0, "fin.sidewash": 1.0,
            "fuselage.u": 20.0, "fuselage.v": 0.0, "fuselage.w": 0.5}
    assert airframe_warnings(calm, d) == []
    strong = {**calm, "horizontal_tail.downwash": 17.0}
    assert any("horizontal tail: 17 m/s of main-rotor wake, more than" in w for w in airframe_warnings(strong, d))
    stalled = {**calm, "horizontal_tail.downwash": 0.0, "fuselage.w": 8.0}  # 22 deg nose-up flow at the tail
    assert any("horizontal tail: angle of attack" in w and "stall" in w for w in airframe_warnings(stalled, d))
    still = {**calm, "fuselage.u": 0.0, "fuselage.w": 0.0, "horizontal_tail.downwash": 0.015, "fin.sidewash": 0.0}
    assert not any("angle of attack" in w for w in airframe_warnings(still, d))  # hover, out of the wake: no flow
    from mbs.aircraft.template import with_polynomial_tables

    tables = aircraft.load(with_polynomial_tables("bo105", tmp_path)).data
    assert airframe_warnings(calm, tables) == []
    steep = {**calm, "fuselage.u": 1.0, "fuselage.w": -20.0}  # descending steeply: alpha -87 deg
    assert not any("beyond the breakpoints" in w for w in airframe_warnings(steep, tables))
    sideways = {**calm, "fuselage.u": -20.0, "fuselage.w": 0.0}  # flying backwards: alpha 180 deg
    assert any("alpha +180.0 deg beyond the breakpoints [-90, 90] deg" in w for w in airframe_warnings(sideways, tables))
    hover = {**calm, "fuselage.u": -1e-7, "fuselage.v": -2e-8, "fuselage.w": -1e-9}  # a hover's round-off: -179 deg
    assert not any("fuselage tables" in w for w in airframe_warnings(hover, tables))  # (a new user: "extend them")


def test_a_surface_at_the_wake_edge_is_named_with_the_width():
    """An AH-1's tailplane half in the wake at 60 kt gave M_θ0 +26 1/s² (no helicopter's) without
    a word: a surface whose immersion is between 0.1 and 0.9 is named, with the wake's width."""
    d = aircraft.load("bo105").data
    calm = {"main_rotor.inflow": 8.0, "horizontal_tail.downwash": 2.0, "fin.sidewash": 1.0, "fuselage.u": 20.0,
            "fuselage.v": 0.0, "fuselage.w": 0.5, "horizontal_tail.wake_immersion": 0.97, "fin.wake_immersion": 0.0}
    assert airframe_warnings(calm, d) == []
    (line,) = airframe_warnings({**calm, "horizontal_tail.wake_immersion": 0.47}, d)
    assert line.startswith("horizontal tail: at the edge of the main rotor's wake (immersion 0.47; the edge is "
                           "smoothed over wake.width = 0.25 m)") and "derivatives" in line


def test_a_fixed_surface_s_force_is_continuous_where_the_air_meets_it_square():
    """The folded angle of attack jumps from +90 to -90 deg as the air crosses a surface's normal;
    the bounded lift jumped with it and an AH-1 whose tail sat square in its hover downwash did not
    trim. A fixed surface's lift is a flat plate's beyond 60 deg: none at 90 deg from either side,
    the force continuous with its slope, the normal force the plate's c_D,90 sin α within 10 %, and
    below 45 deg the section's own, exactly."""
    from mbs.aero.sections import Airfoil, flat_plate_share, section_force

    foil = Airfoil(lift_slope=3.26, cd0=0.01, alpha_stall=0.26, cd_stalled=1.8)
    w_c, w_n = ca.SX.sym("w_c"), ca.SX.sym("w_n")
    plate = ca.Function("f", [w_c, w_n], [ca.vertcat(*section_force(w_c, w_n, foil, 1.225, 1.0, flat_plate=True))])
    bounded = ca.Function("b", [w_c, w_n], [ca.vertcat(*section_force(w_c, w_n, foil, 1.225, 1.0))])
    jac = ca.Function("j", [w_c, w_n], [ca.jacobian(plate(w_c, w_n), w_c)])
    down = -10.0  # m/s through the surface from above
    side = {s: np.asarray(plate(s * 1e-6, down)).ravel() for s in (-1, 1)}
    assert np.allclose(side[-1], side[1], atol=1e-3)  # N: continuous (the drag turns with the air)
    jump = np.asarray(bounded(1e-6, down) - bounded(-1e-6, down)).ravel()
    assert abs(jump[0]) > 50  # N: the bounded lift's jump
    assert np.allclose(np.asarray(jac(1e-6, down)), np.asarray(jac(-1e-6, down)), rtol=1e-3, atol=1e-5)
    q = 0.5 * 1.225 * 20.0**2
    for deg in (60, 70, 80):
        a = np.radians(deg)
        normal = -float(plate(20 * np.cos(a), -20 * np.sin(a))[1]) / q
        assert normal == pytest.approx(1.8 * np.sin(a), rel=0.1), deg
    for angle in (0.1, 0.3, 0.7):  # up to 40 deg: the section's own force, exactly
        wc, wn = 20 * np.cos(angle), -20 * np.sin(angle)
        assert np.array_equal(np.asarray(plate(wc, wn)), np.asarray(bounded(wc, wn)))
    assert float(flat_plate_share(0.49)) == 0.0 and float(flat_plate_share(0.76)) == 1.0


def test_a_schedule_holds_its_end_incidences_beyond_its_airspeeds():
    """A new user's Apache schedule began at 30 kt with 25 deg; below it the spline ran on to 31 deg
    at 20 kt and 44 deg in hover without a word. It holds its first and last incidence."""
    from mbs.aero.empennage import HOLD_WIDTH, Schedule

    sched = Schedule((15.0, 20.0, 30.0), (0.44, 0.32, 0.17), 0.0, 0.0, 0.0, -0.5, 0.8)
    assert float(sched(0.0, 0.0, 0.0)[1]) == pytest.approx(0.44, abs=1e-4)  # the clamp rounds by width²/4d
    assert float(sched(15.0 - 5 * HOLD_WIDTH, 0.0, 0.0)[1]) == pytest.approx(0.44, abs=1e-3)
    assert float(sched(80.0, 0.0, 0.0)[1]) == pytest.approx(0.17, abs=1e-4)
    assert float(sched(20.0, 0.0, 0.0)[1]) == pytest.approx(0.32, abs=1e-9)


def test_a_stabilator_as_printed_trailing_edge_up_positive_and_without_a_fixed_tail_incidence(tmp_path):
    """The Apache's source counts trailing edge down negative; its user flipped every sign by hand,
    and the tail's fixed incidence, which the schedule replaces, was taken without a word. With
    conventions.stabilator_positive = 'trailing edge up' the schedule, gains and stops read
    negated (stops swapped), listed as converted; the fixed incidence is optional beside a
    schedule and warned of as unused when given; a table in two variables is refused naming the
    collective gain."""
    base = aircraft.load(_file(tmp_path, 0.5)).data["stabilator"]
    text = open(_file(tmp_path, 0.5)).read()
    flipped = (text.replace(f"value = {SCHEDULE_DEG}", f"value = {[-x for x in SCHEDULE_DEG]}")
               .replace('collective_gain = { value = 0.5', 'collective_gain = { value = -0.5')
               .replace('incidence_min = { value = -10.0', 'incidence_min = { value = -35.0')
               .replace('incidence_max = { value = 35.0', 'incidence_max = { value = 10.0')
               + '\n[conventions]\nstabilator_positive = { value = "trailing edge up", unit = "-", source = "TEST" }\n')
    path = tmp_path / "flipped.toml"
    path.write_text(flipped)
    report = aircraft.check(path)
    assert report.ok, report.problems
    got = aircraft.load(path).data["stabilator"]
    for key in ("incidence", "collective_gain", "incidence_min", "incidence_max"):
        assert got[key] == pytest.approx(base[key], abs=1e-15), key
    listed = {e: how for e, _, _, how, _ in report.converted}
    assert "times -1 (conventions.stabilator_positive" in listed["stabilator.incidence"]
    assert listed["stabilator.incidence_min"].startswith("minus incidence_max as printed, 10.0 deg")
    assert any(w.startswith("horizontal_tail.incidence: 3.999 deg is not used") for w in report.warnings)
    lines = [x for x in text.splitlines() if not x.startswith("incidence = { value = 0.0698,")]
    (tmp_path / "no_fixed.toml").write_text("\n".join(lines))
    quiet = aircraft.check(tmp_path / "no_fixed.toml")
    assert quiet.ok and not any(w.startswith("horizontal_tail.incidence") for w in quiet.warnings), quiet.problems
    two = text.replace(f'incidence = {{ value = {SCHEDULE_DEG}, unit = "deg"',
                       'incidence = { value = [[0.0, 25, 15.5], [0.5, 25.0, 18.3]], unit = "-, deg, deg"')
    (tmp_path / "two.toml").write_text(two)
    problems = aircraft.check(tmp_path / "two.toml").problems
    assert any(p.startswith("stabilator.incidence: must be one list of numbers in one unit") and "collective_gain"
               in p for p in problems), problems


def test_a_fin_that_loads_the_tail_rotor_in_cruise_is_named():
    """A new user's clockwise EC135 had its fin's zero-lift angle signed for a counter-clockwise
    rotor: at 141 kt the fin pushed the tail with the torque (fan thrust 3443 N against 1593 N,
    power 732 against 642 kW) without a word. A fin side force against the tail rotor, more than a
    quarter of its thrust, in forward flight, is named with its sign convention; the Bo105's own
    trim at 60 m/s has no such line, and its fin turned the other way has."""
    d = aircraft.load("bo105").data
    cruise = {"fuselage.u": 60.0, "fuselage.v": 0.0, "fuselage.w": 2.0, "fin.sidewash": 0.0,
              "tail_rotor.thrust": 600.0, "main_rotor.inflow": 3.0}
    assert not [w for w in airframe_warnings(cruise, d) if w.startswith("fin:")]
    turned = {**d, "vertical_fin": {**d["vertical_fin"], "incidence": -d["vertical_fin"]["incidence"]}}
    (line,) = [w for w in airframe_warnings(cruise, turned) if w.startswith("fin:")]
    assert line.startswith("fin: its side force,") and "to port, pushes the tail the way the counter-clockwise" in line
    assert not [w for w in airframe_warnings({**cruise, "fuselage.u": 10.0}, turned) if w.startswith("fin:")]


def test_a_stabiliser_to_one_side_lifts_where_it_is(tmp_path):
    """A new user's CH-53D has its horizontal stabiliser on the starboard side only, and
    horizontal_tail.y was refused: the surfaces take a y (default the centre line), the model's
    surface and the drawn one sit there, and a wing, whose panels are placed by its span, has none."""
    from aircraft_files import entries, write
    from mbs.models.helicopter.aero import tail_surface
    from mbs.models.helicopter.config import Config
    from mbs.models.helicopter.tree import _fuselage_shape

    raw = entries("bo105")
    raw["horizontal_tail"]["y"] = {"value": 1.5, "unit": "ft", "source": "report"}
    path = write(raw, tmp_path / "side.toml")
    assert aircraft.check(path).ok
    d = aircraft.load(path).data
    surface = tail_surface(d, Config(), "horizontal_tail", "horizontal tail", (0, 0, -1), None)
    assert list(surface.point) == [d["horizontal_tail"]["x"], pytest.approx(0.4572, rel=1e-12), d["horizontal_tail"]["z"]]
    assert _fuselage_shape(d)["parts"][2]["offset"][1] == pytest.approx(0.4572, rel=1e-12)
    assert aircraft.load().data["horizontal_tail"]["y"] == 0.0
    raw["wing"] = {k: {"value": v, "unit": u, "source": "x"} for k, (v, u) in {
        "area": (2.0, "m^2"), "incidence": (0.0, "deg"), "x": (0.0, "m"), "z": (0.0, "m"), "y": (1.0, "m")}.items()}
    assert any(p.startswith("wing.y: unknown entry") for p in aircraft.check(write(raw, tmp_path / "w.toml")).problems)


def test_an_aircraft_without_a_horizontal_tail_leaves_the_section_out(tmp_path):
    """A new user's Sikorsky S-51 had no horizontal tail and could not say so (area 0 refused, the
    section required). Left out, the aircraft flies without one: the check says so, the model has
    no such surface, output or drawn part, and its loads are the tail's of vanishing area; a
    stabilator without the tail it schedules is refused."""
    from aircraft_files import entries, write

    raw = entries("bo105")
    del raw["horizontal_tail"]
    report = aircraft.check(write(raw, tmp_path / "none.toml"))
    assert report.ok, report.problems
    assert any(w.startswith("horizontal_tail: the file has no [horizontal_tail], so the aircraft flies without one")
               for w in report.warnings), report.warnings
    tiny = entries("bo105")
    tiny["horizontal_tail"]["area"].update(value=1e-12)
    reference = scenes.get("forward-flight").system("vm")
    x, p = reference.x0(), reference.params()
    rhs = {}
    for name in ("none", "tiny"):
        path = tmp_path / f"{name}.toml" if name == "none" else write(tiny, tmp_path / "tiny.toml")
        scene = scenes.get("forward-flight").with_aircraft(aircraft.load(path))
        rhs[name] = np.asarray(scene.system("vm").rhs(x, p=p))
        model = scene.model()
    assert np.abs(rhs["none"] - rhs["tiny"]).max() <= 1e-9 * np.abs(rhs["tiny"]).max()
    assert np.abs(rhs["none"] - np.asarray(reference.rhs(x, p=p))).max() > 1e-3  # the Bo105's tail does carry load
    bare = scenes.get("forward-flight").with_aircraft(aircraft.load(tmp_path / "none.toml")).model()
    assert not any(f.name == "horizontal tail" for f in bare.forces) and any(f.name == "horizontal tail"
                                                                            for f in model.forces)
    assert "horizontal_tail.downwash" not in bare.outputs and "fin.sidewash" in bare.outputs
    assert len(bare.bodies["fuselage"].shape["parts"]) == len(model.bodies["fuselage"].shape["parts"]) - 1
    raw["stabilator"] = {"airspeed": {"value": [0, 50], "unit": "m/s", "source": "t"},
                         "incidence": {"value": [0, 0.05], "unit": "rad", "source": "t"},
                         "incidence_min": {"value": -0.2, "unit": "rad", "source": "t"},
                         "incidence_max": {"value": 0.3, "unit": "rad", "source": "t"}}
    refused = aircraft.check(write(raw, tmp_path / "stabilator.toml"))
    assert any("stabilator: schedules a horizontal tail's incidence, and the file has no [horizontal_tail]" in w
               for w in refused.problems), refused.problems


RIGGING = "\n".join([
    "[controls]",
    'collective_lever = { value = [0.0, 10.0], unit = "in", source = "test" }',
    'longitudinal_stick = { value = [-5.0, 5.0], unit = "in", source = "test" }',
    'lateral_stick = { value = [-4.0, 4.0], unit = "in", source = "test" }',
    'pedals = { value = [-2.7, 2.7], unit = "in", source = "test" }',
    'collective = { value = [3.0, 1.6, 0.0, 0.0, 0.0], unit = "deg, deg/in, deg/in, deg/in, deg/in", source = "test" }',
    'longitudinal_cyclic = { value = [0.0, 0.0, -1.6, 0.0, 0.0], unit = "deg, deg/in, deg/in, deg/in, deg/in", '
    'source = "test" }',
    'lateral_cyclic = { value = [0.0, 0.0, 0.0, -1.0, 0.0], unit = "deg, deg/in, deg/in, deg/in, deg/in", source = "test" }',
    'tail_collective = { value = [5.0, 0.0, 0.0, 0.0, 3.0], unit = "deg, deg/in, deg/in, deg/in, deg/in", '
    'source = "test" }', ""])


def _table_file(tmp_path, name: str, rows: list, unit: str, rigging: bool = False) -> str:
    """The stabilator file with its schedule given as an incidence table in collective x airspeed."""
    head, _, block = open(_file(tmp_path, 0.0)).read().partition("[stabilator]\n")
    for key in ("airspeed", "incidence", "collective_gain", "collective_reference"):
        block = re.sub(rf"(^|\n){key} = .*", "", block)
    text = head + "[stabilator]\n" + block
    cells = "[" + ", ".join("[" + ", ".join("nan" if isinstance(c, float) and np.isnan(c) else repr(c) for c in r) + "]"
                            for r in rows) + "]"
    text = text.replace("[stabilator]\n", f'[stabilator]\nincidence_table = {{ value = {cells}, unit = "{unit}", '
                        'source = "TEST" }\n', 1)
    path = tmp_path / name
    path.write_text(text + ("\n" + RIGGING if rigging else ""))
    return str(path)


def test_a_stabilator_schedule_in_collective_and_airspeed_is_read_as_printed(tmp_path):
    """A new user's AH-64 source prints the stabilator's incidence against the collective lever's
    fraction (rows) and airspeed (columns), nonlinear in collective; it could not be written.
    Given as printed, a table linear in the blades' collective gives the incidence of the same
    schedule with a collective gain, to round-off (a natural spline of a line is the line); the
    lever's fractions go to the blades' collective through the rigging; the check refuses the
    fractions without a rigging, a collective gain beside the table and incidences past the stops."""
    from mbs.aircraft.airframe_data import schedule_collective, stabilator_schedule

    gain, ref = 1.5, np.radians(10.0)
    speeds = [float(v) for v in SCHEDULE_KT]
    collectives = [8.0, 10.0, 12.0]  # deg
    rows = [[float("nan"), *speeds]] + [[c, *(i + gain * (c - 10.0) for i in SCHEDULE_DEG)] for c in collectives]
    table = aircraft.load(_table_file(tmp_path, "table.toml", rows, "deg, kt, deg")).data
    plain = aircraft.load(_file(tmp_path, gain)).data
    a, b = stabilator_schedule(table), stabilator_schedule(plain)
    for v, c in ((12.0, 0.15), (30.0, 0.17), (55.0, 0.19), (80.0, 0.2)):  # within the table's airspeeds and collectives
        assert float(a(v, c, 0.0)[1]) == pytest.approx(float(b(v, c, 0.0)[1]), abs=1e-12), (v, c)
    assert float(a(30.0, 0.5, 0.0)[1]) == pytest.approx(float(b(30.0, np.radians(12.0), 0.0)[1]), abs=1e-12)  # held
    lever = [[float("nan"), *speeds]] + [[f, *SCHEDULE_DEG] for f in (0.0, 0.5, 1.0)]
    rigged = aircraft.load(_table_file(tmp_path, "lever.toml", lever, "-, kt, deg", rigging=True)).data
    assert np.degrees(schedule_collective(rigged)) == pytest.approx([3.0, 3.0 + 1.6 * 5.0, 3.0 + 1.6 * 10.0])
    problems = aircraft.check(_table_file(tmp_path, "bare.toml", lever, "-, kt, deg")).problems
    assert any("its collective is a fraction of the lever's travel (unit -), which needs the file's [controls]" in p
               for p in problems), problems
    text = open(_table_file(tmp_path, "both.toml", rows, "deg, kt, deg")).read().replace(
        "[stabilator]\n", '[stabilator]\ncollective_gain = { value = 1.0, unit = "-", source = "TEST" }\n')
    (tmp_path / "both.toml").write_text(text)
    problems = aircraft.check(tmp_path / "both.toml").problems
    assert any("stabilator.collective_gain: the incidence_table carries the collective already" in p for p in problems)
    rows[2][3] = 50.0
    problems = aircraft.check(_table_file(tmp_path, "stop.toml", rows, "deg, kt, deg")).problems
    assert any("stabilator.incidence_table: 50 deg lies beyond the stops [-10, 35] deg" in p for p in problems), problems
    rows[2][3] = float("nan")  # an acceptance test's: it passed the check, and the trim failed without naming it
    problems = aircraft.check(_table_file(tmp_path, "nan.toml", rows, "deg, kt, deg")).problems
    assert any("row 3, column 4 (an incidence) is nan: every cell but the corner must be a finite number" in p
               for p in problems), problems


def test_a_trim_beyond_a_two_variable_schedule_and_rows_beyond_the_collectives_range_are_warned_of(tmp_path):
    """An acceptance test flew a table of 14 to 18 deg at 12.2 deg of collective (the end row held)
    and a table whose collectives were written in rad (8 to 16 rad) without a word."""
    from mbs.models.helicopter.airframe_warnings import airframe_warnings

    speeds = [float(v) for v in SCHEDULE_KT]
    rows = [[float("nan"), *speeds]] + [[c, *SCHEDULE_DEG] for c in (14.0, 16.0, 18.0)]
    d = aircraft.load(_table_file(tmp_path, "high.toml", rows, "deg, kt, deg")).data
    words = airframe_warnings({"fuselage.u": 30.0, "fuselage.w": 0.0, "collective": np.radians(12.19)}, d)
    assert any(w.startswith("stabilator: collective 12.19 deg beyond its incidence_table's 14 to 18 deg") for w in words)
    assert not [w for w in airframe_warnings({"fuselage.u": 30.0, "fuselage.w": 0.0, "collective": np.radians(15.0)}, d)
                if w.startswith("stabilator")]
    words = airframe_warnings({"fuselage.u": 70.0, "fuselage.w": 0.0, "collective": np.radians(15.0)}, d)
    assert any(w.startswith("stabilator: airspeed 70 m/s beyond its schedule's 0 to 61.73 m/s") for w in words), words
    rad = [[float("nan"), *speeds]] + [[c, *SCHEDULE_DEG] for c in (8.0, 12.0, 16.0)]
    report = aircraft.check(_table_file(tmp_path, "rad.toml", rad, "rad, kt, deg"))
    assert any(w.startswith("stabilator.incidence_table: its collectives 458.4 to 916.7 deg reach beyond the "
                            "collective's range") for w in report.warnings), report.warnings
