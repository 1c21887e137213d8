"""Explicit Runge-Kutta methods as data, and the one symbolic stepping kernel."""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np


@dataclass(frozen=True)
class ButcherTableau:
    """Explicit RK method: ``a`` (s, s) strictly lower triangular, weights ``b`` (s,), nodes ``c`` (s,)."""

    name: str
    a: tuple
    b: tuple
    c: tuple
    order: int

    @property
    def stages(self) -> int:
        return len(self.b)

    def stability_polynomial(self) -> np.ndarray:
        """Coefficients (highest power first) of ``R(z) = 1 + z bᵀ (I - z A)⁻¹ 1``.

        For an explicit method ``A`` is nilpotent, so ``R(z) = 1 + sum_k bᵀ A^k 1 z^(k+1)``.
        """
        a, b = np.array(self.a, dtype=float), np.array(self.b, dtype=float)
        coeffs, v = [1.0], np.ones(self.stages)
        for _ in range(self.stages):
            coeffs.append(b @ v)
            v = a @ v
        return np.array(coeffs[::-1])


def rk_step(f: ca.Function, x, t, h, p, tab: ButcherTableau):
    """One explicit RK step of ``x' = f(x, t, p)`` (symbolic, MX or SX)."""
    return x + rk_increment(f, x, t, h, p, tab)


def rk_increment(f: ca.Function, x, t, h, p, tab: ButcherTableau):
    """The update ``h sum_i b_i k_i`` of one explicit RK step (without adding ``x``)."""
    k = []
    for i in range(tab.stages):
        xi = x
        for j in range(i):
            if tab.a[i][j]:
                xi = xi + h * tab.a[i][j] * k[j]
        k.append(f(xi, t + tab.c[i] * h, p))
    return h * sum(bi * ki for bi, ki in zip(tab.b, k) if bi)
