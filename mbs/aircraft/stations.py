"""Positions written as stations, as reports print them: fuselage station (FS, aft), butt line
(BL, to the side of ``conventions.butt_line_positive``) and water line (WL, up), each a length
from the report's datum. With the CG's stations (``aircraft.cg_station``) a position entry
(one whose :attr:`mbs.aircraft.schema.Entry.axis` is set) may be written
``{ station = ..., unit = "in", source = "..." }``; the program turns it into body axes from the
CG (x forward, y starboard, z down):

    x = -(FS - FS_cg),   y = ±(BL - BL_cg),   z = -(WL - WL_cg)

and ``heli aircraft check`` lists each with its stations.
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


def position(axis: str, station, cg: list, butt_line: str) -> float | list:
    """Body-axis position (m) from the CG of ``station`` (m) along ``axis`` ("x", "y", "z" or
    "xyz": then three stations FS, BL, WL); ``cg`` the CG's (FS, BL, WL) in m."""
    if axis == "xyz":
        return [position(a, s, cg, butt_line) for a, s in zip("xyz", station)]
    index, _, sign = AXES[axis]
    side = -1.0 if axis == "y" and butt_line == "port" else 1.0
    return sign * side * (station - cg[index]) + 0.0


def how(axis: str, written, unit: str, cg_written, cg_unit: str, butt_line: str) -> str:
    """What ``heli aircraft check`` says of a converted station."""
    axes = "xyz" if axis == "xyz" else axis
    stations = ", ".join(f"{AXES[a][1]} {w:g}" for a, w in zip(axes, written if axis == "xyz" else [written]))
    cgs = ", ".join(f"{AXES[a][1]} {cg_written[AXES[a][0]]:g}" for a in axes)
    formula = {"x": "-(FS - FS_cg)", "y": f"{'-' if butt_line == 'port' else ''}(BL - BL_cg)", "z": "-(WL - WL_cg)"}
    return (f"from station {stations} {unit} with the CG at {cgs} {cg_unit}: "
            + ", ".join(f"{a} = {formula[a]}" for a in axes))
