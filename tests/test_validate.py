"""``heli validate``: published data read with units, sources and tolerances; the model compared
point by point (units converted, conventions applied), eigenvalues paired; tables, JSON, charts,
exit status; every bad file refused with one line naming the entry.

The packaged validations (the Puma against Padfield's Helisim, the Bo105 against Helisim and
against its flight test) run in ``test_validate_published.py``.
"""
from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from mbs.analysis.flight_modes import FlightMode
from mbs.validate import compare, eigen
from mbs.validate.data import EigenTolerance, ValidationError, from_dict
from mbs.validate.files import load, packaged
from mbs.validate.ours import Model, Point
from test_cli_errors import assert_one_line_error, run_main

HEAD = '[validation]\ntitle = "t"\naircraft = "bo105"\nspeed_unit = "kt"\n'


def toml(text: str, tmp_path: Path) -> Path:
    path = tmp_path / "data.toml"
    path.write_text(HEAD + text)
    return path


TRIM = '[[trim]]\nquantity = "collective"\nunit = "deg"\nspeed = [0, 40]\nvalue = [14.0, 12.0]\nsource = "P1"\n'


@pytest.mark.parametrize("name", packaged())
def test_packaged_files_read_and_every_source_is_named(name):
    v = load(name)
    assert v.series or v.eigenvalues
    for s in v.series:
        assert s.source.split()[0] in v.sources, f"{s.quantity}: source {s.source!r} not in [sources]"
        assert len(s.value) == len(s.speed) and (s.uncertainty >= 0).all()
    for e in v.eigenvalues:
        assert e.source.split()[0] in v.sources
    assert {"axes", "controls"} <= set(v.conventions)


def test_the_sign_off_tolerances_are_the_packaged_ones():
    """Puma: every main derivative within 25 %; Bo105: collective 1 deg, cyclic 1.5, tail
    collective 2.5, pitch attitude 1 deg, power 10 %."""
    puma = {s.quantity: s.tolerance for s in load("puma_helisim").series if s.tolerance}
    assert set(puma) == {"X_u", "Z_w", "M_u", "M_q", "L_p", "N_r", "L_v", "N_v", "Z_θ0", "M_θ1s", "L_θ1c", "N_θ0T"}
    assert {t.relative for t in puma.values()} == {0.25}
    ft = {s.quantity: s.tolerance.absolute or s.tolerance.relative for s in load("bo105_flight_test").series
          if s.tolerance}
    assert ft == {"collective": 1.0, "longitudinal_cyclic": 1.5, "lateral_cyclic": 1.5, "tail_collective": 2.5,
                  "pitch": 1.0, "engine.power": 0.10}
    assert next(s for s in load("bo105_flight_test").series if s.quantity == "engine.power").tolerance.relative


def test_speeds_convert_and_merge(tmp_path):
    v = load(toml(TRIM + TRIM.replace("[0, 40]", "[40, 100]"), tmp_path))
    assert v.speeds("trim") == pytest.approx([0.0, 40 * 1852 / 3600, 100 * 1852 / 3600])
    assert v.speeds("derivative") == []


def test_speeds_as_advance_ratios_are_the_aircraft_files_tip_speed_times_mu(tmp_path):
    """A Bell 206 trial's data were printed against the advance ratio: ``speed_unit = "mu"`` takes
    them as V/(Omega R) of the aircraft file's rotor, and the report shows them as given."""
    from mbs import aircraft
    from mbs.validate import report
    from mbs.validate.data import resolve_speed
    from mbs.validate.runner import Result

    path = toml(TRIM.replace("[0, 40]", "[0.1, 0.25]") + '[[eigenvalues]]\nspeed = 0.2\nvalue = [[-1.0, 0.0]]\n'
                'source = "P1"\n', tmp_path)
    path.write_text(path.read_text().replace('"kt"', '"mu"'))
    d = aircraft.load().data
    tip = d["main_rotor"]["omega"] * d["main_rotor"]["radius"]
    v = resolve_speed(load(path), d)
    assert v.speeds("trim") == pytest.approx([0.1 * tip, 0.25 * tip]) and 200 < tip < 230
    assert v.eigenvalues[0].speed == pytest.approx(0.2 * tip) and v.series[0].shown_speed.tolist() == [0.1, 0.25]
    model = fake_model(v.speeds("trim"))
    for p in model.points.values():
        p.trim.warnings = ["a warning"]
    lines = report.lines(Result(v, model, [(s, compare.rows(s, model)) for s in v.series]))
    assert "  warning at 0.1, 0.25 mu: a warning" in lines, lines
    assert f"  speeds: advance ratios mu = V / (Omega R) of the aircraft file's tip speed Omega R = {tip:.5g} m/s" in lines


def test_a_source_no_series_cites_is_said(tmp_path):
    """A Bell 412 trial's [sources] listed S2, which no series used, without a word."""
    from mbs.validate import report
    from mbs.validate.runner import Result

    v = load(toml(TRIM.replace('"P1"', '"P1 Fig. 3; P3"') + '[sources]\nP1 = "a report"\nP2 = "a web page"\n'
                  'P3 = "a book"\n', tmp_path))
    model = fake_model(v.speeds("trim"))
    res = Result(v, model, [(s, compare.rows(s, model)) for s in v.series])
    lines = report.lines(res)
    assert "  source P1: a report" in lines and "  source P3: a book" in lines
    assert "  source P2: a web page (cited by no series)" in lines
    assert report.summary(res)["uncited_sources"] == ["P2"]


def fake_point(speed: float, problem: str = "") -> Point:
    trim = SimpleNamespace(controls={"collective": math.radians(13.0), "tail_collective": 0.1}, pitch=0.05, roll=-0.02,
                           flapping={"beta0": 0.03}, output_means={"engine.power": 300e3},
                           output_units={"engine.power": "W"})
    modes = [FlightMode(complex(-3.0, 0.0), {}, "pitch subsidence"), FlightMode(complex(0.1, 0.5), {}, "phugoid")]
    a = np.arange(64.0).reshape(8, 8)
    der = SimpleNamespace(table={"M_q": -3.0, "N_θ0T": 9.0}, units={"M_q": "1/s", "N_θ0T": "1/s^2"}, modes=modes, A=a)
    return Point(speed, trim, der, problem)


def fake_model(speeds, bad=()) -> Model:
    m = Model("forward-flight", "fake")
    for v in speeds:
        m.points[round(v, 9)] = fake_point(v, "no trim: Newton failed" if v in bad else "")
    return m


def test_rows_convert_units_and_judge_tolerances(tmp_path):
    """13 deg collective against 14 and 12 published with 1 deg tolerance: the first at the edge
    (within), the second out; kW from W; a relative tolerance; a speed without trim reads
    'no trim' and is not within."""
    v = load(toml(TRIM + '[trim.tolerance]\nabsolute = 1.0\n'
                  '[[trim]]\nquantity = "engine.power"\nunit = "kW"\nspeed = [0]\nvalue = [280.0]\nsource = "P1"\n'
                  'tolerance = { relative = 0.1 }\n', tmp_path))
    speeds = v.speeds("trim")
    model = fake_model(speeds, bad={speeds[1]})
    col, power = (compare.rows(s, model) for s in v.series)
    assert col[0].ours == pytest.approx(13.0) and col[0].difference == pytest.approx(-1.0) and col[0].within
    assert col[1].problem.startswith("no trim") and col[1].within is False and math.isnan(col[1].ours)
    assert power[0].ours == pytest.approx(300.0) and power[0].ratio == pytest.approx(300 / 280) and power[0].within
    assert compare.counts(col + power) == {"rows": 3, "checked": 3, "within": 2, "no_model_value": 1}


def test_a_published_value_within_its_tolerance_of_zero_has_no_ratio(tmp_path):
    """A pitch of 0.20 deg with a 1 deg tolerance showed ours/pub 4.75 (a new user's OH-6A): no
    ratio there, in the table or the JSON; the difference stays."""
    v = load(toml(TRIM.replace("[14.0, 12.0]", "[0.2, 1.5]") + '[trim.tolerance]\nabsolute = 1.0\n', tmp_path))
    near, far = compare.rows(v.series[0], fake_model(v.speeds("trim")))
    assert math.isnan(near.ratio) and near.summary()["ratio"] is None and near.difference == pytest.approx(12.8)
    assert far.ratio == pytest.approx(13.0 / 1.5)


def test_the_report_lists_each_warning_of_the_model_with_its_speeds(tmp_path):
    """The trims' warnings (a control at its stop, a disc tilted beyond what rotors flap) and the
    derivatives' were not in the validation's report: each kind once, at the speeds (in the data's
    unit) that gave it; where only its figures differ, those of the slowest point."""
    from mbs.validate import report
    from mbs.validate.runner import Result

    v = load(toml(TRIM.replace("speed = [0, 40]", "speed = [0, 40, 60, 80, 100, 120]")
                  .replace("[14.0, 12.0]", "[14.0, 12.0, 11.0, 12.0, 13.0, 14.0]"), tmp_path))
    model = fake_model(v.speeds("trim"))
    points = [model.points[k] for k in sorted(model.points)]
    for k, p in enumerate(points):
        p.trim.warnings = ["the same everywhere", f"horizontal tail: angle of attack -{40 + k}.5 deg at its stall"]
    points[0].trim.warnings.append("collective = 1.000 deg is at its stop")
    points[1].derivatives.warnings = ["teetering main rotor: ..."]
    for p in points:  # of the aircraft file, which every trim carries: said once (a new user's Gazelle)
        p.trim.warnings.append("aircraft.inertia: not given, so ...")
    res = Result(v, model, [(s, compare.rows(s, model)) for s in v.series])
    lines = [x for x in report.lines(res) if x.startswith("  warning")]
    assert lines == ["  warning of the aircraft file: aircraft.inertia: not given, so ...",
                     "  warning at 6 points, 0 to 120 kt: the same everywhere",
                     "  warning at 6 points, 0 to 120 kt (the figures at 0 kt): horizontal tail: angle of attack "
                     "-40.5 deg at its stall",
                     "  warning at 0 kt: collective = 1.000 deg is at its stop",
                     "  warning at 40 kt: teetering main rotor: ..."], lines
    listed = report.summary(res)["warnings"]
    assert {"texts": ["collective = 1.000 deg is at its stop"], "speeds_m_s": [0.0]} in listed and len(listed) == 5


def test_sources_of_one_quantity_share_a_chart_panel(tmp_path):
    """Two sources of the collective and one of the power make two panels: the collective's with
    both sources' points and one model line through all their speeds."""
    from mbs.validate import charts
    from mbs.validate.runner import Result

    v = load(toml(TRIM + TRIM.replace("[0, 40]", "[20]").replace("[14.0, 12.0]", "[13.0]").replace('"P1"', '"S2"')
                  + '[[trim]]\nquantity = "engine.power"\nunit = "kW"\nspeed = [0]\nvalue = [280.0]\nsource = "P1"\n',
                  tmp_path))
    model = fake_model(v.speeds("trim"))
    res = Result(v, model, blocks=[(s, compare.rows(s, model)) for s in v.series])
    groups = charts.panels(res.blocks)
    assert [[s.source for s, _ in g] for g in groups] == [["P1", "S2"], ["P1"]]
    path = charts.series_chart(res.blocks, res, tmp_path / "trims.png", "trim")
    assert path.stat().st_size > 10_000


def test_ours_factor_flips_a_sign_convention_and_needs_a_note(tmp_path):
    body = ('[[derivative]]\nquantity = "N_theta0T"\nunit = "1/s^2"\nspeed = [0]\nvalue = [-9.0]\nsource = "P1"\n'
            'tolerance = { relative = 0.25 }\nours_factor = -1\n')
    with pytest.raises(ValidationError, match="needs a note saying why"):
        load(toml(body, tmp_path))
    v = load(toml(body + 'note = "the published tail-rotor pitch is positive the other way"\n', tmp_path))
    row, = compare.rows(v.series[0], fake_model([0.0]))
    assert row.ours == pytest.approx(-9.0) and row.ratio == pytest.approx(1.0) and row.within


def test_entries_of_a_compare_with_their_units(tmp_path):
    """``A[w,q]`` is row w, column q of A (Z_q + U_e, m/(s rad)); ``A[φ,p]`` is dimensionless;
    a unit of another dimension is refused."""
    from mbs.validate.quantities import derivative_value, entry_unit

    point = fake_point(0.0)
    assert derivative_value(point.derivatives, "A[w,q]") == (10.0, "m/s rad")
    assert derivative_value(point.derivatives, "A[φ,p]") == (53.0, "-")
    assert entry_unit("q", "u") == "rad/m s" and entry_unit("v", "phi") == "m/s^2 rad"
    body = '[[derivative]]\nquantity = "A[w,q]"\nunit = "UNIT"\nspeed = [0]\nvalue = [10.0]\nsource = "P1"\n'
    row, = compare.rows(load(toml(body.replace("UNIT", "m/s deg"), tmp_path)).series[0], fake_model([0.0]))
    assert row.ours == pytest.approx(10.0 * math.pi / 180)
    with pytest.raises(ValidationError, match="the states of A are u, w, q"):
        derivative_value(point.derivatives, "A[w,x]")


def test_controls_compare_in_the_published_conventions_and_pilot_positions_in_si():
    """A trim's control is read in the aircraft file's published convention (``Trim.published``:
    B1 = -θ1s with cyclic_pitch "A1, B1"), a pilot control from its file unit to SI, and a
    control derivative per published control angle."""
    from mbs.validate.quantities import derivative_value, trim_value

    trim = SimpleNamespace(controls={"longitudinal_cyclic": 0.02}, published={"longitudinal_cyclic": -0.02},
                           pilot={"longitudinal_stick": 1.5, "pedals": 40.0}, pilot_units={"longitudinal_stick": "in",
                                                                                         "pedals": "%"},
                           flapping={}, output_means={})
    assert trim_value(trim, "longitudinal_cyclic") == (-0.02, "rad")
    assert trim_value(trim, "longitudinal_stick") == (pytest.approx(1.5 * 0.0254), "m")
    assert trim_value(trim, "pedals") == (pytest.approx(0.4), "-")
    der = SimpleNamespace(table={"M_θ1s": 3.0}, published={"M_θ1s": -3.0}, units={"M_θ1s": "1/s^2"})
    assert derivative_value(der, "M_theta1s") == (-3.0, "1/s^2")


def test_control_derivatives_per_inch_of_stick_compare_as_a_report_prints_them(tmp_path, capsys):
    """A new user's CH-53D report prints its control derivatives per inch of control, which could
    not be validated. A derivative per a pilot control is named after it (Z_collective_lever),
    in the SI unit of its travel's kind (per m: 1/s^2); given per inch in a blade angle's name it
    is refused naming the pilot controls' names, and without a rigging saying one is needed.
    ``heli derivatives`` prints them per the file's unit of each control."""
    from mbs.analysis.derivatives import pilot_unit
    from mbs.commands import pilot_derivative_lines
    from mbs.validate.quantities import converter, derivative_value

    assert [pilot_unit("Z", "m"), pilot_unit("L", "m"), pilot_unit("Z", "-"), pilot_unit("N", "rad")] == \
        ["1/s^2", "rad/(s^2 m)", "m/s^2", "1/s^2"]
    der = SimpleNamespace(table={}, pilot={"Z_collective_lever": -131.0}, pilot_units={"Z_collective_lever": "1/s^2"})
    value, unit = derivative_value(der, "Z_collective_lever")
    assert converter(unit, "(ft/sec^2)/in", "x")(value) == pytest.approx(-131.0 * 0.0254 / 0.3048, rel=1e-12)
    forces = {f"{f}_{p}": 1.0 for f in "XYZLMN" for p in ("collective_lever", "longitudinal_stick", "lateral_stick",
                                                          "pedals")}
    res = SimpleNamespace(pilot={**forces, "Z_collective_lever": -131.0},
                          pilot_file_units={"collective_lever": "in", "longitudinal_stick": "cm",
                                            "lateral_stick": "cm", "pedals": "%"})
    lines = pilot_derivative_lines(res)
    assert "lever (/in)" in lines[1] and "pedals (/%)" in lines[1]
    z = lines[2 + 2].split()
    assert z[0] == "Z" and float(z[1]) == pytest.approx(-131.0 * 0.0254, rel=1e-3) and float(z[4]) == 0.01
    text = TRIM.replace("[[trim]]", "[[derivative]]").replace("collective", "Z_θ0").replace('unit = "deg"',
                                                                                          'unit = "(ft/sec^2)/in"')
    code, err = run_main(["validate", str(toml(text, tmp_path)), "--no-charts", "--quiet"], capsys)
    assert_one_line_error(code, err, ["derivative Z_θ0: unit '(ft/sec^2)/in'", "Z_collective_lever, Z_longitudinal_stick",
                                      "needs the aircraft file's [controls] rigging"])


def test_a_report_aircraft_validates_in_its_own_pilot_controls():
    """The UH-60A written from its reports (stick rigging, A1/B1 cyclic) against G2 Table 4 at
    1 kt as printed, stick inches: every row within the loose tolerances the file states, the
    pilot rows equal to the trim's pilot positions, and the report says how the model states
    its controls."""
    from mbs.validate import report
    from mbs.validate.runner import validate

    res = validate(load(Path(__file__).parent / "data" / "uh60a_g2_hover.toml"))
    assert res.all_within, report.lines(res)
    point = res.model.at(1.0 * 1852 / 3600)
    rows = {r.quantity: r for r in res.rows}
    for stick in ("collective_lever", "longitudinal_stick", "lateral_stick", "pedals"):
        assert rows[stick].ours == pytest.approx(point.trim.pilot[stick], rel=1e-12)
    assert rows["longitudinal_stick"].ours == pytest.approx(0.64, abs=0.05)  # G2: 0.127 in
    text = "\n".join(report.lines(res))
    assert "model's controls: blade angles in the aircraft file's conventions" in text
    assert "cyclic as A1, B1; pilot controls through its rigging" in text


def test_eigenvalues_pair_by_least_distance_and_judge_stability_and_size():
    tol = EigenTolerance(frequency=0.25, neutral=0.02, min_frequency=0.05)
    published = np.array([-14.2, 0.28 + 0.49j, 0.28 - 0.49j, 0.01])
    ours = np.array([-8.0 + 1.8j, -8.0 - 1.8j, 0.12 + 0.495j, 0.12 - 0.495j, -0.015, 0.3])
    pairs = eigen.pair(published, ours, list("aabbcd"), 0.0, tol)
    by_pub = {p.published: p for p in pairs}
    roll = by_pub[-14.2]
    assert roll.measure == "rate" and roll.ratio == pytest.approx(abs(-8 + 1.8j) / 14.2) and not roll.within
    phugoid = by_pub[0.28 + 0.49j]
    assert phugoid.ours == 0.12 + 0.495j and phugoid.measure == "frequency" and phugoid.within
    near_zero = by_pub[0.01]
    assert near_zero.ours == -0.015 and near_zero.measure == "stability only" and near_zero.within
    flipped = eigen.pair(np.array([0.13 + 0.79j]), np.array([-0.83 + 2.52j]), ["Dutch roll"], 140.0, tol)[0]
    assert not flipped.same_stability and not flipped.within


def test_model_eigenvalues_include_both_of_a_pair():
    values, names = eigen.model_eigenvalues(fake_point(0.0).derivatives)
    assert sorted(values, key=lambda z: (z.real, z.imag)) == [-3.0, 0.1 - 0.5j, 0.1 + 0.5j]
    assert names.count("phugoid") == 2


def test_csv_carries_the_same_as_toml(tmp_path):
    csv = tmp_path / "d.csv"
    csv.write_text("# title: t\n# aircraft: bo105\n# speed_unit: kt\n# convention axes: body\n# source P1: Padfield\n"
                   "kind,quantity,unit,speed,value,imaginary,uncertainty,tolerance,source,note\n"
                   "trim,collective,deg,0,14.0,,0.1,absolute 1.0,P1,\ntrim,collective,deg,40,12.0,,0.1,absolute 1.0,P1,\n"
                   "eigenvalue,,1/s,0,0.28,0.49,,,P1,\neigenvalue,,1/s,0,0.28,-0.49,,,P1,\n")
    v = load(csv)
    s, = v.series
    assert (s.quantity, s.unit, list(s.shown_speed), list(s.value), s.tolerance.absolute) == (
        "collective", "deg", [0.0, 40.0], [14.0, 12.0], 1.0)
    assert v.sources == {"P1": "Padfield"} and v.conventions == {"axes": "body"}
    assert list(v.eigenvalues[0].value) == [0.28 + 0.49j, 0.28 - 0.49j]


BAD = [
    ("", "nothing to compare"),
    (TRIM.replace('unit = "deg"', 'unit = "furlong"'), "furlong"),
    (TRIM.replace("[0, 40]", "[0]"), "2 values for 1 speeds"),
    (TRIM.replace("[0, 40]", "[0, -40]"), "speed -40 is negative"),
    (TRIM.replace("[14.0, 12.0]", '[14.0, "x"]'), "value must be a non-empty list of finite numbers"),
    (TRIM + "tolerance = 1.0\n", "tolerance must be { absolute = x }"),
    (TRIM + "tolerance = { relative = -0.1 }\n", "tolerance relative = -0.1 must be a positive number"),
    (TRIM + "colour = 3\n", "unknown key(s) colour"),
    (TRIM.replace("14.0, 12.0", "0.0, 12.0") + "tolerance = { relative = 0.1 }\n", "cannot judge the published value 0"),
    (TRIM.replace('source = "P1"\n', ""), "source must be a non-empty text"),
    ("[[eigenvalues]]\nspeed = 0\nvalue = [[1.0]]\nsource = \"P1\"\n", "list of [real, imaginary] pairs"),
    ("[eigenvalue_tolerance]\nfrequency = -1\n" + TRIM, "frequency = -1 must be a number >= 0"),
    ("[extras]\nx = 1\n" + TRIM, "unknown section(s) extras"),
]


@pytest.mark.parametrize("body,words", BAD)
def test_bad_file_is_refused_naming_the_entry(body, words, tmp_path):
    with pytest.raises(ValidationError, match=None) as exc:
        load(toml(body, tmp_path))
    assert words in str(exc.value) and str(tmp_path / "data.toml") in str(exc.value)


def test_bad_speed_unit_and_missing_section(tmp_path):
    with pytest.raises(ValidationError, match="not a speed"):
        from_dict({"validation": {"aircraft": "bo105", "speed_unit": "kg"}}, tmp_path / "x.toml")
    with pytest.raises(ValidationError, match=r"no \[validation\] section"):
        from_dict({}, tmp_path / "x.toml")


@pytest.mark.parametrize("line,words", [
    ("validate nosuch", ["DATA", "no validation file 'nosuch'", "puma_helisim"]),
    ("validate BAD", ["DATA", "unknown key(s) colour"]),
    ("validate puma_helisim --method rk5", ["--method", "'rk5'"]),
    ("validate puma_helisim --out /dev/null/x", ["--out", "/dev/null is a file, not a folder"]),
    ("validate puma_helisim --aircraft nosuch.toml", ["--aircraft", "nosuch.toml"]),
])
def test_bad_invocation_is_one_line_and_exit_2(line, words, capsys, tmp_path):
    bad = toml(TRIM + "colour = 3\n", tmp_path)
    code, err = run_main(line.replace("BAD", str(bad)).split(), capsys)
    assert_one_line_error(code, err, words)
    assert err.startswith("heli validate: error:")


@pytest.mark.parametrize("name, words", [
    ("rotor_colour", "trim 'rotor_colour' is not one of the model's trim quantities: "),
    ("theta0", "trim 'theta0' is not one of the model's trim quantities (did you mean 'collective'?)"),
    ("pedal", "(did you mean 'tail_collective'?) (pilot controls need the aircraft file's [controls] rigging)"),
    ("Mq", "derivative 'Mq' is not one of the model's derivative quantities (did you mean 'M_q'?)"),
])
def test_a_quantity_the_model_lacks_is_refused_before_any_trim(tmp_path, capsys, name, words):
    """A name as reports write it gets the model's own (a new user had a list of 65 names)."""
    text = TRIM.replace("collective", name)
    if name == "Mq":
        text = text.replace("[[trim]]", "[[derivative]]").replace('unit = "deg"', 'unit = "1/s"')
    path = toml(text, tmp_path)
    code, err = run_main(["validate", str(path), "--no-charts", "--quiet"], capsys)
    assert_one_line_error(code, err, [words, "collective" if name != "Mq" else "M_u"])


@pytest.mark.parametrize("si, printed, one", [("N", "lb", 4.4482216152605), ("N m", "ft-lb", 1.3558179483314004),
                                              ("W", "hp", 745.69987158227022), ("m/s", "kts", 1852.0 / 3600)])
def test_published_values_in_a_reports_units_compare_in_si(si, printed, one):
    """A thrust in lb (a pound-force), a torque in ft-lb, a power in hp and a speed in kts."""
    from mbs.validate.quantities import converter

    assert converter(si, printed, "trim")(one) == pytest.approx(1.0, rel=1e-14)


def test_the_json_lists_points_at_the_file_s_and_at_their_own_conditions_together(tmp_path):
    """One series at the test weight beside one at the file's mass made a model whose points are
    keyed by a speed and by a (speed, mass, altitude, CG): the JSON's sort failed with a traceback
    after every trim (a new user's file, as the docs' example is written). Both are listed."""
    from mbs.validate import report
    from mbs.validate.runner import Result

    v = load(toml(TRIM, tmp_path))
    model = fake_model(v.speeds("trim"))
    first = min(model.points)
    model.points[(first, 2200.0, None, None)] = fake_point(first)
    res = Result(v, model, [(s, compare.rows(s, model)) for s in v.series])
    listed = report.summary(res)["model"]
    assert listed["points"][:2] == [{"speed_m_s": first, "mass_kg": None, "altitude_m": None, "cg_x_m": None},
                                    {"speed_m_s": first, "mass_kg": 2200.0, "altitude_m": None, "cg_x_m": None}]
    assert listed["speeds_m_s"] == sorted({first, *(k for k in model.points if not isinstance(k, tuple))})


CSV_HEAD = "# title: t\n# aircraft: bo105\n# speed_unit: kt\n# source P1: Padfield\n"
CSV_ROWS = ("kind,quantity,unit,speed,value,tolerance,source,mass\n"
            "trim,collective,deg,0,14.0,TOL,P1,\ntrim,collective,deg,40,12.0,TOL,P1,\n")


@pytest.mark.parametrize("tolerance, expected", [("absolute 1.0", {"absolute": 1.0}), ("±1.0", {"absolute": 1.0}),
                                                 ("+-1", {"absolute": 1.0}), ("1.0", {"absolute": 1.0}),
                                                 ("relative 0.1", {"relative": 0.1}), ("10%", {"relative": 0.1}),
                                                 ("10 %", {"relative": 0.1})])
def test_a_csv_tolerance_as_people_write_it(tmp_path, tolerance, expected):
    """'±1', '1.0' and '10%' were told "tolerance '' is not a number" (a new user's files)."""
    csv = tmp_path / "d.csv"
    csv.write_text(CSV_HEAD + CSV_ROWS.replace("TOL", tolerance))
    s, = load(csv).series
    assert {k: v for k, v in vars(s.tolerance).items() if v is not None} == pytest.approx(expected)


@pytest.mark.parametrize("change, words", [
    (lambda t: t.replace("# speed_unit: kt\n", ""), "no '# speed_unit:' line; add one above the header"),
    (lambda t: t.replace("# speed_unit: kt", "# speed_units: kt"), "'# speed_units:' is no key of the file (did you "
                                                                     "mean 'speed_unit'?)"),
    (lambda t: t.replace("# source P1", "# sources P1"), "(did you mean 'source'?)"),
    (lambda t: t.replace(",P1,\n", ",P1,4850\n"),
     "collective: mass 4850 has no unit; add a '# mass_unit:' line above the header, e.g. '# mass_unit: lb'"),
    (lambda t: t + "trim,collective,deg,40,12.0,TOL,P1,\n", "line 8: repeats line 7 (trim collective 12 at speed 40)"),
    (lambda t: t + "trim,collective,deg,40,12.5,TOL,P1,\n", None),  # a repeated measurement: taken
    (lambda t: t.replace("40,12.0,TOL,P1,", "40,12.0,TOL,R2,"), "source(s) 'R2' of the rows are not among the "
                                                                  "'# source' lines (P1)"),
    (lambda t: t.replace("TOL", "about one"), "tolerance 'about one': write 'absolute 1.0' or '±1.0'"),
    (lambda t: t.replace(",deg,", ",furlong,"), "the trim rows of 'collective' (lines 6-7): unit 'furlong'"),
])
def test_a_csv_file_says_what_it_cannot_take(tmp_path, change, words):
    """Without '# speed_unit:' the speeds were m/s, a misspelt '#' line a comment, a mass without
    its unit kg, a copied row counted twice, a source nobody named accepted: each silently (a new
    user's files); each is refused, named. A series' problem names its rows' lines, not the TOML
    form's '[[trim]] 1'."""
    csv = tmp_path / "d.csv"
    csv.write_text(change(CSV_HEAD + CSV_ROWS).replace("TOL", "absolute 1.0"))
    if words is None:
        assert len(load(csv).series[0].value) == 3
        return
    with pytest.raises(ValidationError) as err:
        load(csv)
    assert words in str(err.value), str(err.value)


def test_a_csv_speed_unit_written_with_a_blank_is_taken(tmp_path):
    csv = tmp_path / "d.csv"
    csv.write_text(CSV_HEAD.replace("# speed_unit: kt", "# speed unit: kt") + CSV_ROWS.replace("TOL", "absolute 1.0"))
    assert load(csv).speed_unit == "kt"


def test_a_csv_note_on_some_rows_keeps_one_series(tmp_path):
    """A note on the hover row of a collective series split it in two tables and two chart
    entries (a new user's CSV): the rows stay one series, the note printed with its speeds."""
    csv = tmp_path / "d.csv"
    csv.write_text(CSV_HEAD + "kind,quantity,unit,speed,value,source,note\n"
                   "trim,collective,deg,0,14.0,P1,hover\ntrim,collective,deg,40,12.0,P1,\n"
                   "trim,collective,deg,60,11.5,P1,\n"
                   "trim,pitch,deg,0,3.0,P1,read off\ntrim,pitch,deg,40,1.0,P1,read off\n")
    collective, pitch = load(csv).series
    assert list(collective.shown_speed) == [0.0, 40.0, 60.0] and collective.note == "at 0: hover"
    assert pitch.note == "read off"


def test_the_report_echoes_each_condition_and_no_trim_in_the_files_units(tmp_path):
    """A point at 4850 lb and 1000 ft printed as '2199.92 kg, 304.8 m', and a speed that did not
    trim as '128.611 m/s': both in the units of the file, the header naming only what it gives."""
    from mbs.validate import report
    from mbs.validate.data import condition_key
    from mbs.validate.runner import Result

    v = load(toml(TRIM + 'mass = { value = [4850, 5000], unit = "lb" }\n'
                  'altitude = { value = 1000, unit = "ft" }\n', tmp_path))
    s, = v.series
    assert s.shown_conditions == ("4850 lb, 1000 ft", "5000 lb, 1000 ft")
    model = Model("forward-flight", "fake")
    for speed, *condition in s.conditions():
        model.points[condition_key(speed, *condition)] = fake_point(speed, "no trim: Newton failed" if speed > 0 else "")
    res = Result(v, model, [(s, compare.rows(s, model)) for s in v.series])
    text = report.lines(res)
    assert [r.condition for r in res.blocks[0][1]] == ["4850 lb, 1000 ft", "5000 lb, 1000 ft"]
    assert "  at 40 kt, 5000 lb, 1000 ft: no trim: Newton failed" in text, text
    assert "  each point at its mass (a weight added at the CG) and ISA altitude as published" in text
    assert "2 flight conditions in" in text[2], text[2]


def test_a_single_published_point_shows_its_tolerance_in_the_chart(tmp_path):
    """A band needs two speeds, so a one-point series showed none: its tolerance is a bar; two
    series of one source in a panel give one legend entry each for the points and the band."""
    import matplotlib.pyplot as plt

    from mbs.validate import charts

    v = load(toml(TRIM.replace("[0, 40]", "[20]").replace("[14.0, 12.0]", "[13.0]") + "tolerance = { absolute = 1.0 }\n"
                  + TRIM.replace("[0, 40]", "[60]").replace("[14.0, 12.0]", "[11.0]")
                  + 'tolerance = { absolute = 1.0 }\nnote = "another"\n', tmp_path))
    model = fake_model(v.speeds("trim"))
    fig, ax = plt.subplots()
    for s in v.series:
        charts._published(ax, s, compare.rows(s, model), "o")
    bars = [c for c in ax.collections if c.get_label().startswith("tolerance")]
    assert [b.get_segments()[0][:, 1].tolist() for b in bars] == [[12.0, 14.0], [10.0, 12.0]]
    charts._legend(ax)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["tolerance ±1 deg", "published (P1)"]
    plt.close(fig)


def test_a_published_rating_is_a_bound_not_a_value(tmp_path):
    """A new user's Mi-8 had only its engine ratings to compare the power with, and could give them
    only as values with a wide tolerance. A bound is within when ours is on its side: TOML
    { bound = "upper" }, CSV 'at most' or '<=' (and 'at least', '>=')."""
    v = load(toml('[[trim]]\nquantity = "engine.power"\nunit = "kW"\nspeed = [0, 40]\nvalue = [280.0, 320.0]\n'
                  'source = "P1"\ntolerance = { bound = "upper" }\n', tmp_path))
    low, high = compare.rows(v.series[0], fake_model(v.speeds("trim")))
    assert (low.within, high.within) == (False, True)  # ours 300 kW: above 280, below 320
    assert v.series[0].tolerance.describe("kW") == "the published value an upper bound of ours"
    with pytest.raises(ValidationError, match="tolerance bound = 'above' must be"):
        load(toml(TRIM + 'tolerance = { bound = "above" }\n', tmp_path))
    for text, bound in (("at most", "upper"), ("<=", "upper"), ("at least", "lower"), (">=", "lower")):
        csv = tmp_path / "b.csv"
        csv.write_text(CSV_HEAD + CSV_ROWS.replace("TOL", text))
        assert load(csv).series[0].tolerance.bound == bound, text


def test_a_torque_gauge_s_percent_is_an_output_to_validate(tmp_path):
    """A flight test prints torque in % of its gauge: with [engine] torque_reference (the gauge's
    100 %, referred to the main-rotor shaft) the output engine.torque_fraction takes it; the
    engines' torque is engine.power over the rotor speed."""
    from mbs import aircraft, scenes
    from mbs.analysis.trim import periodic_solution
    from aircraft_files import entries, write

    raw = entries("bo105")
    raw["engine"]["torque_reference"] = {"value": 5000.0, "unit": "N m", "source": "test"}
    path = write(raw, tmp_path / "gauge.toml")
    trim = periodic_solution(scenes.get("forward-flight", aircraft.load(path)), 30.0)
    o = trim.output_means
    assert o["engine.torque"] == pytest.approx(o["engine.power"] / 44.4, rel=1e-12)
    assert o["engine.torque_fraction"] == pytest.approx(o["engine.torque"] / (2 * 5000.0), rel=1e-12)  # two engines
    v = load(toml('[[trim]]\nquantity = "engine.torque_fraction"\nunit = "%"\nspeed = [58.3]\nvalue = [97.0]\n'
                  'source = "P1"\n', tmp_path))
    assert v.series[0].unit == "%"


def test_a_per_point_altitude_in_validation_is_the_series_and_a_verdict_needs_a_tolerance(tmp_path):
    """A new user's Gazelle flight test gave [validation] one altitude per speed, as it gives one
    mass per speed, and was told "altitude has 2 values for 1 points" (the eigenvalues' default
    was read from it). It is each series' now; with [[eigenvalues]] it must be one number. A
    run whose series give no tolerance said "all within tolerance": it says nothing was checked."""
    from mbs.validate.report import verdict_lines

    head = HEAD.replace("[validation]\n", '[validation]\nspeed = [0, 40]\naltitude = { value = [300, 320], unit = "m" }\n')
    path = tmp_path / "alt.toml"
    path.write_text(head + TRIM.replace("speed = [0, 40]\n", ""))
    (s,) = load(path).series
    assert list(s.altitude) == [300.0, 320.0]
    path.write_text(head + TRIM.replace("speed = [0, 40]\n", "") + '[[eigenvalues]]\nspeed = 0\nvalue = [[-1, 0]]\n'
                    'source = "P1"\n')
    with pytest.raises(ValidationError, match=r"altitude as a list \(one per point\) gives the \[\[eigenvalues\]\] none"):
        load(path)
    counts = {"trim": {"rows": 2, "within": 0, "checked": 0, "no_model_value": 0}, "derivative": {"rows": 0, "checked": 0}}
    res = SimpleNamespace(counts=lambda: counts, pairs=[], all_within=True)
    assert verdict_lines(res)[-1] == "nothing checked: no series gives a tolerance, so its values are shown, not judged"
    counts["trim"].update(checked=2, within=2)
    assert verdict_lines(res)[-1] == "all within tolerance"


def test_a_series_whose_source_is_not_in_sources_is_refused(tmp_path, capsys):
    """A new user's TOML file cited P9 with only P1 in [sources] and was taken without a word,
    where the CSV form refuses it. A source must begin with a key of [sources]."""
    path = toml('[sources]\nP1 = "a report"\n' + TRIM.replace('source = "P1"', 'source = "P9 Fig. 2"'), tmp_path)
    code, err = run_main(["validate", str(path), "--no-charts", "--quiet"], capsys)
    assert_one_line_error(code, err, ["source(s) 'P9 Fig. 2' do not begin with a key of [sources] (P1)"])
    path.write_text(HEAD + '[sources]\nP1 = "a report"\n' + TRIM.replace('source = "P1"', 'source = "P1 Fig. 2; H"'))
    assert load(path).series[0].source == "P1 Fig. 2; H"
