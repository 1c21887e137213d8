"""A published aircraft written from its reports as printed (tests/data/uh60a_report.toml, the
UH-60A of the GENHEL model): feet, inches, slug ft², lb, degrees, stick inches, stations, wind-axis
fuselage tables about a reference point, a stabilator schedule, whole-aircraft inertias and a
canted, δ3-coupled tail rotor at its real gear ratio. The check is clean, lists every conversion
with its source, and the aircraft trims from hover to 140 kt."""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import pytest

from mbs import aircraft, scenes
from mbs.analysis.trim import evaluators, periodic_solution

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PATH = Path(__file__).parent / "data" / "uh60a_report.toml"
KT = 1852.0 / 3600  # m/s per knot
INCH = 0.0254
LB, SLUG_FT2 = 0.45359237, 14.593902937 * 0.3048**2
NOT_SI = ("ft", "in", "slug", "lb", "deg", "%", "kt", "hp")
EXPECTED_WARNINGS = {
    "tail_rotor.tip_loss: the override 0.92": "G3's tail-rotor tip loss, kept against the derived 0.964",
    "aircraft.inertia: the whole-aircraft inertia less the rotors'": "G2's inertias less the rotors leave an "
    "airframe that breaks the triangle inequality (GENHEL's rotor and aircraft figures do not agree)",
    "tail_rotor.gear_ratio: tail-rotor gear ratio 4.6156": "the periodic analyses turn the tail rotor at 60/13",
}
G2_HOVER = {"speed_kt": 1.0, "pitch": 5.052, "roll": -2.340, "longitudinal_stick": 0.1266, "lateral_stick": 0.2321,
            "collective_lever": 5.719, "pedals": -1.279}
"""G2 Table 4, the 1-kt column: attitudes (deg) and stick positions (in)."""


@pytest.fixture(scope="module")
def report():
    return aircraft.check(PATH)


def _raw() -> dict:
    return tomllib.loads(PATH.read_text())


def test_the_report_aircraft_checks_clean_with_only_the_warnings_it_should_have(report):
    print("\n".join(f"warning: {w}" for w in report.warnings))
    assert report.ok, report.problems
    for w in report.warnings:
        assert any(w.startswith(k) for k in EXPECTED_WARNINGS), f"unexpected warning: {w}"
    assert all(any(w.startswith(k) for w in report.warnings) for k in EXPECTED_WARNINGS)


def test_every_value_given_in_other_units_is_listed_as_converted_with_its_source(report):
    """Each entry written in ft, in, slug ft², lb, deg, %, kt or hp (tables and stations
    included) has a row ``(entry, value, unit, how, source)`` whose source is the file's tag."""
    rows = {}
    for entry, value, unit, how, source in report.converted:
        rows.setdefault(entry, []).append((value, unit, how, source))
    given = [(f"{s}.{k}", e) for s, entries in _raw().items() for k, e in entries.items()
             if any(u in str(e.get("unit", "")) for u in NOT_SI)]
    assert len(given) > 60
    # a table is listed once, as SI per dynamic pressure (not also as the reader's raw form)
    assert not any(isinstance(value, dict) for _, value, *_ in report.converted)
    assert len(rows["fuselage_aero.drag_alpha"]) == 1
    for entry, e in given:
        assert entry in rows, f"{entry} ({e['unit']}) not listed as converted"
        assert all(source == e["source"] for *_, source in rows[entry]), (entry, rows[entry])
    values = {entry: r[0][0] for entry, r in rows.items()}
    assert values["aircraft.mass"] == pytest.approx(16400 * LB, rel=1e-12)
    assert values["main_rotor.hub_x"] == pytest.approx(19.2 * INCH, rel=1e-12)
    assert values["tail_rotor.delta3"] == pytest.approx(math.radians(35.0), rel=1e-12)
    assert values["main_rotor.lag_stiffness"] == pytest.approx(15060 * 0.3048 * LB * 9.80665, rel=1e-12)
    # the whole aircraft's inertia becomes the airframe's: both rows listed, G2's tag on each
    assert [r[0] for r in rows["aircraft.Ixx"]][0] == pytest.approx(5629 * SLUG_FT2, rel=1e-9)
    assert "whole aircraft" in rows["aircraft.Ixx"][1][2]
    # FS 345.5, WL 234.0 about the CG at STA 360.4, WL 247.2: 14.9 in forward, 13.2 in below
    point = next(v for v, _, how, _ in rows["fuselage_aero.reference_point"] if "CG at FS 360.4" in how)
    assert point == pytest.approx([14.9 * INCH, 0.0, 13.2 * INCH], abs=1e-12)
    # every position as printed: G2's and G3's stations less the CG's, the butt line port-positive
    for entry, inches in (("main_rotor.hub_x", 19.2), ("main_rotor.hub_z", -67.8), ("tail_rotor.hub_x", -371.6),
                          ("tail_rotor.hub_y", 14.0), ("tail_rotor.hub_z", -77.5), ("horizontal_tail.x", -339.6),
                          ("horizontal_tail.z", 3.2), ("vertical_fin.x", -334.6), ("vertical_fin.z", -25.8)):
        assert values[entry] == pytest.approx(inches * INCH, abs=1e-12), entry
        assert "from station" in rows[entry][0][2], rows[entry]
    drag = next(v for v, *_ in rows["fuselage_aero (alpha = beta = 0)"])
    assert -drag[0] == pytest.approx(28.0 * 0.3048**2, abs=1e-6)  # D/q of the wind table, the body's -X/q (6 decimals)


def test_the_blade_integrates_to_the_published_mass_first_moment_and_flap_inertia(report):
    """The mass table (EST shape) reproduces G3's blade: 256.9 lb, 86.7 slug ft, 1512.6 slug ft²."""
    derived = {e: v for e, v, _, _ in report.derived}
    assert derived["main_rotor.blade_mass"] == pytest.approx(256.9 * LB, rel=1e-3)
    assert derived["main_rotor.first_moment"] == pytest.approx(86.7 * 14.593902937 * 0.3048, rel=1e-3)
    assert derived["main_rotor.I_flap"] == pytest.approx(1512.6 * SLUG_FT2, rel=1e-3)


# -- trims over the speed range -------------------------------------------------------------------

@pytest.fixture(scope="module")
def trims():
    """Trims of the forward-flight scene at 0, 1 (G2's hover column), 40, 80, 120 and 140 kt,
    one compiled system shared; each speed's wall time."""
    import logging

    sc = scenes.get("forward-flight", aircraft.load(PATH))
    system, stepper = evaluators(sc)
    out, log = {}, logging.getLogger("mbs.analysis.trim")
    handler = logging.Handler(logging.DEBUG)
    handler.emit = lambda record: WARM_STARTS.append((record.levelno, record.getMessage()))
    log.addHandler(handler)
    level, log.level = log.level, logging.DEBUG
    try:
        for kt in (0.0, 1.0, 40.0, 80.0, 120.0, 140.0):
            start = time.perf_counter()
            res = periodic_solution(sc, kt * KT, system=system, stepper=stepper)
            out[kt] = res, time.perf_counter() - start
    finally:
        log.removeHandler(handler)
        log.level = level
    return out


WARM_STARTS: list[tuple[int, str]] = []
"""The trim log's records while the fixture ``trims`` runs."""


def test_the_warm_start_is_announced_once_for_the_aircraft(trims):
    """Six trims of the same file each warm-start from the near gear ratio's trim; the message
    says so once (INFO), the repeats go to DEBUG."""
    import logging

    said = [level for level, text in WARM_STARTS if text.startswith("warm start: first a trim")]
    assert said.count(logging.INFO) <= 1 and said.count(logging.DEBUG) >= 5, said


def _line(kt: float, res, wall: float) -> str:
    c = {k: f"{math.degrees(v):+.3f}" for k, v in res.controls.items()}
    p = {k: f"{v:+.3f}" for k, v in res.pilot.items()}
    return (f"{kt:5.0f} kt: converged {res.converged} in {res.iterations} iterations, {wall:.1f} s, residual "
            f"{res.residuals[-1]:.1e}; controls deg {c}; pitch {math.degrees(res.pitch):+.3f} roll "
            f"{math.degrees(res.roll):+.3f} deg; pilot in {p}")


def test_the_report_aircraft_trims_from_hover_to_140_kt(trims):
    """Every speed converges over the 13-revolution period of 60/13 (the real 4.6156 repeats only
    after 625), with its stick positions inside their travel; the nose drops and the stick moves
    forward as the speed rises."""
    print()
    for kt, (res, wall) in trims.items():
        print(_line(kt, res, wall))
        assert res.converged, f"{kt} kt: {res.reason}"
        assert res.residuals[-1] <= 1e-10 and res.period.revs == 13
        assert abs(res.pilot["longitudinal_stick"]) < 5 and abs(res.pilot["lateral_stick"]) < 5
        assert 0 < res.pilot["collective_lever"] < 10 and abs(res.pilot["pedals"]) < 2.69
    pitch = [trims[kt][0].pitch for kt in (40.0, 80.0, 120.0, 140.0)]
    stick = [trims[kt][0].pilot["longitudinal_stick"] for kt in (40.0, 80.0, 120.0, 140.0)]
    assert all(a > b for a, b in zip(pitch, pitch[1:])) and all(a < b for a, b in zip(stick, stick[1:]))


def test_the_hover_trim_beside_g2_table_4(trims):
    """Our 1-kt trim beside GENHEL's (G2 Table 4): with the fuselage tables, the rotor's blade
    tables and the interference (EK) tables estimated, only loose bounds are physics: the nose up
    and the left bank of a hover with the CG aft of the shaft and the tail rotor above the CG
    (within 3 deg), the stick positions within an inch of the report's (the lever, whose rigging
    gives the collective that lifts the weight, within half an inch)."""
    res, _ = trims[1.0]
    ours = {"pitch": math.degrees(res.pitch), "roll": math.degrees(res.roll), **res.pilot}
    print()
    for k, ref in G2_HOVER.items():
        if k != "speed_kt":
            print(f"{k:20s} ours {ours[k]:+8.3f}   G2 Table 4 {ref:+8.3f}   difference {ours[k] - ref:+.3f}")
    assert ours["pitch"] == pytest.approx(G2_HOVER["pitch"], abs=3.0) and ours["pitch"] > 0
    assert ours["roll"] == pytest.approx(G2_HOVER["roll"], abs=3.0) and ours["roll"] < 0
    assert ours["collective_lever"] == pytest.approx(G2_HOVER["collective_lever"], abs=0.5)
    for k in ("longitudinal_stick", "lateral_stick", "pedals"):
        assert ours[k] == pytest.approx(G2_HOVER[k], abs=1.0), k


def test_a_fuselage_drag_no_helicopter_has_is_warned_of(tmp_path):
    """A new user's fuselage tables printed in ft^2 and labelled m^2 gave 23.6 m^2 of drag area (0.11
    of the disc) with "no problems", and a trim at -17.7 deg of pitch. The Bo105's polynomials give
    1.02 m^2 (0.0135 of its disc), listed; ten times that, or a thrust, is warned of."""
    from aircraft_files import entries, write

    figures = {n: v for n, v, _ in aircraft.check("bo105").figures}
    assert figures["fuselage drag area at zero angles"] == pytest.approx(580.6 / (0.5 * 1.225 * 30.48**2), rel=1e-3)
    assert figures["fuselage drag area per disc area"] == pytest.approx(0.0135, abs=1e-4)
    for factor, words in ((10.0, "is 0.135 of the main rotor's disc area"), (-1.0, "is not a drag")):
        raw = entries("bo105")
        raw["fuselage_aero"]["X"]["value"][0] *= factor
        warnings = aircraft.check(write(raw, tmp_path / "drag.toml")).warnings
        assert any(w.startswith("fuselage_aero: the drag area at zero angle of attack and sideslip") and words in w
                   for w in warnings), warnings
