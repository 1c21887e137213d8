"""Positions written as stations (FS aft, BL, WL up), as reports print them, with the CG's
stations (``aircraft.cg_station``): each becomes the body-axis position from the CG that a hand
conversion gives, ``aircraft check`` lists it with its stations, and every way of writing one
wrongly is a problem naming the entry."""
from __future__ import annotations

import re

import pytest

from mbs import aircraft
from mbs.aircraft._aircraft import evaluate

INCH = 0.0254
CG = (200.0, 3.0, 100.0)  # the CG's FS, BL, WL (in) in these files
CG_LINE = f'cg_station = {{ value = [{CG[0]}, {CG[1]}, {CG[2]}], unit = "in", source = "R1 Table 1" }}\n'


def _bo105() -> str:
    return aircraft.resolve("bo105").read_text()


def _entry(text: str, section: str, key: str, new: str) -> str:
    """``text`` with ``section.key``'s line replaced by ``key = new``."""
    head, sep, rest = text.partition(f"[{section}]\n")
    body, nxt, tail = rest.partition("\n[")
    body, n = re.subn(rf"^{key} = .*$", f"{key} = {new}", body, count=1, flags=re.M)
    assert n == 1, (section, key)
    return head + sep + body + nxt + tail


def _with_cg(text: str, extra: str = "") -> str:
    return text.replace("[aircraft]\n", "[aircraft]\n" + CG_LINE, 1) + extra


def _station(value, unit="in") -> str:
    return f'{{ station = {value}, unit = "{unit}", source = "R1 Table 1" }}'


POSITIONS = [  # entry, station (in), hand conversion (in) with the CG at FS 200, BL 3, WL 100
    ("main_rotor", "hub_x", 205.0, -5.0),
    ("main_rotor", "hub_z", 160.0, -60.0),
    ("tail_rotor", "hub_x", 440.0, -240.0),
    ("tail_rotor", "hub_y", -9.0, -12.0),
    ("tail_rotor", "hub_z", 170.0, -70.0),
    ("horizontal_tail", "x", 380.0, -180.0),
    ("horizontal_tail", "z", 95.0, 5.0),
    ("vertical_fin", "x", 420.0, -220.0),
    ("vertical_fin", "z", 130.0, -30.0),
]


@pytest.mark.parametrize("section,key,station,inches", POSITIONS)
def test_a_station_gives_the_hand_converted_position(section, key, station, inches):
    """x = -(FS - FS_cg), y = BL - BL_cg, z = -(WL - WL_cg), in the file's length unit."""
    data, problems = evaluate(_with_cg(_entry(_bo105(), section, key, _station(station))))
    assert not problems, problems
    assert data[section][key] == pytest.approx(inches * INCH, abs=1e-14)


def test_a_port_positive_butt_line_turns_the_sign_of_y_only():
    text = _with_cg(_entry(_entry(_bo105(), "tail_rotor", "hub_y", _station(-9.0)), "tail_rotor", "hub_x",
                           _station(440.0)))
    text += '\n[conventions]\nbutt_line_positive = { value = "port", unit = "-", source = "R1" }\n'
    data, problems = evaluate(text)
    assert not problems, problems
    assert data["tail_rotor"]["hub_y"] == pytest.approx(12.0 * INCH, abs=1e-14)  # -(BL - BL_cg): to starboard
    assert data["tail_rotor"]["hub_x"] == pytest.approx(-240.0 * INCH, abs=1e-14)


def test_stations_in_metres_and_a_reference_point_as_three_stations():
    """Another length unit converts the same way; a point (the fuselage tables' reference point)
    takes FS, BL, WL together."""
    text = _with_cg(_entry(_bo105(), "main_rotor", "hub_z", _station(160.0 * INCH, "m")))
    data, problems = evaluate(text)
    assert not problems, problems
    assert data["main_rotor"]["hub_z"] == pytest.approx(-60.0 * INCH, abs=1e-14)
    from mbs.aircraft.reader import read
    point = read(_with_cg(_bo105()).replace(
        "[fuselage_aero]\n", '[fuselage_aero]\nreference_point = { station = [210.0, 0.0, 90.0], unit = "in", source = "R2" }\n'))
    # the entry applies only to tables, but the station itself is converted first
    assert point.values["fuselage_aero"]["reference_point"] == pytest.approx([-10 * INCH, -3 * INCH, 10 * INCH])


def test_aircraft_check_lists_each_station_with_the_cg_it_is_taken_from(tmp_path):
    path = tmp_path / "craft.toml"
    path.write_text(_with_cg(_entry(_bo105(), "tail_rotor", "hub_x", _station(440.0))))
    report = aircraft.check(path)
    assert report.ok, report.problems
    rows = [r for r in report.converted if r[0] == "tail_rotor.hub_x"]
    assert len(rows) == 1
    entry, value, unit, how, source = rows[0]
    assert value == pytest.approx(-240.0 * INCH) and unit == "m" and source == "R1 Table 1"
    assert how == "from station FS 440 in with the CG at FS 200 in: x = -(FS - FS_cg)"


BAD = [
    ("no CG stations", lambda t: _entry(t, "main_rotor", "hub_x", _station(205.0)),
     "main_rotor.hub_x: given as a station; give the CG's stations too: [aircraft] cg_station"),
    ("not a position", lambda t: _with_cg(_entry(t, "main_rotor", "radius", _station(200.0))),
     "main_rotor.radius: only a position from the CG may be given as a station"),
    ("value and station", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x",
                                                    '{ value = 1.0, station = 2.0, unit = "in", source = "R1" }')),
     "main_rotor.hub_x: give value or station, not both"),
    ("an angle", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x", _station(2.0, "deg"))),
     "main_rotor.hub_x: unit 'deg'"),
    ("no unit", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x", '{ station = 2.0, source = "R1" }')),
     "main_rotor.hub_x: no unit"),
    ("no source", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x", '{ station = 2.0, unit = "in" }')),
     "main_rotor.hub_x: no source"),
    ("three for one axis", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x", _station("[1.0, 2.0, 3.0]"))),
     "main_rotor.hub_x: station must be one number, the FS of the point"),
    ("text", lambda t: _with_cg(_entry(t, "main_rotor", "hub_x", _station('"aft"'))),
     "main_rotor.hub_x: 'aft' is not a number"),
    ("CG twice", lambda t: _with_cg(t).replace(
        "[fuselage_aero]\n", '[fuselage_aero]\ncg_station = { value = [1.0, 0.0, 1.0], unit = "m", source = "R1" }\n'),
     "fuselage_aero.cg_station: the CG's stations are given as aircraft.cg_station too"),
]


def test_a_cg_station_written_wrongly_is_one_problem_not_two():
    """Two numbers for the CG's three stations: that problem alone, not also 'give the CG's
    stations' for every position given as a station (a new user's OH-6A)."""
    text = _with_cg(_entry(_bo105(), "main_rotor", "hub_x", _station(205.0)))
    bad = text.replace(f"value = [{CG[0]}, {CG[1]}, {CG[2]}]", f"value = [{CG[0]}, {CG[1]}]")
    assert bad != text
    _, problems = evaluate(bad)
    assert len(problems) == 1 and problems[0].startswith("aircraft.cg_station: must be a list of 3 numbers"), problems


@pytest.mark.parametrize("text,expected", [(b[1], b[2]) for b in BAD], ids=[b[0] for b in BAD])
def test_a_station_written_wrongly_is_a_problem_naming_the_entry(text, expected):
    _, problems = evaluate(text(_bo105()))
    assert any(p.startswith(expected) for p in problems), problems


def test_a_point_needs_three_stations():
    from mbs.aircraft.reader import read
    out = read(_with_cg(_bo105()).replace(
        "[fuselage_aero]\n", '[fuselage_aero]\nreference_point = { station = [1.0, 2.0], unit = "in", source = "R2" }\n'))
    assert "fuselage_aero.reference_point: station must be a list of 3 numbers: FS, BL, WL" in out.problems


# -- blade tables against radial stations -----------------------------------------------------------

RADIUS = 4.91  # m, the Bo105's main-rotor radius
TIP_IN = RADIUS / INCH  # the tip's radial station, in


def _chord(rows: str, unit: str) -> str:
    text = re.sub(r"^chord = .*\n", "", _bo105().replace("[main_rotor]\n", "[main_rotor]\n" + (
        f'chord_table = {{ value = {rows}, unit = "{unit}", source = "R3 Fig. 2" }}\n'), 1), count=1, flags=re.M)
    return text


def test_span_tables_against_radial_stations_equal_those_against_r_over_r():
    """A chord table printed against radial stations in inches gives the same r/R rows as the
    hand division by the radius; the tip's station becomes r/R = 1 exactly."""
    stations = [0.2 * TIP_IN, 0.6 * TIP_IN, TIP_IN]
    by_station, problems = evaluate(_chord(f"[[{stations[0]!r}, 11.0], [{stations[1]!r}, 10.6], [{stations[2]!r}, 10.0]]",
                                           "in, in"))
    assert not problems, problems
    by_ratio, problems = evaluate(_chord("[[0.2, 11.0], [0.6, 10.6], [1.0, 10.0]]", "-, in"))
    assert not problems, problems
    flat = [x for row in by_ratio["main_rotor"]["chord_table"] for x in row]
    assert [x for row in by_station["main_rotor"]["chord_table"] for x in row] == pytest.approx(flat, abs=1e-12)
    assert by_station["main_rotor"]["chord_table"][-1][0] == 1.0
    assert by_station["main_rotor"]["chord"] == pytest.approx(by_ratio["main_rotor"]["chord"], rel=1e-12)


@pytest.mark.parametrize("rows, unit", [("[[0.2, 11.0], [0.6, 10.6], [1.0, 10.0]]", "r/R, in"),
                                        ("[[20, 11.0], [60, 10.6], [100, 10.0]]", "% R, in"),
                                        ("[[20, 11.0], [60, 10.6], [100, 10.0]]", "%R, in")])
def test_a_span_tables_first_column_headed_r_over_r_or_per_cent_of_r_reads_as_printed(rows, unit):
    by_ratio, problems = evaluate(_chord("[[0.2, 11.0], [0.6, 10.6], [1.0, 10.0]]", "-, in"))
    assert not problems, problems
    printed, problems = evaluate(_chord(rows, unit))
    assert not problems, problems
    flat = [x for row in by_ratio["main_rotor"]["chord_table"] for x in row]
    assert [x for row in printed["main_rotor"]["chord_table"] for x in row] == pytest.approx(flat, abs=1e-15)


def test_aircraft_check_lists_the_radial_stations_over_the_radius(tmp_path):
    path = tmp_path / "craft.toml"
    path.write_text(_chord("[[19.0, 0.27], [193.0, 0.26]]", "in, m"))
    report = aircraft.check(path)
    assert report.ok, report.problems
    entry, value, unit, how, source = next(r for r in report.converted if r[0] == "main_rotor.chord_table")
    assert value[1][0] == pytest.approx(193.0 * INCH / RADIUS, rel=1e-12) and source == "R3 Fig. 2"
    assert how.startswith("r/R from the radial stations in in over main_rotor.radius 4.91 m")


@pytest.mark.parametrize("rows,unit,expected", [
    ("[[19.0, 0.27], [194.0, 0.26]]", "in, m", "main_rotor.chord_table: the stations r/R (0.0982892, 1.00358)"),
    ("[[19.0, 0.27], [194.0, 0.26]]", "deg, m", "main_rotor.chord_table: unit 'deg'"),
])
def test_radial_stations_beyond_the_tip_or_not_a_length_are_problems(rows, unit, expected):
    _, problems = evaluate(_chord(rows, unit))
    assert any(p.startswith(expected) for p in problems), problems


def test_the_fuselage_reference_station_pair_follows_the_butt_line_convention():
    """The older pair ``fuselage_aero.reference_station`` and ``cg_station`` takes its butt lines
    as ``conventions.butt_line_positive`` says, like every other station."""
    from mbs.aircraft.airframe_data import reference_point

    text = _bo105().replace("[fuselage_aero]\n", '[fuselage_aero]\nmodel = { value = "tables", unit = "-", source = "R" }\n'
                            'axes = { value = "body", unit = "-", source = "R" }\n'
                            'reference_station = { value = [210.0, 5.0, 90.0], unit = "in", source = "R" }\n'
                            'cg_station = { value = [200.0, 3.0, 100.0], unit = "in", source = "R" }\n'
                            'alpha = { value = [-0.5, 0.5], unit = "rad", source = "R" }\n'
                            'X_alpha = { value = [-1.0, -1.0], unit = "m^2", source = "R" }\n', 1)
    text = re.sub(r"^(v_ref|X|Y|Z|M|N|angle_limit) = .*\n", "", text, flags=re.M)
    for side, y in (("starboard", 2.0), ("port", -2.0)):
        data, problems = evaluate(text + f'\n[conventions]\nbutt_line_positive = {{ value = "{side}", unit = "-", '
                                         'source = "R" }\n')
        assert not problems, problems
        assert reference_point(data) == pytest.approx([-10 * INCH, y * INCH, 10 * INCH], abs=1e-14)


@pytest.mark.parametrize("section, key, new, expected", [
    ("main_rotor", "chord", 'chord_table = { value = [], unit = "-, m", source = "R" }',
     "main_rotor.chord_table: an empty table, which would leave chord unset"),
    ("main_rotor", "I_flap", 'lock_number = { value = 0.0, unit = "-", source = "R" }',
     "main_rotor.lock_number: 0 is outside (0, 100]"),
    ("tail_rotor", "hub_x", 'hub_x = { value = -1.2, unit = "R", source = "R" }',
     "tail_rotor.hub_x: unit 'R' applies to a rotor's own lengths, not to a position from the CG"),
])
def test_an_entry_that_would_replace_nothing_or_mean_two_things_is_a_problem(section, key, new, expected):
    """An empty table in place of the number it replaces, a Lock number of 0 and a position in R
    (of which rotor's radius?) are each refused, naming the entry, not accepted and left unused."""
    text = _bo105()
    head, sep, rest = text.partition(f"[{section}]\n")
    rest = re.sub(rf"^{key} = .*$", new, rest, count=1, flags=re.M)
    _, problems = evaluate(head + sep + rest)
    assert any(p.startswith(expected) for p in problems), problems


def test_stations_that_count_forward_and_down_are_taken_as_printed(tmp_path):
    """Simulation data give points as a datum's x forward and z down (a new user's UH-60 flipped
    every sign by hand): ``fuselage_station_positive = "forward"`` and ``water_line_positive =
    "down"`` take them as printed, and the check's formula says so."""
    text = _with_cg(_entry(_entry(_bo105(), "tail_rotor", "hub_x", _station(440.0)), "tail_rotor", "hub_z",
                           _station(160.0)))
    assert "[conventions]" not in text
    text += ('\n[conventions]\nfuselage_station_positive = { value = "forward", unit = "-", source = "R1" }\n'
             'water_line_positive = { value = "down", unit = "-", source = "R1" }\n')
    path = tmp_path / "forward.toml"
    path.write_text(text)
    report = aircraft.check(path)
    assert report.ok, report.problems
    tr = aircraft.load(path).data["tail_rotor"]
    assert tr["hub_x"] == pytest.approx((440.0 - CG[0]) * INCH) and tr["hub_z"] == pytest.approx((160.0 - CG[2]) * INCH)
    hows = {r[0]: r[3] for r in report.converted}
    assert hows["tail_rotor.hub_x"].endswith("x = (FS - FS_cg)") and hows["tail_rotor.hub_z"].endswith("z = (WL - WL_cg)")


def test_a_station_convention_in_a_file_without_stations_is_warned_of(tmp_path):
    """``fuselage_station_positive = "forward"`` where every position is given from the CG changes
    nothing; the check says so (with a station given, it does not)."""
    conventions = ('\n[conventions]\nfuselage_station_positive = { value = "forward", unit = "-", source = "R1" }\n')
    plain, stationed = tmp_path / "plain.toml", tmp_path / "stationed.toml"
    plain.write_text(_bo105() + conventions)
    stationed.write_text(_with_cg(_entry(_bo105(), "tail_rotor", "hub_x", _station(440.0))) + conventions)
    said = [w for w in aircraft.check(plain).warnings if w.startswith("conventions.")]
    assert said == ["conventions.fuselage_station_positive: no position is given as a station, so it changes "
                    "nothing: give the positions as stations ({ station = ..., unit = ..., source = ... } with "
                    "aircraft.cg_station), or leave it out"]
    assert not [w for w in aircraft.check(stationed).warnings if w.startswith("conventions.")]
