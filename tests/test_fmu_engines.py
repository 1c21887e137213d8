"""The FMUs of the engine and turbulence scene (``hover-engines``): throttle inputs, engine failure
times, rotor speed and engine outputs, the air's and the turbulence's parameters, both FMUs equal
to the core; the hover-hold controller's closed loop in moderate turbulence."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fmu import build, hosts
from fmu.native import build as native_build

FAMILY = ("hover-engines",)
AIR = {"turbulence_intensity": 15.433, "turbulence_seed": 4.0, "wind_north": -5.0, "altitude": 500.0,
       "temperature_offset": 10.0}
"""Moderate turbulence (W20 30 kt) carried by a 5 m/s headwind, 500 m up on an ISA + 10 day."""


@pytest.fixture(scope="module")
def python_fmu() -> Path:
    return build.ensure_fmu(FAMILY)[0]


@pytest.fixture(scope="module")
def native_fmu() -> Path:
    return native_build.ensure_native_fmu(FAMILY)[0]


@pytest.fixture(scope="module")
def spec(python_fmu) -> dict:
    with zipfile.ZipFile(python_fmu) as z:
        return json.loads(z.read("resources/heli_models/spec.json"))


def _variables(spec: dict, causality: str) -> list[str]:
    return [v["name"] for v in spec["variables"] if v["causality"] == causality]


def test_the_fmu_has_throttle_inputs_engine_outputs_and_the_airs_parameters(spec):
    inputs, params, outputs = (_variables(spec, c) for c in ("input", "parameter", "output"))
    assert {"engine1_throttle", "engine2_throttle", "collective"} <= set(inputs)
    assert {"engine1_failure_time", "engine2_failure_time", "governor_speed", "turbulence_intensity",
            "turbulence_seed", "altitude", "temperature_offset", "wind_north", "gust_down"} <= set(params)
    assert {"main_rotor.speed", "tail_rotor.speed", "engine1.power", "engine2.torque", "engine1.oei_margin",
            "engine2.takeoff_margin", "engines.torque", "turbulence.down"} <= set(outputs)


def _table(spec: dict, dt: float) -> np.ndarray:
    """Trim inputs; a 0.02 rad collective step at 2 revolutions; engine 1's throttle to 0 at 4 (a
    time written twice is a jump, on fmpy's communication grid)."""
    scene = spec["scenes"]["hover-engines"]
    inputs = _variables(spec, "input")
    stages = [(0.0, 0), (200 * dt, 0), (200 * dt, 1), (400 * dt, 1), (400 * dt, 2)]
    rows = []
    for t, stage in stages:
        row = {n: scene["defaults"][n] for n in inputs}
        row["collective"] += 0.02 if stage >= 1 else 0.0
        row["engine1_throttle"] = 0.0 if stage >= 2 else 1.0
        rows.append((t, *[row[n] for n in inputs]))
    return np.array(rows, dtype=[("time", float)] + [(n, float) for n in inputs])


def _host(mode: str, args: dict, tmp_path: Path) -> dict:
    args_file = tmp_path / f"{mode}-args.json"
    args_file.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", mode, str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, env=dict(os.environ), timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("which", ["python", "native"])
def test_both_fmus_equal_the_core_to_1e_12_through_an_engine_failure_in_turbulence(which, python_fmu, native_fmu,
                                                                                   spec, tmp_path):
    """fmpy drives each FMU over 6 revolutions (the collective step, engine 1's throttle cut) in
    moderate turbulence: every state and every rotor, engine, drive-train and turbulence output
    equals the core's run with the same inputs to 1e-12 (relative to max(1, |value|)); the joint
    loads (forces, moments and pitch torques at the blade roots and hubs, from the reaction pass over the
    accelerations, which the FMU's generated outputs function evaluates in another order) to 1e-10."""
    fmu = python_fmu if which == "python" else native_fmu
    dt = spec["default_experiment"]["step"]
    table = _table(spec, dt)
    names = _variables(spec, "output")
    run = _host("fmpy", {"fmu": str(fmu), "stop": 600 * dt, "dt": dt, "table": hosts.table_rows(table),
                         "names": names, "start_values": AIR, "block": ["mbs", "casadi", "scipy"]}, tmp_path)
    ref = hosts.run_core("hover-engines", hosts.grid(600 * dt, dt), table, params=AIR, names=names)
    rel = {n: float(np.max(np.abs(np.subtract(run[n], ref[n])) / np.maximum(1.0, np.abs(ref[n]))))
           for n in ["time", *names]}
    worst = sorted(rel, key=rel.get)[-3:]
    print(f"{which} FMU against the core: largest differences " + ", ".join(f"{n} {rel[n]:.1e}" for n in worst))
    loads = [n for n in rel if re.search(r"\.((force|moment)_[xyz]|pitch_torque)$", n)]
    rest = max((n for n in rel if n not in loads), key=rel.get)
    print(f"  states and outputs but the joint loads: {rel[rest]:.2e} ({rest})")
    assert rel[rest] <= 1e-12
    assert max(rel[n] for n in loads) <= 1e-10
    power = np.asarray(run["engine1.power"])
    assert power[-1] < 0.7 * power[390]  # engine 1 spools down after its throttle is cut (lag 0.5 s)
    assert np.asarray(run["engine2.power"])[-1] > np.asarray(run["engine2.power"])[390]  # engine 2 takes over
    assert np.ptp(run["turbulence.down"]) > 0.1  # the turbulence acts


@pytest.mark.parametrize("which", ["python", "native"])
def test_an_altitude_outside_the_isa_is_refused_at_initialisation(which, python_fmu, native_fmu, spec, tmp_path):
    dt = spec["default_experiment"]["step"]
    fmu = python_fmu if which == "python" else native_fmu
    proc_args = {"fmu": str(fmu), "stop": dt, "dt": dt, "table": hosts.table_rows(_table(spec, dt)[:1]),
                 "names": ["main_rotor.speed"], "start_values": {"altitude": 25000.0}}
    args_file = tmp_path / "bad.json"
    args_file.write_text(json.dumps(proc_args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", "fmpy", str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode != 0
    assert "altitude" in proc.stderr and "25000" in proc.stderr, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr.split("fmpy")[0] or "outside" in proc.stderr


def test_the_hover_hold_loop_holds_for_a_minute_in_moderate_turbulence(native_fmu, tmp_path):
    """The hover-hold controller FMU and the native helicopter FMU of ``hover-engines`` (its periodic
    start: the governed hover) in the fmpy master loop for 60 s, in moderate Dryden turbulence
    (W20 30 kt, 100 m above the ground) carried by a 5 m/s headwind: the loop holds; the attitude
    and position peaks are reported (the steady headwind alone moves the hover point a few metres,
    the controller having no integral action)."""
    from fmu import controller, cosim
    from fmu.cosim import ssp

    ctrl, _ = controller.ensure_controller_fmu()
    dsg = controller.read_design(ctrl)
    step = controller.default_step()
    heli = {"path": native_fmu, "fmu": native_fmu.name, "inputs": list(controller.OUTPUTS), "outputs": cosim.RECORDED,
            "parameters": {"scene": "hover-engines", "initial_state": "periodic", "turbulence_intensity": 15.433,
                           "wind_north": -5.0, "turbulence_seed": 2.0}}
    loop = {"path": ctrl, "fmu": ctrl.name, "inputs": cosim.RECORDED, "outputs": list(controller.OUTPUTS),
            "parameters": {"gain_scale": 1.0}}
    wires = [(cosim.HELI, n, cosim.CTRL, n) for n in cosim.RECORDED] + [(cosim.CTRL, n, cosim.HELI, n)
                                                                        for n in controller.OUTPUTS]
    system = ssp.write_ssp(tmp_path / "turbulent.ssp", "hover-hold-turbulence",
                           {cosim.HELI: heli, cosim.CTRL: loop}, wires, 60.0)
    res = cosim.run_fmpy(system, 60.0, step, tmp_path / "run")
    peaks = cosim.excursions(res, dsg["trim_inputs"])
    print(f"moderate turbulence, 60 s: attitude peak {peaks['max_attitude_deg']:.2f} deg, position peak "
          f"{peaks['max_drift_m']:.2f} m (final {peaks['final_drift_m']:.2f} m)")
    assert peaks["attitude_beyond_20deg_s"] is None and peaks["max_attitude_deg"] < 10.0
    assert peaks["max_drift_m"] < 30.0
