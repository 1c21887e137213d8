"""Bad cases against the FMU: the host survives, each bad call answers fmi2Error or
fmi2Discard (never fmi2Fatal) with a message naming the call or the variable, repeated bad
calls stay harmless, and a good call afterwards works; start values round-trip; instances
do not leak.

Every case runs in its own fresh interpreter (``python -m fmu_hosts.probe CASE ARGS``, cwd a
temporary folder): a crash shows as that process's exit code. The cases use only the
variable names and the model description, so they run against any FMU of this model: the
fixture ``fmu_path`` is the Python FMU and the native one (``$HELI_NATIVE_FMU`` may name a
native ``.fmu`` file to check instead of the cached build).
"""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from fmu import build

FAMILY = build.DEFAULT_SCENES
ERROR, DISCARD, WARNING = 3, 2, 1  # fmi2Error, fmi2Discard, fmi2Warning
REFUSED = (DISCARD, ERROR)
REPEAT = 10


def _native() -> Path:
    """``$HELI_NATIVE_FMU`` (the path of a native ``.fmu``), else the cached native build."""
    if os.environ.get("HELI_NATIVE_FMU", "build") != "build":
        return Path(os.environ["HELI_NATIVE_FMU"])
    from fmu.native import build as native_build

    return native_build.ensure_native_fmu(FAMILY)[0]


def _fmus() -> dict:
    return {"python": lambda: build.ensure_fmu(FAMILY)[0], "native": _native}


@pytest.fixture(scope="session", params=sorted(_fmus()))
def fmu_path(request) -> Path:
    return _fmus()[request.param]()


def probe(case: str, args: dict, tmp_path: Path, timeout: float = 300) -> dict:
    """Run ``fmu_hosts.probe`` case ``case`` in a fresh interpreter; it must exit with 0."""
    args_file = tmp_path / f"{case}-args.json"
    args_file.write_text(json.dumps({"repeat": REPEAT, **args}))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.probe", case, str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"the host died (exit code {proc.returncode}):\n{proc.stderr[-3000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


def text(rec: dict) -> str:
    return "\n".join(m for _, m in rec["messages"])


def assert_refused(rec: dict, statuses=REFUSED, needles=()) -> None:
    """The call answered one of ``statuses`` and its messages contain every needle."""
    assert rec["status"] in statuses, rec
    assert rec["messages"], f"{rec['call']} refused without a message"
    missing = [n for n in needles if n not in text(rec)]
    assert not missing, (missing, text(rec))


def assert_recovered(rec: dict) -> None:
    assert rec["status"] == 0 and rec["get_status"] == 0 and rec["finite"], rec


# -- wrong value references, wrong order, outputs -----------------------------------------------

def test_unknown_value_reference_is_an_error_every_time(fmu_path, tmp_path):
    res = probe("unknown_vr", {"fmu": str(fmu_path)}, tmp_path)
    for rec in res["get"] + res["set"]:
        assert_refused(rec, (ERROR,), ["987654"])  # the value answered with fmi2Error is undefined
    assert_refused(res["mixed"], (ERROR,), ["987654"])
    assert math.isfinite(res["mixed"]["value"][0])  # the known one is still answered
    assert_recovered(res["after"])


def test_do_step_before_initialisation_is_refused(fmu_path, tmp_path):
    res = probe("step_before_init", {"fmu": str(fmu_path)}, tmp_path)
    for rec in res["steps"]:
        assert_refused(rec)
        assert "dostep" in text(rec).lower()
    assert res["init"] == [0, 0, 0, 0]
    assert_recovered(res["after"])


def test_setting_an_output_is_an_error_and_changes_nothing(fmu_path, tmp_path):
    res = probe("set_output", {"fmu": str(fmu_path), "name": "blade1.flap"}, tmp_path)
    for rec in res["set"]:
        assert_refused(rec, (ERROR,), ["'blade1.flap'"])
    assert res["unchanged"]
    assert_recovered(res["after"])


# -- parameters ---------------------------------------------------------------------------------

@pytest.mark.parametrize("name, value, good", [("max_step", 0.05, 1e-3), ("max_step", 1e-9, 1e-3),
                                               ("initial_forward_speed", 500.0, 20.0)])
def test_bad_parameter_fails_initialisation_until_corrected(fmu_path, tmp_path, name, value, good):
    res = probe("bad_parameter", {"fmu": str(fmu_path), "name": name, "value": value, "good": good}, tmp_path)
    assert_refused(res["set"], (ERROR,), [f"'{name}'", repr(value)])
    for rec in res["exit"]:
        assert_refused(rec, (ERROR,), [f"'{name}'"])
        assert "exitinitializationmode" in text(rec).lower()
    assert res["fix"]["status"] == 0 and res["exit_fixed"]["status"] == 0, res
    assert_recovered(res["after"])


@pytest.mark.parametrize("value", [0.05, 1e-9])
def test_bad_max_step_while_stepping_discards_steps_until_corrected(fmu_path, tmp_path, value):
    res = probe("bad_tunable", {"fmu": str(fmu_path), "name": "max_step", "value": value, "good": 1e-3}, tmp_path)
    assert_refused(res["set"], (ERROR,), ["'max_step'", repr(value)])
    for rec in res["steps"]:
        assert_refused(rec, (DISCARD,), ["'max_step'"])
    assert res["fix"]["status"] == 0
    assert_recovered(res["after"])


@pytest.mark.parametrize("scene", ["ground-run", "hover"])
def test_all_xml_start_values_applied_are_used_and_named(fmu_path, tmp_path, scene):
    """A master that applies every XML start (the primary scene's values) to another scene:
    they are the values in use (as they are when not set), and exitInitializationMode says so:
    hover starts at forward flight's 10 m/s with a warning naming the values; ground-run, which
    has no free fuselage, refuses the 10 m/s (error) until it is set to 0."""
    names = ["blade1.flap", "seesaw.teeter", "total_energy", "fuselage.u", "fuselage.v", "fuselage.w"]
    res = probe("all_starts", {"fmu": str(fmu_path), "scene": scene, "names": names,
                               "fix": {"initial_forward_speed": 0.0}}, tmp_path)
    for key in ("set_scene", "set_starts", "get"):
        assert res[key]["status"] == 0, res[key]
    values = dict(zip(res["get"]["names"], res["get"]["value"]))
    assert all(math.isfinite(v) for v in values.values()), values
    if scene == "hover":
        assert_refused(res["exit"], (WARNING,), ["'initial_forward_speed' = 10.0", "'collective'", "hover"])
        assert math.hypot(values["fuselage.u"], values["fuselage.v"], values["fuselage.w"]) == pytest.approx(10.0)
    else:
        assert_refused(res["exit"], (ERROR,), ["'initial_forward_speed' = 10.0", "no free fuselage"])
        assert res["fixed"] == [0, WARNING], res  # the collective etc. set to forward flight's: a warning
    assert_recovered(res["after"])


# -- steps ---------------------------------------------------------------------------------------

def test_huge_communication_steps_are_discarded_at_once(fmu_path, tmp_path):
    res = probe("huge_steps", {"fmu": str(fmu_path), "sizes": [1e16, 1e4]}, tmp_path, timeout=120)
    for h in ("1e+16", "10000.0"):
        for rec in res[h]:
            assert_refused(rec, (DISCARD,), [f"communicationStepSize = {h}", "sub-steps"])
        assert res[h + "_seconds"] < 2.0, res[h + "_seconds"]  # ten refusals, no integration
    assert_recovered(res["after"])


def test_a_diverging_step_is_undone_and_named(fmu_path, tmp_path):
    """At the largest rotor speed and extreme pitch inputs RK4 at the largest max_step
    lets the teeter angle run away: the step is undone (Discard, naming the state and its
    value), the state stays where it was, and a smaller max_step then steps on."""
    reals = {"omega": 53.3, "max_step": 0.012, "collective": 0.412, "longitudinal_cyclic": 0.175,
             "lateral_cyclic": -0.105}
    res = probe("diverging", {"fmu": str(fmu_path), "reals": reals, "dt": 0.5, "max_steps": 40,
                              "good_max_step": 1e-3}, tmp_path)
    rec = res["refused"]
    assert_refused(rec, (DISCARD,), ["the state stays at t = "])
    assert re.search(r"(hinge angle|state) '[\w.]+' = \S+", text(rec)), text(rec)  # names the state and value
    status, values = rec["time_after"]
    assert status == 0 and math.isfinite(values[0])
    assert_recovered(res["after"])


# -- FMU state -----------------------------------------------------------------------------------

def test_corrupt_serialised_states_are_refused(fmu_path, tmp_path):
    res = probe("corrupt_state", {"fmu": str(fmu_path)}, tmp_path)
    assert res["save_status"] == 0
    for kind in ("garbage", "truncated", "foreign"):
        for rec in res[kind]:
            assert_refused(rec, (ERROR,))
            assert "fmustate" in text(rec).lower(), text(rec)
    assert res["good"]["status"] == 0, res["good"]
    assert_recovered(res["after"])


# -- start values, memory ----------------------------------------------------------------------

def test_real_start_values_round_trip_bit_for_bit(fmu_path, tmp_path):
    res = probe("start_roundtrip", {"fmu": str(fmu_path)}, tmp_path)
    assert {"collective", "max_step", "omega", "initial_forward_speed"} <= set(res["starts"])
    for when in ("instantiated", "initialization", "stepping"):
        assert res[when]["set_status"] == 0 and res[when]["get_status"] == 0, (when, res[when])
        assert res[when]["values"] == res["starts"], when
    assert float(res["text"]["max_step"]).hex() == res["starts"]["max_step"]


def test_a_thousand_instances_do_not_leak(fmu_path, tmp_path):
    res = probe("memory", {"fmu": str(fmu_path), "cycles": 1000, "warmup": 20}, tmp_path, timeout=900)
    print(f"1000 instantiate/free cycles: {res['growth'] / 1e6:.2f} MB ({res['per_cycle'] / 1e3:.1f} kB per cycle)")
    assert res["growth"] < 5e6, res
    assert res["sys_path"][1] == res["sys_path"][0], res  # the resources folder is not added again and again


def test_instantiate_with_damaged_resources_gives_an_instance_answering_errors(fmu_path, tmp_path):
    res = probe("broken_resources", {"fmu": str(fmu_path), "damage": "heli_models/spec.json"}, tmp_path)
    if "skipped" in res:  # the native FMU compiles its data in: it has no resources to damage
        assert "Native" in fmu_path.name, res
        pytest.skip(res["skipped"])
    for rec in [res["setup"], *res["get"], res["step"]]:
        assert_refused(rec, (ERROR,))
    assert "spec.json" in text(res["setup"]) or "JSONDecodeError" in text(res["setup"]), text(res["setup"])
    assert_recovered(res["after"])


def test_reset_after_a_bad_value_gives_a_fresh_instance(fmu_path, tmp_path):
    res = probe("reset", {"fmu": str(fmu_path)}, tmp_path)
    for cycle in res["cycles"]:
        assert cycle["statuses"] == [0, 0, 0, 0, 0] and cycle["step"] == 0, cycle
    assert_recovered(res["after"])


# -- the spec shared with the native FMU (Python FMU only: it reads its spec.json) -------------

@pytest.fixture(scope="session")
def python_fmu() -> Path:
    return build.ensure_fmu(FAMILY)[0]


def test_spec_gives_starts_ranges_hinges_and_limits_and_the_xml_matches_it(python_fmu):
    import zipfile
    from xml.etree import ElementTree

    with zipfile.ZipFile(python_fmu) as z:
        spec = json.loads(z.read("resources/heli_models/spec.json"))
        root = ElementTree.fromstring(z.read("modelDescription.xml"))
    primary = spec["scenes"][spec["primary"]]
    settable = [v for v in spec["variables"] if v["causality"] in ("input", "parameter")]
    assert all("start" in v for v in settable)
    starts = {v["name"]: v["start"] for v in settable}
    assert starts["scene"] == "forward-flight" and starts["collective"] == primary["defaults"]["collective"]
    assert starts["initial_forward_speed"] == primary["forward_speed"]["default"]
    assert spec["limits"] == {"max_substeps": 1000000, "hinge_angle": math.pi / 2}
    for scene in spec["scenes"].values():
        assert scene["ranges"]["max_step"] == [1e-6, 0.012] and scene["ranges"]["initial_forward_speed"] == [-20, 90]
    xml = {sv.get("name"): sv for sv in root.find("ModelVariables")}
    for v in settable:
        element = xml[v["name"]][0]
        for key in ("start", "min", "max"):
            if v.get(key) is not None and element.tag == "Real":
                assert float(element.get(key)) == v[key], (v["name"], key)  # exact: repr round-trips
    assert float(xml["max_step"][0].get("max")) == 0.012


def test_hinge_states_are_the_flap_lag_and_teeter_coordinates(python_fmu):
    import zipfile

    with zipfile.ZipFile(python_fmu) as z:
        spec = json.loads(z.read("resources/heli_models/spec.json"))
        infos = {n: json.loads(z.read(f"resources/heli_models/{s['group']}/info.json"))
                 for n, s in spec["scenes"].items()}
    for name, scene in spec["scenes"].items():
        states = [*infos[name]["q_names"], *infos[name]["v_names"], *infos[name]["z_names"]]
        hinged = sorted(states[i] for i in scene["hinge_states"])
        expected = sorted([f"blade{k}.{a}" for k in range(1, 5) for a in ("flap", "lag")] + ["seesaw.teeter"])
        assert hinged == expected, (name, hinged)
