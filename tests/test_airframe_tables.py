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
    from mbs.aircraft.airframe_data import with_polynomial_tables
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
