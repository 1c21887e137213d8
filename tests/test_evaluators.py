"""The virtual machine and the compiled code agree; float32 runs and keeps energy."""
import numpy as np
import pytest

from trees import random_state

STEP = 2 * np.pi / 44.4 / 100


def _outputs(system, name, x):
    out = getattr(system, name)(x, 0.1)
    return out if isinstance(out, tuple) else (out,)


def test_vm_and_compiled_agree_in_float64(rotor_vm, rotor_compiled):
    for seed in range(3):
        x = random_state(rotor_vm, seed, scale=0.2)
        for f in ("rhs", "energy", "kinematics", "poses"):
            for a, b in zip(_outputs(rotor_vm, f, x), _outputs(rotor_compiled, f, x)):
                assert np.abs(a - b).max() <= 1e-12 * max(1.0, np.abs(a).max()), f
    x0 = rotor_vm.x0()
    a, b = rotor_vm.run(x0, 0.0, STEP, 200, every=10), rotor_compiled.run(x0, 0.0, STEP, 200, every=10)
    assert a.ok and b.ok and np.array_equal(a.t, b.t)
    assert np.abs(a.x - b.x).max() <= 1e-12 * np.abs(a.x).max()


def test_float32_keeps_energy_of_spinning_tree(rotor_vm, rotor_compiled32):
    traj = rotor_compiled32.run(rotor_vm.x0(), 0.0, STEP, 1000, every=10)
    assert traj.ok and traj.x.shape == (101, rotor_vm.info.nx)
    e = np.array([rotor_vm.energy(x)[-1] for x in traj.x])
    assert np.abs(e / e[0] - 1).max() < 1e-5
    # it is really single precision: the states differ from float64 at the 1e-7 level
    ref = rotor_vm.run(rotor_vm.x0(), 0.0, STEP, 1000, every=10).x
    assert 1e-9 < np.abs(traj.x - ref).max() / np.abs(ref).max() < 1e-3


def test_nfev_counts_rhs_evaluations(rotor_compiled):
    before = rotor_compiled.nfev
    rotor_compiled.run(rotor_compiled.x0(), 0.0, STEP, 10)
    rotor_compiled.rhs(rotor_compiled.x0())
    assert rotor_compiled.nfev - before == 4 * 10 + 1


def test_large_sources_compile_at_o1_small_ones_at_o2():
    from mbs.backends.compiled import CFLAGS, LARGE_SOURCE_BYTES, compile_flags

    assert compile_flags("x" * LARGE_SOURCE_BYTES) == CFLAGS
    big = compile_flags("x" * (LARGE_SOURCE_BYTES + 1))
    assert "-O1" in big and "-O2" not in big and set(big) - {"-O1"} == set(CFLAGS) - {"-O2"}


def test_bound_calls_equal_checked_calls(rotor_vm, rotor_compiled):
    """A bound function reads its input buffers and writes its output buffers in place."""
    x = random_state(rotor_vm, 4, scale=0.2)
    for system in (rotor_vm, rotor_compiled):
        rhs, step = system.bind("rhs"), system.bind("step_rk4")
        for buf, value in zip(rhs.inputs, (x, 0.1, system.params())):
            buf[:] = value
        out = rhs.outputs[0]
        rhs()
        assert rhs.outputs[0] is out and np.abs(out - rotor_vm.rhs(x, 0.1)).max() <= 1e-12 * np.abs(out).max()
        for buf, value in zip(step.inputs, (x, 0.0, STEP, system.params())):
            buf[:] = value
        step()
        assert np.abs(step.outputs[0] - rotor_vm.step(x, 0.0, STEP)).max() <= 1e-12 * np.abs(x).max()


def test_bound_call_reports_a_failed_evaluation(rotor_compiled):
    import ctypes

    from mbs.backends.system import Bound

    failing = Bound("rhs", [], [], lambda: ctypes.c_int(1).value)
    with pytest.raises(FloatingPointError, match="generated function rhs reported an error"):
        failing()


def test_translation_units_keep_callers_with_callees(rotor_vm):
    """Functions sharing generated code (the right-hand side inside every step) compile in one
    unit, the fixed-step drivers' functions first; the others on their own, in parallel."""
    from mbs.backends.compiled import UNIT_SEPARATOR, generate, translation_units

    units = translation_units({n: f for n, f in rotor_vm.functions.items() if n != "parts"},
                              rotor_vm.info.methods)
    assert set(units[0]) == {"rhs", "project", *(f"{k}_{m}" for k in ("step", "incr") for m in rotor_vm.info.methods)}
    assert sorted(map(tuple, units[1:])) == [("energy",), ("kin",), ("outputs",), ("poses",)]
    source = generate(rotor_vm.functions, rotor_vm.info, "float64")
    parts = source.split(UNIT_SEPARATOR)
    assert len(parts) == len(units) and "mbs_run_rk4" in parts[0] and "int rhs(" in parts[0]
    assert sum("int rhs(" in p for p in parts) == 1 and not any("int parts(" in p for p in parts)
