"""Positions written as stations, as reports print them: fuselage station (FS, aft unless
``conventions.fuselage_station_positive`` = "forward"), butt line (BL, to the side of
``conventions.butt_line_positive``) and water line (WL, up unless
``conventions.water_line_positive`` = "down"), each a length from the report's datum. With the
CG's stations (``aircraft.cg_station``) a position entry (one whose
:attr:`mbs.aircraft.schema.Entry.axis` is set) may be written
``{ station = ..., unit = "in", source = "..." }``; the program turns it into body axes from the
CG (x forward, y starboard, z down):

    x = -(FS - FS_cg),   y = ±(BL - BL_cg),   z = -(WL - WL_cg)

(each sign turned where the file's stations count the other way) and ``heli aircraft check``
lists each with its stations.
"""
from __future__ import annotations

from dataclasses import dataclass

AXES = {"x": (0, "FS", -1.0), "y": (1, "BL", 1.0), "z": (2, "WL", -1.0)}
"""Body axis -> (index in a station triple, its name, sign of the station difference)."""


@dataclass(frozen=True)
class Given:
    """A position entry given as stations: ``station`` in metres (a number, or three for an
    ``xyz`` entry), its entry's ``axis``, and the meta the reader keeps."""

    section: str
    key: str
    axis: str
    station: float | list
    meta: dict


POSITIVE = {"x": ("fuselage_station_positive", "aft"), "y": ("butt_line_positive", "starboard"),
            "z": ("water_line_positive", "up")}
"""Body axis -> the convention that sets which way its stations count, and its usual value."""


def signs(conventions: dict) -> dict[str, float]:
    """Sign of ``station - station_cg`` in each body axis for the file's ``[conventions]``."""
    return {a: AXES[a][2] * (1.0 if conventions.get(key, usual) == usual else -1.0)
            for a, (key, usual) in POSITIVE.items()}


def position(axis: str, station, cg: list, conventions: dict) -> float | list:
    """Body-axis position (m) from the CG of ``station`` (m) along ``axis`` ("x", "y", "z" or
    "xyz": then three stations FS, BL, WL); ``cg`` the CG's (FS, BL, WL) in m; ``conventions``
    the file's (which way its stations count)."""
    if axis == "xyz":
        return [position(a, s, cg, conventions) for a, s in zip("xyz", station)]
    return signs(conventions)[axis] * (station - cg[AXES[axis][0]]) + 0.0


def how(axis: str, written, unit: str, cg_written, cg_unit: str, conventions: dict) -> str:
    """What ``heli aircraft check`` says of a converted station."""
    axes = "xyz" if axis == "xyz" else axis
    stations = ", ".join(f"{AXES[a][1]} {w:g}" for a, w in zip(axes, written if axis == "xyz" else [written]))
    cgs = ", ".join(f"{AXES[a][1]} {cg_written[AXES[a][0]]:g}" for a in axes)
    sign = signs(conventions)
    formula = {a: f"{'-' if sign[a] < 0 else ''}({AXES[a][1]} - {AXES[a][1]}_cg)" for a in "xyz"}
    return (f"from station {stations} {unit} with the CG at {cgs} {cg_unit}: "
            + ", ".join(f"{a} = {formula[a]}" for a in axes))
