"""Airfoil tables: C81 files read as printed, the smooth interpolant against an independent
evaluation (scipy), section loads and their AD derivatives, and trims and Floquet with tables on."""
from __future__ import annotations

import math
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from mbs import aircraft
from mbs.aero import EPS, Airfoil, Compressibility
from mbs.aero.tables import C81Error, HermiteTable, TableAirfoil, TableSpline, parse_c81, table_section_loads
from mbs.aero.tables.c81 import COEFFICIENTS, CoefficientTable, format_c81
from mbs.aero.tables.interpolant import parabolic_slopes
from mbs.aero.tables.sample import MACH, analytic_c81

RNG = np.random.default_rng(30)

# A file in the layout programs print: name in 30 columns and the counts in 2 columns each (here
# 12 Mach numbers: each row continues on a second line after 7 blanks), numbers that run together
# ("-1.0255-.99") and a first Mach number printed as ".0".
PRINTED = """\
SAMPLE 12% AIRFOIL (1990)     12 512 512 5
         .0     .3     .35    .4     .45    .5     .55    .6     .65
         .7     .75    .8
-180.    .0     .0     .0     .0     .0     .0     .0     .0    0.
         .0     .0     .0
 -15.  -1.19  -1.09  -1.072 -1.0550-1.0255 -.99   -.985  -.98   -.98
        -.98   -.83   -.79
    .0  -.032  -.032  -.035  -.037  -.037  -.037  -.038  -.038  -.037
        -.036  -.035  -.019
  15.   1.19   1.09   1.0725 1.055  1.023  1.023  1.003   .98    .98
         .98    .83    .79
 180.    .0     .0     .0     .0     .0     .0     .0     .0     .0
         .0     .0     .0
         .0     .3     .35    .4     .45    .5     .55    .6     .65
         .7     .75    .8
-180.    .022   .022   .022   .022   .022   .022   .022   .022   .022
         .022   .022   .022
 -15.    .102   .1546  .1706  .1866  .1995  .2124  .221   .2296  .2389
         .2482  .2629  .2776
    .0   .0101  .0101  .0102  .0103  .0103  .0104  .0105  .0105  .0106
         .0108  .0113  .0148
  15.    .102   .1546  .1706  .1866  .1995  .2124  .221   .2296  .2389
         .2482  .2629  .2776
 180.    .022   .022   .022   .022   .022   .022   .022   .022   .022
         .022   .022   .022
         .0     .3     .35    .4     .45    .5     .55    .6     .65
         .7     .75    .8
-180.    .0     .0     .0     .0     .0     .0     .0     .0     .0
         .0     .0     .0
 -15.    .015   .015   .015   .015   .015   .015   .015   .015   .015
         .015   .015   .015
    .0  -.0081 -.0081 -.0082 -.0084 -.0088 -.009  -.0094 -.0098 -.0103
        -.011  -.0118 -.0194
  15.   -.015  -.015  -.015  -.015  -.015  -.015  -.015  -.015  -.015
        -.015  -.015  -.015
 180.    .0     .0     .0     .0     .0     .0     .0     .0     .0
         .0     .0     .0
"""

# Typed by hand: numbers separated by blanks, not in their columns, the counts after a short name.
TYPED = """\
NACA 0012 1 3 1 3 2 3
  0.0
-180 0.0
0 0.0
180 0.0
  0.0
-180 0.02
0 0.008
180 0.02
   0.0 0.5
-180 0.0 0.0
0 0.0 -0.01
180 0.0 0.0
"""


def test_a_c81_file_as_printed_is_read_with_its_continuation_lines_and_numbers_that_run_together():
    c81 = parse_c81(PRINTED)
    assert c81.name == "SAMPLE 12% AIRFOIL (1990)"
    assert np.allclose(c81.CL.mach, [0, .3, .35, .4, .45, .5, .55, .6, .65, .7, .75, .8])
    assert np.allclose(c81.CL.alpha, [-180, -15, 0, 15, 180])
    assert c81.CL.values[1, 3] == -1.055 and c81.CL.values[1, 4] == -1.0255 and c81.CL.values[1, 5] == -0.99 and c81.CL.values[3, 11] == 0.79
    assert c81.CD.values[2, 11] == 0.0148 and c81.CM.values[2, 0] == -0.0081


def test_a_c81_file_typed_by_hand_with_blanks_between_numbers_is_read():
    c81 = parse_c81(TYPED)
    assert c81.name == "NACA 0012" and c81.CM.mach.tolist() == [0.0, 0.5]
    assert c81.CD.values[:, 0].tolist() == [0.02, 0.008, 0.02] and c81.CM.values[1].tolist() == [0.0, -0.01]


def test_a_row_typed_whole_on_one_line_is_read():
    lines = PRINTED.splitlines()
    joined = lines[:3] + [lines[3] + " " + lines[4].strip()] + lines[5:]  # the -180 deg row of CL on one line
    c81 = parse_c81("\n".join(joined))
    assert np.array_equal(c81.CL.values, parse_c81(PRINTED).CL.values)


def test_a_deck_as_some_print_it_reads_as_fortran_reads_it():
    """A 0 in the 7 columns that Fortran's 7X skips before the Mach numbers, and a whole row on one
    line whose numbers run together (``-1.0550-1.0255``): a new user's NACA 0012 deck had both, and
    was refused ("starts with 7 blank columns"; "expected 10 numbers; found 13")."""
    lines = PRINTED.splitlines()
    assert lines[1].startswith("         .0") and "-1.0550-1.0255" in lines[5]
    lines[1] = "  0.   " + lines[1][7:]
    joined = lines[:5] + [lines[5] + " " + lines[6].strip()] + lines[7:]  # the -15 deg row of CL on one line
    c81, plain = parse_c81("\n".join(joined)), parse_c81(PRINTED)
    for c in COEFFICIENTS:
        assert np.array_equal(c81.table(c).values, plain.table(c).values)
        assert np.array_equal(c81.table(c).mach, plain.table(c).mach)


def test_a_written_c81_file_reads_back_to_its_printed_precision():
    c81 = analytic_c81(Airfoil(6.1, 0.008, 0.2), mach=MACH, compressibility=Compressibility(340.3, 0.75))
    back = parse_c81(format_c81("BACK", {c: c81.table(c) for c in COEFFICIENTS}))
    for c in COEFFICIENTS:
        assert np.abs(back.table(c).values - c81.table(c).values).max() <= 5e-5
        assert np.array_equal(back.table(c).alpha, c81.table(c).alpha)


BAD_C81 = {  # what is wrong -> (the text, the words of the message)
    "short header": ("NACA 0012\n", "line 1: the header must hold"),
    "a row too short": (PRINTED.replace("  15.   1.19   1.09   1.0725 1.055  1.023  1.023  1.003   .98    .98",
                                        "  15.   1.19   1.09"), "line 10: expected 10 numbers; found 3 separated by blanks"),
    "angles not increasing": (PRINTED.replace("  15.   1.19", "  -5.   1.19"), "must increase; 0 is followed by -5"),
    "a word for a number": (PRINTED.replace(" -15.  -1.19", " -15.  -x.19"), "line 6: expected 10 numbers"),
    "file ends early": ("\n".join(PRINTED.splitlines()[:30]), "ends before row"),
    "continuation in column 1": (PRINTED.replace("        -.98   -.83   -.79", "-.98   -.83   -.79 .4"),
                                 "line 7: a line of Mach numbers or a continuation line starts with 7 blank"),
}


@pytest.mark.parametrize("what", list(BAD_C81))
def test_a_bad_c81_file_is_one_message_naming_its_line(what):
    text, words = BAD_C81[what]
    with pytest.raises(C81Error) as err:
        parse_c81(text, Path("wing.c81"))
    assert str(err.value).startswith("C81 file wing.c81") and words in str(err.value) and "\n" not in str(err.value)


def test_a_table_that_does_not_close_over_180_deg_is_refused():
    c81 = parse_c81(TYPED.replace("\n180 0.02", "\n180 0.03"))
    with pytest.raises(ValueError, match=r"CD: the value at -180 deg \(0.02\) differs from the value at 180 deg"):
        TableAirfoil.from_c81(c81)
    with pytest.raises(ValueError, match="must run from -180 to 180 deg"):
        HermiteTable("CL", [-20.0, 0.0, 20.0], [0.0], [[0.0], [0.0], [0.0]])


# -- the interpolant against an independent evaluation ------------------------------------------

def _random_tables():
    """Three coefficient tables on grids of their own, as C81 decks have them (one point, 7.3456°,
    and one Mach number, .853, off any lattice: the bins then read the interval first)."""
    grids = [(np.r_[-180, -170, -150, -120, -90, -60, -30, -20, -16, -14, -12, -10, -8, -6, -4, -2, -1, 0, 1, 2, 4,
                    6, 8, 10, 12, 14, 16, 20, 30, 60, 90, 120, 150, 170, 180.], np.r_[0, .3, .4, .5, .6, .7, .8, .9, 1.]),
             (np.r_[-180, -165, -90, -12.5, -3, 0, 0.5, 3, 7.3456, 12, 30, 90, 165, 180.], np.r_[.2, .5, .75, .853]),
             (np.r_[-180, -90, -10, 0, 10, 90, 180.], np.r_[.5])]
    out = []
    for alpha, mach in grids:
        values = RNG.normal(size=(len(alpha), len(mach)))
        values[-1] = values[0]
        out.append((alpha, mach, values))
    return out


def scipy_coefficient(table, alpha: float, mach: float) -> float:
    """The same interpolant by scipy: PCHIP in alpha over the table extended by one point across
    ±180 deg, then a cubic Hermite in Mach with three-point slopes, zero at the ends, held beyond."""
    a_deg, m, v = table
    a = np.radians(a_deg)
    period = a[-1] - a[0]
    column = PchipInterpolator(np.r_[a[-2] - period, a, a[1] + period], np.vstack([v[-2:-1], v, v[1:2]]), axis=0)(alpha)
    if len(m) == 1:
        return float(column[0])
    return float(CubicHermiteSpline(m, column, parabolic_slopes(m, column))(np.clip(mach, m[0], m[-1])))


def test_the_merged_interpolant_equals_each_tables_own_interpolant_at_100_random_points():
    tables = _random_tables()
    spline = TableSpline("test", [HermiteTable(f"c{k}", *t) for k, t in enumerate(tables)])
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [spline(x[0], x[1])])
    points = np.column_stack([RNG.uniform(-np.pi, np.pi, 100), RNG.uniform(-0.1, 1.2, 100)])
    ours = np.array([np.array(f(p)).ravel() for p in points])
    theirs = np.array([[scipy_coefficient(t, *p) for t in tables] for p in points])
    assert np.abs(ours - theirs).max() <= 1e-12 * np.abs(theirs).max()


def test_the_interpolant_passes_through_every_printed_value():
    c81 = parse_c81(PRINTED)
    airfoil = TableAirfoil.from_c81(c81)
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [ca.vertcat(*airfoil.coefficients(x[0], x[1]))])
    for k, c in enumerate(COEFFICIENTS):
        t = c81.table(c)
        got = [[float(f([math.radians(a), m])[k]) for m in t.mach] for a in t.alpha]
        assert np.abs(np.array(got) - t.values).max() <= 1e-14


def test_the_interpolant_is_c1_across_its_grid_points_and_across_180_deg():
    """One-sided slopes at a grid point agree (no kink for Newton or Floquet), also through the
    branch cut at ±180 deg, where reverse flow crosses."""
    airfoil = TableAirfoil.from_c81(parse_c81(PRINTED))
    x = ca.SX.sym("x", 2)
    out = ca.vertcat(*airfoil.coefficients(x[0], x[1]))
    jac = ca.Function("j", [x], [ca.jacobian(out, x)])
    eps = 1e-9
    for a, m in ((math.radians(-15.0), 0.62), (0.0, 0.5), (math.radians(15.0), 0.3), (0.1, 0.55), (0.1, 0.3)):
        left, right = jac([a - eps, m - eps]), jac([a + eps, m + eps])
        assert np.abs(np.array(left - right)).max() <= 1e-6
    below, above = jac([math.pi - 1e-12, 0.5]), jac([-math.pi + 1e-12, 0.5])
    assert np.abs(np.array(below - above)).max() <= 1e-6


# -- section loads ------------------------------------------------------------------------------

RHO, SOUND, AREA, CHORD = 1.2, 340.0, 0.05, 0.27


def _section_function(airfoil: TableAirfoil):
    w = ca.SX.sym("w", 2)
    loads = table_section_loads(w[0], w[1], airfoil, lambda speed: speed / SOUND, RHO, AREA, CHORD)
    return ca.Function("loads", [w], [ca.vertcat(*loads)])


def test_section_loads_equal_the_tables_own_values_at_100_random_angles_and_mach_numbers():
    """The force and moment from the section's air velocity at random (alpha, M) against the same
    load computed from scipy's evaluation of the interpolant at the section's alpha and M (the
    angle of ``atan2(w_n, EPS - w_c)``, EPS = 1e-9 m/s keeping derivatives finite at rest): to
    1e-12."""
    c81 = parse_c81(PRINTED)
    tables = [(c81.table(c).alpha, c81.table(c).mach, c81.table(c).values) for c in COEFFICIENTS]
    f = _section_function(TableAirfoil.from_c81(c81))
    worst = 0.0
    for alpha, mach in zip(RNG.uniform(-np.pi, np.pi, 100), RNG.uniform(0.05, 0.85, 100)):
        speed = mach * SOUND
        w_c, w_n = -speed * math.cos(alpha), speed * math.sin(alpha)  # air from ahead at alpha
        alpha, speed = math.atan2(w_n, EPS - w_c), math.sqrt(w_c**2 + w_n**2 + EPS**2)
        mach = speed / SOUND
        cl, cd, cm = (scipy_coefficient(t, alpha, mach) for t in tables)
        q_area = 0.5 * RHO * speed**2 * AREA
        lift, drag = cl * q_area, cd * q_area  # lift normal to the air's velocity, drag along it
        along = np.array([w_c, w_n]) / speed
        expected = np.r_[lift * np.array([along[1], -along[0]]) + drag * along, cm * q_area * CHORD]
        got = np.array(f([w_c, w_n])).ravel()
        worst = max(worst, np.abs(got - expected).max() / (q_area * CHORD + np.abs(expected).max()))
    assert worst <= 1e-12


def test_the_ad_derivatives_of_the_section_loads_equal_central_differences():
    c81 = parse_c81(PRINTED)
    f = _section_function(TableAirfoil.from_c81(c81))
    w = ca.SX.sym("w", 2)
    jac = ca.Function("j", [w], [ca.jacobian(f(w), w)])
    for alpha, mach in zip(RNG.uniform(-np.pi, np.pi, 20), RNG.uniform(0.05, 0.85, 20)):
        p = mach * SOUND * np.array([-math.cos(alpha), math.sin(alpha)])
        h = 1e-5 * np.linalg.norm(p)
        central = np.column_stack([(np.array(f(p + h * e)) - np.array(f(p - h * e))).ravel() / (2 * h)
                                   for e in np.eye(2)])
        exact = np.array(jac(p))
        assert np.abs(exact - central).max() <= 1e-6 * np.abs(exact).max()


# -- the aircraft file's entry ------------------------------------------------------------------

def _with_airfoils(tmp_path: Path, value, unit="-", c81: str = PRINTED, section: str = "main_rotor") -> Path:
    from aircraft_files import entries, write

    (tmp_path / "wing.c81").write_text(c81)
    raw = entries("bo105")
    raw[section]["airfoils"] = {"value": value, "unit": unit, "source": "test"}
    return write(raw, tmp_path / "tabled.toml")


BROKEN_AIRFOILS = {  # what is wrong -> (value, unit, C81 text, the words of the one line)
    "wrong unit": ([[0.0, "wing.c81"]], "m", PRINTED, "main_rotor.airfoils: unit 'm': give unit = \"-\""),
    "not rows": (["wing.c81"], "-", PRINTED, "main_rotor.airfoils: must be a list of rows [r/R, \"file.c81\"]"),
    "start beyond the tip": ([[1.2, "wing.c81"]], "-", PRINTED, "main_rotor.airfoils: segment start r/R = 1.2 outside"),
    "starts not increasing": ([[0.0, "wing.c81"], [0.0, "wing.c81"]], "-", PRINTED, "must increase"),
    "no such file": ([[0.0, "naca.c81"]], "-", PRINTED, "main_rotor.airfoils: C81 file"),
    "bad C81 file": ([[0.0, "wing.c81"]], "-", "NACA\n", "main_rotor.airfoils: C81 file"),
    "table not closed": ([[0.0, "wing.c81"]], "-", TYPED.replace("\n180 0.02", "\n180 0.03"),
                         "main_rotor.airfoils: wing.c81 CD: the value at -180 deg (0.02) differs"),
    "first segment outboard of the cut-out": ([[0.5, "wing.c81"]], "-", PRINTED,
                                              "main_rotor.airfoils: the first segment starts at r/R = 0.5"),
}


@pytest.mark.parametrize("what", list(BROKEN_AIRFOILS))
def test_a_broken_airfoils_entry_is_one_line_naming_it(what, tmp_path, capsys):
    from test_cli_errors import run_main

    value, unit, c81, words = BROKEN_AIRFOILS[what]
    path = _with_airfoils(tmp_path, value, unit, c81)
    code, err = run_main(["aircraft", "check", str(path)], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and words in lines[0] and "Traceback" not in err, err
    code, err = run_main(["simulate", "hover", "--aircraft", str(path), "--out", str(tmp_path / "out")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err


def test_check_lists_each_airfoil_segment_with_its_file_and_says_what_the_analytic_entries_still_do(tmp_path, capsys):
    from test_cli_errors import run_main

    from mbs.aircraft.report import check

    path = _with_airfoils(tmp_path, [[0.0, "wing.c81"], [0.8, "wing.c81"]])
    code, err = run_main(["aircraft", "check", str(path)], capsys)
    assert code == 0, err
    report = check(path)
    figures = {n: v for n, v, _ in report.figures}
    assert figures["main-rotor airfoil from r/R = 0.8"].startswith("SAMPLE 12% AIRFOIL (1990) from wing.c81 (CL 5 x 12")
    assert any(w.startswith("main_rotor.airfoils: the blade elements use the tables") for w in report.warnings)


def test_a_changed_c81_file_changes_the_aircraft(tmp_path):
    path = _with_airfoils(tmp_path, [[0.0, "wing.c81"]])
    before = aircraft.load(path).digest
    (tmp_path / "wing.c81").write_text(PRINTED.replace("  15.   1.19", "  15.   1.20"))
    after = aircraft.load(path)
    assert after.digest != before and after.data["main_rotor"]["airfoils"][0].c81.CL.values[3, 0] == 1.20


def test_segments_give_each_blade_element_its_airfoil():
    from mbs.aero.tables import BladeAirfoils

    a, b = TableAirfoil.from_c81(parse_c81(PRINTED)), TableAirfoil.from_c81(parse_c81(TYPED))
    blade = BladeAirfoils((0.2, 0.8), (a, b), 340.0)
    assert blade.at(0.2) is a and blade.at(0.79) is a and blade.at(0.8) is b and blade.at(0.99) is b
    with pytest.raises(ValueError, match="inboard of the first airfoil segment"):
        blade.at(0.1)


# -- the generated code -------------------------------------------------------------------------

def test_constant_arrays_do_not_count_towards_the_o1_threshold():
    from mbs.backends.compiled import CFLAGS, LARGE_SOURCE_BYTES, compile_flags

    data = ", ".join(["1.2345678901234567e+00"] * (LARGE_SOURCE_BYTES // 20))
    source = f"static const casadi_real casadi_c0[{LARGE_SOURCE_BYTES // 20}] = \n  {{{data}}};\nint f(void) {{ return 0; }}\n"
    assert len(source) > LARGE_SOURCE_BYTES and compile_flags(source) == CFLAGS
    assert "-O1" in compile_flags(source + "/*" + "x" * LARGE_SOURCE_BYTES + "*/")


def test_a_tables_data_is_generated_once_in_the_unit_of_its_callers(tmp_path):
    """The interpolant (megabytes of constant data in C) is one function of one translation unit:
    the right-hand side and the outputs that call it share that unit."""
    from mbs import scenes
    from mbs.backends.compiled import UNIT_SEPARATOR, generate, translation_units
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic

    path = _with_airfoils(tmp_path, [[0.0, "wing.c81"]])
    vm = VMSystem(symbolic(scenes.get("single-blade-aero").with_aircraft(aircraft.load(path)).model()))
    units = translation_units({n: f for n, f in vm.functions.items() if n != "parts"}, vm.info.methods)
    assert any({"rhs", "outputs"} <= set(u) for u in units)
    parts = generate(vm.functions, vm.info, "float64").split(UNIT_SEPARATOR)
    assert sum("_cells:" in p for p in parts) == 1


def test_a_direction_of_the_section_loads_carries_the_three_coefficients_not_the_tables_cells():
    """Each directional derivative calls the interpolant's own forward derivative (three numbers,
    the reads' derivatives structurally zero inside it): the SX graph of eight directions of one
    element's loads is no larger than the analytic section's (measured 369 against 840
    operations; with the cell's 52 numbers read by a call of their own and the bicubics in the SX
    graph it was 2009)."""
    from mbs.aero.sections import section_force

    airfoil = TableAirfoil.from_c81(parse_c81(PRINTED))
    analytic, comp = Airfoil(5.7, 0.008, 0.5), Compressibility(SOUND, 0.8)
    w, seeds = ca.SX.sym("w", 2), ca.SX.sym("seeds", 2, 8)
    table = ca.vertcat(*table_section_loads(w[0], w[1], airfoil, comp.mach, RHO, AREA, CHORD))
    plain = ca.vertcat(*section_force(w[0], w[1], analytic, RHO, AREA, 1.0, comp.coefficients(analytic)))
    ops = [ca.Function("d", [w, seeds], [ca.jtimes(f, w, seeds)]).n_instructions() for f in (table, plain)]
    print(f"operations of 8 directions: tables {ops[0]}, analytic {ops[1]}")
    assert ops[0] <= ops[1]
    assert airfoil.spline.function.forward(1).nnz_out(0) == 3
