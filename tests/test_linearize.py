"""Linearisation: the AD Jacobian of the right-hand side, and step limits computed from each
method's stability function (not from a table)."""
import math

import numpy as np
import pytest

import mbs
from mbs.dynamics import symbolic
from mbs.integrators import EULER, MIDPOINT, RK4, RK8, ButcherTableau
from mbs.linearize import (boundary, imaginary_axis_limit, max_stable_step, modes, predicted_limits,
                           real_axis_limit, rhs_jacobian)
from mbs.models.demo import driven_rotor, spinning_rotor

HEUN = ButcherTableau("heun", ((0, 0), (1.0, 0)), (0.5, 0.5), (0, 1.0), 2)
KUTTA3 = ButcherTableau("kutta3", ((0, 0, 0), (0.5, 0, 0), (-1.0, 2.0, 0)), (1 / 6, 2 / 3, 1 / 6), (0, 0.5, 1.0), 3)


def _central_differences(f, x, eps):
    cols = []
    for i in range(x.size):
        d = np.zeros_like(x)
        d[i] = eps * max(1.0, abs(x[i]))
        cols.append((f(x + d) - f(x - d)) / (2 * d[i]))
    return np.array(cols).T


@pytest.mark.parametrize("make", [lambda: spinning_rotor(n_blades=2), lambda: driven_rotor(n_blades=2)],
                         ids=["conservative-free-fuselage", "driven-time-dependent"])
def test_ad_jacobian_agrees_with_central_differences(make):
    """Relative to the Jacobian's norm, to 1e-6 (central differences: error ~ eps^2 + round-off/eps)."""
    model = make()
    sym = symbolic(model)
    system = mbs.build(model, "vm")
    x = system.run(system.x0(), 0.0, 1e-3, 37).x[-1]  # a generic state with all rates non-zero
    t, p = 0.037, system.params()
    jac = np.asarray(rhs_jacobian(sym["rhs"])(x, t, p))
    fd = _central_differences(lambda y: system.rhs(y, t, p), x, 1e-6)
    assert np.abs(jac - fd).max() <= 1e-6 * np.abs(jac).max(), np.abs(jac - fd).max() / np.abs(jac).max()


@pytest.mark.parametrize("tab, imag, real", [
    (EULER, 0.0, 2.0),
    (HEUN, 0.0, 2.0),
    (KUTTA3, math.sqrt(3), 2.5127453266183286),
    (RK4, 2 * math.sqrt(2), 2.785293563405282),
    (MIDPOINT, math.inf, math.inf),
])
def test_stability_boundaries_from_the_stability_function(tab, imag, real):
    assert imaginary_axis_limit(tab) == pytest.approx(imag, rel=1e-10)
    assert real_axis_limit(tab) == pytest.approx(real, rel=1e-10)


def test_rk8_boundaries_match_the_published_dop853_values():
    """5.960 on the imaginary and 6.394 on the negative real axis, as tabulated for DOP853's
    8th-order solution. Its stability polynomial has degree 12 with small high-order
    coefficients, which the boundary search must not mistake for round-off."""
    num = RK8.stability_function()[0]
    assert len(num) == 13 and 0 < num[12] < 1e-9
    for direction, published in ((1j, 5.960), (-1.0, 6.394)):
        r = boundary(RK8, direction)
        assert r == pytest.approx(published, abs=1e-3)
        amplification = abs(np.polyval(num[::-1], r * direction))
        assert amplification == pytest.approx(1.0, abs=1e-8)
        assert abs(np.polyval(num[::-1], 1.001 * r * direction)) > 1


@pytest.mark.parametrize("angle", [0.55, 0.7, 0.85, 0.95])
def test_rk4_boundary_is_where_the_amplification_reaches_one(angle):
    """On rays between the negative real and the imaginary axis, |R| = 1 at the computed
    boundary, < 1 just inside and > 1 just outside."""
    mu = complex(-abs(np.cos(np.pi * angle / 2)), abs(np.sin(np.pi * angle / 2)))
    r = boundary(RK4, mu)
    num = RK4.stability_function()[0]
    amp = lambda z: abs(np.polyval(num[::-1], z))  # noqa: E731
    assert amp(r * mu) == pytest.approx(1.0, abs=1e-9)
    assert amp(0.999 * r * mu) < 1 < amp(1.001 * r * mu)


def test_max_stable_step_of_a_damped_oscillator():
    """λ = -ζω ± iω√(1-ζ²): RK4's step is the boundary along that ray over ω."""
    w, z = 100.0, 0.3
    lam = [complex(-z * w, w * math.sqrt(1 - z * z)), complex(-z * w, -w * math.sqrt(1 - z * z))]
    lim = max_stable_step(RK4, lam)
    assert lim.h == pytest.approx(boundary(RK4, lam[0]) / w, rel=1e-12)
    num = RK4.stability_function()[0]
    assert abs(np.polyval(num[::-1], lim.h * lam[0])) == pytest.approx(1.0, abs=1e-9)
    assert max_stable_step(EULER, lam).h == pytest.approx(2 * z / w, rel=1e-9)  # |1 + hλ| = 1


def test_growing_eigenvalues_are_treated_as_neutral_and_zero_ignored():
    lim = predicted_limits([RK4, EULER], [[0.0, complex(1e-3, 50.0)], [complex(-1.0, 0.0)]])
    assert lim["rk4"].h == pytest.approx(2 * math.sqrt(2) / 50.0, rel=1e-6)
    assert lim["euler"].h == 0.0


def test_modes_name_the_dominant_states():
    jac = np.zeros((4, 4))
    jac[0, 2] = jac[1, 3] = 1.0
    jac[2, 0], jac[3, 1] = -4.0, -400.0  # two oscillators, 2 rad/s and 20 rad/s
    m = modes(jac, ["a", "b", "a_rate", "b_rate"], top=2)
    assert [round(x.frequency, 9) for x in m] == [20.0, 2.0]
    assert set(m[0].states) == {"b", "b_rate"}
