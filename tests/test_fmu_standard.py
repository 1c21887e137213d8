"""The FMUs to the letter of the FMI 2.0 and 3.0 standards, each case run in a C host written for
it (``tests/fmu_hosts/script_host.c``, which calls the standard functions only; for the pythonfmu FMU linked
to libpython), on every FMU kind where it applies: the pythonfmu FMU (FMI 2.0 co-simulation), the
native FMU (FMI 2.0 and 3.0, co-simulation and model exchange) and the hover-hold controller.

- stopTime: a step (model exchange: a time) past it is fmiXError naming both times, one that ends
  past it by rounding only is taken, and stopTime before startTime is refused;
- start values: an FMU read from its XML alone runs the same whether the master writes every
  start value or none (also in another scene of the family, and in fmpy);
- the controller's heading: any finite size costs one step of microseconds, never a loop;
- statuses, strings, FMU states and the state machines as the standards define them.
The cases are :mod:`fmu_hosts.conformance`'s; every host run is a fresh process.
"""
from __future__ import annotations

import json
import math
import re
import statistics
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

from fmu import build, controller
from fmu_hosts import conformance, script_host
from fmu_hosts.conformance import DISCARD, ERROR, OK, WARNING
from fmu.native import build as native_build

FAMILY = build.DEFAULT_SCENES
KINDS = {"pythonfmu-cs": ("python", "cs"), "native2-cs": ("native2", "cs"), "native2-me": ("native2", "me"),
         "native3-cs": ("native3", "cs"), "native3-me": ("native3", "me"), "controller-cs": ("controller", "cs")}
HELICOPTER = [k for k in KINDS if not k.startswith("controller")]
NATIVE = [k for k in KINDS if k.startswith("native")]


@pytest.fixture(scope="session")
def fmu_files() -> dict:
    return {"python": lambda: build.ensure_fmu(FAMILY)[0], "native2": lambda: native_build.ensure_native_fmu(FAMILY)[0],
            "native3": lambda: native_build.ensure_native_fmu(FAMILY, fmi=3)[0],
            "controller": lambda: controller.ensure_controller_fmu()[0]}


@pytest.fixture(scope="session")
def hosts(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("script-host")
    return {"plain": script_host.compile_host(folder / "script_host"),
            "python": script_host.compile_host(folder / "script_host_python", python=True)}


@pytest.fixture
def make(fmu_files, hosts, tmp_path):
    """``make(kind)``: the :class:`fmu_hosts.conformance.Target` of one of :data:`KINDS`, unzipped afresh."""
    def target(kind: str) -> conformance.Target:
        which, interface = KINDS[kind]
        python = which == "python"
        return conformance.target(fmu_files[which](), interface, tmp_path / kind, hosts["python" if python else "plain"],
                                  script_host.python_env() if python else None)
    return target


NUMBER = r"[-+0-9.e]+"


def texts(result: dict) -> str:
    return "\n".join(m[2] for m in result["log"])


# -- 1. the controller's heading --------------------------------------------------------------------

def test_controller_heading_of_any_size_takes_one_step_of_microseconds(make):
    """The heading was wrapped by repeated subtraction of 2 pi (1e12 rad: 16.7 s per step, 1e18: no
    return). Now: any finite heading is one remainder(); beyond 2^33 rad, where a double's spacing
    exceeds 2e-6 rad, the step is discarded with a message in logStatusDiscard. Each step's wall
    time in the C host, median of 5: at most 1 ms (an O(n) wrap takes ~1 s at 8e9 rad)."""
    t = make("controller-cs")
    res = conformance.heading_steps(t, [1e9, 8.5e9, 1e18, -1e18, 1e300], 0.01)
    for psi, rec in res.items():
        median = statistics.median(rec["seconds"])
        print(f"heading {psi:g} rad: status {rec['statuses'][0]}, step {median * 1e6:.1f} us (median), "
              f"{max(rec['seconds']) * 1e6:.1f} us (largest)")
        assert median <= 1e-3, (psi, rec["seconds"])
        assert all(math.isfinite(v) for v in rec["outputs"]), (psi, rec)
        if abs(psi) < 2.0 ** 33:
            assert rec["statuses"] == [OK] * 5 and not rec["log"], (psi, rec)
        else:
            assert rec["statuses"] == [DISCARD] * 5, (psi, rec)
            assert {m[1] for m in rec["log"]} == {"logStatusDiscard"}, rec["log"]
            assert f"input 'fuselage.yaw' = {psi:g} rad is beyond" in rec["log"][0][2], rec["log"]


# -- 2. stopTime ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", list(KINDS))
def test_stop_time_is_enforced(kind, make):
    """stopTime before startTime is refused (FMI 2.0 at fmi2SetupExperiment, FMI 3.0 at
    fmi3EnterInitializationMode); with stopTime 2e-10 (relative) short of ten steps, the ten steps
    are taken (the last ends past it by rounding only) and the eleventh is fmiXError naming both
    times; fmi2GetRealStatus(fmi2LastSuccessfulTime) stays at the tenth step's end; model exchange
    takes the time stopTime and refuses one past it."""
    t = make(kind)
    dt = t.facts["step"] or 0.01
    res = conformance.stop_time(t, dt)
    refused = res["early"][1] if t.v3 else res["early"][0]
    assert refused["status"] == ERROR and "stopTime = 0.5 s" in texts(refused) and "startTime = 1" in texts(refused)
    run, stop = res["run"], res["stop"]
    if t.me:
        assert [r["status"] for r in run] == [OK, ERROR], run
        named = re.search(rf"time = ({NUMBER}) s is past stopTime = ({NUMBER}) s", texts(run[1]))
        assert named and float(named[2]) == stop and float(named[1]) > stop, texts(run[1])
        return
    statuses = [r["status"] for r in run if r["cmd"].startswith("step")]
    assert statuses == [OK] * 10 + [ERROR], run
    past = next(r for r in run if r["status"] == ERROR)
    named = re.search(rf"step from ({NUMBER}) s to ({NUMBER}) s ends past stopTime = ({NUMBER}) s", texts(past))
    assert named, texts(past)
    assert [float(x) for x in named.groups()] == [pytest.approx(10 * dt), pytest.approx(11 * dt), stop]
    if not t.v3:
        assert run[-1]["status"] == OK and run[-1]["values"] == [pytest.approx(10 * dt, rel=1e-15)]


# -- 3. start values ----------------------------------------------------------------------------------

CASES = {"primary scene": {}, "hover": {"scene": "hover"}, "periodic start": {"initial_state": "periodic"},
         "hover, periodic": {"scene": "hover", "initial_state": "periodic"}}


RUNS = [(kind, case) for kind in KINDS for case in CASES if kind in HELICOPTER or case == "primary scene"]
"""Every FMU kind with every case; the controller (one design, no scenes) with the first only."""


@pytest.mark.parametrize("kind,case", RUNS, ids=[f"{k}-{c.replace(' ', '_').replace(',', '')}" for k, c in RUNS])
def test_the_same_run_whether_the_master_writes_every_start_value_or_none(kind, case, make):
    """FMI 2.0 section 2.2.7: an input or parameter not set is its XML start. A master writing every
    start value read from the XML and one writing none (only ``case``'s values in both) get the same
    statuses, messages and outputs after 20 steps (model exchange: explicit Euler), bit for bit.
    (Before, setting ``scene = hover`` gave the unset inputs hover's trim, so the two differed.)"""
    t = make(kind)
    dt = t.facts["step"]
    none, every = conformance.start_value_runs(t, CASES[case], 20, dt)
    assert conformance.comparable(none) == conformance.comparable(every)
    exit_ = next(r for r in none if r["cmd"] == "exit")
    steps = [r for r in none if r["cmd"].split()[0] in ("steps", "euler")][0]
    assert steps["status"] == OK and len(steps["values"]) == 20 * len(conformance.scalar_outputs(t)), steps["log"]
    if "scene" in CASES[case]:  # the start values of forward flight in hover: each named, with hover's own
        assert exit_["status"] == WARNING and "scene 'hover' runs with input 'collective'" in texts(exit_)
    else:
        assert exit_["status"] == OK, exit_["log"]


@pytest.mark.parametrize("which", ["python", "native2", "native3"])
def test_fmpy_runs_the_same_with_every_start_value_written_or_none(which, fmu_files, tmp_path):
    """fmpy given every XML start value of the inputs and parameters (as fmpy's GUI and
    ``apply_start_values`` write them) and fmpy given none: hover from the family FMU gives the same
    outputs either way (a fresh process each)."""
    fmu = fmu_files[which]()
    names = ["blade1.flap" if which != "native3" else "seesaw.teeter", "fuselage.u", "main_rotor.thrust"]
    runs = [fmpy_outputs(fmu, {"scene": "hover"}, names, tmp_path, apply) for apply in (False, True)]
    assert runs[0] == runs[1] and len(runs[0]["time"]) == 21


def fmpy_outputs(fmu, start_values: dict, names: list[str], folder: Path, apply: bool = False) -> dict:
    """``fmpy.simulate_fmu`` of ``fmu`` for 20 steps of 2.5 ms in a fresh process (``fmu_hosts.modes``)."""
    args = {"fmu": str(fmu), "stop": 0.05, "dt": 0.0025, "names": names, "apply_defaults": apply,
            "start_values": start_values}
    path = folder / f"args-{len(list(folder.glob('args-*')))}.json"
    path.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", "fmpy_starts", str(path)], cwd=folder,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_scene_with_its_listed_start_values_runs_as_the_fmu_built_for_it(fmu_files, tmp_path):
    """``start_values_of(fmu, "hover")`` (the FMU's ``resources/scene_start_values.json``) runs hover in
    the family FMU as the FMU built for hover alone runs from its XML, bit for bit."""
    names = ["blade1.flap", "seesaw.teeter", "fuselage.u", "fuselage.pitch", "main_rotor.thrust"]
    family, own = fmu_files["python"](), build.ensure_fmu(("hover",))[0]
    values = build.start_values_of(family, "hover")
    assert values["scene"] == "hover" and values["initial_forward_speed"] == 0.0 and "collective" in values
    assert fmpy_outputs(family, values, names, tmp_path) == fmpy_outputs(own, {}, names, tmp_path)


# -- 4. the pythonfmu FMU: strings, status, states ---------------------------------------------------

def test_pythonfmu_refuses_text_that_is_not_utf8_with_an_error(make):
    """Bytes that are not UTF-8 (a stray byte, an overlong NUL, a surrogate) are fmi2Error, as in the
    native FMU (pythonfmu answered fmi2Fatal and its instance was lost); the instance goes on."""
    res = conformance.strings_not_utf8(make("pythonfmu-cs"), 1e-3)
    assert [r["status"] for r in res[2:5]] == [ERROR] * 3, res
    assert all("is not UTF-8 text" in texts(r) for r in res[2:5])
    assert res[5]["status"] == OK and res[6]["strings"] == ["hover"] and res[-1]["status"] == OK, res


@pytest.mark.parametrize("kind", ["pythonfmu-cs", "native2-cs", "controller-cs"])
def test_last_successful_time_and_status_queries(kind, make):
    """fmi2GetRealStatus(fmi2LastSuccessfulTime) is the end of the last step taken: the start time
    before the first, unchanged by steps refused (NaN, infinite, negative); a NULL value pointer
    is fmi2Error (not fmi2Discard)."""
    t = make(kind)
    dt = t.facts["step"] or 0.01
    res = conformance.status_queries(t, dt)
    times = [r["values"][0] for r in res if r["cmd"] == "realstatus 2"]
    assert times == [0.0, dt, dt, dt, dt], res
    assert [r["status"] for r in res if r["cmd"].startswith("step")] == [OK, ERROR, ERROR, ERROR]
    nulls = [r for r in res if r["cmd"].endswith("null")]
    assert [r["status"] for r in nulls] == [ERROR, ERROR] and all("NULL" in texts(r) for r in nulls), nulls
    assert res[-1]["status"] == OK and res[-1]["values"] == [0]


@pytest.mark.parametrize("kind", ["pythonfmu-cs", "native2-cs", "native3-cs"])
def test_damaged_and_foreign_serialized_states_are_refused(kind, make, tmp_path):
    """fmiXDeSerializeFMUState refuses a state truncated or extended by one byte, with one bit
    changed in its data (a checksum covers it) or in the GUID of its header (another build's); the
    intact one restores and the instance steps on."""
    t = make(kind)
    res = conformance.blob_cases(t, t.facts["step"], tmp_path)
    assert [r["status"] for r in res["intact"]] == [OK, OK, OK], res["intact"]
    reasons = {"truncated": "size", "extended": "size", "bit in the data": "checksum", "bit in the GUID": "GUID"}
    for name, word in reasons.items():
        assert res[name][0]["status"] == ERROR and word in texts(res[name][0]), (name, res[name])


@pytest.mark.parametrize("kind", ["pythonfmu-cs", "native2-cs", "native2-me", "native3-cs", "native3-me"])
def test_fmu_states_of_another_instance_or_library_are_refused(kind, make, tmp_path):
    """fmiXSetFMUState refuses a state saved by another instance of the same library and one saved
    by another library of the FMU (a copy; another build the same), and fmiXSerializedFMUStateSize
    the other instance's: each an error naming why; its own state still works."""
    t = make(kind)
    res = conformance.foreign_states(t, t.facts["step"], tmp_path / "copy")
    assert [r["status"] for r in res] == [OK, ERROR, ERROR, ERROR, OK, OK], res
    assert "another instance" in texts(res[1]) and "another FMU library" in texts(res[2])


# -- 5. the native FMU: state machines, messages --------------------------------------------------------

@pytest.mark.parametrize("kind", ["native2-me", "native3-me"])
def test_model_exchange_calls_in_the_wrong_mode_are_errors(kind, make):
    """The FMI 2.0 and 3.0 model-exchange state machines: derivatives in Instantiated,
    CompletedIntegratorStep and SetContinuousStates in Event Mode, NewDiscreteStates
    (UpdateDiscreteStates) in Continuous-Time Mode are fmiXError naming the mode; each in its mode
    is OK; fmi3EnterStepMode on model exchange is an error."""
    res = conformance.me_state_machine(make(kind))
    wrong = ["derivatives in Instantiated", "completed in Event Mode", "states in Event Mode",
             "discrete states in Continuous-Time Mode"]
    for name in wrong:
        assert res[name]["status"] == ERROR and "called in" in texts(res[name]), (name, res[name])
    right = ["exit", "discrete states in Event Mode", "continuous-time mode", "completed", "derivatives", "event mode"]
    assert [res[n]["status"] for n in right] == [OK] * len(right), res
    if "enter step mode" in res:
        assert res["enter step mode"]["status"] == ERROR


def test_fmi3_co_simulation_has_no_event_mode(make):
    """Without Event Mode (eventModeUsed is refused), fmi3EnterStepMode belongs nowhere: an error in
    Instantiated, Initialization Mode and Step Mode, as fmi3UpdateDiscreteStates in Step Mode."""
    res = conformance.cs_state_machine(make("native3-cs"), 1e-3)
    for name in ("enter step mode in Instantiated", "enter step mode in Initialization Mode",
                 "enter step mode in Step Mode", "update discrete states in Step Mode"):
        assert res[name]["status"] == ERROR and "Event Mode" in texts(res[name]), (name, res[name])
    assert res["step"]["status"] == OK


@pytest.mark.parametrize("kind", ["native3-cs", "native3-me"])
def test_fmi3_messages_name_fmi3_variables_and_value_references(kind, make):
    t = make(kind)
    res = conformance.fmi3_messages(t)
    force = t.vr("blade.root.force_x")
    assert f"output 'blade.root.force_x[2]' (value reference {force}) cannot be set" in texts(res["set output"])
    assert f"value reference {t.vr('scene')} is the String variable 'scene'" in texts(res["wrong type"])
    if t.me:
        assert "continuous state 8 ('blade.flap[2]') = nan" in texts(res["state"])
    assert "blade1" not in "".join(texts(r) for r in res.values())


@pytest.mark.parametrize("kind", ["native2-cs", "native3-cs"])
def test_serializing_into_a_null_buffer_says_so(kind, make):
    res = conformance.serialize_into_null(make(kind), 1e-3)
    assert res["null"]["status"] == ERROR and "is NULL" in texts(res["null"]) and "too small" not in texts(res["null"])
    assert res["buffer"]["status"] == OK


def test_fmi3_array_descriptions_name_element_k(fmu_files):
    """``der(blade.flap)`` and every array describe element k as blade k's (no ``blade1``/``blade 1``)."""
    root = ElementTree.fromstring(zipfile.ZipFile(fmu_files["native3"]()).read("modelDescription.xml"))
    arrays = [v for v in root.find("ModelVariables") if v.find("Dimension") is not None]
    assert len(arrays) > 10
    for v in arrays:
        text = v.get("description")
        assert "blade1" not in text and "blade 1" not in text and "element k" in text, (v.get("name"), text)
    der = next(v for v in arrays if v.get("name") == "der(blade.flap)")
    assert der.get("description").startswith("time derivative of blade.flap")
