"""Elastic blades as chains of rigid segments: the continuous blade behind the data file, the
segmented blade's rotating frequencies against their targets, and the elastic-rotor scene."""
from dataclasses import replace

import numpy as np
import pytest

import mbs
from mbs import aircraft
from mbs.models import helicopter
from mbs.models.helicopter.scenes import ELASTIC_ROTOR
from mbs.analysis.blade_modes import segmented_frequencies
from mbs.flexible import uniform_blade as ub
from mbs.models import elastic_blade as eb

DATA = aircraft.load().data
OMEGA = DATA["main_rotor"]["omega"]
TARGETS = {k: DATA["elastic_blade"][f"{k}_frequency"] for k in ub.DIRECTIONS}


def test_the_data_files_stiffnesses_give_the_continuous_blade_its_target_frequencies():
    blade = ub.blade_from_data(DATA)
    found = ub.beam_frequencies(blade, OMEGA)
    assert all(abs(found[k] / OMEGA / TARGETS[k] - 1) < 1e-4 for k in ub.DIRECTIONS)
    derived = ub.calibrate(blade, OMEGA, TARGETS)
    assert all(abs(derived[k] / blade.stiffness(k) - 1) < 1e-3 for k in ub.DIRECTIONS)


def test_the_beam_model_gives_the_closed_forms_of_the_cantilever_at_rest():
    """Uniform cantilever: first bending 1.8751² √(EI/(m L⁴)), first torsion (π/2L) √(GJ/i)."""
    blade = ub.blade_from_data(DATA)
    found, length = ub.beam_frequencies(blade, 0.0), blade.length
    for k in ("flap", "lag"):
        assert found[k] == pytest.approx(1.875104**2 * np.sqrt(blade.stiffness(k) / (blade.mass * length**4)), rel=1e-6)
    exact = np.pi / (2 * length) * np.sqrt(blade.torsion_stiffness / blade.torsional_inertia)
    assert found["torsion"] == pytest.approx(exact, rel=1e-4)


def test_segmented_blade_frequencies_match_the_targets_and_converge():
    """Eigen analysis of the rotating multibody blade: within 1 % of the data's first flap, lag
    and torsion frequencies with 8 segments, and each error falls as the segments double."""
    errors = {n: {k: v / OMEGA / TARGETS[k] - 1 for k, v in segmented_frequencies(n).items()} for n in (8, 16, 32)}
    assert all(abs(e) < 0.01 for e in errors[8].values()), errors[8]
    for coarse, fine in ((8, 16), (16, 32)):
        assert all(abs(errors[fine][k]) < 0.6 * abs(errors[coarse][k]) for k in ub.DIRECTIONS), errors


def test_segments_carry_the_blade_mass_and_their_springs_its_flexibility():
    blade = ub.blade_from_data(DATA)
    m = helicopter.build(replace(ELASTIC_ROTOR, blades=1, rotor_aero=False), name="one-blade")
    segments = [m.bodies[n] for n in eb.segment_names("blade1", 8)]
    assert sum(b.mass for b in segments) == pytest.approx(DATA["main_rotor"]["blade_mass"], rel=1e-12)
    springs = {f.coordinate: f.stiffness for f in m.forces}
    for k in ub.DIRECTIONS:  # the hinges stand for the whole span: Σ 1/k = L / EI
        flexibility = sum(1 / springs[f"{b.name}.{k}"] for b in segments)
        assert flexibility == pytest.approx(blade.length / blade.stiffness(k), rel=1e-12)
    hinges = eb.layout(blade, 8)[0]
    assert np.allclose(np.diff(hinges), blade.length / 8) and hinges[0] == pytest.approx(blade.length / 32)


def test_elastic_rotor_scene_has_96_rates_and_the_rigid_rotors_thrust():
    """Four blades of 8 segments; at the start (straight blades at the estimated coning) the
    blade elements, spread over the segments, give the rigid rotor's thrust and torque."""
    elastic = mbs.build(helicopter.build(ELASTIC_ROTOR, name="elastic"), "vm")
    rigid = mbs.build(helicopter.build(replace(ELASTIC_ROTOR, blade_segments=0), name="rigid"), "vm")
    assert elastic.info.nv == 4 * 8 * 3 and elastic.info.nz == 1
    out = [dict(zip(s.info.output_names, s.outputs(s.x0()))) for s in (elastic, rigid)]
    for key in ("main_rotor.thrust", "main_rotor.torque"):
        assert out[0][key] == pytest.approx(out[1][key], rel=5e-3) and out[1][key] > 0
    h = mbs.scenes.get("elastic-rotor").revolution() / 200
    traj = elastic.run(elastic.x0(), 0.0, h, 40, every=10)
    assert traj.ok and np.abs(traj.x[-1][:elastic.info.nq]).max() < 0.2


@pytest.mark.parametrize("bad", [-1, 2.5, True])
def test_segment_counts_must_be_whole_and_positive(bad):
    with pytest.raises(ValueError, match=f"blade_segments = {bad!r}: an elastic blade needs a whole number"):
        helicopter.build(replace(ELASTIC_ROTOR, blade_segments=bad))


def test_a_free_pitch_bearing_in_front_of_the_elastic_blade_is_refused():
    """Its axis is the root torsion hinge's: the mass matrix would be singular."""
    with pytest.raises(ValueError, match="needs a driven pitch bearing or none"):
        helicopter.build(replace(ELASTIC_ROTOR, rotors="free"))
    free = helicopter.build(replace(ELASTIC_ROTOR, rotors="free", pitch_hinge=False, rotor_aero=False))
    system = mbs.build(free, "vm")
    assert np.all(np.isfinite(system.rhs(system.x0())))


def test_elastic_rotor_hover_is_stable_with_its_structural_damping():
    """Floquet analysis of the periodic hover (one direction per tangent call, 193 states):
    stable; the first torsion mode has the data's structural damping ratio (1 %, which the
    stiffness-proportional hinge dampers give at that frequency; the aerodynamics add little);
    the second torsion mode, weakly unstable without structural damping, decays."""
    from mbs.analysis.floquet import floquet

    res = floquet("elastic-rotor")
    assert res.trim.converged and max(abs(m.multiplier) for m in res.modes) < 0.95
    torsion = sorted((m for m in res.modes if m.name.endswith("torsion")), key=lambda m: m.per_rev)
    first = min(torsion, key=lambda m: abs(m.per_rev - 3.7))  # the collective/differential pair
    assert first.damping_ratio == pytest.approx(DATA["elastic_blade"]["structural_damping"], rel=0.2)
    second = [m for m in torsion if 10 < m.per_rev < 11]
    assert second and max(m.exponent.real for m in second) < -5.0
