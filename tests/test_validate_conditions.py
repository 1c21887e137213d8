"""Published points at their own flight condition (``mass``, ``altitude`` per point, as flight
tests print each point's weight and altitude): read in the report's units, trimmed as a weight at
the CG and in the ISA, and equal to trims of an aircraft file at that mass and of the scene at
that altitude."""
import math

import numpy as np
import pytest

from mbs.validate.data import ValidationError
from mbs.validate.files import load

HEAD = '[validation]\ntitle = "t"\naircraft = "bo105"\nspeed_unit = "kt"\n'
POWER = ('[[trim]]\nquantity = "main_rotor.power"\nunit = "kW"\nspeed = [40, 40, 40]\nvalue = [230, 260, 250]\n'
         'source = "FT"\nmass = { value = [4850.2, 5511.6, 4850.2], unit = "lb" }\n')
LB, FT = 0.45359237, 0.3048


def _file(tmp_path, text: str, name: str = "points.toml"):
    path = tmp_path / name
    path.write_text(HEAD + text)
    return path


def test_points_read_in_the_reports_units_with_file_defaults(tmp_path):
    """Masses in lb per point and an altitude in ft, in the series or for the file ([validation]),
    read in SI; each point's condition is its speed, mass and altitude."""
    own = load(_file(tmp_path, POWER + 'altitude = { value = 1000, unit = "ft" }\n', "own.toml")).series[0]
    assert own.mass == pytest.approx([4850.2 * LB, 5511.6 * LB, 4850.2 * LB], rel=1e-14)
    assert own.altitude == pytest.approx([1000 * FT] * 3, rel=1e-14)
    assert own.conditions()[1][:3] == pytest.approx((40 * 1852 / 3600, 5511.6 * LB, 1000 * FT))
    assert own.conditions()[1][3] is None  # the aircraft file's CG
    path = tmp_path / "file.toml"
    path.write_text(HEAD.replace('speed_unit = "kt"\n', 'speed_unit = "kt"\naltitude = { value = 1000, unit = "ft" }\n')
                    + POWER)
    assert load(path).series[0].conditions() == own.conditions()


@pytest.mark.parametrize("text, words", [
    (POWER.replace("[4850.2, 5511.6, 4850.2]", "[4850.2, 5511.6]"), "mass has 2 values for 3 points"),
    (POWER.replace('unit = "lb" }', 'unit = "ft" }'), "mass: unit 'ft'"),
    (POWER + 'altitude = { value = 30000, unit = "m" }\n', "altitude 30000 m is outside -1000 to 20000 m"),
    (POWER + 'altitude = 300\n', "altitude must be { value = x or [one per point], unit"),
    (POWER + POWER.replace('mass = { value = [4850.2, 5511.6, 4850.2], unit = "lb" }\n',
                           'altitude = { value = 0, unit = "m" }\n'),
     "altitude given for some points but not for main_rotor.power"),
    ('[[derivative]]\nquantity = "X_u"\nunit = "1/s"\nspeed = [40]\nvalue = [-0.02]\nsource = "FT"\n'
     'mass = { value = 5000, unit = "lb" }\n', "mass and the CG apply to [[trim]] series"),
    (POWER + 'cg_x = { value = 1, unit = "in" }\ncg_station = { value = 100, unit = "in" }\n',
     "give the CG once, as cg_station or as cg_x"),
    (POWER + 'cg_x = { value = 50, unit = "in" }\n', "cg_x 50 in is outside -1 to 1 m"),
])
def test_a_bad_condition_is_refused_naming_it(tmp_path, text, words):
    with pytest.raises(ValidationError) as exc:
        load(_file(tmp_path, text))
    assert words in str(exc.value), str(exc.value)


def test_an_unknown_key_of_the_validation_section_is_refused(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text(HEAD.replace('speed_unit = "kt"\n', 'speed_unit = "kt"\nweight = 5000\n') + POWER)
    with pytest.raises(ValidationError, match=r"\[validation\]: unknown key\(s\) weight"):
        load(path)


def test_csv_columns_carry_the_same_conditions(tmp_path):
    """The CSV form's mass and altitude columns (units from '# mass_unit:', '# altitude_unit:')
    equal the TOML form's; a series with the mass of some points only is refused."""
    rows = "".join(f"trim,main_rotor.power,kW,40,{p},FT,{m},{h}\n" for p, m, h in
                   ((230, 4850.2, 500), (260, 5511.6, 500), (250, 4850.2, 500)))
    csv = tmp_path / "d.csv"
    csv.write_text("# title: t\n# aircraft: bo105\n# speed_unit: kt\n# mass_unit: lb\n# altitude_unit: ft\n"
                   "kind,quantity,unit,speed,value,source,mass,altitude\n" + rows)
    s, = load(csv).series
    t, = load(_file(tmp_path, POWER + 'altitude = { value = 500, unit = "ft" }\n')).series
    assert s.conditions() == t.conditions()
    csv.write_text(csv.read_text().replace(",4850.2,500\n", ",,500\n", 1))
    with pytest.raises(ValidationError, match="mass is given for 2 of its 3 points"):
        load(csv)


def test_each_point_trims_at_its_mass_and_altitude_as_the_aircraft_and_the_air_would(tmp_path):
    """The Bo105 at 40 kt: the point at 2500 kg (a weight of 300 kg added at the CG) trims to the
    controls and power of the aircraft file written at 2500 kg (to 0.01 deg and 0.1 %; the
    added weight leaves the inertia), the point at 3000 m to those of the scene in the ISA at
    3000 m (to 1e-6: the same model, its altitude parameter set two ways); the power rises with
    both."""
    from mbs import aircraft, scenes
    from mbs.analysis.trim import periodic_solution
    from mbs.models.helicopter.air_options import with_environment
    from mbs.validate.runner import validate

    heavy = 5511.6 * LB
    path = _file(tmp_path, POWER.replace("mass = { value = [4850.2, 5511.6, 4850.2]", "mass = { value = [2200, "
                                         f"{heavy!r}, 2200]").replace('unit = "lb" }', 'unit = "kg" }')
                 + 'altitude = { value = [0, 0, 3000], unit = "m" }\n')
    res = validate(load(path))
    speed = 40 * 1852 / 3600
    base, mass_point, high = (res.model.at(speed, m, h).trim for m, h in ((2200, 0), (heavy, 0), (2200, 3000)))
    text = aircraft.resolve("bo105").read_text()
    line = next(x for x in text.splitlines() if x.startswith("mass = "))
    file = tmp_path / "heavy.toml"
    file.write_text(text.replace(line, f'mass = {{ value = {heavy!r}, unit = "kg", source = "test" }}'))
    written = periodic_solution(scenes.get("forward-flight", aircraft=aircraft.load(file)), speed)
    isa = periodic_solution(with_environment(scenes.get("forward-flight"), 3000.0), speed)
    for got, want, rel in ((mass_point, written, 1e-3), (high, isa, 1e-6)):
        power = (got.output_means["main_rotor.power"], want.output_means["main_rotor.power"])
        assert power[0] == pytest.approx(power[1], rel=rel)
        for k, value in want.controls.items():
            assert math.degrees(abs(got.controls[k] - value)) < (0.01 if rel > 1e-6 else 1e-6), k
    p = {k: t.output_means["main_rotor.power"] for k, t in (("base", base), ("mass", mass_point), ("high", high))}
    assert p["mass"] > 1.1 * p["base"] and p["high"] > 1.1 * p["base"], p
    rows = res.blocks[0][1]
    assert [r.condition for r in rows] == ["2200 kg, 0 m", f"{heavy:.6g} kg, 0 m", "2200 kg, 3000 m"]
    assert np.isfinite([r.ours for r in rows]).all()


AXIS_ENTRIES = {("main_rotor", "hub_x"): "x", ("main_rotor", "hub_z"): "z", ("tail_rotor", "hub_x"): "x",
                ("tail_rotor", "hub_y"): "y", ("tail_rotor", "hub_z"): "z", ("horizontal_tail", "x"): "x",
                ("horizontal_tail", "z"): "z", ("vertical_fin", "x"): "x", ("vertical_fin", "z"): "z"}


def _in_stations(tmp_path, cg_fs: float, name: str):
    """The Bo105 with fuselage tables about the CG, every position written as its station (FS aft,
    BL starboard, WL up; the CG at FS ``cg_fs``, BL 0, WL 0; m): moving cg_station moves the CG
    and nothing else."""
    import re

    from mbs.aircraft.template import with_polynomial_tables

    folder = tmp_path / name
    folder.mkdir()
    text = with_polynomial_tables("bo105", folder).read_text()
    lines = text.splitlines()
    section = ""
    for i, line in enumerate(lines):
        if line.startswith("["):
            section = line.strip("[]")
        key = line.split(" = ", 1)[0]
        axis = AXIS_ENTRIES.get((section, key))
        if axis:
            x = float(re.search(r"value = (-?[0-9.]+)", line).group(1))
            station = {"x": -x, "y": x, "z": -x}[axis]
            lines[i] = f'{key} = {{ station = {station!r}, unit = "m", source = "test" }}'
        elif section == "fuselage_aero" and key == "reference_point":
            lines[i] = 'reference_point = { station = [0.0, 0.0, 0.0], unit = "m", source = "test" }'
        elif section == "aircraft" and key == "mass":
            lines[i] += f'\ncg_station = {{ value = [{cg_fs!r}, 0.0, 0.0], unit = "m", source = "test" }}'
    path = folder / "bo105_stations.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_point_at_its_own_cg_trims_as_the_aircraft_with_that_cg(tmp_path):
    """The Bo105 (positions as stations) at 30 m/s with the CG at FS 0 and 0.1 m forward (FS -0.1
    m), one validation file: the forward-CG point trims to the controls and attitude of the
    aircraft file with its CG moved there (to 0.005 deg, measured 0.0014: the weight's point moves,
    the inertia stays), and the pitch differs from the mid CG's by more than 0.3 deg (0.49), nose
    down."""
    from mbs import aircraft, scenes
    from mbs.analysis.trim import periodic_solution
    from mbs.validate.runner import validate

    base, forward = _in_stations(tmp_path, 0.0, "mid"), _in_stations(tmp_path, -0.1, "fwd")
    assert aircraft.check(base).ok and aircraft.check(forward).ok
    data = (f'[validation]\ntitle = "t"\naircraft = "{base}"\nspeed_unit = "m/s"\n'
            '[[trim]]\nquantity = "pitch"\nunit = "deg"\nspeed = [30, 30]\nvalue = [0, 0]\nsource = "T"\n'
            'cg_station = { value = [0, -100], unit = "mm" }\n')
    (tmp_path / "cg.toml").write_text(data)
    res = validate(load(tmp_path / "cg.toml"))
    mid, fwd = res.model.at(30.0, cg_x=0.0).trim, res.model.at(30.0, cg_x=0.1).trim
    want = periodic_solution(scenes.get("forward-flight", aircraft=aircraft.load(forward)), 30.0)
    for k, value in want.controls.items():
        assert math.degrees(abs(fwd.controls[k] - value)) < 0.005, (k, fwd.controls[k], value)
    assert math.degrees(abs(fwd.pitch - want.pitch)) < 0.005 and math.degrees(abs(fwd.roll - want.roll)) < 0.005
    assert math.degrees(mid.pitch - fwd.pitch) > 0.3, (mid.pitch, fwd.pitch)
    assert [r.condition for r in res.blocks[0][1]] == ["CG at station 0 mm", "CG at station -100 mm"]


def test_the_chart_shows_the_model_at_every_points_condition():
    """Three points at one speed and three CGs: the chart's model marks all three values (a line
    through speeds kept only one of them); points without conditions keep the line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mbs.validate import charts
    from mbs.validate.compare import Row

    def row(ours, condition=""):
        return Row("trim", "pitch", "deg", 0.0, ours, 1.0, 0.0, ours - 1.0, ours, None, "T", "", condition)

    fig, ax = plt.subplots()
    charts._model(ax, [row(0.5, "CG +0.076 m"), row(2.2, "CG +0 m"), row(4.4, "CG -0.1 m")], "")
    (line,) = ax.get_lines()
    assert sorted(line.get_ydata()) == [0.5, 2.2, 4.4] and line.get_linestyle() == "None"
    ax.clear()
    charts._model(ax, [row(0.5), row(2.2)], "")
    assert len(ax.get_lines()[0].get_ydata()) == 1  # one speed: the plain line's one point
    plt.close(fig)
