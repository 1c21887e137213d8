"""Flight modes of a 6-DOF linear model: eigenvalues of ``A`` named from participation factors.

States in Padfield's 8-state order ``(u, w, q, θ, v, p, φ, r)``. The participation factor of
state ``k`` in mode ``i`` is ``|l_ik r_ki|`` (left and right eigenvectors, ``L = R⁻¹``): it does
not depend on the units of the states. A mode is longitudinal when ``u, w, q, θ`` hold most of
it, lateral otherwise, and is named as in Padfield (Helicopter Flight Dynamics, ch. 4):

* longitudinal: oscillatory with ``w, q`` dominant "short period", with ``u, θ`` dominant
  "phugoid"; real: "heave subsidence" (``w``), "pitch subsidence" (``q, θ``), "speed
  subsidence" (``u``), "divergence" instead of "subsidence" when the eigenvalue is positive;
* lateral: oscillatory "Dutch roll" (with a quarter or more in ``r``), else "lateral
  phugoid" (the sway-roll oscillation of the hover); real: "roll subsidence" (``p``), "yaw
  subsidence" (``r``), "spiral" (``φ, v``). Of two or more lateral oscillations (a light,
  strongly coupled aircraft has them) the Dutch roll is the one with the largest sideslip and
  yaw share (``v + r``); another is the lateral phugoid when ``r`` holds less than a quarter of
  it, else named after its two largest axes ("yaw-pitch oscillation").

A complex pair damped at 90 % of critical or more (coupled subsidences, e.g. roll and pitch
through the rotor's cross-coupling in hover) is named as a real mode after the axis with the
largest share of either group, joined by the next axis when that holds at least half as much
("roll-pitch subsidence"). Of two real modes of one name (a small helicopter's hover has two
led by yaw: the heave couples to it through the torque), the one with the larger share of that
axis keeps the name (of two spirals, the one with more roll angle and sideslip), the other is named
after its two largest axes ("yaw-heave subsidence").
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STATES = ("u", "w", "q", "theta", "v", "p", "phi", "r")
LONGITUDINAL = ("u", "w", "q", "theta")
AXES = {"heave": ("w",), "pitch": ("q", "theta"), "speed": ("u",), "roll": ("p",), "yaw": ("r",)}
"""The states of each axis a mode is named after."""
OVERDAMPED = 0.9  # damping ratio from which a complex pair is named as a subsidence
NEUTRAL = 1e-6  # 1/s: an eigenvalue this small is a neutral root (the heading's), its damping ratio undefined


def damping_ratio(lam: complex) -> float:
    """``-Re λ / |λ|``; NaN for a neutral root (``|λ| < NEUTRAL``), whose sign is round-off."""
    return float(-lam.real / abs(lam)) if abs(lam) >= NEUTRAL else float("nan")


def zeta_text(zeta: float) -> str:
    """A damping ratio for a table, 7 characters; "neutral" for an undefined one."""
    return "neutral" if np.isnan(zeta) else f"{zeta:+7.3f}"


@dataclass
class FlightMode:
    """One eigenvalue ``λ`` (1/s) of ``A`` (one per conjugate pair, ``Im λ >= 0``) and the
    share of each state in it (sums to 1)."""

    eigenvalue: complex
    participation: dict[str, float]
    name: str

    @property
    def damping_ratio(self) -> float:
        return damping_ratio(self.eigenvalue)

    @property
    def period_s(self) -> float | None:
        """Period of the oscillation (s); ``None`` for a real eigenvalue."""
        return 2 * np.pi / self.eigenvalue.imag if self.eigenvalue.imag > 0 else None

    @property
    def time_to_half_s(self) -> float:
        """Time to half (positive) or to double (negative) amplitude, s."""
        return float(np.log(2) / -self.eigenvalue.real) if self.eigenvalue.real else np.inf

    def summary(self) -> dict:
        return {"name": self.name, "eigenvalue": [self.eigenvalue.real, self.eigenvalue.imag],
                "damping_ratio": None if np.isnan(self.damping_ratio) else self.damping_ratio,
                "period_s": self.period_s,
                "time_to_half_s": self.time_to_half_s, "participation": self.participation}


def participation(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (n,) of ``a`` (n, n) and participation factors (n states, n modes), each
    column summing to 1."""
    lam, right = np.linalg.eig(a)
    left = np.linalg.inv(right)
    p = np.abs(left.T * right)
    return lam, p / p.sum(axis=0)


def mode_name(lam: complex, share: dict[str, float]) -> str:
    """Padfield's name of the mode ``lam`` with state shares ``share``."""
    group = lambda *keys: sum(share[k] for k in keys)  # noqa: E731
    oscillatory = abs(lam.imag) > 1e-9 * max(abs(lam), 1e-300)
    if oscillatory and -lam.real >= OVERDAMPED * abs(lam):
        return f"{_axes(share)} {'divergence' if lam.real > 0 else 'subsidence'}"
    if group(*LONGITUDINAL) >= 0.5:
        if oscillatory:
            return "short period" if group("w", "q") > group("u", "theta") else "phugoid"
        return _real(lam, {"heave": share["w"], "pitch": group("q", "theta"), "speed": share["u"]})
    if oscillatory:
        return "Dutch roll" if share["r"] >= 0.25 else "lateral phugoid"
    if group("phi", "v") > max(share["p"], share["r"]):
        return "spiral"
    return _real(lam, {"roll": share["p"], "yaw": share["r"]})


def _axes(share: dict[str, float], joined: bool = False) -> str:
    """The axis with the largest share, joined by the next when that holds at least half as much
    (always with ``joined``)."""
    weights = {axis: sum(share[k] for k in keys) for axis, keys in AXES.items()}
    first, second = sorted(weights, key=weights.get, reverse=True)[:2]
    return f"{first}-{second}" if joined or weights[second] >= 0.5 * weights[first] else first


def _one_dutch_roll(modes: list[FlightMode]) -> None:
    """Name one Dutch roll among two or more lateral oscillations (module docstring)."""
    lateral = [m for m in modes if m.name in ("Dutch roll", "lateral phugoid")]
    if len(lateral) < 2:
        return
    dutch = max(lateral, key=lambda m: m.participation["v"] + m.participation["r"])
    for m in lateral:
        m.name = "Dutch roll" if m is dutch else (
            "lateral phugoid" if m.participation["r"] < 0.25 else f"{_axes(m.participation)} oscillation")


def _one_of_each_subsidence(modes: list[FlightMode]) -> None:
    """Of two or more real modes of one name, the one with the largest share of its axis keeps it;
    the others are named after their two largest axes (module docstring)."""
    for name in sorted({m.name for m in modes if m.name.endswith(("subsidence", "divergence")) or m.name == "spiral"}):
        same = [m for m in modes if m.name == name]
        axis = ("phi", "v") if name == "spiral" else AXES.get(name.split()[0])
        if len(same) < 2 or axis is None:
            continue
        keeper = max(same, key=lambda m: sum(m.participation[k] for k in axis))
        for m in same:
            if m is not keeper:
                kind = "divergence" if m.eigenvalue.real > 0 else "subsidence"
                m.name = f"{_axes(m.participation, joined=True)} {kind}"


def _real(lam: complex, weights: dict[str, float]) -> str:
    """``"<axis> subsidence"`` for the axis with the largest weight, ``divergence`` when growing."""
    return f"{max(weights, key=weights.get)} {'divergence' if lam.real > 0 else 'subsidence'}"


def flight_modes(a: np.ndarray, states=STATES) -> list[FlightMode]:
    """Modes of ``a`` (8, 8) in ``states`` order, one per conjugate pair, least stable first."""
    lam, p = participation(a)
    out = []
    for i in np.flatnonzero(lam.imag >= 0):
        share = {s: float(w) for s, w in zip(states, p[:, i])}
        out.append(FlightMode(complex(lam[i]), share, mode_name(complex(lam[i]), share)))
    _one_dutch_roll(out)
    _one_of_each_subsidence(out)
    return sorted(out, key=lambda m: m.eigenvalue.real, reverse=True)
