"""Induced inflow of a rotor: uniform momentum inflow, Pitt–Peters three-state dynamic inflow, and
the uniform inflow of a ducted fan (a fan-in-fin tail rotor) with its duct's thrust.

Velocities in m/s, positive down through the disc (against the thrust axis); loads in N (the
moments as first moments of the thrust per radius, see :func:`pitt_peters_rates`). Flow at the
hub: ``v_inplane2`` the square of the in-plane speed (m²/s²), ``v_normal`` the hub's speed along
the thrust axis (m/s, climb positive), both of the hub relative to still air.

Sources: D.M. Pitt and D.A. Peters, Vertica 5 (1981) 21-34; D.A. Peters and N. HaQuang,
J. AHS 33 (1988) 64-68; G.D. Padfield, *Helicopter Flight Dynamics*, 2nd ed., §3.2.1.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aero.sections import EPS

INFLOW_MODELS = ("uniform", "pitt-peters")
DUCT_EXIT_RATIO = (0.5, 2.0)  # accepted σ_d: at ½ the duct carries nothing in hover; beyond 2 no fan-in-fin
HARMONICS = ("", "_1s", "_1c")  # state-name suffixes: uniform, sine and cosine components
SKEW_ROUNDING = 0.5  # m/s: rounding of the in-plane speed in the wake skew (see wake_skew)
APPARENT_MASS = (8 / (3 * np.pi), 16 / (45 * np.pi), 16 / (45 * np.pi))  # Peters' M, nondimensional


def momentum_inflow(thrust: float, rho: float, radius: float, v_inplane: float = 0.0,
                    v_normal: float = 0.0) -> float:
    """Glauert momentum-theory induced velocity (m/s) for ``thrust`` (N): the inflow state's equilibrium."""
    area, v = np.pi * radius**2, np.sqrt(abs(thrust) / (2 * rho * np.pi * radius**2))
    for _ in range(100):
        v_total = np.hypot(v_inplane, v_normal + v)
        v = 0.5 * v + 0.5 * thrust / (2 * rho * area * max(v_total, 1e-6))
    return float(v)


def uniform_rate(v, thrust, v_inplane2, v_normal, rho: float, radius: float, area_factor: float = 1.0):
    """``dv/dt`` (m/s²) of the uniform inflow ``v`` (m/s) under ``thrust`` (N).

    ``(8/3) ρ R³ v' = T − 2 ρ B² A V_T v``, ``V_T = sqrt(V_inplane² + (V_normal + v)²)``, the
    Pitt–Peters apparent mass of the uniform component; its equilibrium is Glauert's momentum
    theory. ``area_factor`` B² (tip loss as an effective disc area, 1 without).
    """
    area = np.pi * radius**2 if area_factor == 1.0 else area_factor * np.pi * radius**2
    v_total = ca.sqrt(v_inplane2 + (v_normal + v) ** 2 + EPS**2)
    apparent_mass = 8.0 / 3.0 * rho * radius**3
    return (thrust - 2 * rho * area * v_total * v) / apparent_mass


def _ducted_flow(v, v_normal, exit_ratio: float):
    """Through-flow at the fan ``U = V_normal + v`` and far-wake speed ``w = U / σ_d`` (m/s),
    with ``|U|``, ``|w|``, ``|V_normal|`` smoothed (``sqrt(x² + EPS²)``)."""
    through = v_normal + v
    wake = through / exit_ratio
    def size(x):
        return ca.sqrt(x**2 + EPS**2)
    return through, wake, size(through), size(wake), size(v_normal)


def ducted_fan_thrust(v, v_normal, rho: float, radius: float, exit_ratio: float, area_factor: float = 1.0):
    """``(T_fan, T_duct)`` (N): the thrust of the fan and of its duct when the fan's induced
    velocity is ``v`` (m/s, down through the disc) and the hub moves at ``v_normal`` (m/s) along
    the thrust axis, for a duct whose exit area is ``exit_ratio`` σ_d times the disc's.

    Ideal axial momentum theory of a shrouded rotor (J. L. Pereira, *Hover and Wind-Tunnel
    Testing of Shrouded Rotors for Improved Micro Air Vehicle Design*, PhD thesis, University of
    Maryland, 2008, ch. 2; T. Jardin et al., "Revisiting Froude's Theory for Hovering Shrouded
    Rotor", AIAA 2015): the duct fixes the far wake's area at σ_d A, so the wake leaves at
    ``w = U/σ_d``; the mass flow ``ρ A U`` gains ``w − V_normal``, ``T = ρ A |U| (w − V_normal)``,
    and the fan's pressure jump ``½ ρ (w|w| − V_normal|V_normal|)`` (Bernoulli before and after
    it) carries ``T_fan = ½ ρ A (w|w| − V_normal|V_normal|)``; the duct's lip suction carries the
    rest. In hover ``T_fan/T = 1/(2 σ_d)`` and the power ``T^1.5 / sqrt(4 σ_d ρ A)``; σ_d = ½ is
    the open rotor's hover. The in-plane flow does not enter the duct's mass flow (the duct turns the flow
    through it axial): no translational lift. ``area_factor`` B² as in :func:`uniform_rate`.
    """
    area = area_factor * np.pi * radius**2
    through, wake, through_size, wake_size, normal_size = _ducted_flow(v, v_normal, exit_ratio)
    fan = 0.5 * rho * area * (wake * wake_size - v_normal * normal_size)
    return fan, rho * area * through_size * (wake - v_normal) - fan


def ducted_rate(v, thrust, v_normal, rho: float, radius: float, exit_ratio: float, area_factor: float = 1.0):
    """``dv/dt`` (m/s²) of a ducted fan's uniform inflow ``v`` (m/s) under the fan's blade-element
    ``thrust`` (N): ``(8/3) ρ R³ v' = T − T_fan(v)`` with :func:`ducted_fan_thrust`'s ``T_fan``, the
    apparent mass of :func:`uniform_rate`; its equilibrium is the ducted rotor's momentum theory."""
    fan, _ = ducted_fan_thrust(v, v_normal, rho, radius, exit_ratio, area_factor)
    return (thrust - fan) / (8.0 / 3.0 * rho * radius**3)


def wake_skew(v0, v_inplane2, v_normal):
    """``(V_T, V_m, tan(χ/2), cos χ)`` of the disc flow with uniform inflow ``v0`` (m/s).

    Total inflow ``λ = V_normal + v0``; ``V_T = sqrt(V_inplane² + λ²)`` (m/s) drives the uniform
    component, ``V_m = (V_inplane² + λ (λ + v0)) / V_T`` (m/s, Peters and HaQuang's mass-flow
    parameter: ``2 v0`` in hover, where a perturbation of momentum theory's ``T = 2 ρ A v0²``
    sees twice the mean flow) the gradients; wake skew
    ``χ = atan(V_inplane / λ)`` (0 in hover, π/2 edgewise). ``tan(χ/2)`` takes ``|V_inplane|``,
    which has a kink at zero; it is rounded to ``|V| (1 − exp(−V²/δ²))`` with
    :data:`SKEW_ROUNDING` ``δ``: exactly 0 in hover, ``|V|³/δ²`` near it (twice differentiable,
    so Newton converges quadratically on the hover's periodic solution, whose in-plane speed
    oscillates through zero), ``|V|`` to 1e-7 from 2 m/s.
    """
    lam = v_normal + v0
    v_t = ca.sqrt(v_inplane2 + lam**2 + EPS**2)
    v_m = (v_inplane2 + lam * (lam + v0)) / v_t
    rounded = ca.sqrt(v_inplane2 + EPS**2) * (1 - ca.exp(-v_inplane2 / SKEW_ROUNDING**2))
    tan_half = rounded / (v_t + lam)
    return v_t, v_m, tan_half, lam / v_t


def pitt_peters_gains(tan_half, cos_chi):
    """Entries ``(a, b, c)`` of the static gain matrix ``L(χ)`` in state order (0, 1s, 1c).

    ``L = [[1/2, 0, −a], [0, b, 0], [a, 0, c]]`` with ``a = (15π/64) tan(χ/2)``,
    ``b = 4/(1 + cos χ)``, ``c = 4 cos χ/(1 + cos χ)`` (Peters & HaQuang's matrix, moments
    signed as the thrust's first moments so that b, c > 0; the 0–1c block has determinant
    ``c/2 + a² > 0`` at every skew).
    """
    return 15 * np.pi / 64 * tan_half, 4 / (1 + cos_chi), 4 * cos_chi / (1 + cos_chi)


def pitt_peters_rates(v, loads, v_inplane2, v_normal, rho: float, radius: float, area_factor: float = 1.0):
    """``dv/dt`` (3,) (m/s²) of ``v = (v0, v1s, v1c)`` (m/s; induced velocity at radius r and
    azimuth ψ: ``v0 + (r/R)(v1s sin ψ + v1c cos ψ)``).

    ``loads = (T, M_s, M_c)`` (N): thrust and its first moments ``Σ dT (r/R) sin ψ``,
    ``Σ dT (r/R) cos ψ`` (ψ from the tail, advancing side at 90°). Equations, per component i:
    ``ρ B² A R M_i v_i' = F_i − ρ B² A V_i (L⁻¹ v)_i``, with ``V = (V_T, V_m, V_m)``, Peters'
    ``M = diag(8/(3π), 16/(45π), 16/(45π))`` and ``L(χ)`` of :func:`pitt_peters_gains`;
    ``area_factor`` B² (tip loss, 1 without). Steady state: ``v = L V⁻¹ F / (ρ B² A)``.
    """
    area = area_factor * np.pi * radius**2
    v_t, v_m, tan_half, cos_chi = wake_skew(v[0], v_inplane2, v_normal)
    a, b, c = pitt_peters_gains(tan_half, cos_chi)
    det = c / 2 + a**2
    l_inv_v = ((c * v[0] + a * v[2]) / det, v[1] / b, (-a * v[0] + v[2] / 2) / det)
    return [(loads[i] - rho * area * speed * l_inv_v[i]) / (rho * area * radius * APPARENT_MASS[i])
            for i, speed in enumerate((v_t, v_m, v_m))]


def induced_velocity(v, x_over_r, y_over_r):
    """Induced velocity (m/s) at a disc point ``(x/R, y/R)`` of the non-rotating shaft frame
    (x aft, y towards the advancing side): ``v0 + v1s y/R + v1c x/R``; ``v`` (3,) m/s."""
    return v[0] + v[1] * y_over_r + v[2] * x_over_r
