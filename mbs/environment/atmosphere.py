"""The International Standard Atmosphere (ISO 2533, ICAO Doc 7488): troposphere and lower
stratosphere, with a temperature offset.

Altitude ``h`` (m) is geopotential pressure altitude: the ISA pressure ``p(h)`` holds whatever the
temperature, and the air is ``ΔT`` (K) warmer than the ISA's at that pressure ("ISA + 20" is
``ΔT = 20``). Up to the tropopause at 11 000 m the temperature falls at 6.5 K/km,
``T = T0 − 0.0065 h``, ``p = p0 (T_ISA/T0)^(g0/(R L))``; above it, to 20 000 m, the temperature is
216.65 K and ``p = p11 exp(−g0 (h − 11000)/(R T11))``. Density ``ρ = p / (R (T_ISA + ΔT))``, speed
of sound ``a = sqrt(γ R T)``, dynamic viscosity by Sutherland's law
``μ = 1.458e-6 T^1.5 / (T + 110.4)``. Every function takes numbers or CasADi symbols (a model's
altitude parameter).

Sea level: ρ0 = 1.2249991 kg/m³ and a0 = 340.294 m/s from these constants; the aircraft files'
``[environment]`` give the rounded 1.225 and 340.3, so a scene keeps the file's values unless
it asks for the ISA (:class:`mbs.environment.air.Air`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca

T0 = 288.15  # K, sea-level temperature
P0 = 101325.0  # Pa, sea-level pressure
R = 287.05287  # J/(kg K), specific gas constant of dry air
GAMMA = 1.4  # ratio of specific heats
G0 = 9.80665  # m/s², standard gravity
LAPSE = 0.0065  # K/m, temperature lapse rate of the troposphere
TROPOPAUSE = 11000.0  # m
T11 = T0 - LAPSE * TROPOPAUSE  # 216.65 K
P11 = P0 * (T11 / T0) ** (G0 / (R * LAPSE))  # Pa at the tropopause
ALTITUDE_RANGE = (-1000.0, 20000.0)
"""m: the altitudes these formulas cover (the troposphere, a little below sea level, and the
isothermal layer to 20 km); the ISA's next layer is not modelled."""
OFFSET_RANGE = (-60.0, 60.0)
"""K: temperature offsets accepted (ISA − 60 to ISA + 60)."""


def _symbolic(x) -> bool:
    return isinstance(x, (ca.SX, ca.MX, ca.DM))


def _exp(x):
    return ca.exp(x) if _symbolic(x) else math.exp(x)


def _sqrt(x):
    return ca.sqrt(x) if _symbolic(x) else math.sqrt(x)


def check(altitude: float, offset: float = 0.0) -> None:
    """ValueError naming the value when ``altitude`` (m) or ``offset`` (K) is outside the ranges."""
    low, high = ALTITUDE_RANGE
    if not (math.isfinite(altitude) and low <= altitude <= high):
        raise ValueError(f"altitude {altitude:g} m is outside the ISA's range modelled here, [{low:g}, {high:g}] m "
                         "(troposphere and the isothermal layer above it)")
    low, high = OFFSET_RANGE
    if not (math.isfinite(offset) and low <= offset <= high):
        raise ValueError(f"temperature offset {offset:g} K is outside [{low:g}, {high:g}] K")


def standard_temperature(h):
    """ISA temperature (K) at the pressure altitude ``h`` (m)."""
    if _symbolic(h):
        return ca.if_else(h < TROPOPAUSE, T0 - LAPSE * h, T11)
    return T0 - LAPSE * h if h < TROPOPAUSE else T11


def pressure(h):
    """Static pressure (Pa) at the pressure altitude ``h`` (m)."""
    below = P0 * (1 - LAPSE * h / T0) ** (G0 / (R * LAPSE))
    above = P11 * _exp(-G0 * (h - TROPOPAUSE) / (R * T11))
    if _symbolic(h):
        return ca.if_else(h < TROPOPAUSE, below, above)
    return below if h < TROPOPAUSE else above


def temperature(h, offset=0.0):
    """Air temperature (K): the ISA's at ``h`` (m) plus ``offset`` (K)."""
    return standard_temperature(h) + offset


def density(h, offset=0.0):
    """Air density (kg/m³) at pressure altitude ``h`` (m), ``offset`` (K) off the ISA."""
    return pressure(h) / (R * temperature(h, offset))


def density_altitude(rho: float) -> float:
    """The pressure altitude (m) at which the standard day has the density ``rho`` (kg/m³),
    clipped to :data:`ALTITUDE_RANGE`."""
    from scipy.optimize import brentq

    low, high = ALTITUDE_RANGE
    rho = min(max(rho, density(high)), density(low))
    return float(brentq(lambda h: density(h) - rho, low, high, xtol=1e-6))


def speed_of_sound(h, offset=0.0):
    """Speed of sound (m/s), ``sqrt(γ R T)``."""
    return _sqrt(GAMMA * R * temperature(h, offset))


def viscosity(h, offset=0.0):
    """Dynamic viscosity (Pa s), Sutherland's law."""
    t = temperature(h, offset)
    return 1.458e-6 * t * _sqrt(t) / (t + 110.4)


@dataclass(frozen=True)
class Conditions:
    """The air at one altitude (m) and offset (K): density kg/m³, pressure Pa, temperature K,
    speed of sound m/s, viscosity Pa s, density ratio ``σ = ρ/ρ0``."""

    altitude: float
    offset: float
    density: float
    pressure: float
    temperature: float
    speed_of_sound: float
    viscosity: float

    @property
    def density_ratio(self) -> float:
        return self.density / density(0.0)


def conditions(altitude: float, offset: float = 0.0) -> Conditions:
    """The ISA at ``altitude`` (m) and ``offset`` (K), checked (:func:`check`)."""
    check(altitude, offset)
    return Conditions(altitude, offset, density(altitude, offset), pressure(altitude), temperature(altitude, offset),
                      speed_of_sound(altitude, offset), viscosity(altitude, offset))
