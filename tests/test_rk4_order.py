"""RK4 converges at fourth order on a conservative rotor tree."""
import numpy as np
import pytest

import mbs
from mbs.models.demo import spinning_rotor

REVS, OMEGA = 2, 44.4


@pytest.fixture(scope="module")
def rotor2():
    return mbs.build(spinning_rotor(n_blades=2, free_fuselage=True, omega=OMEGA), "compiled")


def _run(system, steps_per_rev):
    T = 2 * np.pi / OMEGA
    return system.run(system.x0(), 0.0, T / steps_per_rev, steps_per_rev * REVS)


def _max_energy_error(system, traj):
    e = np.array([system.energy(x)[-1] for x in traj.x])
    return np.abs(e / e[0] - 1).max()


def test_rk4_final_state_error_falls_16x_per_halving(rotor2):
    ref = _run(rotor2, 6400).x[-1]
    errors = [np.linalg.norm(_run(rotor2, n).x[-1] - ref) for n in (100, 200, 400)]
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(np.abs(ratios / 16 - 1) <= 0.25), ratios


def test_rk4_energy_error_falls_at_least_14x_per_halving(rotor2):
    errors = [_max_energy_error(rotor2, _run(rotor2, n)) for n in (100, 200)]
    assert errors[0] / errors[1] >= 14, errors


def test_rk8_converges_at_eighth_order(rotor2):
    """The Dormand-Prince 8th-order weights with a fixed step: halving the step divides the
    final-state error by 2^8 (observed order within 0.5 of 8)."""
    def final(steps_per_rev):
        T = 2 * np.pi / OMEGA
        return rotor2.run(rotor2.x0(), 0.0, T / steps_per_rev, steps_per_rev * REVS, method="rk8").x[-1]

    ref = final(1600)
    e1, e2 = (np.linalg.norm(final(n) - ref) for n in (25, 50))
    assert abs(np.log2(e1 / e2) - 8) <= 0.5, (e1, e2)
