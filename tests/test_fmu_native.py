"""The native FMU (C only, no Python at run time): its library and model description, a C
master (dlopen) against fmpy and against the pythonfmu FMU, rebuilding from its sources,
misuse and bad input, an awkward unzip folder, and memory over many instances.

Every FMU run happens in a fresh process (the C host, ``python -m fmu_hosts.modes`` or
``python -m fmu_hosts.native_checks``). Both FMUs are built once per session and cached on disk.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

from fmu import build, hosts
from fmu.native import build as native_build
from fmu.native import platforms, run

FAMILY = build.DEFAULT_SCENES
REVS = 10


@pytest.fixture(scope="session")
def native_fmu() -> Path:
    return native_build.ensure_native_fmu(FAMILY)[0]


@pytest.fixture(scope="session")
def spec() -> dict:
    return native_build.native_spec(FAMILY)[0]


@pytest.fixture(scope="session")
def facts(native_fmu) -> dict:
    return run.facts(native_fmu)


@pytest.fixture(scope="session")
def unzipped(native_fmu, tmp_path_factory) -> Path:
    return run.extract(native_fmu, tmp_path_factory.mktemp("native") / "fmu")


@pytest.fixture(scope="session")
def host_exe(tmp_path_factory) -> Path:
    return run.compile_host(tmp_path_factory.mktemp("host") / "heli_fmi_host")


@pytest.fixture(scope="session")
def checks(native_fmu, tmp_path_factory) -> dict:
    """Every case of :mod:`fmu_hosts.native_checks`, each in its own instance, in one fresh process."""
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.native_checks", str(native_fmu)], capture_output=True,
                          text=True, cwd=tmp_path_factory.mktemp("checks"), timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return {**json.loads(proc.stdout.strip().splitlines()[-1]), "_stderr": proc.stderr}


def trims(spec: dict, scene: str) -> dict:
    return {v["name"]: spec["scenes"][scene]["defaults"][v["name"]] for v in spec["variables"]
            if v["causality"] == "input"}


def own_reals(spec: dict, scene: str) -> dict:
    """The Real values a master writes for ``scene`` to run as its own FMU (its trim inputs, its forward
    speed), where they differ from the XML starts (the primary scene's)."""
    return {n: v for n, v in build.scene_start_values(spec, scene).items() if n != "scene"}


def fmpy_run(fmu: Path, scene: str, spec: dict, dt: float, steps: int, names: list[str], tmp_path: Path,
             start_values: dict | None = None, inputs: dict | None = None) -> dict:
    """``fmpy.simulate_fmu`` of ``fmu`` in a fresh process (``python -m fmu_hosts.modes fmpy``), the
    inputs held at ``inputs`` (default the scene's trim)."""
    table = [{"time": 0.0, **{n: (inputs or spec["scenes"][scene]["defaults"])[n] for n in trims(spec, scene)}}]
    periodic = (start_values or {}).get("initial_state") == "periodic"
    args = {"fmu": str(fmu), "stop": steps * dt, "dt": dt, "table": table, "names": names,
            "start_values": {**build.scene_start_values(spec, scene, periodic), **(start_values or {})}}
    path = tmp_path / f"fmpy-{scene}-{fmu.stem}.json"
    path.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", "fmpy", str(path)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def max_rel(a: dict, b: dict, names: list[str]) -> float:
    return max(float(np.max(np.abs(np.subtract(a[n], b[n])) / np.maximum(1.0, np.abs(b[n])))) for n in names)


def messages(case: dict) -> str:
    return "\n".join(m for _, m in case["messages"])


# -- 1. the library and the model description -----------------------------------------------------

def test_library_needs_no_python_and_exports_only_fmi(unzipped, facts):
    so = run.library(unzipped, facts["identifier"])
    undefined = subprocess.run(["nm", "-D", "--undefined-only", str(so)], capture_output=True, text=True, check=True)
    names = [line.split()[-1] for line in undefined.stdout.splitlines() if line.strip()]
    assert names and not [n for n in names if n.startswith(("Py", "_Py"))]
    defined = subprocess.run(["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True, check=True)
    exported = {line.split()[-1] for line in defined.stdout.splitlines() if " T " in line}
    assert {"fmi2Instantiate", "fmi2DoStep", "fmi2SerializeFMUstate"} <= exported
    assert all(n.startswith(("fmi2", "fmi3")) for n in exported), sorted(exported)  # one library serves both


def _scalar_variables(fmu: Path) -> list[dict]:
    root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    out = []
    for sv in root.find("ModelVariables"):
        child = sv[0]
        out.append({**sv.attrib, "type": child.tag, **{f"@{k}": v for k, v in child.attrib.items()}})
    return out


def _comparable(v: dict) -> dict:
    number = lambda x: float(x) if x is not None else None  # noqa: E731
    start = v.get("@start")
    return {**{k: v.get(k) for k in ("name", "valueReference", "description", "causality", "variability", "type",
                                     "@unit")},
            "min": number(v.get("@min")), "max": number(v.get("@max")),
            "start": number(start) if v["type"] == "Real" and start is not None else start}


def test_model_description_has_the_pythonfmu_variables(native_fmu, python_fmu, spec):
    native, python = _scalar_variables(native_fmu), _scalar_variables(python_fmu)
    derivatives = native[len(python):]  # model exchange: the state derivatives follow the pythonfmu FMU's variables
    assert [v["name"] for v in derivatives] == [f"der({s})" for s in spec["me"]["states"]]
    native = native[:len(python)]
    same = lambda v: {**_comparable(v), "description": None} if v["name"] == "evaluator" else _comparable(v)  # noqa: E731
    assert [same(v) for v in native] == [same(v) for v in python]  # the native evaluator offers no vm
    assert [v["name"] for v in native] == [v["name"] for v in spec["variables"]]
    for v in native:
        if v["type"] == "Real" and "@start" in v:
            assert v["@start"] == "%.17g" % float(v["@start"]), v["name"]  # 17 significant digits


def test_model_description_declares_cosimulation_sources_and_structure(native_fmu, facts):
    z = zipfile.ZipFile(native_fmu)
    root = ElementTree.fromstring(z.read("modelDescription.xml"))
    cs, me = root.find("CoSimulation"), root.find("ModelExchange")
    assert cs.get("modelIdentifier") == me.get("modelIdentifier") == facts["identifier"] == "HeliRotorNative_forward_flight"
    assert cs.get("needsExecutionTool") == "false"
    for kind in (cs, me):
        assert kind.get("canGetAndSetFMUstate") == "true" and kind.get("canSerializeFMUstate") == "true"
        assert kind.get("providesDirectionalDerivative") == "true"
    sources = [f.get("name") for f in cs.find("SourceFiles")]
    assert sources == [f.get("name") for f in me.find("SourceFiles")]
    assert {"heli_core.c", "fmi2Functions.c"} <= set(sources) and all(f"sources/{s}" in z.namelist() for s in sources)
    built = {p.fmi2 for p in platforms.available() if p.fmi2}  # win64 where mingw is installed (CI: always)
    assert {n.split("/")[1] for n in z.namelist() if n.startswith("binaries/")} == built
    assert [n for n in z.namelist() if n.startswith("resources/")] == ["resources/scene_start_values.json"]
    svs = list(root.find("ModelVariables"))
    outputs = [str(i + 1) for i, sv in enumerate(svs) if sv.get("causality") == "output"]
    derivatives = [str(i + 1) for i, sv in enumerate(svs) if sv[0].get("derivative")]
    states = {sv[0].get("derivative") for sv in svs if sv[0].get("derivative")}
    assert [u.get("index") for u in root.find("ModelStructure/Outputs")] == outputs
    assert [u.get("index") for u in root.find("ModelStructure/Derivatives")] == derivatives
    initial = [u.get("index") for u in root.find("ModelStructure/InitialUnknowns")]
    assert initial == sorted(set(outputs) | set(derivatives) | states, key=int)
    assert root.find("UnitDefinitions") is not None and root.find("DefaultExperiment") is not None


# -- 2. the C host against fmpy and against the pythonfmu FMU -------------------------------------------

@pytest.mark.parametrize("scene", FAMILY)
def test_c_host_equals_fmpy_and_the_pythonfmu_fmu(scene, native_fmu, python_fmu, spec, facts, unzipped, host_exe,
                                                  tmp_path):
    dt = spec["scenes"][scene]["revolution"] / spec["scenes"][scene]["steps_per_rev"]
    steps, names = REVS * spec["scenes"][scene]["steps_per_rev"], facts["outputs"]
    c_run = run.run_host(host_exe, run.library(unzipped, facts["identifier"]), facts, scene, dt, steps,
                         {**trims(spec, scene), **own_reals(spec, scene)}, names)
    native = fmpy_run(native_fmu, scene, spec, dt, steps, names, tmp_path)
    python = fmpy_run(python_fmu, scene, spec, dt, steps, names, tmp_path)
    assert len(c_run["time"]) == len(native["time"]) == len(python["time"]) == steps
    np.testing.assert_allclose(c_run["time"], native["time"], rtol=1e-12, atol=1e-12)
    for n in names:
        np.testing.assert_allclose(c_run[n], native[n], rtol=1e-12, atol=1e-12, err_msg=n)
        np.testing.assert_allclose(native[n], python[n], rtol=1e-9, atol=1e-9, err_msg=n)
    print(f"{scene}: C host vs fmpy {max_rel(c_run, native, names):.1e}, native vs pythonfmu "
          f"{max_rel(native, python, names):.1e}")


@pytest.mark.parametrize("settings", [{"integrator": "rk8"}, {"initial_forward_speed": 25.0},
                                      {"omega": 40.0, "max_step": 4e-4}, {"initial_state": "periodic"},
                                      {"initial_state": "periodic", "initial_forward_speed": 25.0}],
                         ids=["rk8", "speed", "omega-max_step", "periodic", "periodic-speed"])
def test_parameters_act_as_in_the_pythonfmu_fmu(settings, native_fmu, python_fmu, spec, facts, tmp_path):
    dt, names = facts["step"], facts["outputs"]
    native = fmpy_run(native_fmu, "forward-flight", spec, dt, 60, names, tmp_path, settings)
    python = fmpy_run(python_fmu, "forward-flight", spec, dt, 60, names, tmp_path, settings)
    default = fmpy_run(native_fmu, "forward-flight", spec, dt, 60, names, tmp_path)
    for n in names:
        np.testing.assert_allclose(native[n], python[n], rtol=1e-9, atol=1e-9, err_msg=n)
    assert max_rel(native, default, names) > 1e-9  # the setting changed the run


@pytest.mark.parametrize("scene", ["hover", "ground-run"])
def test_periodic_start_is_the_pythonfmu_fmus_and_periodic(scene, native_fmu, python_fmu, spec, facts, tmp_path):
    """``initial_state = "periodic"``: the native FMU starts from the same stored trim as the
    pythonfmu FMU (its inputs the defaults) and, with them held, repeats after the full
    period of 4 revolutions."""
    sc = spec["scenes"][scene]
    dt, steps = sc["revolution"] / sc["steps_per_rev"], 4 * sc["steps_per_rev"] + 1
    names = [n for n in facts["outputs"] if n.endswith((".flap", ".lag", ".teeter"))]
    periodic = {"initial_state": "periodic"}
    native = fmpy_run(native_fmu, scene, spec, dt, steps, names, tmp_path, periodic, sc["periodic"]["defaults"])
    python = fmpy_run(python_fmu, scene, spec, dt, steps, names, tmp_path, periodic, sc["periodic"]["defaults"])
    for n in names:
        np.testing.assert_allclose(native[n], python[n], rtol=1e-12, atol=1e-12, err_msg=n)
        assert abs(native[n][steps - 1] - native[n][0]) < 1e-10, n


def test_serialised_state_restored_in_a_fresh_process_continues_identically(native_fmu, spec, facts, tmp_path):
    dt = facts["step"]
    table = hosts.pitch_schedule(trims(spec, "forward-flight"), dt, 100, revs=(0.5, 1.0, 1.5, 2.0))
    args = {"fmu": str(native_fmu), "stop": 300 * dt, "dt": dt, "t1": 120 * dt, "blob": str(tmp_path / "state.bin"),
            "table": hosts.table_rows(table), "names": facts["outputs"], "reals": {"max_step": dt / 3}}
    results = []
    for mode in ("save", "restore"):
        (tmp_path / "args.json").write_text(json.dumps(args))
        proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", mode, str(tmp_path / "args.json")], cwd=tmp_path,
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-3000:]
        results.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    assert len(results[0]["time"]) == 180
    for n in ["time", *facts["outputs"]]:
        assert results[0][n] == results[1][n], n  # bit for bit, Kahan terms included


# -- 3. validation and a rebuild from the shipped sources -------------------------------------------------

def test_fmpy_validate_finds_no_problems(native_fmu, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "fmpy.cli", "validate", str(native_fmu)], cwd=tmp_path,
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "No problems found" in proc.stdout, proc.stdout + proc.stderr


def _rebuild(unzipdir: Path) -> None:
    """fmpy's rebuild of the platform binary from ``sources/`` (CMake, its own headers). Its
    CMake project does not link libm: the sources then take the math functions from
    libm.so.6 themselves (``heli_libm.h``)."""
    import fmpy.util

    rebuild = getattr(fmpy.util, "compile_platform_binary", None)
    if rebuild is None:
        from fmpy.build import build_platform_binary as rebuild
    os.environ.setdefault("CMAKE_BUILD_PARALLEL_LEVEL", "2")
    rebuild(str(unzipdir))


def _plain_cc(unzipdir: Path, so: Path) -> None:
    """``cc -shared -fPIC -O2 -I sources <the SourceFiles of the model description>``: no -lm."""
    from mbs.backends.compiled import find_compiler

    root = ElementTree.fromstring((unzipdir / "modelDescription.xml").read_bytes())
    files = [str(unzipdir / "sources" / f.get("name")) for f in root.find("CoSimulation").iter("File")]
    subprocess.run([find_compiler(), "-shared", "-fPIC", "-O2", "-I", str(unzipdir / "sources"), *files, "-o",
                    str(so)], check=True, capture_output=True)


LIBM = {"sin", "cos", "sincos", "atan2", "asin", "tanh", "exp", "fmin", "fmax", "ceil", "sqrt", "pow"}


@pytest.mark.parametrize("how", ["fmpy", "cc"])
def test_rebuilt_from_sources_loads_without_libm_and_equals_the_shipped_binary(how, unzipped, facts, spec, host_exe,
                                                                               tmp_path):
    """fmpy's CMake rebuild and a plain ``cc`` of the listed sources link no libm: the library
    loads in a C host that has none (``host_exe`` does not link it) and gives the shipped
    binary's outputs bit for bit."""
    if how == "fmpy" and shutil.which("cmake") is None:
        pytest.skip("fmpy rebuilds FMUs with CMake")
    copy = shutil.copytree(unzipped, tmp_path / "rebuilt")
    so = run.library(copy, facts["identifier"])
    so.unlink()
    _rebuild(copy) if how == "fmpy" else _plain_cc(copy, so)
    assert so.exists()
    needed = subprocess.run(["readelf", "-d", str(so)], capture_output=True, text=True).stdout
    undefined = subprocess.run(["nm", "-D", "--undefined-only", str(so)], capture_output=True, text=True).stdout
    assert "libm" not in needed and not LIBM & {w.split("@")[0] for w in undefined.split()}, undefined
    assert "libm" not in subprocess.run(["ldd", str(host_exe)], capture_output=True, text=True).stdout
    dt, names = facts["step"], facts["outputs"]
    runs = [run.run_host(host_exe, lib, facts, "forward-flight", dt, 200, trims(spec, "forward-flight"), names)
            for lib in (run.library(unzipped, facts["identifier"]), so)]
    via_fmpy = fmpy_run(copy, "forward-flight", spec, dt, 200, names, tmp_path)  # fmpy: a fresh Python process
    for n in names:
        assert runs[1][n] == runs[0][n], n
        np.testing.assert_allclose(via_fmpy[n], runs[0][n], rtol=1e-12, atol=1e-12, err_msg=n)


# -- 4. misuse and bad input ---------------------------------------------------------------------------------

def test_unknown_value_references_and_wrong_types_are_errors(checks):
    case = checks["unknown_vr"]
    assert case["statuses"] == [[3, 3, 3, 3]] * 10
    text = messages(case)
    assert text.count("fmi2GetReal: unknown value reference 999") == 10
    assert text.count("fmi2SetReal: unknown value reference 999") == 10
    assert "value reference 0 is the Real variable 'collective', not a String" in text
    assert case["good_get"] == 0 and case["good_step"] == 0


def test_calls_out_of_order_are_errors(checks):
    case = checks["step_before_init"]
    assert case["statuses"] == [3] * 12 and case["good_step"] == 0
    text = messages(case)
    assert "fmi2DoStep called in instantiated mode" in text
    assert text.count("fmi2DoStep called in initialization mode") == 10
    assert "fmi2EnterInitializationMode called in initialization mode" in text


def test_bad_parameter_fails_initialisation_until_corrected(checks):
    case = checks["bad_parameter"]
    assert case["set"] == 3 and case["statuses"] == [3] * 10
    assert case["good_exit"] == 0 and case["good_step"] == 0
    assert messages(case).count("exitInitializationMode failed: parameter 'omega' = 1000.0 rad/s is outside its "
                                "range [22.2, 53.3]") == 10


def test_corrupt_serialised_states_are_refused(checks):
    case = checks["corrupt_state"]
    assert case["statuses"] == [[3, 3, 3]] * 10
    text = messages(case)
    for needle in ("checksum does not match", "size does not match", "magic header"):
        assert text.count(needle) == 10, needle
    assert case["good_step"] == 0 and case["after_restore"] == case["continued"]  # the good blob still restores


def test_xml_start_values_written_or_not_are_the_values_in_use(checks):
    """In ground-run, the XML start values written and not written give the same values and the same
    answers: forward flight's initial_forward_speed = 10 m/s is refused by name (with or without
    "its start value") until it is set to 0, and both runs then step alike."""
    case = checks["start_values"]
    assert case["set"] == 0 and case["exits"] == [3, 3, 0, 0] and case["steps"] == [0, 0]  # fmpy hides warnings
    applied, plain = case["before"]
    assert applied == plain
    values = dict(zip(case["names"], applied))
    assert values["initial_forward_speed"] == pytest.approx(10.0) == case["starts"]["initial_forward_speed"]
    assert values["collective"] == case["starts"]["collective"]
    assert case["after"][0] == case["after"][1]
    text = messages(case)
    assert "'initial_forward_speed' = 10.0 m/s: the scene 'ground-run' has no free fuselage" in text
    assert "'initial_forward_speed' = 10.0 m/s (its start value): the scene 'ground-run'" in text


def test_huge_communication_steps_are_discarded_at_once(checks):
    case = checks["huge_steps"]
    for h in ("1e+16", "10000.0"):
        status, seconds = case[h]
        assert status == 2 and seconds < 0.5, (h, case[h])
    text = messages(case)
    assert "communicationStepSize = 1e+16 s" in text and "more than the limit of 1000000" in text
    assert case["good_step"] == 0


def test_max_step_out_of_range_or_too_fine_is_discarded(checks):
    case = checks["max_step"]
    assert case["tiny"] == [3, 2] and case["small"] == [0, 0, 2] and case["good_step"] == 0
    text = messages(case)
    assert "parameter 'max_step' = 1e-09 s is outside its range [1e-06, 0.012]" in text
    assert "max_step = 1e-06 s needs 283026" in text and "sub-steps, more than the limit of 1000000" in text


def test_diverging_run_is_discarded_and_the_state_kept(checks):
    case = checks["diverging"]
    assert case["status"] == 2 and case["again"] == 2 and 50 < case["steps"] < 400
    assert all(math.isfinite(v) and abs(v) <= math.pi / 2 for v in case["held"])
    text = messages(case)
    assert "left the hinge range" in text and "state 'seesaw.teeter'" in text and "max_step = 0.012 s" in text
    assert f"the state stays at t = {case['t']!r} s" in text
    assert case["set_beyond"] == 3 and case["beyond"] == 2 and "'max_step' = 0.05 s is outside its range" in text


def test_nan_and_out_of_range_inputs_are_discarded_until_corrected(checks):
    case = checks["nan_input"]
    assert case["first"] == 0 and case["statuses"] == [3, 2, 3, 2] and case["good_step"] == 0
    text = messages(case)
    assert "input 'collective' = nan rad is not a finite number" in text
    assert "input 'collective' = 0.9 rad is outside its range [0.133, 0.412]" in text
    assert "'collective' = nan" in checks["_stderr"]  # visible without a logger too


def test_setting_an_output_is_an_error_and_harmless(checks, facts):
    case = checks["set_output"]
    assert case["statuses"] == [3, 3] and case["good_step"] == 0
    assert f"output 'blade1.flap' (value reference {facts['vr']['blade1.flap']}) cannot be set" in messages(case)


def test_reset_terminate_and_rollback(checks):
    case = checks["life_cycle"]
    assert case["after_terminate"] == [3, 3] and case["reset"] == 0
    assert case["rerun"] == case["first"]  # after fmi2Reset the same run again
    assert case["rolled_back"] == case["first"]  # fmi2SetFMUstate in the same instance
    assert case["status_queries"] == [2, 0, 0]
    assert "fmi2DoStep called in terminated mode" in messages(case)


def test_calls_without_an_instance_or_callbacks_do_not_crash(checks):
    case = checks["no_instance"]
    assert case["null_calls"] == [3, 3] and case["bare"] and case["bare_calls"] == [3, 3]
    assert case["wrong_guid"] is None
    err = checks["_stderr"]
    assert "fmi2GetFMUstate called without a valid instance (NULL)" in err
    assert "(bare) error: fmi2GetReal called in instantiated mode" in err and "does not match this FMU's" in err


# -- 5. and 6. unzip folder, memory -------------------------------------------------------------------------

def test_runs_from_a_folder_with_awkward_characters(native_fmu, spec, facts, host_exe, tmp_path):
    folder = run.extract(native_fmu, tmp_path / "a#b&c%d ü")
    dt, names = facts["step"], facts["outputs"]
    c_run = run.run_host(host_exe, run.library(folder, facts["identifier"]), facts, "hover", dt, 20,
                         {**trims(spec, "hover"), **own_reals(spec, "hover")}, names)
    via_fmpy = fmpy_run(folder, "hover", spec, dt, 20, names, tmp_path)
    for n in names:
        np.testing.assert_allclose(c_run[n], via_fmpy[n], rtol=1e-12, atol=1e-12, err_msg=n)


def test_instantiate_free_cycles_do_not_grow_memory(unzipped, facts, host_exe):
    before, after = run.host_cycles(host_exe, run.library(unzipped, facts["identifier"]), facts, "forward-flight", 1000)
    print(f"resident memory after 10 cycles {before} kB, after 1000 {after} kB")
    assert after - before < 5 * 1024
