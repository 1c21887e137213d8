"""What a strict FMI 2.0 host meets, on both FMUs (pythonfmu and native): a start value equal
to its XML start is used (was it set is recorded), misuse of h and t is fmi2Error (not
fmi2Discard), an empty instance name and a foreign GUID are refused, a communication step
rounded to whole nanoseconds is one sub-step, fmi2Terminated stays false after a discard,
fmi2GetFMUstate into the same state does not grow memory, a too small serialisation buffer
is refused, a state restored into an instance in another phase steps on, unknown log
categories are refused, and every unit has its SI base units.

Each case runs in a fresh interpreter (``python -m fmu_hosts.probe_fmi CASE ARGS``).
"""
from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

from fmu import build

FAMILY = build.DEFAULT_SCENES
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3


def _native() -> Path:
    from fmu.native import build as native_build

    return native_build.ensure_native_fmu(FAMILY)[0]


FMUS = {"python": lambda: build.ensure_fmu(FAMILY)[0], "native": _native}


@pytest.fixture(scope="session", params=sorted(FMUS))
def fmu_path(request) -> Path:
    return FMUS[request.param]()


def probe(case: str, args: dict, tmp_path: Path) -> dict:
    args_file = tmp_path / f"{case}-args.json"
    args_file.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.probe_fmi", case, str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"the host died (exit code {proc.returncode}):\n{proc.stderr[-3000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


def model_description(fmu: Path) -> ElementTree.Element:
    return ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))


def xml_start(fmu: Path, name: str) -> str:
    sv = next(sv for sv in model_description(fmu).find("ModelVariables") if sv.get("name") == name)
    return sv[0].get("start")


# -- start values --------------------------------------------------------------------------------

def test_start_value_equal_to_its_xml_start_is_used(fmu_path, tmp_path):
    """The issue's case: hover with initial_forward_speed = 10.0 m/s (the XML start, forward
    flight's) starts at 10 m/s, not at hover's 0; a collective equal to the forward-flight start
    is used in hover; exitInitializationMode warns about both."""
    speed, collective = float(xml_start(fmu_path, "initial_forward_speed")), float(xml_start(fmu_path, "collective"))
    assert speed == 10.0
    res = probe("start_equal", {"fmu": str(fmu_path), "scene": "hover", "names": ["fuselage.u", "collective"],
                                "reals": {"initial_forward_speed": speed, "collective": collective}}, tmp_path)
    assert res["values"]["collective"] == collective
    assert abs(res["values"]["fuselage.u"] - speed) < 0.02 * speed, res["values"]  # body u ≈ V cos(pitch)
    assert res["statuses"][-1] == WARNING, res
    warned = "\n".join(m for s, m in res["exit_messages"] if s == "warning")
    assert "'initial_forward_speed' = 10.0" in warned and "'collective'" in warned and "hover" in warned, warned


# -- doStep misuse, instantiate ------------------------------------------------------------------

def test_misuse_of_step_size_and_time_is_an_error_not_a_discard(fmu_path, tmp_path):
    res = probe("step_misuse", {"fmu": str(fmu_path)}, tmp_path)
    for name, rec in res["bad"].items():
        assert rec["status"] == ERROR, (name, rec)
        assert rec["messages"], name
    assert res["good"]["status"] == OK, res["good"]


def test_empty_instance_name_and_foreign_guid_are_refused(fmu_path, tmp_path):
    res = probe("instantiate", {"fmu": str(fmu_path)}, tmp_path)
    assert not res["empty name"]["created"] and "instanceName" in str(res["empty name"]["messages"])
    assert not res["other GUID"]["created"] and "GUID" in str(res["other GUID"]["messages"])
    assert res["good"]["created"], res["good"]


def test_default_step_rounded_to_nanoseconds_is_one_substep(fmu_path, tmp_path):
    """A master counting whole nanoseconds (libcosim) rounds the default step (= max_step) up
    by < 0.5 ns: one sub-step, bit for bit the run with max_step set to that step."""
    step = float(model_description(fmu_path).find("DefaultExperiment").get("stepSize"))
    dt = round(step * 1e9) / 1e9
    assert dt > step
    res = probe("nanosecond_step", {"fmu": str(fmu_path), "dt": dt, "steps": 20,
                                    "names": ["blade1.flap", "fuselage.q", "main_rotor.thrust"]}, tmp_path)
    assert res["default max_step"] == res["max_step = step"]
    assert all(row[0] == OK for row in res["default max_step"])


# -- status, states, logging ---------------------------------------------------------------------

def test_terminated_status_stays_false_after_a_discard(fmu_path, tmp_path):
    res = probe("terminated_status", {"fmu": str(fmu_path), "collective": float(xml_start(fmu_path, "collective"))},
                tmp_path)
    assert res["good_step"] == OK and res["discarded_step"] == DISCARD and res["recovered_step"] == OK, res
    for when in ("after_good", "after_discard", "after_recovery"):
        assert res[when] == [OK, False], (when, res)


def test_fmu_state_into_the_same_state_does_not_grow_memory(fmu_path, tmp_path):
    res = probe("state_into_same", {"fmu": str(fmu_path), "warmup": 200, "calls": 10_000}, tmp_path)
    assert res["worst"] == OK and res["same_address"], res
    assert res["growth"] < 1_000_000, f"RSS grew {res['growth'] / 1e6:.1f} MB over 10,000 fmi2GetFMUstate"


def test_serialising_into_a_too_small_buffer_is_an_error(fmu_path, tmp_path):
    res = probe("small_buffer", {"fmu": str(fmu_path)}, tmp_path)
    assert res["small"]["status"] == ERROR and "too small" in str(res["small"]["messages"]), res
    assert res["full"] == OK


def test_state_restored_into_an_instance_in_another_phase_steps_on(fmu_path, tmp_path):
    res = probe("restore_phase", {"fmu": str(fmu_path), "name": "blade1.flap"}, tmp_path)
    assert res["save"] == OK
    for phase in ("instantiated", "initialization", "terminated"):
        rec = res[phase]
        assert rec["restore"] == OK and rec["step"] == OK and rec["equal"], (phase, rec)


def test_unknown_log_category_is_an_error(fmu_path, tmp_path):
    res = probe("log_categories", {"fmu": str(fmu_path)}, tmp_path)
    assert res["known"]["status"] == OK
    assert res["unknown"]["status"] == ERROR and "logNoSuchCategory" in str(res["unknown"]["messages"])


# -- model description ------------------------------------------------------------------------------

def test_every_unit_has_its_si_base_units(fmu_path):
    units = {u.get("name"): u.find("BaseUnit") for u in model_description(fmu_path).find("UnitDefinitions")}
    assert {n for n, b in units.items() if b is None} == set()
    assert units["N m"].attrib == {"kg": "1", "m": "2", "s": "-2"}
    assert units["W"].attrib == {"kg": "1", "m": "2", "s": "-3"}


def test_native_fmu_offers_no_virtual_machine():
    sv = next(sv for sv in model_description(_native()).find("ModelVariables") if sv.get("name") == "evaluator")
    assert "vm:" not in sv.get("description") and sv[0].get("start") == "compiled"


def test_guid_comes_from_the_content_and_a_rebuild_keeps_it(tmp_path):
    """pythonfmu's builder makes a time- and MAC-based GUID (uuid1) at every build; ours is
    derived from what the FMU is built from: a fresh build gives the cached FMU's GUID."""
    import uuid

    cached = model_description(build.ensure_fmu(FAMILY)[0]).get("guid")
    proc = subprocess.run([sys.executable, "-m", "fmu.build", "--dest", str(tmp_path / "again.fmu")], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert model_description(tmp_path / "again.fmu").get("guid") == cached
    assert uuid.UUID(cached).version == 5
