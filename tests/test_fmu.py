"""The FMI 2.0 co-simulation FMU: validation, agreement with the core and between importers,
state save/restore, independent instances, bad input, and ``heli demo``.

Every FMU runs in a fresh interpreter (``python -m fmu_hosts.modes MODE ARGS``) whose working
directory is a temporary folder, never in the pytest process: pythonfmu shares
``sys.modules`` with its host. The FMU is built once per session (and cached on disk).
"""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

from fmu import build, hosts

FAMILY = build.DEFAULT_SCENES


@pytest.fixture(scope="session")
def fmu_path(python_fmu) -> Path:
    return python_fmu


@pytest.fixture(scope="session")
def spec(python_spec) -> dict:
    return python_spec


@pytest.fixture(scope="session")
def dt(spec) -> float:
    return spec["default_experiment"]["step"]


@pytest.fixture(scope="session")
def names(spec) -> list[str]:
    return [v["name"] for v in spec["variables"] if v["causality"] == "output"]


def trim_inputs(spec: dict, scene: str = "forward-flight") -> dict:
    return {v["name"]: spec["scenes"][scene]["defaults"][v["name"]]
            for v in spec["variables"] if v["causality"] == "input"}


def host(mode: str, args: dict, tmp_path: Path, env: dict | None = None) -> dict:
    """Run ``fmu_hosts.modes`` in a fresh interpreter with ``tmp_path`` as working directory."""
    args_file = tmp_path / f"{mode}-args.json"
    args_file.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", mode, str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, env={**os.environ, **(env or {})}, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    result["_stderr"] = proc.stderr
    return result


def max_diff(a: dict, b: dict, names: list[str]) -> str:
    """Largest difference relative to max(1, |b|), and the output where it occurs."""
    rel = {n: float(np.max(np.abs(np.subtract(a[n], b[n])) / np.maximum(1.0, np.abs(b[n])))) for n in names}
    worst = max(rel, key=rel.get)
    return f"{rel[worst]:.2e} ({worst}); angles and rates: {max(v for n, v in rel.items() if n != 'total_energy'):.2e}"


def assert_close(fmu_run: dict, ref: dict, names: list[str], rtol: float, atol: float) -> None:
    for n in ["time", *names]:
        np.testing.assert_allclose(fmu_run[n], ref[n], rtol=rtol, atol=atol, err_msg=n)


# -- 1. the model description -------------------------------------------------------------------

def test_fmpy_validate_finds_no_problems(fmu_path, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "fmpy.cli", "validate", str(fmu_path)], cwd=tmp_path,
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "No problems found" in proc.stdout


def test_model_description_declares_units_ranges_and_structure(fmu_path, spec):
    root = ElementTree.fromstring(zipfile.ZipFile(fmu_path).read("modelDescription.xml"))
    svs = root.find("ModelVariables").findall("ScalarVariable")
    assert all(sv.get("variability") for sv in svs)
    by_name = {sv.get("name"): sv for sv in svs}
    units = {u.get("name") for u in root.find("UnitDefinitions")}
    for name in ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective"):
        real = by_name[name].find("Real")
        assert by_name[name].get("causality") == "input" and real.get("unit") == "rad"
        assert float(real.get("min")) < float(real.get("start")) < float(real.get("max"))
    for name, unit in [("blade1.flap", "rad"), ("blade4.lag_rate", "rad/s"), ("seesaw.teeter", "rad"),
                       ("main_rotor.azimuth", "rad"), ("tail_rotor.azimuth", "rad"), ("fuselage.z", "m"),
                       ("fuselage.roll", "rad"), ("fuselage.u", "m/s"), ("fuselage.r", "rad/s"),
                       ("total_energy", "J"), ("max_step", "s"), ("omega", "rad/s")]:
        assert by_name[name].find("Real").get("unit") == unit, name
        assert unit in units
    outputs = [i + 1 for i, sv in enumerate(svs) if sv.get("causality") == "output"]
    initial = [int(u.get("index")) for u in root.find("ModelStructure/InitialUnknowns")]
    model_outputs = [v for v in spec["variables"] if v.get("kind") == "output"]
    assert len(model_outputs) >= 10  # azimuths, thrusts, torques, powers, inflow ratios, ...
    assert initial == outputs and len(outputs) == 9 + 9 + len(model_outputs) + 12 + 1
    assert {sv.get("name"): sv.get("variability") for sv in svs if sv.get("causality") == "parameter"} == {
        "scene": "fixed", "evaluator": "fixed", "integrator": "fixed", "initial_state": "fixed", "max_step": "tunable",
        "omega": "fixed", "initial_forward_speed": "fixed"}
    assert by_name["initial_state"].find("String").get("start") == "scene"
    ex = root.find("DefaultExperiment")
    rev = spec["scenes"]["forward-flight"]["revolution"]
    assert float(ex.get("stepSize")) == pytest.approx(rev / 100) and float(ex.get("stopTime")) == pytest.approx(10 * rev)


def test_staged_code_never_imports_the_hosts_mbs(tmp_path):
    entry, package = build.stage_code(tmp_path)
    sources = [tmp_path / f"{entry}.py", *package.rglob("*.py")]
    assert package.name.startswith("heli_rotor_") and entry.startswith("heli_rotor_slave_")
    for path in sources:
        assert not re.search(r"^\s*(from|import)\s+(mbs|fmu)\b", path.read_text(), re.MULTILINE), path
    assert f"from {package.name}.backends.compiled import CompiledSystem" in (tmp_path / f"{entry}.py").read_text()


# -- 2. fmpy with an input table against the core --------------------------------------------

def test_fmpy_with_input_table_equals_direct_core_run(fmu_path, spec, dt, names, tmp_path):
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100)
    stop = 700 * dt
    run = host("fmpy", {"fmu": str(fmu_path), "stop": stop, "dt": dt, "table": hosts.table_rows(table),
                        "names": names, "block": ["mbs", "casadi", "scipy"]}, tmp_path)
    assert run["time"][-1] == pytest.approx(stop, abs=1e-12) and len(run["time"]) == 700
    ref = hosts.run_core("forward-flight", hosts.grid(stop, dt), table, names=names)
    assert_close(run, ref, names, rtol=1e-9, atol=1e-9)
    print(f"fmpy vs core: max difference {max_diff(run, ref, names)} over {len(names)} outputs")
    thrust = np.asarray(run["main_rotor.thrust"])
    assert thrust[300] > thrust[150] * 1.05  # the collective step at 2 revolutions arrived


def test_variable_communication_steps_equal_the_core_with_the_same_substeps(fmu_path, spec, dt, names, tmp_path):
    rng = np.random.default_rng(3)
    times = np.concatenate([[0.0], np.cumsum(rng.uniform(0.2, 3.7, 60) * dt)]).tolist()
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100, revs=(0.1, 0.2, 0.3, 0.4))
    run = host("steps", {"fmu": str(fmu_path), "times": times, "table": hosts.table_rows(table), "names": names},
               tmp_path)
    ref = hosts.run_core("forward-flight", times, table, names=names)
    assert_close(run, ref, names, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("scene", ["hover", "ground-run"])
def test_scene_parameter_selects_the_family_member(fmu_path, spec, dt, names, scene, tmp_path):
    table = hosts.pitch_schedule(trim_inputs(spec, scene), dt, 100, revs=(0.5, 1.0, 1.5, 2.0))
    stop = 250 * dt
    run = host("fmpy", {"fmu": str(fmu_path), "stop": stop, "dt": dt, "table": hosts.table_rows(table),
                        "names": names, "start_values": build.scene_start_values(spec, scene)}, tmp_path)
    ref = hosts.run_core(scene, hosts.grid(stop, dt), table)
    present = [n for n in names if n in ref]
    assert_close(run, ref, present, rtol=1e-9, atol=1e-9)
    if scene == "ground-run":  # the fuselage is clamped: its outputs are its fixed pose
        assert set(names) - set(present) >= {"fuselage.x", "fuselage.u", "fuselage.pitch"}
        for n in ("fuselage.x", "fuselage.u", "fuselage.r", "fuselage.roll"):
            assert np.all(np.asarray(run[n]) == 0.0), n


def test_vm_evaluator_agrees_with_the_compiled_one(fmu_path, spec, dt, names, tmp_path):
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100, revs=(0.05, 0.1, 0.15, 0.2))
    args = {"fmu": str(fmu_path), "stop": 40 * dt, "dt": dt, "table": hosts.table_rows(table), "names": names}
    compiled = host("fmpy", args, tmp_path)
    vm = host("fmpy", {**args, "start_values": {"evaluator": "vm"}, "block": ["mbs", "scipy"]}, tmp_path)
    assert_close(vm, compiled, names, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("evaluator", ["compiled", "vm"])
def test_rk8_integrator_equals_the_core_run_with_rk8(fmu_path, spec, dt, names, evaluator, tmp_path):
    """``integrator = "rk8"`` runs the shipped 8th-order driver: equal to the core's rk8 run,
    and different from RK4 at the same step (by about RK4's error, far above round-off)."""
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100, revs=(0.1, 0.2, 0.3, 0.4))
    stop = 60 * dt
    run = host("fmpy", {"fmu": str(fmu_path), "stop": stop, "dt": dt, "table": hosts.table_rows(table),
                        "names": names, "start_values": {"integrator": "rk8", "evaluator": evaluator}}, tmp_path)
    grid = hosts.grid(stop, dt)
    assert_close(run, hosts.run_core("forward-flight", grid, table, names=names, method="rk8"), names,
                 rtol=1e-9, atol=1e-9)
    rk4 = hosts.run_core("forward-flight", grid, table, names=names)
    assert np.max(np.abs(np.subtract(run["seesaw.teeter"], rk4["seesaw.teeter"]))) > 1e-7


@pytest.mark.parametrize("start", ["scene", "periodic"])
def test_initial_forward_speed_sets_the_flight_speed(start, fmu_path, tmp_path):
    res = host("initial", {"fmu": str(fmu_path), "reals": {"initial_forward_speed": 25.0},
                           "strings": {"initial_state": start},
                           "names": ["fuselage.u", "fuselage.v", "fuselage.w", "fuselage.roll",
                                     "fuselage.pitch", "fuselage.yaw"]}, tmp_path)
    u, v, w, roll, pitch, yaw = res["values"]
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    r = np.array([[cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy],
                  [cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy],
                  [-sp, sr * cp, cr * cp]])
    np.testing.assert_allclose(r @ [u, v, w], [25.0, 0.0, 0.0], atol=1e-12)
    assert abs(pitch) > 1e-3  # the scene's trimmed attitude is kept


# -- the periodic start ----------------------------------------------------------------------------

def periodic_inputs(spec: dict, scene: str) -> dict:
    """The inputs of the periodic trim of ``scene`` (the defaults with ``initial_state = "periodic"``)."""
    return {v["name"]: spec["scenes"][scene]["periodic"]["defaults"][v["name"]]
            for v in spec["variables"] if v["causality"] == "input"}


def held(inputs: dict) -> list[dict]:
    """An input table holding ``inputs`` from t = 0."""
    return [{"time": 0.0, **inputs}]


@pytest.mark.parametrize("scene", FAMILY)
def test_periodic_start_is_periodic_from_the_first_step(fmu_path, spec, scene, tmp_path):
    """``initial_state = "periodic"`` with the trim's inputs held: every hinge angle and rate
    repeats after the full period (4 revolutions: the tail rotor turns 21 times) to 1e-10,
    from the first step; the scene's own start (blades released at zero lag) rings instead."""
    sc = spec["scenes"][scene]
    dt = sc["revolution"] / sc["steps_per_rev"]
    period = 4 * sc["steps_per_rev"]
    hinges = [v["name"] for v in spec["variables"] if v["causality"] == "output" and v.get("kind") == "state"
              and re.search(r"\.(flap|lag|teeter)(_rate)?$", v["name"])]
    args = {"fmu": str(fmu_path), "stop": (period + 1) * dt, "dt": dt, "table": held(periodic_inputs(spec, scene)),
            "names": hinges}
    runs = {start: host("fmpy", {**args, "start_values": {**build.scene_start_values(spec, scene, start == "periodic"),
                                                          "initial_state": start}}, tmp_path)
            for start in ("periodic", "scene")}
    for n in hinges:
        rate = n.endswith("_rate")
        scale = 2 * math.pi / sc["revolution"] if rate else 1.0  # rates per rad/s of rotor speed
        drift = abs(runs["periodic"][n][period] - runs["periodic"][n][0]) / scale
        assert drift < 1e-10, (n, drift)
    lag = np.asarray(runs["scene"]["blade1.lag"])
    assert abs(lag[period] - lag[0]) > 1e-3  # 1e7 times the periodic start's drift


def test_periodic_start_with_input_table_equals_the_core_from_the_stored_trim(fmu_path, spec, dt, names, tmp_path):
    """The demo's run: the FMU started periodic under the collective step and cyclic doublet
    (on the trim's inputs) equals the core's run from the stored periodic state."""
    per = spec["scenes"]["forward-flight"]["periodic"]
    table = hosts.pitch_schedule(periodic_inputs(spec, "forward-flight"), dt, 100, revs=(0.5, 1.0, 1.5, 2.0))
    stop = 250 * dt
    run = host("fmpy", {"fmu": str(fmu_path), "stop": stop, "dt": dt, "table": hosts.table_rows(table),
                        "names": names, "start_values": {"initial_state": "periodic"}}, tmp_path)
    ref = hosts.run_core("forward-flight", hosts.grid(stop, dt), table, names=names, x0=per["x0"])
    assert_close(run, ref, names, rtol=1e-9, atol=1e-9)


def test_stored_periodic_starts_hold_for_the_current_model_and_are_in_the_fmu(spec):
    """``fmu/periodic_starts.json`` (written by ``python -m fmu.periodic``) still holds for the
    model the FMU is built from: after the shooting interval the state returns to 1e-8; the
    FMU carries it with its provenance."""
    from mbs import scenes
    from mbs.backends import build as build_system

    from fmu import periodic

    stored = periodic.stored()
    for scene in FAMILY:
        sc = scenes.get(scene)
        system = build_system(sc.model(), "vm")
        entry = stored[scene]
        assert periodic.residual(entry, system, sc) <= periodic.TOLERANCE, scene
        assert entry["max_abs_residual"] <= 1e-10 and entry["provenance"]["generated_by"].startswith("python -m")
        shipped = spec["scenes"][scene]["periodic"]
        assert shipped["x0"] == [entry["state"][n] for n in system.info.state_names]
        assert shipped["trim"]["provenance"] == entry["provenance"] and shipped["trim"]["check_residual"] <= 1e-8
        released = {**entry, "state": dict(zip(system.info.state_names, system.x0()))}
        assert periodic.residual(released, system, sc) > 1e-3  # the check can fail


# -- 3. a second importer ------------------------------------------------------------------------

def test_libcosim_gives_the_same_outputs_as_fmpy(fmu_path, spec, names, tmp_path):
    dt = 1e-3  # libcosim counts time in whole nanoseconds
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100, revs=(1.0, 2.0, 2.5, 3.0))
    args = {"fmu": str(fmu_path), "stop": 400 * dt, "dt": dt, "table": hosts.table_rows(table), "names": names}
    fmpy_run = host("fmpy", args, tmp_path)
    cosim_run = host("libcosim", args, tmp_path)
    assert len(cosim_run["time"]) == len(fmpy_run["time"]) == 400
    # a load or a power is a sum of terms up to the largest of its unit (the blades' centrifugal pull,
    # 1e5 N; the engine power): its round-off scales with that
    units = {v["name"]: v["unit"] for v in spec["variables"]}
    scale = {u: max(float(np.abs(fmpy_run[n]).max()) for n in names if units[n] == u) for u in ("N", "N m", "W")}
    for n in ["time", *names]:
        np.testing.assert_allclose(cosim_run[n], fmpy_run[n], rtol=1e-12, atol=1e-12 * scale.get(units.get(n), 1.0),
                                   err_msg=n)
    print(f"libcosim vs fmpy: max difference {max_diff(cosim_run, fmpy_run, names)}")


# -- 4. and 5. state, instances ------------------------------------------------------------------

def test_serialised_state_restored_in_a_fresh_process_continues_identically(fmu_path, spec, dt, names, tmp_path):
    table = hosts.pitch_schedule(trim_inputs(spec), dt, 100, revs=(0.5, 1.0, 1.5, 2.0))
    args = {"fmu": str(fmu_path), "stop": 300 * dt, "dt": dt, "t1": 120 * dt, "blob": str(tmp_path / "state.bin"),
            "table": hosts.table_rows(table), "names": names, "reals": {"max_step": dt / 3}}
    first = host("save", args, tmp_path)
    second = host("restore", args, tmp_path)
    assert len(first["time"]) == 180
    for n in ["time", *names]:
        assert first[n] == second[n], n  # bit for bit, integrator compensation included


def test_two_instances_in_one_process_stay_independent(fmu_path, spec, dt, names, tmp_path):
    trim = trim_inputs(spec)
    tables = [hosts.pitch_schedule(trim, dt, 100, collective_step=s, revs=(0.3, 0.6, 0.9, 1.2)) for s in (0.03, -0.05)]
    stop = 200 * dt
    res = host("two", {"fmu": str(fmu_path), "stop": stop, "dt": dt, "names": names,
                       "tables": [hosts.table_rows(t) for t in tables]}, tmp_path)
    refs = [hosts.run_core("forward-flight", hosts.grid(stop, dt), t, names=names) for t in tables]
    for run, ref in zip(res["runs"], refs):
        assert_close({"time": res["time"], **run}, ref, names, rtol=1e-9, atol=1e-9)
    assert abs(res["runs"][0]["main_rotor.thrust"][-1] - res["runs"][1]["main_rotor.thrust"][-1]) > 1000.0


# -- 6. bad input ---------------------------------------------------------------------------------

def test_bad_input_gives_a_discard_and_a_message_naming_it(fmu_path, dt, tmp_path):
    cases = [
        {"name": "nan input", "set": {"collective": float("nan")}, "fix": {"collective": 0.25}},
        {"name": "infinite input", "set": {"lateral_cyclic": float("-inf")}, "fix": {"lateral_cyclic": 0.0}},
        {"name": "pitch out of range", "set": {"tail_collective": 0.9}, "fix": {"tail_collective": 0.1}},
        {"name": "zero step", "step": 0.0},
        {"name": "negative step", "step": -dt},
        # 90 m/s at 120 % rotor speed in 0.012 s steps (the hover at these settings stays bounded since the tail's
        # lift is continuous through 90 deg)
        {"name": "diverging", "init_strings": {"scene": "forward-flight"},
         "init": {"omega": 53.3, "max_step": 0.012, "initial_forward_speed": 90.0},
         "set": {"collective": 0.412}, "step": 3.0},
        {"name": "fixed parameter changed", "set": {"omega": 40.0}, "fix": {"omega": 44.4}},
    ]
    res = host("errors", {"fmu": str(fmu_path), "dt": dt, "cases": cases}, tmp_path)
    expect = {"nan input": ["'collective' = nan"], "infinite input": ["'lateral_cyclic' = -inf"],
              "pitch out of range": ["'tail_collective' = 0.9", "outside its range"],
              "zero step": ["communicationStepSize = 0.0"], "negative step": [f"communicationStepSize = {-dt!r}"],
              "diverging": ["doStep", "max_step = 0.012"], "fixed parameter changed": ["'omega'", "fixed"]}
    for case in cases:
        r = res[case["name"]]
        assert r["init_status"] == 0 and r["first_step"] == 0, r
        misuse = case["name"] in ("zero step", "negative step")  # fmi2Error: a smaller step would not help
        assert r["step_status"] == (3 if misuse else 2), (case["name"], r)  # the step did not happen
        text = "\n".join(m for _, m in r["messages"])
        assert all(e in text for e in expect[case["name"]]), (case["name"], text)
        assert any(s in ("error", "discard") for s, _ in r["messages"])
        if "fix" in case:
            assert r["recovered_status"] == 0, (case["name"], r)
    diverged = "\n".join(m for _, m in res["diverging"]["messages"])
    assert "hinge angle 'seesaw.teeter'" in diverged or "diverged" in diverged, diverged
    assert "'collective' = nan" in res["_stderr"]  # also visible without a logger


def test_bad_parameter_fails_initialisation_with_a_message(fmu_path, dt, tmp_path):
    cases = [{"name": "scene", "init_strings": {"scene": "no-such-scene"}},
             {"name": "step", "init": {"max_step": -1.0}},
             {"name": "speed", "init_strings": {"scene": "ground-run"}, "init": {"initial_forward_speed": 5.0}}]
    res = host("errors", {"fmu": str(fmu_path), "dt": dt, "cases": cases}, tmp_path)
    for case, needle in zip(cases, ["'scene' = 'no-such-scene'", "'max_step' = -1.0", "no free fuselage"]):
        r = res[case["name"]]
        assert r["init_status"] == 3, r  # fmi2Error (the slave logs the error, the FMI front end reports it)
        assert needle in "\n".join(m for _, m in r["messages"]), r


def test_exception_inside_the_slave_is_logged_with_its_traceback(fmu_path, tmp_path):
    res = host("broken", {"fmu": str(fmu_path)}, tmp_path)
    assert res["init_status"] == 3  # fmi2Error: logged, never fmi2Fatal
    text = "\n".join(m for _, m in res["messages"])
    assert "Traceback (most recent call last)" in text and "JSONDecodeError" in text and "info.py" in text


# -- 7. the main job ---------------------------------------------------------------------------

def test_heli_demo_writes_its_files_from_a_fresh_cache(tmp_path):
    out, cache = tmp_path / "demo", tmp_path / "cache"
    heli = Path(sys.executable).with_name("heli")
    proc = subprocess.run([str(heli), "demo", "--out", str(out), "--revs", "3", "--json"], cwd=tmp_path,
                          capture_output=True, text=True, env={**os.environ, "MBS_CACHE_DIR": str(cache)},
                          timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    cached = Path(res["fmu_cached"])
    assert res["build_s"] > 0 and cached.is_relative_to(cache)
    assert res["fmu"] == str(out / cached.name) and (out / cached.name).read_bytes() == cached.read_bytes()
    for name in ("results.csv", "hinge_angles.png", "run.json"):
        assert (out / name).stat().st_size > 1000, name
    assert res["initial_state"] == "periodic" and res["trim"]["max_abs_residual"] <= 1e-10
    header = (out / "results.csv").read_text().split("\n", 1)[0].split(",")
    assert {"time", "blade1.flap", "seesaw.teeter", "fuselage.qw", "collective", "total_energy"} <= set(header)
    rows = np.loadtxt(out / "results.csv", delimiter=",", skiprows=1)
    assert rows.shape[0] == 301 and rows[-1, 0] == pytest.approx(res["simulated_s"])
    lag = rows[:, header.index("blade1.lag")]  # periodic until the collective step at 2 revolutions
    assert np.max(np.abs(lag[100:201] - lag[:101])) < 1e-5
    assert str(out / "results.csv") in proc.stdout
    if "viewer" in res["files"]:
        assert (out / "viewer.html").stat().st_size > 100_000
        page = (out / "fly.html").read_text()  # the scene to fly, the model inlined as WebAssembly
        assert res["files"]["fly"] == str(out / "fly.html") and 'id="model-wasm"' in page and len(page) > 500_000


# -- the plan, in-process (no FMU runs here) --------------------------------------------------

def test_plan_takes_the_variables_from_the_models(spec):
    variables = {v["name"]: v for v in spec["variables"]}
    inputs = [n for n, v in variables.items() if v["causality"] == "input"]
    assert inputs == ["collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective"]
    hinges = [f"blade{k}.{a}" for k in range(1, 5) for a in ("flap", "lag")] + ["seesaw.teeter"]
    assert all(variables[h]["causality"] == "output" for h in hinges + [h + "_rate" for h in hinges])
    assert variables["fuselage.qw"]["causality"] == "local" and variables["main_rotor.inflow"]["unit"] == "m/s"
    ground = spec["scenes"]["ground-run"]
    assert ground["forward_speed"] is None and ground["group"] != spec["scenes"]["forward-flight"]["group"]
    assert spec["scenes"]["hover"]["group"] == spec["scenes"]["forward-flight"]["group"]  # one compiled model
    assert spec["scenes"]["forward-flight"]["forward_speed"]["default"] == pytest.approx(10.0)
    assert spec["scenes"]["hover"]["forward_speed"]["default"] == pytest.approx(0.0, abs=1e-12)
