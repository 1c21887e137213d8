"""The modal blade (a flexible body with modal coordinates) against beam theory: the
cantilever at rest, the rotating uniform beam of the published tables, the Southwell form,
the lag's -Ω² term and the extensible blade. Every frequency is an eigenvalue of the AD
Jacobian of the multibody equations (:mod:`mbs.flexible.frequencies`): the centrifugal
stiffening comes from the kinematics (the bent blade's foreshortening), not from a formula."""
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from mbs import aircraft
from mbs.flexible.beam import ModalBlade
from mbs.flexible.frequencies import rotating_frequencies
from mbs.flexible.uniform_blade import Blade, beam_frequencies, blade_from_data

# Dimensionless uniform beam: L = 1 m, m = 1 kg/m, EI = 1 N m², so that ω and Ω are the
# dimensionless frequency and speed Ω* = Ω √(m L⁴ / EI); a thin section (no rotary inertia
# to speak of: Euler–Bernoulli, as the tables).
UNIT = Blade(root=0.0, tip=1.0, mass=1.0, chord=2e-3, thickness=2e-4, flap_stiffness=1.0, lag_stiffness=1.0,
             torsion_stiffness=1.0)

EULER_BERNOULLI = (1.875104069, 4.694091133, 7.854757438)  # β_n L of the clamped-free beam

# First flapwise (out-of-plane) frequency of the rotating uniform cantilever, no hub radius,
# against Ω*: S. M. Hamza Cherif, A. Houmat, "Natural frequencies of rotating cantilever flexible
# beams by using the p-version of the finite element method", ICAS 2004, Table 2 (the values of
# Hodges & Rutkowski, AIAA J. 19 (1981) 1459, and Wright et al., J. Appl. Mech. 49 (1982) 197).
FLAP_PUBLISHED = {2: 4.1373, 4: 5.5850, 6: 7.3603, 8: 9.2568, 10: 11.2023, 50: 51.0805}

# The same table's chordwise (in-plane) frequencies of the extensible beam of slenderness ratio
# L √(A/I) = 70: the Coriolis coupling with the stretch lowers them below the inextensible
# beam's √(ω_flap² - Ω*²).
CHORDWISE_SLENDERNESS_70 = {2: 3.6195, 4: 3.888, 6: 4.2393, 8: 4.6105, 10: 4.97, 50: 7.3362}


def test_the_cantilever_at_rest_has_the_euler_bernoulli_frequencies():
    """Bending (β_n L)² √(EI / (m L⁴)) and torsion (2n - 1) π / (2L) √(GJ / i), n = 1..3, to 0.1 %
    with three modes per direction, on a blade not of unit size."""
    blade = Blade(root=0.3, tip=5.3, mass=6.0, chord=0.01, thickness=0.001, flap_stiffness=6.0e4,
                  lag_stiffness=1.5e5, torsion_stiffness=900.0)
    found = rotating_frequencies(ModalBlade(blade, (3, 0, 3), omega=0.0), 0.0)
    length = blade.length
    bending = [b**2 * np.sqrt(blade.flap_stiffness / (blade.mass * length**4)) for b in EULER_BERNOULLI]
    torsion = [(2 * n - 1) * np.pi / (2 * length) * np.sqrt(blade.torsion_stiffness / blade.torsional_inertia)
               for n in (1, 2, 3)]
    np.testing.assert_allclose(found["flap"], bending, rtol=1e-3)
    np.testing.assert_allclose(found["torsion"], torsion, rtol=1e-3)


def test_a_basis_made_for_another_speed_still_gives_the_cantilever():
    """Shapes of the blade turning at Ω* = 12, six of them, taken at rest: the first three
    bending frequencies still within 0.1 % of Euler–Bernoulli (a Ritz basis, not the answer)."""
    found = rotating_frequencies(ModalBlade(UNIT, (6, 0, 0), omega=12.0), 0.0)["flap"][:3]
    np.testing.assert_allclose(found, [b**2 for b in EULER_BERNOULLI], rtol=1e-3)


@pytest.mark.parametrize("speed, published", FLAP_PUBLISHED.items())
def test_the_rotating_beam_has_the_published_flap_and_lag_frequencies(speed, published):
    """Four modes per direction (the beam's own rotating modes at that speed): the first flap
    frequency within 0.5 % of the table (1e-4 in fact), and the first lag frequency of the
    same beam within 0.5 % of √(ω_flap² - Ω*²), the exact lag frequency of a uniform
    inextensible beam with EI_lag = EI_flap (the lag equation is the flap equation with the
    centrifugal -m Ω² added)."""
    found = rotating_frequencies(ModalBlade(UNIT, (4, 4, 0), omega=float(speed)), float(speed))
    assert found["flap"][0] == pytest.approx(published, rel=5e-3)
    assert found["flap"][0] == pytest.approx(published, rel=1e-4)
    assert found["lag"][0] == pytest.approx(np.sqrt(published**2 - speed**2), rel=5e-3)


def test_the_lag_frequency_carries_the_minus_omega_squared_term():
    """With EI_lag = EI_flap the multibody blade's lag frequency is its flap frequency less the
    centrifugal Ω² (ω_lag² = ω_flap² - Ω², to 1e-5: the thin section's rotary inertia), at
    every speed: the -Ω² comes out of the kinematics."""
    for speed in (1.0, 5.0, 20.0):
        found = rotating_frequencies(ModalBlade(UNIT, (4, 4, 0), omega=speed), speed)
        assert found["lag"][0] ** 2 == pytest.approx(found["flap"][0] ** 2 - speed**2, rel=1e-5)
        assert found["lag"][0] < found["flap"][0]


def _euler_bernoulli_mode(beta: float):
    sigma = (np.cosh(beta) + np.cos(beta)) / (np.sinh(beta) + np.sin(beta))
    def shape(x):
        return np.cosh(beta * x) - np.cos(beta * x) - sigma * (np.sinh(beta * x) - np.sin(beta * x))

    def slope(x):
        return beta * (np.sinh(beta * x) + np.sin(beta * x) - sigma * (np.cosh(beta * x) - np.cos(beta * x)))
    return shape, slope


def test_southwell_form_of_the_flap_frequencies():
    """ω² ≈ ω₀² + K Ω²: at small speeds the multibody blade's K of the first two flap modes is
    Rayleigh's ∫ T φ'² / ∫ m φ² of the cantilever's own mode with the centrifugal tension
    T = m Ω² (L² - r²) / 2 (K₁ = 1.1933, K₂ = 6.478 here, by quadrature of the closed-form modes);
    at higher speeds Southwell's form, an upper bound, overestimates ω² (the mode shape
    adapts): by 0.11 % at Ω* = 2, 6.2 % at Ω* = 12 and 15 % at Ω* = 50."""
    at_rest = rotating_frequencies(ModalBlade(UNIT, (4, 0, 0), omega=0.0), 0.0)["flap"]
    for n, beta in enumerate(EULER_BERNOULLI[:2]):
        shape, slope = _euler_bernoulli_mode(brentq(lambda b: np.cos(b) * np.cosh(b) + 1, beta - 0.1, beta + 0.1))
        southwell = quad(lambda x: (1 - x * x) / 2 * slope(x) ** 2, 0, 1)[0] / quad(lambda x: shape(x) ** 2, 0, 1)[0]
        slow = rotating_frequencies(ModalBlade(UNIT, (4, 0, 0), omega=0.1), 0.1)["flap"][n]
        assert (slow**2 - at_rest[n] ** 2) / 0.1**2 == pytest.approx(southwell, rel=1e-4)
        assert southwell == pytest.approx((1.1933, 6.478)[n], abs=1e-3)
    k1 = quad(lambda x: (1 - x * x) / 2 * _euler_bernoulli_mode(EULER_BERNOULLI[0])[1](x) ** 2, 0, 1)[0] / \
        quad(lambda x: _euler_bernoulli_mode(EULER_BERNOULLI[0])[0](x) ** 2, 0, 1)[0]
    for speed, over in ((2.0, 0.00107), (12.0, 0.062), (50.0, 0.148)):
        found = rotating_frequencies(ModalBlade(UNIT, (4, 0, 0), omega=speed), speed)["flap"][0]
        assert (at_rest[0] ** 2 + k1 * speed**2) / found**2 - 1 == pytest.approx(over, rel=0.02)


def test_a_fixed_non_rotating_basis_holds_to_moderate_speeds():
    """The cantilever's own modes (four per direction) at every speed: the first flap frequency
    within 0.5 % of the table up to Ω* = 10, the lag within 0.5 % of √(ω_flap² - Ω*²) up to
    Ω* = 10; at Ω* = 50 the rotating beam's mode is far from the cantilever's and four such
    modes are 1.1 % off in flap and 24 % in lag (which is why the blade takes its own rotating
    modes at the rotor speed)."""
    for speed in (2, 6, 10):
        found = rotating_frequencies(ModalBlade(UNIT, (4, 4, 0), omega=0.0), float(speed))
        assert found["flap"][0] == pytest.approx(FLAP_PUBLISHED[speed], rel=5e-3)
        assert found["lag"][0] == pytest.approx(np.sqrt(FLAP_PUBLISHED[speed] ** 2 - speed**2), rel=5e-3)
    far = rotating_frequencies(ModalBlade(UNIT, (4, 4, 0), omega=0.0), 50.0)
    assert far["flap"][0] / FLAP_PUBLISHED[50] - 1 == pytest.approx(0.011, abs=0.002)
    assert far["lag"][0] / np.sqrt(FLAP_PUBLISHED[50] ** 2 - 2500) - 1 == pytest.approx(0.24, abs=0.01)


@pytest.mark.parametrize("speed, published", CHORDWISE_SLENDERNESS_70.items())
def test_the_extensible_beam_has_the_published_chordwise_frequencies(speed, published):
    """EA = 70² EI / L² and axial modes: the chordwise frequency by the linear theory (about the
    undeformed beam, as the table) within 0.5 % (0.03 % in fact) with four lag and four axial
    modes, below the inextensible beam's: the stretch's Coriolis coupling, from the kinematics."""
    beam = ModalBlade(replace(UNIT, axial_stiffness=70.0**2), {"lag": 4, "axial": 4}, omega=float(speed))
    found = rotating_frequencies(beam, float(speed), linear=True)["lag"][0]
    assert found == pytest.approx(published, rel=5e-3)
    assert found == pytest.approx(published, rel=3e-4)
    assert found < np.sqrt(FLAP_PUBLISHED[speed] ** 2 - speed**2)


def test_where_the_rotor_blade_stretch_stops_mattering():
    """The Bo105 blade (lag 0.68/rev) made extensible: the first lag frequency about its
    stretched equilibrium falls in proportion to the centrifugal strain m Ω² L² / EA, by
    0.08 % at 0.28 % strain (EA = 1e8 N, a composite blade's order) and 0.27 % at 0.93 %; the
    inextensible blade is the limit. Rotor blades strain a few tenths of a per cent at most, so
    leaving the stretch out changes the lag frequency by less than 0.1 %."""
    d = aircraft.load().data
    blade, omega = blade_from_data(d), d["main_rotor"]["omega"]
    modes = {"flap": 1, "lag": 4, "torsion": 1, "axial": 3}
    stiff = rotating_frequencies(ModalBlade(blade, (1, 4, 1), omega), omega)["lag"][0]
    drops = {}
    for ea in (1e10, 1e8, 3e7):
        beam = ModalBlade(replace(blade, axial_stiffness=ea), modes, omega)
        strain = blade.mass * omega**2 * blade.length**2 / ea
        drops[strain] = 1 - rotating_frequencies(beam, omega)["lag"][0] / stiff
    strains = sorted(drops)
    assert drops[strains[0]] < 2e-5 and 0 < drops[strains[1]] < 1e-3 < drops[strains[2]] < 3e-3
    assert drops[strains[2]] / drops[strains[1]] == pytest.approx(strains[2] / strains[1], rel=0.1)


def test_the_bo105_modal_blade_has_the_continuous_blades_frequencies():
    """The blade of the aircraft file, one mode per direction (its own rotating modes), against
    the continuous blade's finite elements behind the file (:func:`beam_frequencies`): flap,
    lag and torsion within 0.1 % at the rotor speed, also with a hub radius of 0.5 m."""
    d = aircraft.load().data
    omega = d["main_rotor"]["omega"]
    for root in (0.0, 0.5):
        blade = replace(blade_from_data(d), root=root)
        found = rotating_frequencies(ModalBlade(blade, (1, 1, 1), omega), omega)
        reference = beam_frequencies(blade, omega)
        for k in ("flap", "lag", "torsion"):
            assert found[k][0] == pytest.approx(reference[k], rel=1e-3), (root, k)


def test_bad_mode_counts_are_refused():
    for bad, words in (((1, -1, 1), "lag = -1"), ((0, 0, 0), "at least one mode"), ({"twist": 1}, "unknown mode"),
                       ((1, 1, 1, 1), "axial stiffness EA"), (0.5, "give one whole count"),
                       (2.0, "give one whole count"), ((1, 2.5, 1), "lag = 2.5")):
        with pytest.raises(ValueError, match=words):
            ModalBlade(UNIT, bad, 0.0)
