"""A tail surface's lift-curve slope is the whole surface's (3-D); a section's (2-D) slope goes in with
the surface's aspect ratio and is converted by Helmbold's formula, and one given without it is warned of."""
import math

import pytest

from aircraft_files import entries, write
from mbs import aircraft
from mbs.aircraft.reader import surface_slope


def test_helmbold_meets_lifting_line_at_large_and_slender_wing_at_small_aspect_ratio():
    a = 2 * math.pi
    assert surface_slope(a, 1e4) == pytest.approx(a / (1 + a / (math.pi * 1e4)), rel=1e-7)
    assert surface_slope(a, 1e-3) == pytest.approx(math.pi * 1e-3 / 2, rel=1e-3)
    assert surface_slope(6.0, 1.8) == pytest.approx(2.3819, abs=1e-4)


def test_a_section_slope_with_the_aspect_ratio_is_converted_and_listed(tmp_path):
    """A fin printed with a = 6 /rad and aspect ratio 1.8 (a new user's Prouty helicopter: taken as
    the surface's, 2.5 times too effective, without a word)."""
    raw = entries("bo105")
    raw["vertical_fin"]["lift_slope"] = {"value": 6.0, "unit": "1/rad", "source": "report", "note": "section"}
    alone = aircraft.check(write(raw, tmp_path / "alone.toml"))
    assert alone.ok and any(w.startswith("vertical_fin.lift_slope: 6 1/rad reads as a section's (2-D) slope")
                            for w in alone.warnings), alone.warnings
    raw["vertical_fin"]["aspect_ratio"] = {"value": 1.8, "unit": "-", "source": "report"}
    path = write(raw, tmp_path / "converted.toml")
    assert aircraft.load(path).data["vertical_fin"]["lift_slope"] == pytest.approx(surface_slope(6.0, 1.8), rel=1e-12)
    report = aircraft.check(path)
    assert not [w for w in report.warnings if "lift_slope" in w]
    (how,) = [r[3] for r in report.converted if r[0] == "vertical_fin.lift_slope"]
    assert how.startswith("the surface's from the section's 6 1/rad and vertical_fin.aspect_ratio 1.8 (Helmbold")


def test_the_shipped_surfaces_are_given_as_surfaces():
    for name in ("bo105", "puma", "lynx"):
        assert not [w for w in aircraft.check(name).warnings if "lift_slope" in w], name
