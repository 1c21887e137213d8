"""Bad input gives a clear error naming the bad body, joint or value."""
import numpy as np
import pytest

import mbs
from mbs import Hinge, Model


def _model() -> Model:
    m = Model("m")
    m.add_parameter("omega", 10.0, "rad/s")
    m.add_body("a", "world", Hinge((0, 0, 1)), mass=1.0)
    return m


def test_unknown_parent():
    m = _model()
    m.add_body("b", "nowhere", Hinge((0, 0, 1)), mass=1.0)
    with pytest.raises(ValueError, match="body 'b': unknown parent 'nowhere'"):
        mbs.build(m, "vm")


def test_duplicate_names():
    m = _model()
    with pytest.raises(ValueError, match="duplicate body name 'a'"):
        m.add_body("a", "world", Hinge((0, 0, 1)), mass=1.0)
    with pytest.raises(ValueError, match="duplicate parameter name 'omega'"):
        m.add_parameter("omega", 1.0)


def test_cycle():
    m = _model()
    m.add_body("b", "c", Hinge((0, 0, 1)), mass=1.0)
    m.add_body("c", "b", Hinge((0, 0, 1)), mass=1.0)
    with pytest.raises(ValueError, match=r"bodies \['b', 'c'\] form a cycle"):
        mbs.build(m, "vm")


@pytest.mark.parametrize("mass", [0.0, -1.0, float("nan")])
def test_non_positive_mass(mass):
    with pytest.raises(ValueError, match=f"body 'b': mass {mass} kg must be positive"):
        _model().add_body("b", "a", Hinge((0, 0, 1)), mass=mass)


@pytest.mark.parametrize("inertia, words", [
    ([[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], "is not symmetric"),
    (np.diag([1.0, -1.0, 1.0]), "is not positive definite"),
    (np.diag([1.0, 1.0, 3.0]), "violate the triangle inequality"),
])
def test_bad_inertia(inertia, words):
    with pytest.raises(ValueError, match=f"body 'b': .*{words}"):
        _model().add_body("b", "a", Hinge((0, 0, 1)), mass=1.0, inertia=inertia)


def test_bad_joint_axis():
    with pytest.raises(ValueError, match="joint axis .* must be a finite non-zero vector"):
        Hinge((0, 0, 0))


def test_non_finite_state_and_input():
    system = mbs.build(_model(), "vm")
    with pytest.raises(ValueError, match=r"state x\[1\] \('a.angle_rate'\) is nan"):
        system.rhs([0.0, np.nan])
    with pytest.raises(ValueError, match="parameter 'omega' is inf"):
        system.rhs([0.0, 0.0], p={"omega": np.inf})
    with pytest.raises(ValueError, match="unknown parameter 'omgea'"):
        system.rhs([0.0, 0.0], p={"omgea": 1.0})
    with pytest.raises(ValueError, match=r"state must have shape \(2,\)"):
        system.rhs([0.0])
    with pytest.raises(ValueError, match="step size h = -0.1 s must be positive"):
        system.run([0.0, 0.0], 0.0, -0.1, 10)


def test_divergence_is_reported_not_returned_as_nan():
    m = Model("stiff", gravity=(0, 0, 0))
    m.add_body("a", "world", Hinge((0, 0, 1), stiffness=1e6), mass=1.0, com=(1, 0, 0),
               inertia=np.eye(3) * 0.1)
    system = mbs.build(m, "vm")
    traj = system.run(system.x0(**{"a.angle": 0.1}), 0.0, 0.01, 2000)  # h*omega ~ 9.5 > 2.83
    assert traj.result is mbs.Result.nonfinite and "stability limit" in traj.message
    assert np.all(np.isfinite(traj.x))


def test_missing_compiler_names_the_fallback(monkeypatch):
    monkeypatch.setenv("CC", "no-such-compiler-xyz")
    with pytest.raises(ValueError, match="backend='vm'") as err:
        mbs.build(_model(), "compiled")
    assert isinstance(err.value, mbs.CompilerNotFound)


def test_vm_refuses_float32():
    with pytest.raises(ValueError, match="float64 only"):
        mbs.build(_model(), "vm", "float32")


def test_extra_state_needs_a_rate():
    m = _model()
    m.add_state("inflow", 1.0, "m/s")
    with pytest.raises(ValueError, match=r"no force element sets the rate of extra states \['inflow'\]"):
        mbs.build(m, "vm")

