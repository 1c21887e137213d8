"""Model exchange of the native FMU (FMI 2.0 and 3.0) under fmpy's CVode, against the core's
RK4, and the FMI 3.0 FMU against the FMI 2.0 one; the free fuselage's quaternion under a host's
integrator; a scene that clamps the fuselage; model-exchange misuse.

The FMUs are C only, so fmpy loads them in this process."""
from __future__ import annotations

import ctypes
import functools

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from fmu import build
from fmu.native import build as native_build

FAMILY = ("forward-flight", "hover", "ground-run")
CVODE_RTOL = 1e-10


@pytest.fixture(scope="module")
def fmus() -> dict:
    return {v: native_build.ensure_native_fmu(FAMILY, fmi=v)[0] for v in (2, 3)}


@functools.lru_cache(maxsize=1)
def family_spec() -> dict:
    return native_build.native_spec(FAMILY)[0]


@pytest.fixture(scope="module")
def spec() -> dict:
    return family_spec()


def revolution(spec: dict, scene: str) -> float:
    return spec["scenes"][scene]["revolution"]


def hinges(spec: dict) -> list[str]:
    return [v["name"] for v in spec["variables"] if v["causality"] == "output" and v.get("kind") == "state"
            and v["name"].endswith((".flap", ".lag", ".teeter"))]


def core_rk4(scene: str, revs: float, steps_per_rev: int = 400):
    """The core's RK4 run of ``scene`` (its defaults): (times, states, state names)."""
    from mbs import scenes
    from mbs.backends import build

    model = scenes.get(scene).model()
    vm = build(model, "compiled")
    rev = scenes.get(scene).revolution(vm, vm.params())
    n = int(round(revs * steps_per_rev))
    traj = vm.run(np.array(vm.info.x0), 0.0, rev / steps_per_rev, n, every=1, method="rk4")
    assert traj.ok, traj.message
    return traj.t, traj.x, vm.info.state_names


def me_run(fmu, scene: str, stop: float, interval: float, output: list[str], **kw):
    """fmpy's CVode on the ME FMU, ``scene`` as its own FMU starts it; without stopTime: fmpy's CVode
    asks for derivatives past it (it steps beyond an output point and interpolates back), which the
    FMU refuses as the standard requires."""
    return simulate_fmu(str(fmu), fmi_type="ModelExchange", solver="CVode", relative_tolerance=CVODE_RTOL,
                        stop_time=stop, output_interval=interval, output=output, set_stop_time=False,
                        start_values=build.scene_start_values(family_spec(), scene), **kw)


@pytest.mark.parametrize("scene", ["forward-flight", "hover"])
def test_cvode_run_of_the_me_fmu_equals_the_cores_rk4(scene, fmus, spec):
    """One revolution under fmpy's CVode (BDF, rtol 1e-10): every hinge angle equals the core's
    RK4 at 400 steps per revolution to 1e-6 rad."""
    rev, names = revolution(spec, scene), hinges(spec)
    res = me_run(fmus[2], scene, rev, rev / 100, names)
    t, x, states = core_rk4(scene, 1.0)
    assert res["time"][-1] == pytest.approx(rev, rel=1e-12)
    for name in names:
        core = np.interp(res["time"], t, x[:, states.index(name)])
        assert np.max(np.abs(res[name] - core)) < 1e-6, name
    worst = max(np.max(np.abs(res[n] - np.interp(res["time"], t, x[:, states.index(n)]))) for n in names)
    print(f"{scene}: CVode ME vs core RK4 (400/rev) largest hinge difference {worst:.2e} rad")


def _fmi3_elements(res, name: str) -> np.ndarray:
    """An FMI 3.0 array output of fmpy's result: (rows, elements)."""
    return np.asarray(res[name]).reshape(len(res["time"]), -1)


@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_fmi3_fmu_equals_the_fmi2_fmu(kind, fmus, spec):
    """Forward flight, one revolution: CS to 1e-12, ME (CVode) to the solver's tolerance; the
    FMI 3.0 arrays ``blade.flap`` and ``blade.lag`` hold blade k's flap and lag."""
    rev = revolution(spec, "forward-flight")
    blades = sorted({n.split(".")[0] for n in hinges(spec) if n.startswith("blade")})
    scalars = [f"{b}.{q}" for q in ("flap", "lag") for b in blades]
    kw = dict(fmi_type=kind, stop_time=rev, output_interval=rev / 100, start_values={"scene": "forward-flight"})
    if kind == "ModelExchange":
        kw.update(solver="CVode", relative_tolerance=CVODE_RTOL, set_stop_time=False)
    two = simulate_fmu(str(fmus[2]), output=[*scalars, "fuselage.roll"], **kw)
    three = simulate_fmu(str(fmus[3]), output=["blade.flap", "blade.lag", "fuselage.roll"], **kw)
    tol = 1e-12 if kind == "CoSimulation" else 1e-7
    assert np.array_equal(two["time"], three["time"])
    for q in ("flap", "lag"):
        arr = _fmi3_elements(three, f"blade.{q}")
        assert arr.shape[1] == len(blades)
        for k, b in enumerate(blades):
            np.testing.assert_allclose(arr[:, k], two[f"{b}.{q}"], rtol=0, atol=tol, err_msg=f"{b}.{q}")
    np.testing.assert_allclose(three["fuselage.roll"], two["fuselage.roll"], rtol=0, atol=tol)


def test_quaternion_norm_drifts_only_by_the_integration_error_and_is_never_used(fmus, spec):
    """The model uses q/|q| (rotation, Euler angles) and q' = q (x) (0, w)/2 keeps |q| along the
    exact solution: after 5 revolutions under CVode |q| - 1 stays at the solver's tolerance,
    and a state with the quaternion scaled by 1.3 gives the same derivatives of every other
    state and the same outputs, its quaternion rates scaled by 1.3."""
    rev = revolution(spec, "forward-flight")
    quat = ["fuselage.qw", "fuselage.qx", "fuselage.qy", "fuselage.qz"]
    res = me_run(fmus[2], "forward-flight", 5 * rev, rev / 20, quat)
    norm = np.sqrt(sum(np.asarray(res[q]) ** 2 for q in quat))
    drift = np.max(np.abs(norm - 1))
    assert drift < 1e-8, drift
    print(f"|q| - 1 after 5 revolutions of CVode (rtol {CVODE_RTOL:g}): {drift:.1e}")
    inst, states = _me_instance(fmus[2], "forward-flight")
    try:
        x = _get(inst.getContinuousStates, len(states))
        dx, y = _derivatives_and_outputs(inst, x, len(states))
        scaled = x.copy()
        iq = [states.index(q) for q in quat]
        scaled[iq] *= 1.3
        dx2, y2 = _derivatives_and_outputs(inst, scaled, len(states))
        other = [k for k in range(len(states)) if k not in iq]
        np.testing.assert_allclose(dx2[other], dx[other], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(dx2[iq], 1.3 * dx[iq], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(y2, y, rtol=1e-12, atol=1e-9)
    finally:
        inst.terminate()
        inst.freeInstance()


def _me_instance(fmu, scene: str, start_values: dict | None = None, logger=None):
    """An FMI 2.0 ME instance of ``fmu`` in continuous-time mode; (instance, state names)."""
    from fmpy import extract, instantiate_fmu

    md = read_model_description(str(fmu))
    inst = instantiate_fmu(extract(str(fmu)), md, fmi_type="ModelExchange", logger=logger)
    inst.setupExperiment(startTime=0.0)
    inst.enterInitializationMode()
    vr = {v.name: v.valueReference for v in md.modelVariables}
    inst.setString([vr["scene"]], [scene])
    for name, value in (start_values or {}).items():
        inst.setReal([vr[name]], [value])
    inst.exitInitializationMode()
    inst.newDiscreteStates()
    inst.enterContinuousTimeMode()
    inst.output_vrs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    return inst, [d.variable.derivative.name for d in md.derivatives]


def _get(fn, n: int) -> np.ndarray:
    buf = (ctypes.c_double * n)()
    fn(buf, n)
    return np.array(buf[:])


def _derivatives_and_outputs(inst, x: np.ndarray, n: int):
    inst.setContinuousStates((ctypes.c_double * n)(*x), n)
    return _get(inst.getDerivatives, n), np.array(inst.getReal(inst.output_vrs))


def test_clamped_fuselage_scene_holds_the_fuselage_states(fmus, spec):
    """ground-run clamps the fuselage: model exchange has the primary scene's 35 states, the
    fuselage's derivatives are 0 and its states keep their clamped values under CVode; the
    hinge angles follow the core's RK4 of ground-run to 1e-6 rad."""
    rev = revolution(spec, "ground-run")
    res = me_run(fmus[2], "ground-run", rev, rev / 100, [*hinges(spec), "fuselage.x", "fuselage.qw"])
    assert np.ptp(res["fuselage.x"]) == 0 and np.ptp(res["fuselage.qw"]) == 0
    t, x, states = core_rk4("ground-run", 1.0)
    for name in hinges(spec):
        if name in states:
            assert np.max(np.abs(res[name] - np.interp(res["time"], t, x[:, states.index(name)]))) < 1e-6, name
    own = {n: v for n, v in build.scene_start_values(spec, "ground-run").items() if n != "scene"}
    inst, names = _me_instance(fmus[2], "ground-run", own)  # as its own FMU: nothing to warn about
    try:
        dx = _get(inst.getDerivatives, len(names))
        assert all(dx[k] == 0 for k, n in enumerate(names) if n.startswith("fuselage."))
    finally:
        inst.terminate()
        inst.freeInstance()


def test_model_exchange_misuse_is_a_clear_error(fmus):
    """A wrong number of states, a non-finite state, doStep on a model-exchange instance: errors
    that say what is wrong; max_step set in model exchange: a warning that it does nothing."""
    from fmpy.fmi1 import FMICallException

    messages: list[str] = []
    inst, names = _me_instance(fmus[2], "forward-flight", {"max_step": 1e-3},
                               logger=lambda env, name, status, cat, msg: messages.append(msg.decode()))
    try:
        n = len(names)
        with pytest.raises(FMICallException):
            inst.getContinuousStates((ctypes.c_double * (n - 1))(), n - 1)
        bad = _get(inst.getContinuousStates, n)
        bad[5] = float("nan")
        with pytest.raises(FMICallException):
            inst.setContinuousStates((ctypes.c_double * n)(*bad), n)
        do_step = inst.dll.fmi2DoStep
        do_step.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int]
        assert do_step(inst.component, 0.0, 0.01, 1) == 3
    finally:
        inst.terminate()
        inst.freeInstance()
    text = "\n".join(messages)
    assert f"fmi2GetContinuousStates: {n - 1} values, but this FMU has {n} continuous states" in text
    assert f"continuous state 5 ('{names[5]}') = nan is not finite" in text
    assert "fmi2DoStep: this instance is for model exchange" in text
    assert "parameter 'max_step' was set, but it sets the FMU's own integrator" in text


def _fmi3_cs(fmu, name: str):
    from fmpy import extract, instantiate_fmu

    md = read_model_description(str(fmu))
    inst = instantiate_fmu(extract(str(fmu)), md, fmi_type="CoSimulation")
    inst.enterInitializationMode(startTime=0.0)
    inst.setString([next(v.valueReference for v in md.modelVariables if v.name == "scene")], ["forward-flight"])
    inst.exitInitializationMode()
    vr = next(v.valueReference for v in md.modelVariables if v.name == "blade.flap")
    return inst, vr, float(md.defaultExperiment.stepSize)


def test_fmi3_state_is_saved_serialised_and_restored_bit_for_bit(fmus):
    """FMI 3.0 (canGetAndSetFMUState, canSerializeFMUState): 20 steps, save and serialise, 30
    more; the state restored in the same instance and deserialised into a fresh one continue
    bit for bit (the four blades' flap as one array)."""
    inst, vr, dt = _fmi3_cs(fmus[3], "a")
    fresh, _, _ = _fmi3_cs(fmus[3], "b")
    try:
        for k in range(20):
            inst.doStep(k * dt, dt)
        state = inst.getFMUState()
        blob = inst.serializeFMUState(state)

        def run(target) -> list:
            out = []
            for k in range(20, 50):
                target.doStep(k * dt, dt)
                out.append(target.getFloat64([vr], 4))
            return out

        first = run(inst)
        inst.setFMUState(state)
        again = run(inst)
        fresh.setFMUState(fresh.deserializeFMUState(blob))
        elsewhere = run(fresh)
        assert len(first[-1]) == 4 and first == again == elsewhere
        inst.freeFMUState(state)
    finally:
        for i in (inst, fresh):
            i.terminate()
            i.freeInstance()
