"""Tail surfaces with published coefficient tables (``coefficient_table``: rows angle of attack,
c_L, c_D) in place of the analytic section: the section force is the tables' natural spline
(against scipy's, an independent implementation), its AD derivatives equal central differences,
a table sampled from the analytic section trims as the analytic section does, and every
ill-formed table is a problem naming the entry."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from aircraft_files import entries, to_toml, write
from mbs import aircraft, scenes
from mbs.aero.sections import Airfoil, TableSection, section_force
from mbs.analysis.trim import periodic_solution

SURFACES = ("horizontal_tail", "vertical_fin")
ANALYTIC = ("lift_slope", "cd0", "cd2", "alpha_stall", "cd_stalled")


def _sampled(section: dict, step_deg: float = 1.0) -> list[list[float]]:
    """Rows (alpha rad, c_L, c_D) of the file's analytic section every ``step_deg`` over ±90 deg."""
    foil = Airfoil(*(section[k] for k in ANALYTIC))
    alpha = np.radians(np.arange(-90.0, 90.0 + step_deg / 2, step_deg))
    a = ca.SX.sym("a")
    f = ca.Function("f", [a], list(foil.coefficients(a)))
    return [[float(x), float(f(x)[0]), float(f(x)[1])] for x in alpha]


def _with_tables(tmp_path, rows_of=None, keep_analytic: bool = False):
    """The Bo105 with both tail surfaces given by tables (default: sampled from its analytic sections)."""
    raw, data = entries("bo105"), aircraft.load("bo105").data
    for section in SURFACES:
        rows = (rows_of or {}).get(section) or _sampled(data[section])
        raw[section]["coefficient_table"] = {"value": rows, "unit": "rad, -, -", "source": "sampled"}
        if not keep_analytic:
            for key in ANALYTIC:
                raw[section].pop(key, None)
    return write(raw, tmp_path / "tables.toml")


def test_the_section_force_is_the_tables_natural_spline():
    """At 100 random angles within and beyond the rows, the force of a table section equals
    q S (c_L, c_D) of scipy's natural cubic spline through the rows (linear beyond the ends)."""
    rows = np.array([[-0.6, -1.0, 0.9], [-0.2, -0.7, 0.05], [0.0, 0.0, 0.01], [0.15, 0.6, 0.02], [0.3, 1.1, 0.08],
                     [0.5, 0.8, 0.6], [1.2, 0.2, 1.4]])
    table = TableSection(*(tuple(c) for c in rows.T))
    spline = CubicSpline(rows[:, 0], rows[:, 1:], bc_type="natural")
    rng = np.random.default_rng(7)
    alpha = rng.uniform(-1.0, 1.5, 100)
    for a in alpha:
        speed = 30.0
        w_c, w_n = -speed * math.cos(a), speed * math.sin(a)  # air from ahead, at alpha to the chord
        f_c, f_n = (float(v) for v in section_force(w_c, w_n, table, 1.2, 0.8))
        inside = rows[0, 0] <= a <= rows[-1, 0]
        end = 0 if a < rows[0, 0] else -1
        cl, cd = spline(a) if inside else rows[end, 1:] + (a - rows[end, 0]) * spline(rows[end, 0], 1)
        q = 0.5 * 1.2 * 0.8 * speed
        assert f_c == pytest.approx(q * (cl * w_n + cd * w_c), rel=1e-10, abs=1e-9)
        assert f_n == pytest.approx(q * (-cl * w_c + cd * w_n), rel=1e-10, abs=1e-9)


def test_the_table_sections_ad_derivatives_equal_central_differences():
    rows = np.array([[-0.6, -1.0, 0.9], [-0.2, -0.7, 0.05], [0.0, 0.0, 0.01], [0.15, 0.6, 0.02], [0.3, 1.1, 0.08]])
    table = TableSection(*(tuple(c) for c in rows.T))
    w = ca.SX.sym("w", 2)
    force = ca.vertcat(*section_force(w[0], w[1], table, 1.2, 0.8))
    f, jac = ca.Function("f", [w], [force]), ca.Function("j", [w], [ca.jacobian(force, w)])
    rng = np.random.default_rng(3)
    for _ in range(20):
        x = np.array([-rng.uniform(10, 60), rng.uniform(-20, 20)])
        fd = np.column_stack([(f(x + h) - f(x - h)).full().ravel() / 2e-6 for h in 1e-6 * np.eye(2)])
        assert np.abs(jac(x).full() - fd).max() <= 1e-5 * max(1.0, np.abs(fd).max())


def test_a_table_sampled_from_the_analytic_section_trims_as_the_analytic_section(tmp_path):
    """Both tail surfaces as tables sampled every degree from their analytic sections: the 30 m/s
    trim's controls and attitudes equal the analytic model's to 1e-4 deg (measured 3e-7 deg in the
    controls, 8e-7 deg in pitch: the spline's interpolation error of the sampled coefficients),
    and the check lists no problem."""
    path = _with_tables(tmp_path)
    report = aircraft.check(path)
    assert report.ok, report.problems
    base = periodic_solution(scenes.get("forward-flight"), 30.0)
    tab = periodic_solution(scenes.get("forward-flight").with_aircraft(str(path)), 30.0)
    assert base.converged and tab.converged
    print(f"\nlargest control difference {max(math.degrees(abs(tab.controls[k] - v)) for k, v in base.controls.items()):.2e}"
          f" deg, pitch {math.degrees(tab.pitch - base.pitch):+.2e} deg, roll {math.degrees(tab.roll - base.roll):+.2e} deg")
    for key, value in base.controls.items():
        assert math.degrees(abs(tab.controls[key] - value)) <= 1e-4, key
    assert math.degrees(abs(tab.pitch - base.pitch)) <= 1e-4 and math.degrees(abs(tab.roll - base.roll)) <= 1e-4
    assert not any("stall" in w for w in tab.warnings)


def test_a_trim_beyond_the_table_warns(tmp_path):
    """A horizontal-tail table over ±2 deg only: the 30 m/s trim's tail angle lies beyond it."""
    narrow = [[math.radians(-2.0), -0.11, 0.01], [0.0, 0.0, 0.01], [math.radians(2.0), 0.11, 0.01]]
    path = _with_tables(tmp_path, {"horizontal_tail": narrow})
    res = periodic_solution(scenes.get("forward-flight").with_aircraft(str(path)), 30.0)
    assert any(w.startswith("horizontal tail: angle of attack") and "beyond its coefficient table" in w
               for w in res.warnings), res.warnings


@pytest.mark.parametrize("rows, keep, expected", [
    ([[-0.1, 0.0, 0.01]], False, "horizontal_tail.coefficient_table: one row; give at least two"),
    ([[0.1, 0.0, 0.01], [-0.1, 0.0, 0.01]], False, "horizontal_tail.coefficient_table: the angles of attack must "
                                                   "increase; row 2 (-5.73 deg) follows row 1 (5.73 deg)"),
    ([[-0.1, 0.0, 0.01], [0.0, 0.0, 0.01], [0.0, 0.0, 0.01]], False,
     "horizontal_tail.coefficient_table: the angles of attack must increase; row 3 (0 deg) follows row 2 (0 deg)"),
    ([[-2.0, 0.0, 1.0], [0.0, 0.0, 0.01]], False, "horizontal_tail.coefficient_table: angles of attack -114.6 to 0 "
                                                  "deg; give them within -90..90 deg"),
    (None, True, "horizontal_tail.coefficient_table: replaces horizontal_tail.lift_slope; leave lift_slope out"),
])
def test_an_ill_formed_table_or_one_beside_the_analytic_section_is_a_problem(tmp_path, rows, keep, expected):
    path = _with_tables(tmp_path, {"horizontal_tail": rows} if rows else None, keep_analytic=keep)
    report = aircraft.check(path)
    assert any(p.startswith(expected) for p in report.problems), report.problems


def test_a_table_printed_per_dynamic_pressure_or_on_the_rotor_disc_is_read_as_printed(tmp_path):
    """The horizontal tail's table printed as L/q, D/q in ft² and the fin's as coefficients on the
    main rotor's disc (``πR^2``) load as the plain coefficient tables on each surface's area (to
    1e-14) and are listed with the conversion; a force column in lbf is refused, named."""
    data = aircraft.load("bo105").data
    plain = {s: _sampled(data[s], 10.0) for s in SURFACES}
    area = {s: data[s]["area"] for s in SURFACES}
    disc = math.pi * data["main_rotor"]["radius"] ** 2
    printed = {"horizontal_tail": [[a, cl * area["horizontal_tail"] / 0.3048**2, cd * area["horizontal_tail"] / 0.3048**2]
                                   for a, cl, cd in plain["horizontal_tail"]],
               "vertical_fin": [[a, cl * area["vertical_fin"] / disc, cd * area["vertical_fin"] / disc]
                                for a, cl, cd in plain["vertical_fin"]]}
    raw = entries("bo105")
    for section, unit in (("horizontal_tail", "rad, ft^2, ft^2"), ("vertical_fin", "rad, πR^2, πR^2")):
        raw[section]["coefficient_table"] = {"value": printed[section], "unit": unit, "source": "report"}
        for key in ANALYTIC:
            raw[section].pop(key, None)
    path = write(raw, tmp_path / "printed.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    loaded = aircraft.load(path).data
    for section in SURFACES:
        got, want = np.array(loaded[section]["coefficient_table"]), np.array(plain[section])
        assert np.abs(got - want).max() <= 1e-14 * np.abs(want).max(), section
    how = {r[0]: r[3] for r in report.converted}
    assert how["horizontal_tail.coefficient_table"].startswith(
        f"coefficients on horizontal_tail.area: c_L per dynamic pressure over horizontal_tail.area "
        f"{area['horizontal_tail']:.6g} m^2; c_D per dynamic pressure")
    assert f"c_L on the main rotor's disc area {disc:.6g} m^2 times {disc / area['vertical_fin']:.6g}" in \
        how["vertical_fin.coefficient_table"]
    raw["horizontal_tail"]["coefficient_table"]["unit"] = "rad, lbf, ft^2"
    bad = aircraft.check(write(raw, tmp_path / "bad.toml"))
    assert "horizontal_tail.coefficient_table: unit 'lbf' of a force column is a force; give - (a coefficient on the " \
        "surface's area), an area (L/q, D/q: ft^2) or πR^2" in " ".join(bad.problems), bad.problems


def _full_circle(rows: list[list[float]], step: int = 10) -> list[list[float]]:
    """Rows over ±90 deg (every ``step`` deg) continued over the full circle as the folded angle
    reads them: c(θ) = c(θ ∓ π) beyond ±90 deg."""
    by_deg = {round(math.degrees(a)): (cl, cd) for a, cl, cd in rows}
    out = []
    for deg in range(-180, 181, step):
        folded = deg + 180 if deg < -90 else deg - 180 if deg > 90 else deg
        out.append([math.radians(deg), *by_deg[folded]])
    return out


def test_a_full_circle_table_is_read_at_the_air_s_own_angle():
    """A tail table printed from -180 to 180 deg (a new user's UH-60 stabilator, cut to ±90 by hand
    and its reverse-flow rows lost): read at the air's full-circle angle, the printed reverse-flow
    rows are used as they are. Built as the folded table continued (c(θ) = c(θ ∓ π)), its force
    equals the folded table's at every row angle, forward and reverse flow, to 1e-9; with its
    reverse-flow lift doubled it differs only in reverse flow."""
    from mbs.aero.sections import TableSection, section_force

    half = _sampled(aircraft.load("bo105").data["horizontal_tail"], 10.0)
    full = _full_circle(half)
    doubled = [[a, 2 * cl if abs(a) > math.pi / 2 else cl, cd] for a, cl, cd in full]
    sections = [TableSection(*(tuple(c) for c in zip(*rows))) for rows in (half, full, doubled)]
    assert [s.full_circle for s in sections] == [False, True, True]
    w = ca.SX.sym("w", 2)
    forces = [ca.Function("f", [w], [ca.vertcat(*section_force(w[0], w[1], s, 1.2, 2.0))]) for s in sections]
    for deg in range(-170, 171, 10):
        v = 30.0 * np.array([-math.cos(math.radians(deg)), math.sin(math.radians(deg))])  # atan2(w_n, -w_c) = deg
        f_half, f_full, f_doubled = (np.asarray(f(v)).ravel() for f in forces)
        assert f_full == pytest.approx(f_half, rel=1e-9, abs=1e-9), deg
        assert (np.abs(f_doubled - f_full).max() > 1.0) == (abs(deg) > 90 and deg % 180 != 0), deg


def test_full_circle_tail_tables_trim_as_the_analytic_sections_and_one_that_does_not_close_is_refused(tmp_path):
    """Both tail surfaces as full-circle tables (the 1-degree samples continued over ±180 deg): the
    30 m/s trim equals the analytic model's to 1e-4 deg (measured 2.8e-7 deg in the controls, 7.5e-7
    deg in pitch), as the ±90 deg tables do; a table beyond
    ±90 deg that does not close at ±180 deg is refused, named."""
    data = aircraft.load("bo105").data
    path = _with_tables(tmp_path, {s: _full_circle(_sampled(data[s]), 1) for s in SURFACES})
    report = aircraft.check(path)
    assert report.ok, report.problems
    base = periodic_solution(scenes.get("forward-flight"), 30.0)
    tab = periodic_solution(scenes.get("forward-flight").with_aircraft(str(path)), 30.0)
    assert base.converged and tab.converged
    for key, value in base.controls.items():
        assert math.degrees(abs(tab.controls[key] - value)) <= 1e-4, key
    assert math.degrees(abs(tab.pitch - base.pitch)) <= 1e-4 and math.degrees(abs(tab.roll - base.roll)) <= 1e-4
    rows = _full_circle(_sampled(data["horizontal_tail"], 10.0))
    rows[-1][1] += 0.1
    problems = aircraft.check(_with_tables(tmp_path, {"horizontal_tail": rows})).problems
    assert any(p.startswith("horizontal_tail.coefficient_table: angles of attack -180 to 180 deg; give them within "
                            "-90..90 deg") and "the same c_L and c_D at both ends" in p for p in problems), problems


def test_a_tail_table_printed_as_polynomials_in_degrees_is_taken_as_printed(tmp_path):
    """A new user's Gazelle report prints the horizontal tail's c_L and c_D as polynomials in the
    angle in degrees, in per cent; the table was refused as a law. Written as printed, with the
    breakpoints where they hold, it reads as the same rows tabulated by hand, to round-off; a
    law that is not finite at a breakpoint, or a value not of that form, is refused naming it."""
    lift, drag = "5.7*alpha - 0.0021*alpha^3", "1.1 + 0.004*alpha^2 + 1.2e-5*alpha^4"
    alpha = [-20.0, -15.0, -10.0, -5.0, 0.0, 5.0, 10.0, 15.0, 20.0]
    cl = [(5.7 * a - 0.0021 * a**3) / 100 for a in alpha]
    cd = [(1.1 + 0.004 * a**2 + 1.2e-5 * a**4) / 100 for a in alpha]
    hand, law = entries("bo105"), entries("bo105")
    for raw in (hand, law):
        for key in ANALYTIC:
            raw["horizontal_tail"].pop(key, None)
    hand["horizontal_tail"]["coefficient_table"] = {
        "value": [[math.radians(a), l, d] for a, l, d in zip(alpha, cl, cd)], "unit": "rad, -, -", "source": "t"}

    def with_law(value: str, name: str):
        line = f'coefficient_table = {{ value = {value}, law = "expression", unit = "deg, %, %", source = "eq. 12" }}'
        text = to_toml(law).replace("[horizontal_tail]\n", "[horizontal_tail]\n" + line + "\n", 1)
        (tmp_path / name).write_text(text)
        return tmp_path / name

    printed = f'{{ alpha = {alpha}, lift = "{lift}", drag = "{drag}" }}'
    by_hand = aircraft.load(write(hand, tmp_path / "hand.toml")).data["horizontal_tail"]["coefficient_table"]
    as_printed = aircraft.load(with_law(printed, "law.toml")).data["horizontal_tail"]["coefficient_table"]
    assert np.allclose(np.array(as_printed), np.array(by_hand), rtol=1e-14, atol=1e-15)
    report = aircraft.check(with_law(printed.replace(drag, "1.1/alpha"), "bad.toml"))
    assert any("horizontal_tail.coefficient_table: the drag law '1.1/alpha' is not finite at alpha = 0" in p
               for p in report.problems), report.problems
    report = aircraft.check(with_law('"5.7*alpha"', "bad2.toml"))
    assert any("value must be { alpha = [breakpoints], lift =" in p for p in report.problems), report.problems
    # the per-cent laws read as numbers (unit "deg, -, -"): c_L up to 97 passed without a word
    text = with_law(printed, "dash.toml").read_text().replace('unit = "deg, %, %"', 'unit = "deg, -, -"')
    (tmp_path / "dash.toml").write_text(text)
    report = aircraft.check(tmp_path / "dash.toml")
    assert report.ok and any(w.startswith("horizontal_tail.coefficient_table: c_L up to 97.2") and "(% or -)" in w
                             for w in report.warnings), report.warnings
    report = aircraft.check(with_law(printed.replace("alpha - 0.0021", "alpah - 0.0021"), "typo.toml"))
    assert any("the law may use alpha (in deg, the breakpoints' unit)" in p for p in report.problems), report.problems
