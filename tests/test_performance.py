"""Power available against power required (:mod:`mbs.performance`): the Bo105's hover ceilings in and
out of ground effect at ISA and ISA + 20 against its published figure, and the largest level speed,
from trims swept on Dask."""
from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from mbs import aircraft
from mbs.environment import atmosphere as isa
from mbs.performance.available import power_available
from mbs.performance.ceiling import hover_ceilings, level_speeds, zero_crossing

BO105 = aircraft.load().data
FT = 0.3048
PUBLISHED = {"oge": 5400 * FT, "ige": 8200 * FT}
"""Bo105 CBS-4 at 2500 kg, ISA: HOGE 5,400 ft and HIGE 8,200 ft, the operator's transcription of its
flight manual's hover charts in an electronic flight bag (github.com/eforgan/efbbo105,
src/lib/calculations.ts); no ISA + 20 figure was found."""


def test_power_available_is_the_ratings_lapse_and_the_gearbox_limit():
    e = BO105["engine"]
    assert power_available(BO105, 0.0) == e["transmission_power"]  # 2 x 313 kW above the 500 kW gearbox
    lapse = isa.pressure(4000.0) / isa.P0 / (isa.temperature(4000.0, 20.0) / isa.T0) ** e["lapse_temperature"]
    assert power_available(BO105, 4000.0, 20.0) == pytest.approx(2 * e["takeoff_power"] * lapse, rel=1e-14)
    assert power_available(BO105, 1000.0, 0.0, engines_out=1) == pytest.approx(
        e["oei_power"] * isa.pressure(1000.0) / isa.P0 / (isa.temperature(1000.0) / isa.T0) ** e["lapse_temperature"])
    assert power_available(BO105, 0.0, 0.0, engines_out=2) == 0.0


def test_a_piston_engine_holds_its_derated_rating_to_its_critical_altitude(tmp_path):
    """A new user's R22 (a 180 hp O-360 derated to 131 hp take-off) could only be given a
    turboshaft's lapse. A piston engine's rating holds until its full-throttle power, lapsing as
    1.132 sigma - 0.132 (Gagg and Ferrar), falls to it: for 131 of 180 hp at sigma 0.7596, about
    2800 m in the ISA; a turboshaft's entries with it are refused; one engine needs no OEI rating."""
    from aircraft_files import entries, write

    hp = 745.69987158227022
    raw = entries("bo105")
    engine = raw["engine"]
    for key in ("lapse_temperature", "oei_power"):  # one engine: no other to fail, no OEI rating
        del engine[key]
    engine.update(model={"value": "piston", "unit": "-", "source": "POH"},
                  count={"value": 1, "unit": "-", "source": "POH"},
                  takeoff_power={"value": 131, "unit": "hp", "source": "POH"},
                  max_continuous_power={"value": 124, "unit": "hp", "source": "POH"},
                  transmission_power={"value": 131, "unit": "hp", "source": "POH"},
                  full_throttle_power={"value": 180, "unit": "hp", "source": "engine data"})
    path = write(raw, tmp_path / "piston.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    d = aircraft.load(path).data
    sigma = lambda h: isa.pressure(h) / isa.P0 / (isa.temperature(h) / isa.T0)  # noqa: E731
    assert sigma(2700.0) > (131 / 180 + 0.132) / 1.132 > sigma(2900.0)
    for h in (0.0, 1000.0, 2700.0):
        assert power_available(d, h) == pytest.approx(131 * hp, rel=1e-12), h
    for h in (2900.0, 4000.0):
        assert power_available(d, h) == pytest.approx(180 * hp * (1.132 * sigma(h) - 0.132), rel=1e-12), h
    engine["lapse_temperature"] = {"value": 1.0, "unit": "-", "source": "x"}
    bad = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert "engine.lapse_temperature: applies only when engine.model = 'turboshaft'; leave it out" in bad.problems
    del engine["lapse_temperature"]
    engine["count"]["value"] = 2  # two engines: the rating is needed again
    twin = aircraft.check(write(raw, tmp_path / "twin.toml"))
    assert [p for p in twin.problems if p.startswith("engine.")] == [
        "engine.oei_power: missing (an engine's one-engine-inoperative rating (the power the remaining engine may give "
        "when another has failed), sea level, ISA (not needed with one engine), in W)"]


def test_the_ceiling_is_the_margins_last_zero():
    assert zero_crossing(np.array([0.0, 1000.0, 2000.0]), np.array([10.0, 5.0, -5.0])) == pytest.approx(1500.0)
    assert zero_crossing(np.array([0.0, 1000.0]), np.array([10.0, 5.0])) is None


@pytest.fixture(scope="module")
def ceilings():
    res = hover_ceilings([0.0, 1000.0, 2000.0, 3000.0, 4000.0], [2500.0], [0.0, 20.0], workers=2)
    return {(c.ground, c.offset): c for c in res}


def test_hover_ceilings_out_of_and_in_ground_effect_against_the_published_figure(ceilings):
    """2500 kg. Out of ground effect at ISA within 10 % of the flight manual's 5,400 ft (1,532 m
    against 1,646 m); in ground effect (skids 1 m above the ground) the model hovers 36 % higher than
    its 8,200 ft (3,397 m against 2,499 m: the gearbox limit and the engines' lapse are estimates and
    the image rotor's saving at 0.77 R is larger than the manual's); ISA + 20 lowers both."""
    for ground in ("oge", "ige"):
        c = ceilings[(ground, 0.0)]
        print(f"{ground.upper()} ISA: {c.ceiling:.0f} m ({c.ceiling / FT:.0f} ft) against {PUBLISHED[ground]:.0f} m; "
              f"ISA+20: {ceilings[(ground, 20.0)].ceiling:.0f} m")
    assert ceilings[("oge", 0.0)].ceiling == pytest.approx(PUBLISHED["oge"], rel=0.10)
    assert ceilings[("ige", 0.0)].ceiling == pytest.approx(PUBLISHED["ige"], rel=0.40)
    for ground in ("oge", "ige"):
        assert ceilings[(ground, 20.0)].ceiling < ceilings[(ground, 0.0)].ceiling - 500.0
    assert ceilings[("ige", 0.0)].ceiling > ceilings[("oge", 0.0)].ceiling


def test_largest_level_speed_at_sea_level_and_lower_up_high():
    """2200 kg, ISA: the largest level speed at sea level between 65 and 80 m/s (the Bo105's never-
    exceed speed is 145 kt, 75 m/s); at 1500 m less."""
    res = {c.altitude: c for c in level_speeds([50.0, 60.0, 70.0, 80.0], [0.0, 1500.0], [2200.0], [0.0], workers=2)}
    print({h: c.speed for h, c in res.items()})
    assert 65.0 < res[0.0].speed < 80.0
    assert res[1500.0].speed is None or res[1500.0].speed < res[0.0].speed


def test_a_trim_needing_more_power_than_the_engines_make_warns():
    """Hover at 2200 kg, ISA: at 3000 m the engines' 443 kW is within what they make; at 4500 m
    the 471 kW required is beyond it, and the warning gives power_available there. In the file's
    air the density altitude of its density is used (ISA's density inverted to 1e-6 m)."""
    import json

    from mbs.cli import main

    said = {}
    for altitude in (3000.0, 4500.0):
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            assert main(["trim", "--speed", "0", "--altitude", f"{altitude:g}", "--json", "--quiet"]) == 0
        said[altitude] = [w for w in json.loads(out.getvalue())["warnings"] if w.startswith("engine.power")]
    assert said[3000.0] == []
    available = power_available(BO105, 4500.0) / 1e3
    assert len(said[4500.0]) == 1 and f"more than the engines make available, {available:.1f} kW in ISA 4500 m" in \
        said[4500.0][0], said
    for h in (-500.0, 0.0, 2345.0, 11500.0):
        assert isa.density_altitude(isa.density(h)) == pytest.approx(h, abs=1e-6)
    heavy = {**BO105, "environment": {**BO105["environment"], "rho": isa.density(4500.0)}}
    from types import SimpleNamespace

    from mbs.analysis.trim_checks import power

    trim = SimpleNamespace(output_means={"engine.power": 471.1e3})
    said = power(trim, heavy)  # the file's air, no ISA: at its density altitude
    assert len(said) == 1 and "in the file's air (density altitude 4500 m)" in said[0], said
    assert power(trim, BO105) == []


def test_performance_takes_an_aircraft_file_and_refuses_one_without_engine_ratings(capsys):
    """A new user's EC135 could not be given to 'heli performance' (Bo105 only). It takes
    --aircraft, its masses default to the file's, and an aircraft without rated engines is refused
    before any trim is swept."""
    from mbs.cli import main
    from mbs.performance.commands import _masses
    from types import SimpleNamespace

    assert _masses(SimpleNamespace(masses=None, aircraft=aircraft.load("puma"))).tolist() == [5805.0]
    assert _masses(SimpleNamespace(masses="2000,2500", aircraft=None)).tolist() == [2000.0, 2500.0]
    assert main(["performance", "speed", "--aircraft", "puma", "--workers", "0", "--quiet"]) == 2
    assert "the aircraft file's [engine] needs model = \"turboshaft\" or \"piston\"" in capsys.readouterr().err


def test_performance_sweeps_take_the_units_a_flight_manual_prints():
    """An R22 user's altitudes in ft and mass in lb were refused where trim took kt."""
    from mbs.performance.commands import ALTITUDES, HUB_HEIGHTS, MASSES, SPEEDS

    assert ALTITUDES("0:10000ft:3") == pytest.approx([0.0, 1524.0, 3048.0])
    assert ALTITUDES("0,2km") == pytest.approx([0.0, 2000.0])
    assert MASSES("1370lb") == pytest.approx([1370 * 0.45359237])
    assert SPEEDS("80kt:140kt:4")[-1] == pytest.approx(140 * 1852 / 3600)
    assert HUB_HEIGHTS("10ft") == pytest.approx([3.048])
    with pytest.raises(ValueError, match="outside the altitudes a sweep takes"):
        ALTITUDES("70000ft")


def test_a_sweep_without_its_zero_says_which_way_it_lies_and_what_to_extend():
    """A new user's ceiling sweep printed only "not within the swept altitudes": the ceiling was
    above the top altitude. The line now gives the side, the margin at that end and the option."""
    from mbs.performance.commands import _no_crossing

    above = _no_crossing([0.0, 1000.0, 3000.0], [90e3, 60e3, 12.5e3], "m", "altitude", "--altitudes")
    assert above == "above the highest altitude swept, 3000 m (margin +12.5 kW there): extend --altitudes"
    below = _no_crossing([20.0, 40.0], [-3e3, float("nan")], "m/s", "speed", "--speeds")
    assert below == "below the lowest speed swept, 20 m/s (margin -3.0 kW there): extend --speeds or lighten the " \
                    "aircraft"
    assert _no_crossing([0.0], [float("nan")], "m", "altitude", "--altitudes") == "no trim converged"
