"""J_u and H from forward-mode AD agree with central finite differences of body velocities."""
import numpy as np
import pytest

import mbs
from mbs.models.demo import driven_rotor
from trees import random_state, random_tree


def _velocities(system, x, t):
    return system.kinematics(x, t)[0]


@pytest.mark.parametrize("make", [driven_rotor, lambda: random_tree(7, 12, True)], ids=["driven-rotor", "random"])
def test_ju_and_h_match_finite_differences(make):
    system = mbs.build(make(), "vm")
    nq, t = system.info.nq, 0.37
    x = random_state(system, 3, scale=0.3)
    V, Ju, H = system.kinematics(x, t)
    d = 1e-4
    fd_ju = np.column_stack([(_velocities(system, x + d * e, t) - _velocities(system, x - d * e, t)) / (2 * d)
                             for e in np.eye(system.info.nx)[nq:]])
    F = np.r_[system.rhs(x, t)[:nq], np.zeros(system.info.nv)]
    d = 1e-5
    fd_h = (_velocities(system, x + d * F, t + d) - _velocities(system, x - d * F, t - d)) / (2 * d)
    assert np.abs(Ju - fd_ju).max() <= 1e-6 * np.abs(Ju).max()
    assert np.abs(H - fd_h).max() <= 1e-6 * np.abs(H).max()
    assert np.abs(H).max() > 0.1  # H is not trivially zero


@pytest.mark.parametrize("make", [driven_rotor, lambda: random_tree(11, 12, True)], ids=["driven-rotor", "random"])
def test_composite_mass_matrix_is_the_product_ju_t_m_ju(make):
    """The generated ``Mt`` (summed over subtrees) equals the paper's product J_uᵀ M J_u."""
    from scipy.linalg import block_diag

    model = make()
    system = mbs.build(model, "vm")
    x, t = random_state(system, 5, scale=0.3), 0.37
    ju = system.kinematics(x, t)[1]
    m = block_diag(*[block_diag(b.mass * np.eye(3), b.inertia) for b in model.order()])
    mt = np.array(system.functions["parts"](x, t, system.params())[1])
    assert np.abs(mt - ju.T @ m @ ju).max() <= 1e-12 * np.abs(mt).max()
