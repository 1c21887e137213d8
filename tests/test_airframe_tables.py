"""Airframe tables as published: splines against scipy, wind/stability axes about a reference
point turned to body axes about the CG against a hand computation, AD against differences."""
import casadi as ca
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from mbs.aero.airframe_tables import AirframeTable, flow_angles
from mbs.aero.interpolation import Spline, Spline2
from mbs.aero.sections import EPS

RHO = 1.225
RNG = np.random.default_rng(30)
ALPHA = np.radians(np.array([-180, -90, -40, -20, -10, -5, 0, 5, 10, 20, 40, 90, 180.0]))
BETA = np.radians(np.array([-90, -30, -15, -5, 0, 5, 15, 30, 90.0]))


def _random_table(axes: str) -> tuple[AirframeTable, dict]:
    parts = {i: [("alpha", RNG.normal(size=len(ALPHA))), ("beta", RNG.normal(size=len(BETA))),
                 ("alpha_beta", RNG.normal(size=(len(ALPHA), len(BETA))))] for i in range(6)}
    reference = tuple(RNG.normal(size=3))
    return AirframeTable(axes, reference, ALPHA, BETA, parts), parts


def _hand(parts, reference, axes, u, v, w):
    """Body-axis force (N) and moment about the CG (N m) by scipy's natural splines and numpy."""
    speed2 = u * u + v * v + w * w
    a, b = np.arctan2(w, u + EPS), np.arcsin(v / np.sqrt(speed2 + EPS**2))
    c = []
    for i in range(6):
        one = {"alpha": CubicSpline(ALPHA, parts[i][0][1], bc_type="natural")(a),
               "beta": CubicSpline(BETA, parts[i][1][1], bc_type="natural")(b)}
        rows = [CubicSpline(BETA, row, bc_type="natural")(b) for row in parts[i][2][1]]
        c.append(one["alpha"] + one["beta"] + CubicSpline(ALPHA, rows, bc_type="natural")(a))
    q = 0.5 * RHO * speed2
    if axes == "body":
        f, m = np.array(c[:3]), np.array(c[3:])
    else:
        bb = b if axes == "wind" else 0.0
        x = np.array([np.cos(a) * np.cos(bb), np.sin(bb), np.sin(a) * np.cos(bb)])
        z = np.array([-np.sin(a), 0.0, np.cos(a)])
        y = np.cross(z, x)
        f = -c[0] * x + c[1] * y - c[2] * z
        m = c[3] * x + c[4] * y + c[5] * z
    return q * f, q * (m + np.cross(reference, f))


def _loads_function(table: AirframeTable) -> ca.Function:
    uvw = ca.SX.sym("uvw", 3)
    alpha, beta, speed2 = flow_angles(uvw[0], uvw[1], uvw[2])
    force, moment = table.body_per_q(alpha, beta)
    q = 0.5 * RHO * speed2
    return ca.Function("loads", [uvw], [ca.vertcat(q * force, q * moment)])


def test_splines_equal_scipy_natural_splines_and_continue_linearly():
    y = RNG.normal(size=len(ALPHA))
    spline, ref = Spline(ALPHA, y), CubicSpline(ALPHA, y, bc_type="natural")
    for t in RNG.uniform(ALPHA[0], ALPHA[-1], 100):
        assert spline(t) == pytest.approx(float(ref(t)), abs=1e-12)
    for t in (ALPHA[0] - 0.3, ALPHA[-1] + 0.7):
        end = ALPHA[0] if t < ALPHA[0] else ALPHA[-1]
        assert spline(t) == pytest.approx(float(ref(end) + ref(end, 1) * (t - end)), abs=1e-12)
    with pytest.raises(ValueError, match="strictly increasing"):
        Spline([0.0, 0.0, 1.0], [1.0, 2.0, 3.0])


@pytest.mark.parametrize("axes", ["wind", "stability", "body"])
def test_table_about_a_reference_point_gives_the_hand_computed_body_loads_about_the_cg(axes):
    """100 random velocities (α, β anywhere, V 1..80 m/s): the program's body-axis force and moment
    about the CG equal scipy's splines turned by numpy's rotation and moved by ``r × F`` to 1e-12
    (relative to the largest load)."""
    table, parts = _random_table(axes)
    fn = _loads_function(table)
    for _ in range(100):
        vel = RNG.normal(size=3)
        vel *= RNG.uniform(1, 80) / np.linalg.norm(vel)
        got = np.array(fn(vel)).ravel()
        f, m = _hand(parts, np.array(table.reference), axes, *vel)
        want = np.concatenate([f, m])
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()


def test_ad_jacobian_of_the_table_loads_equals_central_differences():
    table, _ = _random_table("wind")
    uvw = ca.SX.sym("uvw", 3)
    fn = _loads_function(table)
    jac = ca.Function("j", [uvw], [ca.jacobian(fn(uvw), uvw)])
    for _ in range(20):
        vel = RNG.normal(size=3) * 20
        h = 1e-5
        fd = np.column_stack([(np.array(fn(vel + h * e)) - np.array(fn(vel - h * e))).ravel() / (2 * h)
                              for e in np.eye(3)])
        ad = np.array(jac(vel))
        assert np.abs(ad - fd).max() <= 1e-6 * max(1.0, np.abs(ad).max())


def test_two_argument_spline_is_the_tensor_product_of_natural_splines():
    z = RNG.normal(size=(len(ALPHA), len(BETA)))
    spline = Spline2(ALPHA, BETA, z)
    a, b = 0.37, -0.21
    rows = [CubicSpline(BETA, row, bc_type="natural")(b) for row in z]
    cols = [CubicSpline(ALPHA, col, bc_type="natural")(a) for col in z.T]
    assert spline(a, b) == pytest.approx(float(CubicSpline(ALPHA, rows, bc_type="natural")(a)), abs=1e-12)
    assert spline(a, b) == pytest.approx(float(CubicSpline(BETA, cols, bc_type="natural")(b)), abs=1e-12)


def test_tables_sampling_the_padfield_polynomials_reproduce_the_trim(tmp_path):
    """Forward flight at 30 m/s, every switch on: the trim with the Bo105's polynomials sampled
    every 5 deg over ±90 deg (clipped as the model clips them) as body-axis loads at their speed
    equals the polynomials' within 0.01 deg in every control and attitude; aircraft check lists
    the tables' conversion (loads at 30.48 m/s over q) with their source."""
    from mbs import aircraft, scenes
    from mbs.aircraft.template import with_polynomial_tables
    from mbs.analysis.trim import periodic_solution

    path = with_polynomial_tables("bo105", tmp_path)
    report = aircraft.check(path)
    assert report.ok, report.problems
    rows = {r[0]: r for r in report.converted}
    assert "30.48 m/s" in rows["fuselage_aero.X_alpha"][3] and rows["fuselage_aero.X_alpha"][4] == "polynomials sampled"
    base = periodic_solution(scenes.get("forward-flight"), 30.0)
    tab = periodic_solution(scenes.get("forward-flight").with_aircraft(str(path)), 30.0)
    assert base.converged and tab.converged
    for key, value in base.controls.items():
        assert np.degrees(abs(tab.controls[key] - value)) < 0.01, key
    assert np.degrees(abs(tab.pitch - base.pitch)) < 0.01 and np.degrees(abs(tab.roll - base.roll)) < 0.01


WIND_SECTION = """[fuselage_aero]
model = { value = "tables", unit = "-", source = "R1" }
axes = { value = "wind", unit = "-", source = "R1" }
reference_station = { value = [345.5, 2.0, 234.0], unit = "in", source = "R1 table 2" }
cg_station = { value = [360.0, 0.0, 247.2], unit = "in", source = "R1 table 1" }
alpha = { value = [-20, -10, 0, 10, 20], unit = "deg", source = "R1" }
beta = { value = [-20, 0, 20], unit = "deg", source = "R1" }
reference_area = { value = 100.0, unit = "ft^2", source = "R1" }
reference_length = { value = 10.0, unit = "ft", source = "R1" }
drag_alpha = { value = [40.1, 35.2, 33.0, 35.9, 42.4], unit = "ft^2", source = "R1 D/q" }
lift_alpha_beta = { value = [[-0.3, -0.3, -0.3], [-0.15, -0.14, -0.15], [0.0, 0.01, 0.0], [0.15, 0.16, 0.15], [0.3, 0.31, 0.3]], unit = "-", source = "R1 CL" }
pitch_alpha = { value = [-1200, -600, 0, 600, 1200], unit = "ft^3", source = "R1 M/q" }
side_beta = { value = [30.0, 0.0, -30.0], unit = "ft^2", source = "R1 Y/q" }
roll_beta = { value = [-0.01, 0.0, 0.01], unit = "-", source = "R1 Cl" }
"""


def _with_section(tmp_path, section: str, name: str = "wind.toml"):
    import re
    from mbs import aircraft

    text = re.sub(r"\[fuselage_aero\].*?(?=\n\[horizontal_tail\])", lambda _: section,
                  aircraft.resolve("bo105").read_text(), flags=re.S)
    path = tmp_path / name
    path.write_text(text)
    return path


def _assert_same_loads(tables, rel: float, n: int = 10) -> None:
    """Two fuselage tables give the same body loads per q at ``n`` random (α, β) to ``rel``."""
    for a, b in RNG.uniform(-0.3, 0.3, (n, 2)):
        got, want = (np.concatenate([x.full().ravel() for x in t.body_per_q(a, b)]) for t in tables)
        assert np.abs(got - want).max() <= rel * np.abs(want).max()


def test_a_report_table_in_wind_axes_about_stations_is_converted_and_listed(tmp_path):
    """Tables as printed (ft², ft³, coefficients on 100 ft² and 10 ft, wind axes, moments about a
    station): aircraft check is clean, lists the reference point from the CG (x = −(FS − FS_cg),
    y = BL − BL_cg, z = −(WL − WL_cg), in m) and each table's factor with its source; the model's
    body-axis loads about the CG equal the hand conversion at 20 random (α, β) to 1e-12."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    report = aircraft.check(_with_section(tmp_path, WIND_SECTION))
    assert report.ok, report.problems
    rows = {r[0]: r for r in report.converted}
    ref = np.array([360.0 - 345.5, 2.0, 247.2 - 234.0]) * 0.0254
    assert rows["fuselage_aero.reference_station"][1] == pytest.approx(ref.tolist(), abs=1e-6)
    assert rows["fuselage_aero.lift_alpha_beta"][4] == "R1 CL" and "coefficients times 9.2903" in \
        rows["fuselage_aero.lift_alpha_beta"][3]
    table = fuselage_table(aircraft.load(_with_section(tmp_path, WIND_SECTION)).data)
    ft2, ft3, s, sl = 0.3048**2, 0.3048**3, 100 * 0.3048**2, 1000 * 0.3048**3
    grid_a, grid_b = np.radians([-20, -10, 0, 10, 20]), np.radians([-20, 0, 20])
    lift = np.array([[-0.3, -0.3, -0.3], [-0.15, -0.14, -0.15], [0.0, 0.01, 0.0], [0.15, 0.16, 0.15],
                     [0.3, 0.31, 0.3]])
    for a, b in RNG.uniform(-0.3, 0.3, (20, 2)):
        nat = lambda x, y, t: float(CubicSpline(x, y, bc_type="natural")(t))
        drag = nat(grid_a, ft2 * np.array([40.1, 35.2, 33.0, 35.9, 42.4]), a)
        rows_b = [nat(grid_b, s * row, b) for row in lift]
        c = [drag, nat(grid_b, ft2 * np.array([30.0, 0.0, -30.0]), b), nat(grid_a, rows_b, a),
             nat(grid_b, sl * np.array([-0.01, 0.0, 0.01]), b), nat(grid_a, ft3 * np.array([-1200, -600, 0, 600, 1200]), a), 0.0]
        x = np.array([np.cos(a) * np.cos(b), np.sin(b), np.sin(a) * np.cos(b)])
        z = np.array([-np.sin(a), 0.0, np.cos(a)])
        y = np.cross(z, x)
        f = -c[0] * x + c[1] * y - c[2] * z
        m = c[3] * x + c[4] * y + c[5] * z + np.cross(ref, f)
        force, moment = table.body_per_q(a, b)
        got = np.concatenate([force.full().ravel(), moment.full().ravel()])
        want = np.concatenate([f, m])
        assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()


@pytest.mark.parametrize("change, words", [
    (("reference_station", "ref_station"), "unknown entry"),
    (('side_beta = {', 'Y_beta = {'), "Y is not a component in wind axes"),
    (("[30.0, 0.0, -30.0]", "[30.0, 0.0]"), "side_beta: 2 values for 3 breakpoints"),
    (('reference_area = { value = 100.0, unit = "ft^2", source = "R1" }\n', ""), "coefficients need fuselage_aero.reference_area"),
    (('unit = "ft^3", source = "R1 M/q"', 'unit = "ft^2", source = "R1 M/q"'), "unit 'ft^2' is an area; give a volume (M/q)"),
    (('[-20, -10, 0, 10, 20], unit = "deg"', '[-20, -10, 10, 0, 20], unit = "deg"'), "breakpoints must increase"),
    (('cg_station = { value = [360.0, 0.0, 247.2], unit = "in", source = "R1 table 1" }\n', ""), "reference_point: missing"),
])
def test_bad_tables_are_named(tmp_path, change, words):
    from mbs import aircraft

    report = aircraft.check(_with_section(tmp_path, WIND_SECTION.replace(*change)))
    assert any(words in p for p in report.problems), report.problems


def test_load_tables_printed_in_lb_and_ft_lb_are_pounds_force_and_listed_so(tmp_path):
    """A drag table in ``lb`` and a pitching-moment table in ``ft-lb`` at the reference speed read
    as the same tables in lbf and ft lbf (body loads equal to round-off); the check says how."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    loads = WIND_SECTION + 'reference_speed = { value = 100.0, unit = "ft/s", source = "R1" }\n'
    loads = loads.replace('[40.1, 35.2, 33.0, 35.9, 42.4], unit = "ft^2"', '[476.8, 418.5, 392.4, 426.8, 504.1], unit = "{f}"')
    loads = loads.replace('[-1200, -600, 0, 600, 1200], unit = "ft^3"', '[-14266, -7133, 0, 7133, 14266], unit = "{m}"')
    pounds = _with_section(tmp_path, loads.replace("{f}", "lb").replace("{m}", "ft-lb"), "pounds.toml")
    plain = _with_section(tmp_path, loads.replace("{f}", "lbf").replace("{m}", "ft lbf"), "plain.toml")
    tables = [fuselage_table(aircraft.load(p).data) for p in (pounds, plain)]
    _assert_same_loads(tables, 1e-14, 5)
    how = {p: {r[0]: r[3] for r in aircraft.check(p).converted} for p in (pounds, plain)}
    assert "loads in lb (lb as pound-force)" in how[pounds]["fuselage_aero.drag_alpha"]
    assert "loads in ft-lb (lb as pound-force)" in how[pounds]["fuselage_aero.pitch_alpha"]
    assert "pound-force" not in how[plain]["fuselage_aero.drag_alpha"]


def test_a_table_printed_as_a_law_in_its_angle_is_the_law_at_the_breakpoints(tmp_path):
    """``M/q = XM1 + XM2 α`` (ft³, ft³/rad) and ``Y/q`` with a per-degree slope, written as printed
    with ``law = "polynomial"``, load as the tables of the law's values at the breakpoints (to
    1e-12) and are listed with the law; a law with one unit for two coefficients, a slope in the
    wrong unit, or a law on a two-argument table is refused, each named."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    xm1, xm2, yb = -6.901, 280.405, -1.5  # ft^3, ft^3/rad, ft^2/deg
    law = WIND_SECTION.replace('[-1200, -600, 0, 600, 1200], unit = "ft^3", source = "R1 M/q"',
                               f'[{xm1}, {xm2}], law = "polynomial", unit = "ft^3, ft^3/rad", source = "R1 XM1, XM2"')
    law = law.replace('[30.0, 0.0, -30.0], unit = "ft^2"', f'[0.0, {yb}], law = "polynomial", unit = "ft^2, ft^2/deg"')
    grid_a, grid_b = np.array([-20, -10, 0, 10, 20]), np.array([-20, 0, 20])
    plain = WIND_SECTION.replace("[-1200, -600, 0, 600, 1200]", str((xm1 + xm2 * np.radians(grid_a)).tolist()))
    plain = plain.replace("[30.0, 0.0, -30.0]", str((yb * grid_b).tolist()))
    tables = [fuselage_table(aircraft.load(_with_section(tmp_path, s, n)).data)
              for s, n in ((law, "law.toml"), (plain, "plain.toml"))]
    _assert_same_loads(tables, 1e-12)
    how = {r[0]: r[3] for r in aircraft.check(_with_section(tmp_path, law, "law.toml")).converted}
    assert how["fuselage_aero.pitch_alpha"].startswith(f"the polynomial [{xm1}, {xm2}] ft^3, ft^3/rad in alpha (rad)")
    for old, new, words in (
            ('unit = "ft^3, ft^3/rad"', 'unit = "ft^3"', "2 coefficients but 1 units; give one unit per coefficient"),
            ('unit = "ft^3, ft^3/rad"', 'unit = "ft^3, ft^2"', "unit 'ft^2' of c_1 is an area; give c_0's unit per "
                                                               "angle^1"),
            ("lift_alpha_beta = { value", 'lift_alpha_beta = { law = "polynomial", value',
             'law = "polynomial" applies to a fuselage_aero table in alpha or in beta only'),
            ('law = "polynomial", unit = "ft^2', 'law = "spline", unit = "ft^2', "law 'spline' is not known")):
        report = aircraft.check(_with_section(tmp_path, law.replace(old, new), "bad.toml"))
        assert any(words in p for p in report.problems), (words, report.problems)


def test_coefficients_on_the_rotor_disc_and_radius_are_read_as_printed(tmp_path):
    """Coefficients based on the main rotor's disc area and radius, as rotorcraft wind-tunnel
    reports print them (``reference_area`` in ``πR^2``, ``reference_length`` in ``R``), load as the
    same tables with πR² and R in m² and m (body loads equal to 1e-14) and are listed with the
    factor; either unit on the other reference is refused, named."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    radius = aircraft.load("bo105").data["main_rotor"]["radius"]
    area_m2, length_m = f"{np.pi * radius**2!r}", f"{radius!r}"
    base = ('reference_area = { value = 100.0, unit = "ft^2", source = "R1" }',
            'reference_length = { value = 10.0, unit = "ft", source = "R1" }')
    disc = WIND_SECTION.replace(base[0], 'reference_area = { value = 1.0, unit = "pi R^2", source = "R1 p. 6" }')
    disc = disc.replace(base[1], 'reference_length = { value = 1, unit = "R", source = "R1 p. 6" }')
    plain = WIND_SECTION.replace(base[0], f'reference_area = {{ value = {area_m2}, unit = "m^2", source = "R1" }}')
    plain = plain.replace(base[1], f'reference_length = {{ value = {length_m}, unit = "m", source = "R1" }}')
    capitals = disc.replace('unit = "pi R^2"', 'unit = "PI R^2"')
    tables = [fuselage_table(aircraft.load(_with_section(tmp_path, s, n)).data)
              for s, n in ((disc, "disc.toml"), (plain, "plain.toml"), (capitals, "capitals.toml"))]
    _assert_same_loads(tables[:2], 1e-14)
    _assert_same_loads(tables[1:], 1e-14)
    how = {r[0]: r[3] for r in aircraft.check(_with_section(tmp_path, disc, "disc.toml")).converted}
    assert how["fuselage_aero.reference_area"] == f"times the main rotor's disc area {np.pi * radius**2:.6g} m^2: " \
                                                  "from 1.0 pi R^2"
    assert how["fuselage_aero.reference_length"] == f"times main_rotor.radius {radius:.6g} m: from 1 R"
    for old, new, words in ((' unit = "pi R^2"', ' unit = "R"', "unit 'R': a reference area in the main rotor's "
                                                                 "disc area is πR^2"),
                            (' unit = "R"', ' unit = "πR²"', "unit 'πR²': a reference length in the main rotor's "
                                                             "radius is R")):
        report = aircraft.check(_with_section(tmp_path, disc.replace(old, new, 1), "bad.toml"))
        assert any(words in p for p in report.problems), (words, report.problems)


OWN_ANGLES = """[fuselage_aero]
model = { value = "tables", unit = "-", source = "R2" }
axes = { value = "wind", unit = "-", source = "R2" }
reference_point = { value = [0.1, 0.0, -0.3], unit = "m", source = "R2" }
drag_alpha = { value = [[-25, 44.0], [-12, 36.1], [-3, 33.2], [8, 35.0], [17, 40.3], [30, 52.0]], unit = "deg, ft^2", source = "R2 fig. 3" }
pitch_alpha = { value = [[-20, -1150], [-6, -420], [0, -40], [9, 510], [22, 1310]], unit = "deg, ft^3", source = "R2 fig. 4" }
side_beta = { value = [[-30, 41.0], [-10, 14.2], [0, 0.0], [12, -17.5], [30, -40.2]], unit = "deg, ft^2", source = "R2 fig. 5" }
lift_alpha_beta = { value = [[nan, -25, 0, 15, 25], [-18, -30.1, -31.0, -30.4, -29.8], [-4, -6.2, -5.9, -6.0, -6.3], [7, 11.5, 12.6, 12.1, 11.9], [20, 32.0, 33.4, 32.8, 32.2]], unit = "deg, deg, ft^2", source = "R2 table 6" }
"""


LIFT_GRID = [[-30.1, -31.0, -30.4, -29.8], [-6.2, -5.9, -6.0, -6.3], [11.5, 12.6, 12.1, 11.9], [32.0, 33.4, 32.8, 32.2]]


def _natural(x, y, t) -> float:
    """The natural cubic spline through ``(x, y)`` at ``t``, continued linearly beyond its ends."""
    spline, end = CubicSpline(x, y, bc_type="natural"), np.clip(t, x[0], x[-1])
    return float(spline(end) + (t - end) * spline(end, 1))


def test_curves_digitised_at_their_own_angles_are_read_as_printed(tmp_path):
    """Each curve of a report digitised at its own angles (rows ``[angle, value]``, units
    ``"deg, ft^2"``) and a table in alpha and beta on its own grid (a first row ``[nan, beta...]``,
    then rows ``[alpha, values...]``, units ``"deg, deg, ft^2"``) need no shared breakpoints: every
    component per q equals scipy's natural splines through its own points (tensor product for the
    grid) at 20 random angles to 1e-12 (linear beyond them), and the check lists each table's
    angles in rad; rows of three cells, four units, decreasing angles, the units swapped, a curve
    on a two-angle table and a grid on a one-angle table, a corner that is not nan, and ragged
    rows are refused, each named."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    path = _with_section(tmp_path, OWN_ANGLES, "own.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    table = fuselage_table(aircraft.load(path).data)
    ft2, ft3 = 0.3048**2, 0.3048**3
    curves = {0: ([-25, -12, -3, 8, 17, 30], ft2 * np.array([44.0, 36.1, 33.2, 35.0, 40.3, 52.0]), "alpha"),
              4: ([-20, -6, 0, 9, 22], ft3 * np.array([-1150, -420, -40, 510, 1310]), "alpha"),
              1: ([-30, -10, 0, 12, 30], ft2 * np.array([41.0, 14.2, 0.0, -17.5, -40.2]), "beta")}
    for a, b in RNG.uniform(-0.8, 0.8, (20, 2)):
        got = table.per_q(a, b)
        for i, (angles, values, arg) in curves.items():
            want = _natural(np.radians(angles), values, a if arg == "alpha" else b)
            assert abs(float(got[i]) - want) <= 1e-12 * np.abs(values).max(), (i, a, b)
        rows_b = [_natural(np.radians([-25, 0, 15, 25]), ft2 * np.array(r), b) for r in LIFT_GRID]
        lift = _natural(np.radians([-18, -4, 7, 20]), np.array(rows_b), a)
        assert abs(float(got[2]) - lift) <= 1e-12 * ft2 * 33.4, (a, b)
    how = {r[0]: r[3] for r in report.converted}
    assert how["fuselage_aero.side_beta"] == (f"at its own beta {[float(f'{v:.6g}') for v in np.radians([-30, -10, 0, 12, 30])]} "
                                              "rad; per dynamic pressure, from ft^2")
    for old, new, words in (
            ('[-25, 44.0], [-12, 36.1]', '[-25, 44.0, 1], [-12, 36.1]', "must be rows [angle, value]"),
            ('unit = "deg, ft^2", source = "R2 fig. 3"', 'unit = "deg, ft^2, -, -", source = "R2 fig. 3"',
             "takes two units, the angle's and the values'"),
            ('[-12, 36.1], [-3, 33.2]', '[-3, 36.1], [-12, 33.2]', "breakpoints must increase: -12 follows -3"),
            ('unit = "deg, ft^3"', 'unit = "ft^3, deg"', "'ft^3'"),
            ('side_beta = {', 'side_alpha_beta = {', "rows [angle, value] make a curve in one angle"),
            ('lift_alpha_beta = {', 'lift_alpha = {', "a table on an alpha x beta grid (three units) is for lift_alpha_beta"),
            ('[[nan, -25, 0, 15, 25]', '[[0, -25, 0, 15, 25]', "the first row's first cell is 0; write nan there"),
            ('[-4, -6.2, -5.9, -6.0, -6.3]', '[-4, -6.2, -5.9, -6.0]', "rows of one length")):
        bad = aircraft.check(_with_section(tmp_path, OWN_ANGLES.replace(old, new), "bad.toml"))
        assert any(words in p for p in bad.problems), (words, bad.problems)


def test_a_trim_beyond_a_tables_own_angles_warns_naming_the_table(tmp_path):
    """The own-angle tables of OWN_ANGLES (drag -25..30 deg, pitch -20..22 deg, side force
    -30..30 deg, lift -18..20 x -25..25 deg): a flight at alpha -24 deg warns for the pitch and
    lift tables (not the drag's); one at beta +28 deg for the lift table only; level flight none."""
    from mbs import aircraft
    from mbs.models.helicopter.airframe_warnings import airframe_warnings

    d = aircraft.load(_with_section(tmp_path, OWN_ANGLES, "own.toml")).data
    level = {"fuselage.u": 40.0, "fuselage.v": 0.0, "fuselage.w": 1.0}
    assert not any("fuselage tables" in w for w in airframe_warnings(level, d))
    steep = {**level, "fuselage.w": 40.0 * np.tan(np.radians(-24.0))}
    said = [w for w in airframe_warnings(steep, d) if "fuselage tables" in w]
    assert len(said) == 2 and "fuselage_aero.pitch_alpha's own angles [-20, 22] deg" in said[0], said
    assert "alpha -24.0 deg beyond fuselage_aero.lift_alpha_beta's own angles [-18, 20] deg" in said[1], said
    sideslip = {**level, "fuselage.v": 40.0 * np.tan(np.radians(28.0))}
    said = [w for w in airframe_warnings(sideslip, d) if "fuselage tables" in w]
    assert len(said) == 1 and "beta +" in said[0] and "lift_alpha_beta's own angles [-25, 25] deg" in said[0], said


def test_a_law_printed_with_functions_of_the_angle_is_the_law_at_the_breakpoints(tmp_path):
    """``D/q = 33 + 12 sin²α`` (ft²) and ``N/q = -900 sin β cos β`` (ft³) written as printed with
    ``law = "expression"`` load as the tables of their values at the breakpoints (to 1e-12); the
    check lists the law; an unknown name, another function, an attribute, a law infinite at a
    breakpoint and a law on a two-argument table are refused, each named."""
    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table

    law = WIND_SECTION.replace('drag_alpha = { value = [40.1, 35.2, 33.0, 35.9, 42.4], unit = "ft^2"',
                               'drag_alpha = { value = "33 + 12*sin(α)^2", law = "expression", unit = "ft^2"')
    law += 'yaw_beta = { value = "-900 * sin(beta) * cos(beta)", law = "expression", unit = "ft^3", source = "R1" }\n'
    grid_a, grid_b = np.radians([-20, -10, 0, 10, 20]), np.radians([-20, 0, 20])
    plain = WIND_SECTION.replace("[40.1, 35.2, 33.0, 35.9, 42.4]", str((33 + 12 * np.sin(grid_a) ** 2).tolist()))
    plain += f'yaw_beta = {{ value = {(-900 * np.sin(grid_b) * np.cos(grid_b)).tolist()}, unit = "ft^3", source = "R1" }}\n'
    tables = [fuselage_table(aircraft.load(_with_section(tmp_path, s, n)).data)
              for s, n in ((law, "law.toml"), (plain, "plain.toml"))]
    _assert_same_loads(tables, 1e-12)
    how = {r[0]: r[3] for r in aircraft.check(_with_section(tmp_path, law, "law.toml")).converted}
    assert how["fuselage_aero.drag_alpha"].startswith("the law '33 + 12*sin(α)^2' ft^2 in alpha (rad)")
    for old, new, words in (("sin(α)^2", "sin(gamma)^2", "'gamma' is not known; the law may use alpha (rad), pi"),
                            ("sin(α)^2", "np.sin(alpha)", "a call of one argument to sin, cos, tan, exp, sqrt, abs"),
                            ("sin(α)^2", "alpha.real", "Attribute is not accepted"),
                            ("12*sin(α)^2", "12/sin(α)", "the law '33 + 12/sin(α)' is not finite at alpha = 0 deg"),
                            ("-900 * sin(beta)", "-900 * sin(alpha)", "'alpha' is not known; the law may use beta"),
                            ("lift_alpha_beta = { value", 'lift_alpha_beta = { law = "expression", value',
                             'law = "expression" applies to a fuselage_aero table in alpha or in beta only')):
        report = aircraft.check(_with_section(tmp_path, law.replace(old, new), "bad.toml"))
        assert any(words in p for p in report.problems), (words, report.problems)


def test_tables_printed_with_the_other_sideslip_sign_are_read_at_minus_beta(tmp_path):
    """A report whose sideslip is positive with the wind from port (a new user's UH-60 tables, whose
    side force then aided the sideslip without a word): its tables written as printed with
    ``sideslip_positive = "wind from port"`` give the loads of the same tables mirrored in β, to
    1e-12, in body and in wind axes, and the check lists the reading."""
    import re

    from mbs import aircraft
    from mbs.aircraft.airframe_data import fuselage_table
    from mbs.aircraft.template import with_polynomial_tables

    path = with_polynomial_tables("bo105", tmp_path)
    text = path.read_text()
    assert "[-90.0, -85.0" in text and "Y_beta" in text  # a grid symmetric in β: mirrored, the values reversed

    def reversed_list(match):
        values = match.group(2).split(", ")
        return f"{match.group(1)}[{', '.join(reversed(values))}]"

    mirrored = re.sub(r"^((?:Y|N)_beta = \{ value = )\[([^\]]*)\]", reversed_list, text, flags=re.M)
    mirrored = mirrored.replace('axes = { value = "body"', 'sideslip_positive = { value = "wind from port", unit = '
                                '"-", source = "report" }\naxes = { value = "body"')
    other = tmp_path / "port.toml"
    other.write_text(mirrored)
    assert mirrored != text
    for axes in ("body", "wind"):
        tables = [fuselage_table(aircraft.load(p).data) for p in (path, other)]
        for table in tables:
            table.axes = axes
        for alpha, beta in ((0.1, 0.2), (-0.3, -0.25), (0.05, 0.6)):
            (f0, m0), (f1, m1) = (table.body_per_q(alpha, beta) for table in tables)
            assert np.allclose(np.r_[f1.full().ravel(), m1.full().ravel()], np.r_[f0.full().ravel(), m0.full().ravel()],
                               rtol=0.0, atol=1e-12), (axes, alpha, beta)
    rows = {r[0]: r[3] for r in aircraft.check(other).converted}
    assert rows["fuselage_aero.sideslip_positive"].startswith("the tables read at -beta")
