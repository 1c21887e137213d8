"""A cambered section's zero-lift angle as reports print it (``zero_lift_angle``, on the rotors'
and the tail surfaces' analytic sections): ``c_L = a (α − α_0)``, the drag polar and the stall
guard about the zero-lift line. For a tail surface that is its incidence turned by −α_0; for a
rotor, its collective turned by α_0."""
import json
import math

import numpy as np
import pytest

from mbs import aircraft
from mbs.aero.sections import Airfoil, ZeroLiftShift
from mbs.cli import main


def test_the_section_is_the_symmetric_one_about_its_zero_lift_line():
    section = Airfoil(5.7, 0.009, 0.3, 0.25, 1.8, -0.01)
    shifted = ZeroLiftShift(section, math.radians(-2.0))
    for alpha in np.random.default_rng(3).uniform(-1.5, 1.5, 40):
        want = [float(c) for c in section.coefficients(alpha + math.radians(2.0))]
        assert [float(c) for c in shifted.coefficients(alpha)] == pytest.approx(want, rel=1e-15, abs=1e-15)
        assert [float(c) for c in shifted.coefficients_of(alpha, np.sin(alpha) ** 2)] == pytest.approx(
            want, rel=1e-15, abs=1e-15)


def _file(tmp_path, name: str, section: str, line: str | None = None, old: str | None = None,
          new: str | None = None) -> str:
    head, sep, rest = aircraft.resolve("bo105").read_text().partition(f"[{section}]\n")
    if old is not None:
        assert old in rest
        rest = rest.replace(old, new, 1)
    path = tmp_path / name
    path.write_text(head + sep + (line + "\n" if line else "") + rest)
    return str(path)


def _trim(capsys, path: str | None, speed: float = 30.0) -> dict:
    assert main(["trim", "forward-flight", "--speed", str(speed), "--json", "--quiet"]
                + (["--aircraft", path] if path else [])) == 0
    return json.loads(capsys.readouterr().out)


def test_a_tail_zero_lift_angle_is_its_incidence_turned_and_a_rotors_its_collective(tmp_path, capsys):
    """The Bo105 at 30 m/s: its horizontal tail with zero_lift_angle -3 deg trims as with its
    incidence 3 deg larger, to 1e-12 rad (measured 3e-15); its main rotor's blades with -0.02 rad
    trim 0.02 rad less collective, to 1e-6 rad (measured 1.2e-7; the blades' own pitch inertia
    differs), the other controls and the attitude within 1e-5 rad (measured 1.6e-6)."""
    incidence = 'incidence = { value = 0.0698, unit = "rad", source = "S1a", note = "S2 says 0: conflict" }'
    zero = _trim(capsys, _file(tmp_path, "zl.toml", "horizontal_tail",
                               'zero_lift_angle = { value = -3.0, unit = "deg", source = "test" }'))
    turned = _trim(capsys, _file(tmp_path, "inc.toml", "horizontal_tail", old=incidence,
                                 new=f'incidence = {{ value = {0.0698 + math.radians(3.0)!r}, unit = "rad", '
                                     'source = "test" }'))
    for key in zero["controls"]:
        assert zero["controls"][key] == pytest.approx(turned["controls"][key], abs=1e-12)
    assert zero["pitch"] == pytest.approx(turned["pitch"], abs=1e-12)
    blades = _trim(capsys, _file(tmp_path, "blades.toml", "main_rotor",
                                 'zero_lift_angle = { value = -0.02, unit = "rad", source = "test" }'))
    plain = _trim(capsys, None)
    assert blades["controls"]["collective"] - plain["controls"]["collective"] == pytest.approx(-0.02, abs=1e-6)
    for key in ("lateral_cyclic", "longitudinal_cyclic", "tail_collective"):
        assert blades["controls"][key] == pytest.approx(plain["controls"][key], abs=1e-5)
    assert blades["pitch"] == pytest.approx(plain["pitch"], abs=1e-5)


def test_a_zero_lift_angle_beside_a_coefficient_table_is_refused(tmp_path):
    rows = "[[-0.3, -1.0, 0.05], [0.0, 0.0, 0.01], [0.3, 1.0, 0.05]]"
    path = _file(tmp_path, "both.toml", "horizontal_tail",
                 f'coefficient_table = {{ value = {rows}, unit = "rad, -, -", source = "test" }}\n'
                 'zero_lift_angle = { value = -3.0, unit = "deg", source = "test" }')
    problems = aircraft.check(path).problems
    assert any("replaces horizontal_tail.zero_lift_angle; leave zero_lift_angle out" in p for p in problems), problems
