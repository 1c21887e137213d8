"""Continuous turbulence after the military specifications: Dryden and von Kármán forms, their
intensities and scale lengths against height (MIL-F-8785C §3.7; MIL-HDBK-1797 Appendix A, the
same forms), as a frozen field sampled where each rotor flies.

**Intensities and scale lengths** (:func:`intensities`, :func:`scale_lengths`; ``h`` the height
above the ground, in ft inside the formulas): at low altitude (h ≤ 1000 ft) ``σ_w = 0.1 W20``
(``W20`` the wind speed at 20 ft: light 15 kt, moderate 30 kt, severe 45 kt),
``σ_u = σ_v = σ_w / (0.177 + 0.000823 h)^0.4``, ``L_w = h``, ``L_u = L_v = h / (0.177 + 0.000823 h)^1.2``
(h not below 10 ft); at and above 2000 ft the three intensities are the probability-of-exceedance
table's at the severity of ``W20`` (light 1e-2, moderate 1e-3, severe 1e-5; linear in ``W20``
between them) and ``L = 1750 ft`` (Dryden) or ``2500 ft`` (von Kármán); between 1000 and 2000 ft
both vary linearly in h.

**Spectra** (one-sided, spatial frequency ``Ω`` rad/m, ``∫ Φ dΩ = σ²``; ``x = L Ω``):

* Dryden: ``Φ_u = σ² (2L/π) / (1 + x²)``, ``Φ_v = Φ_w = σ² (L/π) (1 + 3x²) / (1 + x²)²``;
* von Kármán: ``Φ_u = σ² (2L/π) / (1 + (1.339 x)²)^(5/6)``,
  ``Φ_v = Φ_w = σ² (L/π) (1 + (8/3)(1.339 x)²) / (1 + (1.339 x)²)^(11/6)``.

**The field** (:class:`TurbulenceField`): frozen in the air mass and varying along north (the
direction the scenes fly), each component a sum of :data:`LINES` sinusoids, one per band of
``x = LΩ`` from 0.01 to 100 (four decades, equal in log), at the band's geometric centre with the
band's power (its spectrum's integral, scaled so the lines carry all of σ²: the 1.3 % of a Dryden
spectrum's variance outside the bands, 3.4–4.0 % of a von Kármán's, goes to the bands, whose level
is that much above the specification's, :func:`captured`) and a phase drawn from the run-time
``turbulence_seed``. A point at north ``X`` (m, world)
sees the field at ``ξ = X − W_north t`` (``W_north`` the steady wind, when the scene has one), so the
tail rotor meets what the main rotor met a transport delay before. The field is evaluated at two
stations, the main and the tail rotor's hubs (the aircraft's heading taken as north), and every
other point takes it linearly between them. Stationary from the first step, the same for a
seed on any machine and any worker; a function of the state, time and parameters only.
"""
from __future__ import annotations

import math
from functools import lru_cache

import casadi as ca
import numpy as np

FT = 0.3048  # m
KT = 0.514444  # m/s
FORMS = ("dryden", "von-karman")
LINES = 24  # sinusoids per component
BAND = (1e-2, 1e2)  # range of L Ω covered by the lines
SEVERITY_W20 = (0.0, 15 * KT, 30 * KT, 45 * KT)  # m/s: none, light, moderate, severe
W20_MODERATE = 30 * KT
HEIGHT_FT = (500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0, 55000.0, 65000.0, 75000.0, 80000.0)
EXCEEDANCE_FT_S = {  # σ (ft/s) against h (ft): MIL-HDBK-1797 Fig. 266 (MIL-F-8785C Fig. 7) as tabulated
    "light (1e-2)": (4.2, 3.6, 3.3, 1.6, 0, 0, 0, 0, 0, 0, 0, 0),
    "moderate (1e-3)": (6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0, 0, 0, 0, 0),
    "severe (1e-5)": (11.8, 13.0, 16.0, 15.1, 11.6, 9.7, 8.1, 8.2, 7.9, 4.9, 3.2, 2.1),
}
MEDIUM_HIGH_L_FT = {"dryden": 1750.0, "von-karman": 2500.0}
LOW, HIGH = 1000.0, 2000.0  # ft: the low-altitude model up to LOW, the table from HIGH


def _smbolic(x) -> bool:
    return isinstance(x, (ca.SX, ca.MX, ca.DM))


def _select(cond, a, b):
    return ca.if_else(cond, a, b) if any(_smbolic(v) for v in (cond, a, b)) else (a if cond else b)


def _low_altitude(h_ft, w20):
    """``(σ_u, σ_w, L_u, L_w)`` in ft/s and ft of the low-altitude model (h from 10 ft)."""
    h = ca.fmax(h_ft, 10.0) if _smbolic(h_ft) else max(h_ft, 10.0)
    base = 0.177 + 0.000823 * h
    sigma_w = 0.1 * w20 / FT
    return sigma_w / base**0.4, sigma_w, h / base**1.2, h


@lru_cache(maxsize=None)
def _table() -> ca.Function:
    """σ (ft/s) of the probability-of-exceedance table against (h ft, W20 m/s)."""
    rows = np.vstack([np.zeros(len(HEIGHT_FT)), *[np.array(v) for v in EXCEEDANCE_FT_S.values()]])  # (4, nh)
    return ca.interpolant("exceedance", "linear", [list(HEIGHT_FT), list(SEVERITY_W20)], rows.ravel(order="C"))


def _medium_high(h_ft, w20):
    return _table()(ca.vertcat(ca.fmin(ca.fmax(h_ft, HEIGHT_FT[0]), HEIGHT_FT[-1]),
                               ca.fmin(ca.fmax(w20, 0.0), SEVERITY_W20[-1])))


def intensities(height, w20):
    """``(σ_u, σ_v, σ_w)`` (m/s) at ``height`` (m above the ground) for the wind at 20 ft ``w20`` (m/s)."""
    h = height / FT
    su, sw, _, _ = _low_altitude(h, w20)
    s2000 = _medium_high(ca.DM(HIGH) if not _smbolic(h) else HIGH, w20)
    su1000, sw1000, _, _ = _low_altitude(LOW, w20)
    mix = ca.fmin(ca.fmax((h - LOW) / (HIGH - LOW), 0), 1) if _smbolic(h) else min(max((h - LOW) / (HIGH - LOW), 0), 1)
    high = _medium_high(h, w20)
    u = _select(h <= LOW, su, _select(h >= HIGH, high, su1000 + mix * (s2000 - su1000)))
    w = _select(h <= LOW, sw, _select(h >= HIGH, high, sw1000 + mix * (s2000 - sw1000)))
    out = tuple(FT * c for c in (u, u, w))
    return out if _smbolic(height) or _smbolic(w20) else tuple(float(c) for c in out)


def scale_lengths(height, form: str = "dryden"):
    """``(L_u, L_v, L_w)`` (m) at ``height`` (m above the ground) for the spectral ``form``."""
    _check_form(form)
    h = height / FT
    _, _, lu, lw = _low_altitude(h, 0.0)
    _, _, lu1000, lw1000 = _low_altitude(LOW, 0.0)
    big = MEDIUM_HIGH_L_FT[form]
    mix = ca.fmin(ca.fmax((h - LOW) / (HIGH - LOW), 0), 1) if _smbolic(h) else min(max((h - LOW) / (HIGH - LOW), 0), 1)
    u = _select(h <= LOW, lu, _select(h >= HIGH, big, lu1000 + mix * (big - lu1000)))
    w = _select(h <= LOW, lw, _select(h >= HIGH, big, lw1000 + mix * (big - lw1000)))
    return tuple(FT * c for c in (u, u, w))


def _check_form(form: str) -> None:
    if form not in FORMS:
        raise ValueError(f"turbulence form {form!r}: choose one of {', '.join(FORMS)}")


def spectrum(form: str, component: str, x):
    """The spectrum's shape ``Φ / (σ² L)`` at ``x = L Ω`` (``∫ shape dx = 1``); ``component`` u, v or w."""
    _check_form(form)
    x = np.asarray(x, dtype=float)
    if form == "dryden":
        return 2 / np.pi / (1 + x**2) if component == "u" else (1 + 3 * x**2) / (1 + x**2) ** 2 / np.pi
    y = (1.339 * x) ** 2
    return 2 / np.pi / (1 + y) ** (5 / 6) if component == "u" else (1 + 8 / 3 * y) / (1 + y) ** (11 / 6) / np.pi


@lru_cache(maxsize=None)
def band_powers(form: str, component: str) -> tuple[np.ndarray, np.ndarray]:
    """``(edges, power)``: the bands of ``LΩ`` and each band's share of σ² in the spectrum."""
    from scipy.integrate import quad

    edges = np.geomspace(*BAND, LINES + 1)
    return edges, np.array([quad(lambda x: float(spectrum(form, component, x)), a, b, limit=200)[0]
                            for a, b in zip(edges[:-1], edges[1:])])


def captured(form: str, component: str) -> float:
    """The share of σ² the specification's spectrum has inside :data:`BAND`."""
    return float(band_powers(form, component)[1].sum())


@lru_cache(maxsize=None)
def lines(form: str, component: str) -> tuple[np.ndarray, np.ndarray]:
    """``(x_k, a_k)``: the lines' ``LΩ`` (the bands' geometric centres) and amplitudes per σ,
    ``Σ a_k² / 2 = 1`` (each band's power, scaled by 1/:func:`captured`)."""
    edges, power = band_powers(form, component)
    return np.sqrt(edges[:-1] * edges[1:]), np.sqrt(2 * power / power.sum())


@lru_cache(maxsize=None)
def _phase_constants() -> np.ndarray:
    """(3, LINES, 2): per component and line the seed's multiplier and an offset, fixed for ever."""
    rng = np.random.default_rng(20240611)
    return np.stack([rng.uniform(100.0, 1000.0, (3, LINES)), rng.uniform(0.0, 1.0, (3, LINES))], axis=-1)


def phases(seed):
    """(3, LINES) phases (rad) of a ``seed`` (a whole number; SX or a number):
    ``2π frac(seed a_k + b_k)``."""
    c = _phase_constants()
    frac = (lambda y: y - ca.floor(y)) if _smbolic(seed) else (lambda y: y - np.floor(y))
    return [[2 * math.pi * frac(seed * c[i, k, 0] + c[i, k, 1]) for k in range(LINES)] for i in range(3)]


def field(form: str, xi, sigma, length, phase) -> list:
    """The field's (u, v, w) (m/s) at the air-mass coordinate ``xi`` (m): ``sigma``, ``length``
    (3,) the components' intensities (m/s) and scale lengths (m), ``phase`` from :func:`phases`."""
    cos = ca.cos if any(_smbolic(v) for v in (xi, *sigma, *length)) else np.cos
    out = []
    for i, comp in enumerate("uvw"):
        x, a = lines(form, comp)
        s = xi / length[i]
        out.append(sigma[i] * sum(a[k] * cos(x[k] * s + phase[i][k]) for k in range(LINES)))
    return out


class TurbulenceField:
    """The turbulence of a scene as one of its air's motions (:class:`mbs.environment.Air`):
    ``form`` (:data:`FORMS`), the stations' body x (m: main and tail rotor hubs), the body whose
    origin carries them, and whether the scene has a steady wind (its ``wind_north`` moves the
    air mass). Run-time parameters ``turbulence_intensity`` (W20, m/s), ``turbulence_seed``, and
    the scene's ``height`` (m, of the start above the ground)."""

    def __init__(self, form: str, stations: tuple[float, float], body: str = "fuselage", wind: bool = False,
                 intensity: float = W20_MODERATE, seed: int = 1):
        _check_form(form)
        self.form, self.stations, self.body, self.wind = form, stations, body, wind
        self.intensity, self.seed = intensity, seed

    def add_parameters(self, model) -> None:
        model.add_parameter("turbulence_intensity", self.intensity, "m/s", "turbulence intensity: the wind speed at "
                            "20 ft of MIL-F-8785C (light 7.7, moderate 15.4, severe 23.2 m/s; 0: none)", low=0.0,
                            high=SEVERITY_W20[-1])
        model.add_parameter("turbulence_seed", self.seed, "1", "seed of the turbulence's phases (a whole number)",
                            low=0.0, high=2.0**31)

    def _xi(self, state, north):
        drift = state.p["wind_north"] * state.t if self.wind else 0
        return north - drift

    def _stations(self, state):
        """Per station (main, tail) its ξ (m) and the field (u, v, w) there; once per state."""
        key = "air.turbulence"
        if key not in state.signals:
            origin = state.body(self.body).position[0]
            p = state.p
            sigma = intensities(p["height"], p["turbulence_intensity"])
            length = scale_lengths(p["height"], self.form)
            phase = phases(ca.floor(p["turbulence_seed"]))
            values = []
            for x in self.stations:
                xi = self._xi(state, origin + x)
                values.append((xi, field(self.form, xi, sigma, length, phase)))
            state.signals[key] = values
        return state.signals[key]

    def velocity(self, state, position):
        """The turbulence's velocity (3,) (m/s, world: north, east, down) at ``position`` (m, world)."""
        (xi_1, f1), (xi_2, f2) = self._stations(state)
        share = (self._xi(state, position[0]) - xi_1) / (xi_2 - xi_1)
        return ca.vertcat(*[a + share * (b - a) for a, b in zip(f1, f2)])

    def at_station(self, state, k: int):
        """The field (3,) (m/s) at station ``k`` (0 main, 1 tail)."""
        return ca.vertcat(*self._stations(state)[k][1])
