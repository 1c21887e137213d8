"""Smooth interpolation of published tables in the generated code: natural cubic splines.

A natural cubic spline through the breakpoints is twice continuously differentiable (no kink for
Newton, Floquet or the AD Jacobians) and, its second derivative being zero at the ends, continues
linearly beyond them without a kink. The pieces are selected with step functions of the argument
(``t >= x_k``, of zero derivative), so the same code evaluates floats, numpy values and CasADi
symbols, and forward-mode AD differentiates the spline exactly. A table in two arguments is the
tensor-product spline: the spline along the second argument of each row, then along the first
argument through those values (a spline is linear in its data, so the order does not matter).
"""
from __future__ import annotations

import numpy as np


def _natural_coefficients(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Coefficients (n+1, 4, m) of the natural spline's pieces ``c0 + c1 d + c2 d² + c3 d³``,
    ``d = t - x_k``: row 0 the line below ``x_0``, rows 1..n-1 the cubics, row n the line above."""
    from scipy.interpolate import CubicSpline

    cs = CubicSpline(x, y, bc_type="natural", axis=0)
    inner = np.stack([cs.c[3], cs.c[2], cs.c[1], cs.c[0]], axis=1)  # (n-1, 4, m)
    slope = cs(x[[0, -1]], 1)
    zeros = np.zeros_like(slope[0])
    below = np.stack([y[0], slope[0], zeros, zeros])[None]
    above = np.stack([y[-1], slope[1], zeros, zeros])[None]
    return np.concatenate([below, inner, above])


class Spline:
    """Natural cubic spline through ``(x_k, y_k)``, ``x`` strictly increasing (n >= 2); ``y``
    (n,) or (n, m) for m curves on the same breakpoints. ``spline(t)`` is a scalar, or a list of
    m values, for a float or a CasADi scalar ``t``."""

    def __init__(self, x, y):
        self.x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        if self.x.ndim != 1 or len(self.x) < 2 or np.any(np.diff(self.x) <= 0):
            raise ValueError("breakpoints must be at least two strictly increasing numbers")
        self.vector = y.ndim == 2
        y2 = y if self.vector else y[:, None]
        if y2.shape[0] != len(self.x):
            raise ValueError(f"{y2.shape[0]} values for {len(self.x)} breakpoints")
        self.coef = _natural_coefficients(self.x, y2)  # (n+1, 4, m)
        self.origin = np.concatenate([self.x[:1], self.x])  # the line below starts at x_0 too

    def __call__(self, t):
        steps = [1.0] + [1.0 * (t >= xk) for xk in self.x] + [0.0]
        pieces = [steps[k] - steps[k + 1] for k in range(len(self.origin))]  # exactly one is 1
        d = t - _select(pieces, self.origin)
        out = []
        for j in range(self.coef.shape[2]):
            c = [_select(pieces, self.coef[:, p, j]) for p in range(4)]
            out.append(c[0] + d * (c[1] + d * (c[2] + d * c[3])))
        return out if self.vector else out[0]


def _select(pieces, values):
    """``values[k]`` of the piece whose indicator is 1 (the others are exactly 0)."""
    total = 0.0
    for s, v in zip(pieces, values):
        if v != 0.0:
            total = total + s * float(v)
    return total


class Spline2:
    """Tensor-product natural cubic spline of ``z`` (len(x), len(y)) on the grid ``x`` × ``y``;
    ``spline(s, t)`` for floats or CasADi scalars."""

    def __init__(self, x, y, z):
        z = np.asarray(z, dtype=float)
        if z.shape != (len(x), len(y)):
            raise ValueError(f"table of shape {z.shape}, not {len(x)} x {len(y)}")
        self.rows = Spline(y, z.T)  # m = len(x) curves along y
        self.cardinal = Spline(x, np.eye(len(x)))  # the spline along x is linear in its values

    def __call__(self, s, t):
        weights, values = self.cardinal(s), self.rows(t)
        return sum(w * v for w, v in zip(weights, values))
