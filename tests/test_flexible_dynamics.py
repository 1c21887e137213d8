"""A flexible body in the tree's dynamics: the segmented chain's limit, the paper's Jacobians
against finite differences, the mass matrix as J_uᵀ M J_u, energy conservation at RK4's order,
and the dynamics paths it takes."""
import re
from dataclasses import replace

import numpy as np
import pytest
from scipy.linalg import block_diag
from scipy.spatial.transform import Rotation

import mbs
from mbs.dynamics import symbolic
from mbs.flexible.beam import ModalBlade
from mbs.flexible.body import add_flexible_blade
from mbs.flexible.uniform_blade import Blade
from mbs.linearize import rhs_jacobian
from mbs.models import helicopter
from mbs.models.elastic_blade import add_segmented_blade
from trees import random_state, random_tree

BLADE = Blade(root=0.2, tip=1.2, mass=2.0, chord=0.1, thickness=0.02, flap_stiffness=60.0, lag_stiffness=150.0,
              torsion_stiffness=2.0, damping_time=(2e-3, 1e-3, 4e-3))
FRAME = Rotation.from_euler("xyz", [0.3, -0.2, 0.5]).as_matrix()


def tree_with_blade(kind: str, n, seed: int = 5, dampers: bool = False, free_base: bool = False):
    """A random tree of 6 bodies with ``BLADE`` on its body b3 (placed off its origin, turned):
    a flexible body of ``n`` modes per direction (``kind="modal"``) or a chain of ``n`` segments."""
    m = random_tree(seed, 6, free_base=free_base)
    if kind == "modal":
        add_flexible_blade(m, ModalBlade(BLADE, n, 0.0), "blade", "b3", at=BLADE.root * FRAME[:, 0], frame=FRAME,
                           dampers=dampers)
    else:
        add_segmented_blade(m, BLADE, n, "blade", "b3", FRAME, dampers=dampers)
    return m


def _tree_coordinates(system) -> list[int]:
    return [i for i, n in enumerate(system.info.q_names) if re.match(r"b\d", n)]


def _run_tree(model, step: float, duration: float = 0.3) -> np.ndarray:
    """The random tree's own coordinates after ``duration`` s from random rates, blade at rest."""
    system = mbs.build(model, "compiled")
    x, rig = system.x0(), _tree_coordinates(system)
    x[[system.info.nq + i for i in rig]] = np.random.default_rng(1).normal(size=len(rig))
    n = int(round(duration / step))
    traj = system.run(x, 0.0, step, n, every=n)
    assert traj.ok, traj.message
    return traj.x[-1][rig]


def test_a_flexible_body_in_a_random_tree_is_the_limit_of_the_segmented_chain():
    """The tree (gravity, springs, dampers) moving 0.3 s with the blade as a modal body (four
    modes per direction; two give the same to 4e-6 of the motion) and as chains of 4, 8 and 16
    rigid segments: the chain's difference from the modal body falls with every doubling of
    the segments, nearly as 1/n² (by 3.6 and 3.3: 3.9e-4, 1.1e-4, 3.3e-5 of the motion)."""
    modal = _run_tree(tree_with_blade("modal", 4), 1e-4)
    scale = np.abs(modal).max()
    assert np.abs(_run_tree(tree_with_blade("modal", 2), 1e-4) - modal).max() < 1e-5 * scale
    gaps = [np.abs(_run_tree(tree_with_blade("chain", n), 1e-4) - modal).max() / scale for n in (4, 8, 16)]
    assert gaps[0] / gaps[1] > 2.5 and gaps[1] / gaps[2] > 2.5, gaps
    assert gaps[2] < 5e-5, gaps


@pytest.fixture(scope="module")
def flexible_tree():
    model = tree_with_blade("modal", (2, 2, 1), seed=7, dampers=True, free_base=True)
    return model, mbs.build(model, "vm")


def _deformed(system, seed: int) -> np.ndarray:
    """A random state with the blade bent and twisted (modal coordinates ~0.05) and moving."""
    return random_state(system, seed, scale=0.3) * np.r_[np.ones(system.info.nq), np.ones(system.info.nv)]


def test_section_jacobians_by_ad_equal_finite_differences(flexible_tree):
    """``J_u`` and ``H`` of every body, the flexible body's sections included (their columns in
    the modal rates: the elastic Jacobians), against central differences, to 1e-7."""
    _, system = flexible_tree
    nq, t = system.info.nq, 0.37
    x = _deformed(system, 3)
    _, ju, h = system.kinematics(x, t)
    sections = [i for i, b in enumerate(system.info.bodies) if b["name"].startswith("blade:")]
    assert sections and np.abs(ju[6 * sections[0]:6 * sections[-1] + 6, -5:]).max() > 0.1  # elastic columns

    def velocities(xx, tt):
        return system.kinematics(xx, tt)[0]

    d = 1e-5
    fd_ju = np.column_stack([(velocities(x + d * e, t) - velocities(x - d * e, t)) / (2 * d)
                             for e in np.eye(system.info.nx)[nq:]])
    rates = np.r_[system.rhs(x, t)[:nq], np.zeros(system.info.nv)]
    fd_h = (velocities(x + d * rates, t + d) - velocities(x - d * rates, t - d)) / (2 * d)
    assert np.abs(ju - fd_ju).max() <= 1e-7 * np.abs(ju).max()
    assert np.abs(h - fd_h).max() <= 1e-7 * np.abs(h).max() and np.abs(h).max() > 0.1


def test_the_mass_matrix_with_a_flexible_body_is_ju_t_m_ju(flexible_tree):
    """The composite path's ``Mt`` (sections' momentum and own block added to the subtree sums)
    equals the paper's product over every body and section, to 1e-12."""
    model, system = flexible_tree
    x, t = _deformed(system, 5), 0.37
    ju = system.kinematics(x, t)[1]
    m = block_diag(*[block_diag(b.mass * np.eye(3), b.inertia) for b in model.order()])
    mt = np.array(system.functions["parts"](x, t, system.params())[1])
    assert np.abs(mt - ju.T @ m @ ju).max() <= 1e-12 * np.abs(mt).max()


def test_the_state_jacobian_by_ad_equals_finite_differences(flexible_tree):
    """The exact Jacobian of the right-hand side (linearisation, Floquet) against central
    differences, to 1e-7 of its largest entry."""
    model, system = flexible_tree
    x, t, p = _deformed(system, 9), 0.2, system.params()
    jac = np.array(rhs_jacobian(system.functions["rhs"])(x, t, p))
    d = 1e-6
    fd = np.column_stack([(system.rhs(x + d * e, t) - system.rhs(x - d * e, t)) / (2 * d)
                          for e in np.eye(system.info.nx)])
    assert np.abs(jac - fd).max() <= 1e-7 * np.abs(jac).max()


def test_a_flexible_model_takes_the_composite_path():
    """The sections share their body's modal rates, which the articulated recursion does not
    take: the composite path is chosen, and asking for the other is refused in one line."""
    model = tree_with_blade("modal", 1)
    assert symbolic(model).path == "composite"
    with pytest.raises(ValueError, match="has flexible bodies.*articulated path takes rigid bodies only"):
        symbolic(model, path="articulated")


# -- energy -------------------------------------------------------------------------------

STRUCTURAL = helicopter.Config(rotors="free", rotor_aero=False, airframe_aero=False, dampers=False, tail_rotor=False,
                               blade_modes=(2, 2, 1))


@pytest.fixture(scope="module")
def structural():
    """The paper's conservative case with modal blades: free fuselage, free hub spinning from
    the initial condition, free pitch bearings, no aerodynamics or dampers, gravity on."""
    return mbs.build(helicopter.build(STRUCTURAL, name="structural-modal"), "compiled")


def _run(system, steps_per_rev, revs=2):
    period = 2 * np.pi / 44.4
    x = system.x0(**{"blade1.flap_rate": 2.0, "blade2.lag_rate": -1.0, "blade3.torsion_rate": 3.0})
    return system.run(x, 0.0, period / steps_per_rev, steps_per_rev * revs)


def _energy_error(system, traj) -> float:
    e = np.array([system.energy(x)[-1] for x in traj.x])
    return float(np.abs(e / e[0] - 1).max())


def test_a_conservative_flexible_model_keeps_its_energy_at_rk4_order(structural):
    """Flexible blades, no sources or sinks: the relative energy error falls at least 14x per
    halving of the step (fourth order, as the rigid tree's) and the final state's error
    converges at an observed order within 0.5 of 4; the elastic energy takes part (the blades
    vibrate)."""
    errors = [_energy_error(structural, _run(structural, n)) for n in (100, 200)]
    assert errors[0] / errors[1] >= 14, errors
    ref = _run(structural, 6400).x[-1]
    finals = [np.linalg.norm(_run(structural, n).x[-1] - ref) for n in (200, 400, 800)]
    orders = np.log2(np.array(finals[:-1]) / np.array(finals[1:]))
    assert np.all(np.abs(orders - 4) <= 0.5), orders
    energy = structural.energy(_run(structural, 100, revs=1).x[-1])
    assert energy[3] > 1.0  # strain energy of the vibrating blades, J
