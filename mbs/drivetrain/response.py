"""The rotor speed's response to a collective step in the engine model's own linear form.

Padfield's engine and governor (:mod:`mbs.drivetrain.engine`) about a steady hover, with the
rotor as a quasi-steady torque ``Q(Ω, θ0)`` on the drive train's inertia ``I``. Deviations:
rotor speed ``ω`` (rad/s), each engine's power ``ε`` and fuel ``w`` (fractions of take-off power),
the governor's lag state ``z``:

    I ω' = η n P_TO ε / Ω0 − (Q0 / Ω0) ω − Q_Ω ω − Q_θ Δθ0
    e = −ω / Ω_ref,   c = (τ_lead/τ_lag) e + z,   τ_lag z' = (1 − τ_lead/τ_lag) e − z
    τ_f w' = c / droop + K_θ Δθ0 − w,   τ_g ε' = w − ε

(``Q0``: the engines' torque at trim; its ``− (Q0/Ω0) ω`` is a constant power's torque rising as the
speed falls; ``Q_Ω``, ``Q_θ``: the rotors' steady torque derivatives, the tail rotor's referred
through the gear ratio). The step response is exact (the matrix exponential).
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from mbs.drivetrain.engine import Turboshaft


def linear_model(eng: Turboshaft, inertia: float, omega: float, torque: float, q_omega: float, q_theta: float,
                 reference: float):
    """``(A, b)`` of ``x = (ω, ε, w, z)``: ``x' = A x + b Δθ0``."""
    n, p_to = eng.count, eng.takeoff_power
    r = eng.governor_lead / eng.governor_lag
    de = -1.0 / reference  # d(e)/d(ω)
    a = np.zeros((4, 4))
    a[0] = [-(torque / omega + q_omega) / inertia, eng.efficiency * n * p_to / omega / inertia, 0.0, 0.0]
    a[1] = [0.0, -1 / eng.gas_generator_time_constant, 1 / eng.gas_generator_time_constant, 0.0]
    a[2] = [r * de / eng.governor_droop / eng.fuel_time_constant, 0.0, -1 / eng.fuel_time_constant,
            1 / eng.governor_droop / eng.fuel_time_constant]
    a[3] = [(1 - r) * de / eng.governor_lag, 0.0, 0.0, -1 / eng.governor_lag]
    b = np.array([-q_theta / inertia, 0.0, eng.anticipation / eng.fuel_time_constant, 0.0])
    return a, b


def step_response(a: np.ndarray, b: np.ndarray, step: float, times: np.ndarray) -> np.ndarray:
    """``x(t)`` (n, 4) after a step ``step`` of the input at ``t = 0`` from ``x = 0`` (exact, by the
    matrix exponential of the augmented system)."""
    big = np.zeros((5, 5))
    big[:4, :4], big[:4, 4] = a, b * step
    out = []
    for t in times:
        out.append(expm(big * t)[:4, 4])
    return np.array(out)
