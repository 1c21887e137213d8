"""A wing (an attack helicopter's stub wing): the optional ``[wing]`` section, one panel on the
centre line or two a quarter of the span out, each a lifting surface in the free stream (and the
main rotor's wake with the tail-wake switch). A new user's AH-1 could not be given its stub wing."""
from __future__ import annotations

import json
import math

import pytest

from aircraft_files import entries, write
from mbs import aircraft
from mbs.cli import main

WING = {"area": (1.5, "m^2"), "span": (3.0, "m"), "incidence": (8.5, "deg"), "x": (0.0, "m"), "z": (0.3, "m"),
        "lift_slope": (4.0, "1/rad"), "alpha_stall": (0.26, "rad"), "cd0": (0.01, "-"), "cd_stalled": (1.8, "-")}


def _with_wing(tmp_path, **change):
    raw = entries("bo105")
    raw["wing"] = {k: {"value": v, "unit": u, "source": "test"} for k, (v, u) in {**WING, **change}.items()}
    return write(raw, tmp_path / "winged.toml")


def _trim(capsys, *args) -> dict:
    assert main(["trim", "forward-flight", "--speed", "50", "--json", "--quiet", *args]) == 0
    return json.loads(capsys.readouterr().out.strip().splitlines()[-1])


def test_a_wing_carries_its_closed_form_lift_off_the_rotor(tmp_path, capsys):
    """At 50 m/s the two panels meet the air at the trim's angle (incidence plus the flow's), equal
    on both sides in level flight; the rotor's thrust falls by the wing's lift q S a α within 10 %
    (the rest: the lift's tilt with the attitude, the wing's drag, the retrimmed rotor)."""
    path = _with_wing(tmp_path)
    assert aircraft.check(path).ok
    winged, plain = _trim(capsys, "--aircraft", str(path)), _trim(capsys)
    assert winged["converged"] and plain["converged"]
    alpha = winged["outputs"]["wing1.alpha"]
    assert alpha == pytest.approx(winged["outputs"]["wing2.alpha"], abs=1e-6)
    assert math.radians(8.5) + winged["pitch"] - 0.02 < alpha < math.radians(8.5) + winged["pitch"] + 0.02
    lift = 0.5 * 1.225 * 50.0**2 * 1.5 * 4.0 * alpha
    relief = plain["outputs"]["main_rotor.thrust"] - winged["outputs"]["main_rotor.thrust"]
    assert relief == pytest.approx(lift, rel=0.1), (relief, lift)


def test_a_wing_s_entries_are_checked_like_a_tail_s(tmp_path):
    raw = entries("bo105")
    raw["wing"] = {k: {"value": v, "unit": u, "source": "test"} for k, (v, u) in WING.items() if k != "lift_slope"}
    report = aircraft.check(write(raw, tmp_path / "bad.toml"))
    assert not report.ok and any(p.startswith("wing.lift_slope: missing") for p in report.problems), report.problems
    report = aircraft.check(_with_wing(tmp_path, lift_slope=(6.0, "1/rad")))
    assert any(w.startswith("wing.lift_slope: 6 1/rad reads as a section's") for w in report.warnings), report.warnings
    assert aircraft.load(_with_wing(tmp_path, span=(0.0, "m"))).data["wing"]["span"] == 0.0
