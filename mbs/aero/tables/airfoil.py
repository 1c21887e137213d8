"""Airfoils from tables: lift, drag and pitching-moment coefficients against angle of attack
(-180..180 deg) and Mach number, one airfoil per radial segment of a blade.

Section axes as in :mod:`mbs.aero.sections`: ``c`` along the chord towards the leading edge,
``n`` the lift direction at zero incidence. The angle of attack is the full-circle angle of the
air velocity, ``alpha = atan2(w_n, -w_c)`` (+-pi when the air meets the trailing edge head on),
which the table covers whole: reverse flow is the table's, not a folded angle. Units: SI, rad.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np

from mbs.aero.sections import EPS
from mbs.aero.tables.c81 import C81, COEFFICIENTS
from mbs.aero.tables.interpolant import HermiteTable, TableSpline


@dataclass(frozen=True, eq=False)
class TableAirfoil:
    """One airfoil's tables as one smooth interpolant (:class:`TableSpline`) of ``[alpha, Mach]``
    with the outputs ``(c_L, c_D, c_M)``; ``c_M`` about the quarter chord, positive nose up."""

    name: str
    spline: TableSpline

    @classmethod
    def from_c81(cls, c81: C81, name: str | None = None) -> TableAirfoil:
        tables = [HermiteTable(f"{c81.path.name} {c}", *_columns(c81.table(c))) for c in COEFFICIENTS]
        label = name or _identifier(c81.path.stem)
        return cls(c81.name or c81.path.stem, TableSpline(f"airfoil_{label}", tables))

    def coefficients(self, alpha, mach) -> tuple:
        """``(c_L, c_D, c_M)`` at ``alpha`` (rad, within +-pi) and Mach number ``mach``."""
        out = self.spline(alpha, mach)
        return out[0], out[1], out[2]


def _columns(table) -> tuple:
    return table.alpha, table.mach, table.values


def _identifier(text: str) -> str:
    """``text`` as a CasADi function name's part: letters, digits, single underscores."""
    words = "".join(ch if ch.isalnum() and ch.isascii() else " " for ch in text).split()
    return "_".join(words).lower() or "table"


@dataclass(frozen=True)
class BladeAirfoils:
    """The airfoil of each radial segment: ``starts`` (r/R where each segment begins,
    increasing), ``airfoils`` one per segment (the last reaches the tip); the section Mach
    number is the air speed over ``speed_of_sound`` (m/s) when ``mach_effects``, else the tables'
    lowest Mach number (the incompressible section)."""

    starts: tuple
    airfoils: tuple
    speed_of_sound: float
    mach_effects: bool = True

    def at(self, r_over_radius: float) -> TableAirfoil:
        """The airfoil of the segment holding the station ``r_over_radius``."""
        k = int(np.searchsorted(np.asarray(self.starts), r_over_radius, side="right")) - 1
        if k < 0:
            raise ValueError(f"station r/R = {r_over_radius:.4g} lies inboard of the first airfoil segment, which "
                             f"starts at r/R = {self.starts[0]:.4g}")
        return self.airfoils[k]

    def mach(self, speed):
        """Section Mach number of the air speed ``speed`` (m/s); 0 (the lowest tabulated) without
        Mach effects."""
        return speed * (1.0 / self.speed_of_sound) if self.mach_effects else 0.0


def table_section_loads(w_c, w_n, airfoil: TableAirfoil, mach_of, rho: float, area: float, chord: float,
                        lift_factor: float = 1.0):
    """Force (N) and pitching moment (N m, nose up) on a section from the air velocity relative to
    it, in section axes (:func:`mbs.aero.sections.section_force`'s ``w_c``, ``w_n``, ``area``,
    ``lift_factor``); ``mach_of(speed)`` the section Mach number. Returns ``(f_c, f_n, m)``."""
    alpha = ca.atan2(w_n, EPS - w_c)
    speed = ca.sqrt(w_c**2 + w_n**2 + EPS**2)
    cl, cd, cm = airfoil.coefficients(alpha, mach_of(speed))
    if lift_factor != 1.0:
        cl = lift_factor * cl
    k = 0.5 * rho * area * speed
    return k * (cl * w_n + cd * w_c), k * (-cl * w_c + cd * w_n), k * speed * chord * cm


@dataclass(frozen=True, eq=False)
class AirfoilSegment:
    """A radial segment of a blade from ``start`` (r/R) to the next segment's: the C81 file as
    written in the aircraft file (``name``), its tables (``c81``), its interpolant (``airfoil``)
    and the SHA-256 of the file (``digest``)."""

    start: float
    name: str
    c81: C81
    airfoil: TableAirfoil
    digest: str

    @classmethod
    def read(cls, start: float, path: Path, name: str) -> AirfoilSegment:
        """The segment from ``start`` with the C81 file ``path``; ValueError naming the problem."""
        from mbs.aero.tables.c81 import read_c81

        c81 = read_c81(path)
        return cls(start, name, c81, TableAirfoil.from_c81(c81), file_digest(path))

    def describe(self) -> str:
        t = [self.c81.table(c) for c in COEFFICIENTS]
        sizes = ", ".join(f"{c} {len(x.alpha)} x {len(x.mach)}" for c, x in zip(COEFFICIENTS, t))
        machs = f"Mach {min(x.mach[0] for x in t):g}..{max(x.mach[-1] for x in t):g}"
        return f"{self.c81.name or '(no name)'} from {self.name} ({sizes} angles x Mach numbers, {machs})"


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    import hashlib

    return hashlib.sha256(Path(path).read_bytes()).hexdigest()
