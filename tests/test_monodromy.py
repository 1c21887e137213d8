"""The monodromy from forward-mode AD through the generated step equals central finite
differences of the fixed-step map; the period and tail-rotor symmetry of the Bo105 model."""
import numpy as np
import pytest

from mbs import scenes
from mbs.analysis.monodromy import TangentStepper
from mbs.analysis.period import rotor_period


def _central_differences(run, z, eps=1e-6):
    """Columns ``(run(z + e_i d) - run(z - e_i d)) / 2d``, ``d = eps max(1, |z_i|)``."""
    cols = []
    for i in range(z.size):
        d = np.zeros_like(z)
        d[i] = eps * max(1.0, abs(z[i]))
        cols.append((run(z + d) - run(z - d)) / (2 * d[i]))
    return np.array(cols).T


@pytest.fixture(scope="module")
def single_blade():
    sc = scenes.get("single-blade")
    return sc, sc.system("compiled")


@pytest.mark.parametrize("backend", ["compiled", "vm"])
@pytest.mark.parametrize("method", ["rk4", "rk8"])
def test_single_blade_monodromy_equals_central_differences(single_blade, backend, method):
    """One revolution (50 steps) from a displaced state: ``[dx/dx0, dx/dp]`` to 1e-6 relative."""
    sc, system = single_blade
    stepper = TangentStepper(sc.model(), method, backend)
    assert stepper.backend == backend
    x0, p = system.x0(**{"blade1.flap": 0.02, "blade1.lag": -0.01, "blade1.lag_rate": 0.3}), system.params()
    h, n, nx = sc.revolution(system) / 50, 50, system.info.nx
    sens = stepper.monodromy(x0, p, 0.0, h, n)
    run = lambda z: system.run(z[:nx], 0.0, h, n, every=n, p=z[nx:], method=method).x[-1]  # noqa: E731
    fd = _central_differences(run, np.r_[x0, p])
    assert np.abs(sens.x - run(np.r_[x0, p])).max() < 1e-13
    assert np.abs(sens.dx - fd).max() <= 1e-6 * np.abs(sens.dx).max()
    assert sens.steps == n and sens.nfev == n * stepper.stages and sens.nfwd >= n * stepper.stages * (nx + 1)


def test_narrower_blocks_give_the_same_sensitivities(single_blade, monkeypatch):
    """The block width bounds the generated code of large models (one direction per block for
    the 193-state elastic rotor, 8 for the Bo105 scenes); the derivative does not depend on it."""
    from mbs.analysis import monodromy

    assert [monodromy.block_width(nx, 4) for nx in (22, 35, 47, 48, 49, 193)] == [8, 8, 8, 8, 7, 1]
    sc, system = single_blade
    x0, p = system.x0(**{"blade1.flap": 0.02, "blade1.lag_rate": 0.3}), system.params()
    h = sc.revolution(system) / 50
    wide = TangentStepper(sc.model(), "rk4", "compiled")
    monkeypatch.setattr(monodromy, "STATE_DIRECTIONS_PER_BLOCK", system.info.nx)  # one direction per block
    narrow = TangentStepper(sc.model(), "rk4", "compiled")
    assert (wide.block, narrow.block) == (8, 1)
    a, b = wide.monodromy(x0, p, 0.0, h, 50), narrow.monodromy(x0, p, 0.0, h, 50)
    assert np.array_equal(a.x, b.x) and np.abs(a.dx - b.dx).max() <= 1e-13 * np.abs(a.dx).max()


def test_forward_flight_sensitivity_to_state_and_controls_equals_central_differences():
    """The full helicopter (33 states, 5 parameters), 6 steps from its initial state; the
    directions are propagated in blocks, so 38 columns test the padding of the last one."""
    sc = scenes.get("forward-flight")
    system = sc.system("compiled")
    stepper = TangentStepper(sc.model(), "rk4", "compiled")
    x0, p = system.x0(), system.params()
    h, n, nx = sc.revolution(system) / 100, 6, system.info.nx
    sens = stepper.monodromy(x0, p, 0.01, h, n)
    run = lambda z: system.run(z[:nx], 0.01, h, n, every=n, p=z[nx:]).x[-1]  # noqa: E731
    fd = _central_differences(run, np.r_[x0, p])
    assert np.abs(sens.dx - fd).max() <= 1e-6 * np.abs(sens.dx).max()


def test_bo105_period_is_four_revolutions_shot_over_two_with_the_teeter_reversed():
    system = scenes.get("forward-flight").system("compiled")
    period = rotor_period(system.info, 44.4, 5.25)
    names = system.info.state_names
    assert (period.revs, period.full_revs) == (2, 4)
    assert [names[i] for i in period.flip] == ["seesaw.teeter", "seesaw.teeter_rate"]
    assert rotor_period(scenes.get("single-blade").system("compiled").info, 44.4).revs == 1


def test_the_model_is_equivariant_under_the_half_period_symmetry():
    """``f(x, t + 2T) = S f(S x, t)`` at a generic state: the tail rotor, turned by half a
    revolution, is the same rotor with the teeter reversed."""
    system = scenes.get("forward-flight").system("compiled")
    period = rotor_period(system.info, 44.4, 5.25)
    s = period.symmetry(system.info.nx)
    x = system.run(system.x0(**{"seesaw.teeter": 0.01}), 0.0, 1e-3, 37).x[-1]
    t = 0.0123
    lhs, rhs = system.rhs(x, t + period.duration), s * system.rhs(s * x, t)
    assert np.abs(lhs - rhs).max() <= 1e-9 * np.abs(lhs).max()
    assert np.abs(lhs - system.rhs(x, t)).max() > 1e-3 * np.abs(lhs).max()  # time does matter


def test_a_gear_ratio_without_a_short_period_is_refused_by_the_model_s_period():
    """Lynx-like 5.209 (185.6/35.63 rad/s) repeats only after 1000 revolutions: a model turning
    its tail rotor so has no period to shoot over (the periodic analyses build the model of
    :func:`mbs.analysis.period.periodic_scene`, whose ratio repeats, instead); a rigid tail rotor
    of four identical blades repeats after a quarter of its turn (5.25: one main-rotor revolution)."""
    system = scenes.get("forward-flight").system("compiled")
    with pytest.raises(ValueError, match=r"gear ratio 5.209 repeats the rotors only every 1000 main-rotor "
                                         r"revolutions.* at 5.2142857 instead \(period 14 .*speed \+0.1015 %\).*"
                                         r"repeats sooner.*gear ratio of e.g. 5.21429"):
        rotor_period(system.info, 44.4, 5.209)
    rigid = scenes.get("forward-flight", "lynx").system("compiled")
    assert rotor_period(rigid.info, 35.63, 5.25).revs == 1 and rotor_period(rigid.info, 35.63, 5.8).revs == 5
