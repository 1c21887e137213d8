"""Floquet analysis against closed forms: the hover flap mode of a single blade with
aerodynamics (Lock number), and the stability chart of the damped Mathieu equation."""
from dataclasses import replace

import numpy as np
import pytest

import mbs
from mbs import scenes
from mbs.analysis import flap_lag_frequencies, hinge_inertia
from mbs.analysis.floquet import analyse
from mbs.analysis.monodromy import TangentStepper
from mbs.analysis.trim import periodic_solution
from mbs import aircraft
from mbs.models.mathieu import PERIOD, mathieu


# -- (a) the flap mode of a single blade in hover ------------------------------------------

@pytest.fixture(scope="module")
def blade():
    """Floquet modes of ``single-blade-aero`` in hover with zero cyclic (an axisymmetric,
    time-invariant rotating system), the periodic solution and the system."""
    model, system, stepper, sol = zero_cyclic_hover(scenes.get("single-blade-aero"))
    return analyse(sol, system, stepper), sol, system


def zero_cyclic_hover(sc):
    """``sc``'s model with zero cyclic, its compiled system, RK4 tangent stepper and periodic
    solution (converged)."""
    model = sc.model()
    for name in ("lateral_cyclic", "longitudinal_cyclic"):
        model.parameters[name] = replace(model.parameters[name], default=0.0)
    system, stepper = mbs.build(model, "compiled"), TangentStepper(model, "rk4")
    sol = periodic_solution(sc, system=system, stepper=stepper)
    assert sol.converged, sol.reason
    return model, system, stepper, sol


def _blade_constants(system, sol) -> dict:
    """The model's own numbers: hinge inertia ``I_β`` (kg m²), flap frequency ``ν`` (per rev)
    from the spring and centrifugal stiffness, and the strip sums ``Σ r^k Δr`` over the
    blade elements (8 strips from the 0.2 R root cut-out), hover inflow ``v`` (m/s)."""
    d = aircraft.load().data
    mr, rho = d["main_rotor"], d["environment"]["rho"]
    b = system.info.bodies[system.info.body_names.index("blade1")]
    nu, _ = flap_lag_frequencies(b["mass"], b["com"], b["inertia"], mr["flap_hinge_offset"], mr["flap_stiffness"],
                                 mr["lag_stiffness"], mr["omega"])
    i_beta = hinge_inertia(b["mass"], b["com"], b["inertia"])[1, 1]
    r0 = mr["root_cutout"] * mr["radius"]
    dr = (mr["radius"] - r0) / mr["elements"]
    r = r0 + dr * (np.arange(mr["elements"]) + 0.5)
    return {"nu": nu, "I": i_beta, "rho": rho, "a": mr["lift_slope"], "c": mr["chord"], "R": mr["radius"],
            "omega": mr["omega"], "kappa": mr["kappa"], "S": {k: float(np.sum(r**k) * dr) for k in (1, 2, 3)},
            "v": sol.state["main_rotor.inflow"]}


def test_hover_flap_mode_matches_the_lock_number_closed_form(blade):
    """``λ = Ω(−γ*/16 ± i √(ν² − (γ*/16)²))`` (Bramwell, Johnson: the flap equation in hover with
    quasi-steady strip theory, uniform inflow, no hinge offset), with the model's Lock number
    ``γ = ρ a c R⁴ / I_β = 5.07`` corrected for the root cut-out and the strips:
    ``γ* = ρ a c · 4 Σ r³ Δr / I_β = 0.994 γ``; ``ν = 1.117`` from the spring. Within 3 % in
    damping and frequency (measured −1.3 %: the dynamic inflow, next test)."""
    res, sol, system = blade
    k = _blade_constants(system, sol)
    gamma = k["rho"] * k["a"] * k["c"] * k["R"] ** 4 / k["I"]
    gamma_star = k["rho"] * k["a"] * k["c"] * 4 * k["S"][3] / k["I"]
    assert gamma == pytest.approx(5.07, abs=0.01) and gamma_star == pytest.approx(0.9936 * gamma, rel=1e-3)
    flap = [m for m in res.modes if m.name.startswith("flap") and m.exponent.imag > 0]
    assert len(flap) == 1
    lam = flap[0].exponent / k["omega"]
    assert lam.real == pytest.approx(-gamma_star / 16, rel=0.03)
    assert lam.imag == pytest.approx(np.sqrt(k["nu"] ** 2 - (gamma_star / 16) ** 2), rel=0.03)


def test_hover_flap_mode_with_the_dynamic_inflow_correction(blade):
    """The same flap equation coupled with the linearised Pitt-Peters inflow of the model
    (``(8/3) ρ R³ δv' = δT − 4 ρ A v δv`` in hover; the blades see ``κ δv``):

        I_β β'' + C β' + I_β ν² Ω² β = −κ D δv,     C = ½ ρ a c Ω Σ r³ Δr,  D = ½ ρ a c Ω Σ r² Δr
        δT = −D β' − κ E δv,                          E = ½ ρ a c Ω Σ r Δr

    Its eigenvalues give the flap mode within 1 % (measured: damping −0.8 %, frequency −0.4 %;
    the plain Lock form is −1.3 % in both) and the real inflow-coning mode within 1 % (0.4 %).
    What remains is left out of the closed form: the flap-lag coupling (Coriolis at 2.9°
    coning, aerodynamic; with the lag hinge 1000 times stiffer the frequency agrees to 0.13 %),
    the stall guard's lift-slope reduction at the sections' 6-8° incidence and the inflow-angle
    terms (damping −0.6 % then)."""
    res, sol, system = blade
    k = _blade_constants(system, sol)
    half = 0.5 * k["rho"] * k["a"] * k["c"] * k["omega"]
    c, d, e = (half * k["S"][n] for n in (3, 2, 1))
    m_app, area = 8 / 3 * k["rho"] * k["R"] ** 3, np.pi * k["R"] ** 2
    a = np.array([[0, 1, 0],
                  [-k["nu"] ** 2 * k["omega"] ** 2, -c / k["I"], -k["kappa"] * d / k["I"]],
                  [0, -d / m_app, -(k["kappa"] * e + 4 * k["rho"] * area * k["v"]) / m_app]])
    lam = np.linalg.eigvals(a)
    flap_cf, inflow_cf = lam[np.argmax(lam.imag)], lam[np.argmin(np.abs(lam.imag))].real
    flap = max(res.modes, key=lambda m: m.exponent.imag if m.name.startswith("flap") else -1).exponent
    inflow = [m.exponent.real for m in res.modes if "inflow" in m.name]
    assert flap.real == pytest.approx(flap_cf.real, rel=0.01)
    assert flap.imag == pytest.approx(flap_cf.imag, rel=0.01)
    assert len(inflow) == 1 and inflow[0] == pytest.approx(inflow_cf, rel=0.01)


# -- (b) the damped Mathieu equation ---------------------------------------------------------
#
# x'' + 2ζ x' + (δ + ε cos t) x = 0. With t = 2τ it is Mathieu's y'' + (a − 2q cos 2τ) y = 0
# with a = 4δ, q = −2ε (plus damping 4ζ). The first instability tongue issues from δ = 1/4:
#   undamped, its boundaries are δ = 1/4 ± ε/2 − ε²/8 ∓ ε³/32 + O(ε⁴)   (from the characteristic
#     values a₁, b₁ = 1 ± q − q²/8 ∓ q³/64 − q⁴/1536 + ..., Abramowitz & Stegun, Handbook of
#     Mathematical Functions, 20.2.25; to O(ε²) also in Nayfeh & Mook,
#     Nonlinear Oscillations, Wiley 1979, ch. 5);
#   damped, it is |δ − 1/4| < ½ √(ε² − 4ζ²) to first order in ε and ζ (Nayfeh & Mook, ch. 5,
#     the damped Mathieu equation by multiple scales, in these variables): damping ζ > ε/2
#     removes it.
# Stable means every Floquet multiplier of the period 2π inside the unit circle (|ρ| <= 1).

STEPS = 200


@pytest.fixture(scope="module")
def multipliers():
    model = mathieu()
    system, stepper = mbs.build(model, "compiled"), TangentStepper(model, "rk4")

    def get(delta: float, epsilon: float, zeta: float) -> np.ndarray:
        p = system.params(delta=delta, epsilon=epsilon, zeta=zeta)
        sens = stepper.monodromy(np.zeros(2), p, 0.0, PERIOD / STEPS, STEPS)
        return np.linalg.eigvals(sens.dx[:, :2])
    return get


def _stable(rho: np.ndarray) -> bool:
    return bool(np.abs(rho).max() <= 1 + 1e-9)


@pytest.mark.parametrize("delta, epsilon, zeta, stable", [
    (0.25, 0.2, 0.0, False),   # tongue centre; boundaries 0.145 .. 0.345
    (0.18, 0.2, 0.0, False),
    (0.32, 0.2, 0.0, False),
    (0.10, 0.2, 0.0, True),
    (0.40, 0.2, 0.0, True),
    (0.25, 0.2, 0.05, False),  # damped tongue 0.158 .. 0.332
    (0.12, 0.2, 0.05, True),
    (0.37, 0.2, 0.05, True),
    (0.245, 0.2, 0.12, True),  # ζ > ε/2: no tongue
    (0.245, 0.2, 0.08, False),  # ½ √(ε² − 4ζ²) = 0.06
])
def test_mathieu_points_lie_on_the_right_side_of_the_boundary(multipliers, delta, epsilon, zeta, stable):
    rho = multipliers(delta, epsilon, zeta)
    assert _stable(rho) == stable, (delta, epsilon, zeta, rho)
    if not stable:  # the first tongue: a real multiplier below −1 (a solution of period 4π)
        assert rho[np.argmax(np.abs(rho))].real < -1 and abs(rho[np.argmax(np.abs(rho))].imag) < 1e-9
    if zeta == 0.0 and stable:  # undamped: on the unit circle (RK4 at 200 steps loses < 1e-9)
        assert np.abs(np.abs(rho) - 1).max() < 1e-9


def _boundary(multipliers, inside: float, outside: float, epsilon: float) -> float:
    """δ where the undamped multipliers leave the unit circle, by bisection between ``inside``
    (unstable) and ``outside`` (stable), to 1e-7."""
    while abs(inside - outside) > 1e-7:
        mid = 0.5 * (inside + outside)
        inside, outside = (mid, outside) if not _stable(multipliers(mid, epsilon, 0.0)) else (inside, mid)
    return 0.5 * (inside + outside)


def test_mathieu_tongue_boundaries_match_the_perturbation_series(multipliers):
    """ε = 0.1: the bisected boundaries equal 1/4 ± ε/2 − ε²/8 to 1e-4 (measured 3.1e-5, the
    cubic term), and with the cubic term ∓ε³/32 (from ∓q³/64 in a₁, b₁) to 1e-6 (the quartic
    term is −ε⁴/384 = −2.6e-7)."""
    eps = 0.1
    lower = _boundary(multipliers, 0.25, 0.15, eps)
    upper = _boundary(multipliers, 0.25, 0.35, eps)
    assert lower == pytest.approx(0.25 - eps / 2 - eps**2 / 8, abs=1e-4)
    assert upper == pytest.approx(0.25 + eps / 2 - eps**2 / 8, abs=1e-4)
    assert lower == pytest.approx(0.25 - eps / 2 - eps**2 / 8 + eps**3 / 32, abs=1e-6)
    assert upper == pytest.approx(0.25 + eps / 2 - eps**2 / 8 - eps**3 / 32, abs=1e-6)
