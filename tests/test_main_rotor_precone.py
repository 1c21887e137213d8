"""The main rotor's precone as reports print it: the rest angle of the blades' flap spring (a
hingeless or bearingless rotor's built-in coning)."""
import json
import math

import pytest

from mbs import aircraft
from mbs.aircraft import derived
from mbs.cli import main
from test_cli_errors import run_main


def _precone(tmp_path, degrees: float, spring: bool = True) -> str:
    head, sep, rest = aircraft.resolve("bo105").read_text().partition("[main_rotor]\n")
    if not spring:
        old = next(x for x in rest.splitlines() if x.startswith("flap_stiffness = "))
        rest = rest.replace(old, 'flap_stiffness = { value = 0.0, unit = "N m/rad", source = "test" }', 1)
    path = tmp_path / f"precone_{degrees}_{spring}.toml"
    path.write_text(head + sep + f'precone = {{ value = {degrees}, unit = "deg", source = "test" }}\n' + rest)
    return str(path)


def test_a_precone_cones_a_hingeless_rotor_by_its_springs_share(tmp_path, capsys):
    """The Bo105 (equivalent hinge at the axis, spring K) in hover with 2.5 deg of precone: the
    coning rises by K β_pc / (I Ω² ν²), the spring's share of the flap equation, within 2 %
    (measured 0.4 %: the blade's aerodynamics move a little with it); the controls within
    2e-4 rad."""
    runs = {}
    for name, path in (("precone", _precone(tmp_path, 2.5)), ("plain", None)):
        assert main(["trim", "hover", "--speed", "0", "--json", "--quiet"] + (["--aircraft", path] if path else [])) == 0
        runs[name] = json.loads(capsys.readouterr().out)
    mr = aircraft.load("bo105").data["main_rotor"]
    closed = mr["flap_stiffness"] * math.radians(2.5) / (mr["I_flap"] * mr["omega"] ** 2
                                                          * derived.flap_frequency(mr) ** 2)
    rise = runs["precone"]["flapping"]["beta0"] - runs["plain"]["flapping"]["beta0"]
    assert rise == pytest.approx(closed, rel=0.02)
    for key, value in runs["plain"]["controls"].items():
        assert runs["precone"]["controls"][key] == pytest.approx(value, abs=2e-4)


def test_a_precone_without_a_spring_is_warned_and_the_elastic_blade_refuses_it(tmp_path, capsys):
    report = aircraft.check(_precone(tmp_path, 2.75, spring=False))
    assert report.ok and any(w.startswith("main_rotor.precone: 2.75 deg without a flap spring does nothing")
                             for w in report.warnings), report.warnings
    code, err = run_main(["simulate", "elastic-rotor-modal", "--aircraft", _precone(tmp_path, 2.5), "--revs", "0.1",
                          "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and "main_rotor.precone: the modal blade is a straight beam" in err, err
