"""Linearisation of ``x' = f(x, t, p)``: the exact Jacobian from forward-mode AD, its
eigenvalues, and the largest stable step of each fixed-step method.

Stability of a step size: a method applied to ``y' = λ y`` gives ``y_{n+1} = R(hλ) y_n``
with ``R`` from the method's tableau (:meth:`ButcherTableau.stability_function`). The
largest stable step is the largest ``h`` with ``|R(hλ_i)| <= 1`` for every eigenvalue
``λ_i`` of ``df/dx``. Eigenvalues with a positive real part (physically growing modes, or
round-off around the imaginary axis) are moved onto the imaginary axis first: the limit
concerns the neutral and damped modes, which a stable method must not amplify.

For a rotor the Jacobian depends on the state (azimuth, speeds), so
:func:`predicted_limits` takes the eigenvalues at several states along a run.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.integrators import ButcherTableau


def rhs_jacobian(rhs: ca.Function) -> ca.Function:
    """``rhs_jac(x, t, p) -> J`` (nx, nx) dense, ``J = d rhs / dx``, exact.

    One forward-mode directional derivative of ``rhs`` per state, looped (``map``, serial):
    the generated code holds the derivative of ``rhs`` once, so it compiles in seconds
    where the fully expanded Jacobian would take minutes.
    """
    nx, np_ = rhs.size1_in(0), rhs.size1_in(2)
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", np_)
    fwd = rhs.forward(1).map(nx, "serial")
    y = rhs(x, t, p)
    cols = fwd(ca.repmat(x, 1, nx), ca.repmat(t, 1, nx), ca.repmat(p, 1, nx), ca.repmat(y, 1, nx),
               ca.MX.eye(nx), ca.MX.zeros(1, nx), ca.MX.zeros(np_, nx))
    return ca.Function("rhs_jac", [x, t, p], [ca.densify(cols)], ["x", "t", "p"], ["J"])


@dataclass
class Mode:
    """One eigenvalue ``λ`` (1/s) of the Jacobian with the states that dominate its eigenvector."""

    eigenvalue: complex
    states: list[str]

    @property
    def frequency(self) -> float:
        """Undamped natural frequency ``|λ|``, rad/s."""
        return abs(self.eigenvalue)

    def describe(self) -> str:
        lam = self.eigenvalue
        return f"λ = {lam.real:.4g} {'+-'[lam.imag < 0]} {abs(lam.imag):.4g}i 1/s ({', '.join(self.states)})"


def modes(jac: np.ndarray, state_names: list[str], top: int = 3) -> list[Mode]:
    """Eigenvalues of ``jac`` (nx, nx), largest ``|λ|`` first, one per conjugate pair."""
    lam, vec = np.linalg.eig(np.asarray(jac, dtype=float))
    out = []
    for i in np.argsort(-np.abs(lam)):
        if lam[i].imag < 0:
            continue
        w = np.abs(vec[:, i])
        out.append(Mode(complex(lam[i]), [state_names[j] for j in np.argsort(-w)[:top]]))
    return out


def _ray_polynomial(coeffs: np.ndarray, mu: complex) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients (lowest first) of ``|P(r mu)|^2`` as a real polynomial in ``r``, and the
    sums of the magnitudes of the products that make each one (the scale of its round-off)."""
    a = np.asarray(coeffs, dtype=complex) * mu ** np.arange(len(coeffs))
    return np.real(np.convolve(a, np.conj(a))), np.convolve(np.abs(a), np.abs(a))


def boundary(tab: ButcherTableau, direction: complex) -> float:
    """Distance ``r`` from 0 along ``z = r direction`` to the edge of the stability region.

    Computed from the stability function ``R = N/D``: the first ``r > 0`` at which
    ``|N(z)|^2 - |D(z)|^2`` turns positive. 0 if ``|R| > 1`` immediately (explicit Euler
    on the imaginary axis), ``inf`` if never (A-stable methods in the left half plane).
    """
    mu = complex(direction) / abs(direction)
    num, den = tab.stability_function()
    (pn, sn), (pd, sd) = _ray_polynomial(num, mu), _ray_polynomial(den, mu)
    d, scale = np.zeros(max(len(pn), len(pd))), np.zeros(max(len(pn), len(pd)))
    d[:len(pn)] += pn
    d[:len(pd)] -= pd
    scale[:len(sn)] += sn
    scale[:len(sd)] += sd
    # coefficients that cancel (R = e^z to the method's order) leave round-off of their scale;
    # a threshold relative to the largest coefficient would also drop the genuinely small
    # high-order ones of a high-order method
    d[np.abs(d) <= 1e-12 * scale] = 0.0
    nz = np.flatnonzero(d)
    if nz.size == 0:
        return np.inf
    if d[nz[0]] > 0:
        return 0.0
    roots = np.roots(d[::-1])
    real = np.sort(roots[(np.abs(roots.imag) < 1e-9 * (1 + np.abs(roots))) & (roots.real > 1e-12)].real)
    for r in real:
        if np.polyval(d[::-1], r * (1 + 1e-7)) > 0:
            return float(r)
    return np.inf


def imaginary_axis_limit(tab: ButcherTableau) -> float:
    """Largest ``|hλ|`` on the imaginary axis (RK4: 2√2 = 2.828)."""
    return boundary(tab, 1j)


def real_axis_limit(tab: ButcherTableau) -> float:
    """Largest ``|hλ|`` on the negative real axis (RK4: 2.785)."""
    return boundary(tab, -1.0)


@dataclass
class StepLimit:
    """Largest stable step ``h`` (s) of a method and the eigenvalue that sets it."""

    method: str
    h: float
    eigenvalue: complex | None
    reach: float  # |hλ| at the limit along the limiting eigenvalue's direction


def max_stable_step(tab: ButcherTableau, eigenvalues) -> StepLimit:
    """``h`` such that ``|R(hλ)| <= 1`` for all ``λ`` (see the module docstring)."""
    best = StepLimit(tab.name, np.inf, None, np.inf)
    for lam in np.asarray(eigenvalues, dtype=complex).ravel():
        lam = complex(min(lam.real, 0.0), lam.imag)
        if abs(lam) < 1e-9:
            continue
        r = boundary(tab, lam)
        if r / abs(lam) < best.h:
            best = StepLimit(tab.name, r / abs(lam), lam, r)
    return best


def predicted_limits(tabs, eigenvalue_sets) -> dict[str, StepLimit]:
    """Per method, the smallest stable step over several eigenvalue sets (states of a run)."""
    lams = np.concatenate([np.asarray(e, dtype=complex).ravel() for e in eigenvalue_sets])
    return {t.name: max_stable_step(t, lams) for t in tabs}
