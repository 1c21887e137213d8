"""The modal elastic rotor (``elastic-rotor-modal``: Bo105 blades as flexible bodies) against
the segmented blade of 32 segments, its hover trim and Floquet analysis, and the scene."""
from dataclasses import replace

import numpy as np
import pytest

import mbs
from mbs import aircraft, scenes
from mbs.dynamics import symbolic
from mbs.flexible.frequencies import classify, equilibrium
from mbs.analysis.blade_modes import modal_frequencies, segmented_frequencies
from mbs.flexible import uniform_blade as ub
from mbs.linearize import rhs_jacobian
from mbs.models import elastic_blade as eb
from mbs.models import helicopter
from mbs.models.helicopter.scenes import ELASTIC_ROTOR, ELASTIC_ROTOR_MODAL

DATA = aircraft.load().data
OMEGA = DATA["main_rotor"]["omega"]
MODES = ELASTIC_ROTOR_MODAL.blade_modes


def test_the_modal_blade_has_the_32_segment_blades_frequencies():
    """One blade in vacuum on its driven hub: the scene's modal blade's first flap, lag and
    torsion frequencies within 1 % of the 32-segment chain's (0.15 % in fact; both within
    0.2 % of the continuous blade behind the data file)."""
    modal, chain = modal_frequencies(MODES), segmented_frequencies(32)
    targets = {k: DATA["elastic_blade"][f"{k}_frequency"] * OMEGA for k in ub.DIRECTIONS}
    for k in ub.DIRECTIONS:
        assert modal[k] == pytest.approx(chain[k], rel=1e-2), k
        assert modal[k] == pytest.approx(chain[k], rel=2e-3), k
        assert modal[k] == pytest.approx(targets[k], rel=2e-3) and chain[k] == pytest.approx(targets[k], rel=2e-3)


def _hover_model(cfg, name, data=None):
    """``cfg``'s rotor (of the aircraft ``data``, default the Bo105) at the hover collective
    without cyclic: axisymmetric, so its periodic solution is an equilibrium in the turning frame."""
    model = helicopter.build(cfg, data, name=name)
    for c in ("lateral_cyclic", "longitudinal_cyclic"):
        model.parameters[c].default = 0.0
    return model


def _hover(cfg, name):
    """(thrust N, per direction the frequencies rad/s, state, model) of the axisymmetric hover:
    the equilibrium by Newton on the AD residual, the frequencies the eigenvalues of the AD
    Jacobian there."""
    model = _hover_model(cfg, name)
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    start = np.zeros(sym.layout.nx)
    start[sym.layout.nq + sym.layout.nv:] = [model.states[n].initial for n in sym.layout.z_names]
    x = equilibrium(sym, p, start)
    thrust = float(np.array(sym["outputs"](x, 0.0, p)).ravel()[list(model.outputs).index("main_rotor.thrust")])
    return thrust, classify(np.array(rhs_jacobian(sym["rhs"])(x, 0.0, p)), sym.layout.q_names), x, model


@pytest.fixture(scope="module")
def hover_modal():
    return _hover(ELASTIC_ROTOR_MODAL, "modal-hover")


@pytest.fixture(scope="module")
def hover_chain32():
    return _hover(replace(ELASTIC_ROTOR, blade_segments=32), "chain32-hover")


def _outputs(model, x) -> dict[str, float]:
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    return dict(zip(model.outputs, np.array(sym["outputs"](x, 0.0, p)).ravel()))


def test_the_modal_rotors_hover_equals_the_32_segment_rotors(hover_modal, hover_chain32):
    """Hinge-free rotor, hover collective, four blades, aerodynamics with uniform dynamic
    inflow: the periodic solution (an equilibrium in the turning frame) and its Floquet
    exponents (the Jacobian's eigenvalues there) of the modal rotor against the rotor of
    32-segment blades: thrust within 0.5 % (0.05 %: 17689 N against 17680 N, the chain's
    thrust still rising 9 N per doubling of its segments), first flap, lag and torsion
    frequencies within 1 % (0.2 %)."""
    thrust, found = hover_modal[:2]
    chain_thrust, chain = hover_chain32[:2]
    assert thrust == pytest.approx(chain_thrust, rel=5e-3)
    assert thrust == pytest.approx(chain_thrust, rel=1e-3)
    for k in ub.DIRECTIONS:
        assert found[k][0] == pytest.approx(chain[k][0], rel=1e-2), k
        assert found[k][0] == pytest.approx(chain[k][0], rel=3e-3), k


def test_the_modal_blades_spanwise_moments_equal_the_32_segment_blades(hover_modal, hover_chain32):
    """Torsion, flap and lag bending moments of blade 1 in the axisymmetric hover at the
    8-segment blade's joint radii (``blade1.station2`` … ``station8``): the modal blade's,
    stiffness times curvature, against the 32-segment blade's joint loads (its springs'
    moments) interpolated to those radii, within 3 % of the chain's largest moment of each
    kind (measured: 2.4 %, 2.5 % and 2.0 %; two modes per direction give a curvature
    with two shapes' worth of detail)."""
    from mbs.models.modal_blade import station_radii

    modal, chain = _outputs(hover_modal[3], hover_modal[2]), _outputs(hover_chain32[3], hover_chain32[2])
    inner = eb.layout(ub.blade_from_data(DATA), 32)[0][1:]
    for comp in ("moment_x", "moment_y", "moment_z"):
        profile = np.array([chain[f"blade1.station{j}.{comp}"] for j in range(2, 33)])
        scale = np.abs(profile).max()
        for j, radius in station_radii(DATA).items():
            assert modal[f"blade1.station{j}.{comp}"] == pytest.approx(np.interp(radius, inner, profile),
                                                                       abs=0.03 * scale), (comp, j)


def test_a_mirrored_modal_blade_has_the_same_spanwise_moments(hover_modal, tmp_path):
    """The Bo105 mirrored (clockwise rotor) at the same collective: the modal blade's station
    moments, read as those of the mirror image, equal the counter-clockwise rotor's (1e-8 of
    the largest)."""
    from aircraft_files import mirrored

    cw = aircraft.load(mirrored(tmp_path / "mirrored.toml"))
    model = _hover_model(ELASTIC_ROTOR_MODAL, "modal-hover-cw", cw)
    model.parameters["collective"].default = hover_modal[3].parameters["collective"].default  # its own trim differs
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    start = np.zeros(sym.layout.nx)
    start[sym.layout.nq + sym.layout.nv:] = [model.states[n].initial for n in sym.layout.z_names]
    got, want = _outputs(model, equilibrium(sym, p, start)), _outputs(hover_modal[3], hover_modal[2])
    names = [n for n in want if ".station" in n]
    assert len(names) == 4 * 7 * 3
    scale = max(abs(want[n]) for n in names)
    for n in names:
        assert got[n] == pytest.approx(want[n], abs=1e-8 * scale), n


@pytest.fixture(scope="module")
def evaluators():
    """The scene's compiled model and tangent stepper (built once)."""
    from mbs.analysis.trim import evaluators as build

    return build(scenes.get("elastic-rotor-modal"))


def test_the_modal_rotors_shooting_trim_and_floquet_equal_its_equilibrium(hover_modal, evaluators):
    """The generated RK4 driver's periodic solution (Newton shooting over one revolution of
    N = 120 steps) of the axisymmetric hover is the equilibrium (states to 1e-6 of their
    scale), and its Floquet multipliers (eigenvalues of the monodromy of the discrete map, by
    forward AD through it) are those of RK4 applied to the Jacobian there: ``R(hλ)^N`` for
    each eigenvalue λ, with ``R`` RK4's stability polynomial, to 1e-7."""
    from mbs.analysis.floquet import analyse
    from mbs.analysis.trim import periodic_solution

    system, stepper = evaluators
    x_eq, model = hover_modal[2:]
    sc = scenes.get("elastic-rotor-modal")
    cyclic = [q for q in system.info.parameters if q["name"] in ("lateral_cyclic", "longitudinal_cyclic")]
    saved = [q["default"] for q in cyclic]
    try:
        for q in cyclic:
            q["default"] = 0.0
        sol = periodic_solution(sc, system=system, stepper=stepper)
        result = analyse(sol, system, stepper)
    finally:
        for q, v in zip(cyclic, saved):
            q["default"] = v
    assert sol.converged
    assert np.abs(sol.x0 - x_eq).max() <= 1e-6 * np.abs(x_eq).max()
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    z = np.linalg.eigvals(np.array(rhs_jacobian(sym["rhs"])(x_eq, 0.0, p))) * 2 * np.pi / OMEGA / sc.steps_per_rev
    expected = (1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) ** sc.steps_per_rev
    got = np.array([m.multiplier for m in result.modes] + [np.conj(m.multiplier) for m in result.modes
                                                            if m.multiplier.imag != 0])
    assert len(got) == len(expected)
    assert max(np.abs(got - mu).min() for mu in expected) < 1e-7


def test_the_modal_scene_trims_and_is_stable_with_its_structural_damping(evaluators):
    """The scene (hover controls with cyclic): the periodic trim converges, every Floquet
    multiplier lies inside the unit circle, and the first torsion modes (collective and
    differential, 3.7/rev) have the data's structural damping ratio (1 %, within 20 %), as on
    the segmented rotor."""
    from mbs.analysis.floquet import floquet

    system, stepper = evaluators
    res = floquet("elastic-rotor-modal", system=system, stepper=stepper)
    assert res.trim.converged and max(abs(m.multiplier) for m in res.modes) < 0.95
    torsion = [m for m in res.modes if m.name in ("collective torsion", "differential torsion")
               and abs(m.per_rev - DATA["elastic_blade"]["torsion_frequency"]) < 0.1]
    assert torsion
    assert all(m.damping_ratio == pytest.approx(DATA["elastic_blade"]["structural_damping"], rel=0.2) for m in torsion)
