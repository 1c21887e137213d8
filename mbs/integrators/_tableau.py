"""Runge-Kutta methods as data, their stability functions, and the one symbolic stepping kernel."""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np


@dataclass(frozen=True)
class ButcherTableau:
    """RK method: ``a`` (s, s), weights ``b`` (s,), nodes ``c`` (s,).

    Explicit when ``a`` is strictly lower triangular; otherwise the stage equations are
    implicit and need a nonlinear solve (see :mod:`mbs.integrators.midpoint`).
    """

    name: str
    a: tuple
    b: tuple
    c: tuple
    order: int

    @property
    def stages(self) -> int:
        return len(self.b)

    @property
    def explicit(self) -> bool:
        return not np.any(np.triu(np.array(self.a, dtype=float)))

    def stability_function(self) -> tuple[np.ndarray, np.ndarray]:
        """``R(z) = N(z) / D(z)`` for ``y' = λ y``, ``z = hλ``; coefficients, lowest power first.

        ``R(z) = 1 + z bᵀ (I - z A)⁻¹ 1 = det(I - z A + z 1 bᵀ) / det(I - z A)``, and
        ``det(I - z M)`` has the coefficients of the characteristic polynomial of ``M``.
        """
        a, b = np.array(self.a, dtype=float), np.array(self.b, dtype=float)
        num = np.real(np.poly(a - np.outer(np.ones(self.stages), b)))
        den = np.real(np.poly(a))
        return _clean(num), _clean(den)

    def stability_polynomial(self) -> np.ndarray:
        """Coefficients (highest power first) of ``R(z)`` of an explicit method (``D = 1``)."""
        if not self.explicit:
            raise ValueError(f"{self.name} is implicit: its stability function is rational; "
                             "use stability_function()")
        return self.stability_function()[0][::-1]


def _clean(c: np.ndarray) -> np.ndarray:
    """Drop round-off from the determinant expansion (coefficients are rationals of order 1)."""
    c = np.where(np.abs(c) < 1e-13, 0.0, c)
    nz = np.flatnonzero(c)
    return c[: nz[-1] + 1] if nz.size else c[:1]


def rk_step(f: ca.Function, x, t, h, p, tab: ButcherTableau):
    """One explicit RK step of ``x' = f(x, t, p)`` (symbolic, MX or SX)."""
    return x + rk_increment(f, x, t, h, p, tab)


def rk_increment(f: ca.Function, x, t, h, p, tab: ButcherTableau):
    """The update ``h sum_i b_i k_i`` of one explicit RK step (without adding ``x``)."""
    if not tab.explicit:
        raise ValueError(f"rk_increment handles explicit tableaux only; {tab.name} is implicit")
    k = []
    for i in range(tab.stages):
        xi = x
        for j in range(i):
            if tab.a[i][j]:
                xi = xi + h * tab.a[i][j] * k[j]
        k.append(f(xi, t + tab.c[i] * h, p))
    return h * sum(bi * ki for bi, ki in zip(tab.b, k) if bi)
