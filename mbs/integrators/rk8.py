"""Dormand and Prince's 8th-order explicit Runge-Kutta method, used with a fixed step.

The 12-stage, 8th-order solution of DOP853 (Hairer, Nørsett and Wanner, *Solving Ordinary
Differential Equations I*, 2nd ed., 1993, section II.10), without its error estimators and
dense output. The coefficients are taken from SciPy's copy of the published tableau, so
none are retyped here. Stability: 5.96 on the imaginary axis and 6.39 on the negative real
axis (computed from the tableau, :mod:`mbs.linearize`), that is 0.50 per evaluation on the
imaginary axis against RK4's 0.71.
"""
from __future__ import annotations

from scipy.integrate._ivp import dop853_coefficients as _dp

from mbs.integrators._tableau import ButcherTableau

_S = _dp.N_STAGES

RK8 = ButcherTableau(
    name="rk8",
    a=tuple(tuple(float(v) for v in row[:_S]) for row in _dp.A[:_S]),
    b=tuple(float(v) for v in _dp.B),
    c=tuple(float(v) for v in _dp.C[:_S]),
    order=8,
)
