"""The FMU's FMI front end (``fmu/pythonfmu/shim``) in front of pythonfmu's binary: resource paths with
``#&%`` and non-ASCII characters, statuses (an error logged during a call is fmi2Error, a
fatal error of pythonfmu leaves a dead instance that answers fmi2Error instead of crashing),
logging with loggingOn = false, a host without Python, misuse, and the packaging.

Every FMU runs in a fresh interpreter (this file run as a script, ``MODES`` below) whose
working directory is a temporary folder; the C host is compiled here with the machine's cc.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

from fmu import build, hosts
from fmu.pythonfmu import shim

FAMILY = build.DEFAULT_SCENES
ODD_FOLDER = "a#b&c%d ü"
NAMES = ["blade1.flap", "seesaw.teeter", "main_rotor.thrust", "fuselage.u"]


@pytest.fixture(scope="session")
def fmu_path(python_fmu) -> Path:
    return python_fmu


@pytest.fixture(scope="session")
def dt(python_spec) -> float:
    return python_spec["default_experiment"]["step"]


def unzip(fmu: Path, folder: Path) -> Path:
    folder.mkdir(parents=True)
    with zipfile.ZipFile(fmu) as z:
        z.extractall(folder)
    return folder


def host(mode: str, args: dict, tmp_path: Path) -> dict:
    """Run ``MODES[mode](args)`` in a fresh interpreter with ``tmp_path`` as working directory."""
    args_file = tmp_path / f"{mode}-args.json"
    args_file.write_text(json.dumps(args))
    proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), mode, str(args_file)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    result["_stderr"] = proc.stderr
    return result


# -- resource locations ------------------------------------------------------------------------

def test_unzipped_into_an_odd_folder_runs_like_a_plain_one(fmu_path, dt, tmp_path):
    odd, plain = unzip(fmu_path, tmp_path / ODD_FOLDER), unzip(fmu_path, tmp_path / "plain")
    args = {"fmu": str(fmu_path), "dt": dt, "steps": 5, "names": NAMES}
    run_odd = host("steps", {**args, "unzipdir": str(odd)}, tmp_path)
    run_plain = host("steps", {**args, "unzipdir": str(plain)}, tmp_path)
    assert run_odd["statuses"] == [0] * 5, run_odd["messages"]
    assert run_odd["outputs"] == run_plain["outputs"]
    assert run_odd["outputs"][-1][0] != run_odd["outputs"][0][0]  # it did step


def test_simulate_fmu_on_an_odd_unzip_folder_equals_the_fmu_file(fmu_path, dt, tmp_path):
    odd = unzip(fmu_path, tmp_path / ODD_FOLDER)
    args = {"dt": dt, "stop": 10 * dt, "names": NAMES}
    from_dir = host("simulate", {**args, "fmu": str(odd)}, tmp_path)
    from_file = host("simulate", {**args, "fmu": str(fmu_path)}, tmp_path)
    assert len(from_dir["time"]) == 11 and math.isclose(from_dir["time"][-1], 10 * dt)
    assert from_dir == {**from_file, "_stderr": from_dir["_stderr"]}


# -- statuses ----------------------------------------------------------------------------------

def test_an_error_logged_by_the_slave_makes_the_call_return_fmi2error(fmu_path, dt, tmp_path):
    """setReal of a value the slave refuses (logged with status error, no exception) answers
    fmi2Error (3) every time; the instance stays usable."""
    res = host("refused", {"fmu": str(fmu_path), "dt": dt}, tmp_path)
    assert res["nan"] == [3] * 10 and res["step_after_nan"] == 2 and res["recovered"] == 0, res
    assert sum("'collective' = nan" in m for s, m in res["messages"] if s == "error") >= 10


def test_setreal_of_an_unknown_value_reference_is_an_error_not_a_crash(fmu_path, dt, tmp_path):
    """Needs the slave to refuse an unknown value reference by logging (not raising)."""
    res = host("unknown_vr", {"fmu": str(fmu_path), "dt": dt}, tmp_path)
    assert res["statuses"] == [3] * 10, res["messages"][-3:]
    assert res["step"] == 0, res["messages"][-3:]


def test_a_fatal_error_of_pythonfmu_leaves_a_dead_instance_answering_errors(echo_fmu, tmp_path):
    """An exception in a pythonfmu slave (the rotor slave never lets one out; the small test
    slave below raises on purpose when x < 0) makes pythonfmu answer fmi2Fatal after it has
    dropped its Python objects. Its next call would crash the host; the shim answers
    fmi2Error, frees the instance without touching pythonfmu's, and a new instance in the
    same process works."""
    res = host("fatal", {"fmu": str(echo_fmu), "dt": 0.1}, tmp_path)
    assert res["fatal_step"] == 4, res
    assert res["after"] == [3] * 10, res
    assert res["freed"] and res["second_step"] == 0, res
    text = "\n".join(m for _, m in res["messages"])
    assert "pythonfmu reported fmi2Fatal" in text and "fmi2DoStep: instance 'dying' is unusable" in text
    assert "fmi2GetReal: instance 'dying' is unusable" in text


def test_errors_reach_the_logger_with_logging_off(fmu_path, dt, tmp_path):
    res = host("quiet", {"fmu": str(fmu_path), "dt": dt}, tmp_path)
    assert res["set"] == 3 and res["step"] == 2
    statuses = [s for s, _ in res["messages"]]
    assert "error" in statuses and "discard" in statuses
    assert all(s != "ok" for s in statuses), res["messages"]
    assert any("'collective' = nan rad is not a finite number" in m for _, m in res["messages"])


def test_misuse_gives_errors_naming_the_call(fmu_path, dt, tmp_path):
    res = host("misuse", {"fmu": str(fmu_path), "dt": dt}, tmp_path)
    assert res["statuses"] == {"step_before_init": 3, "null_arrays": 3, "null_component": 3,
                               "exit_twice": 3, "null_string": 3, "set_after_terminate": 3,
                               "unsupported": 3, "step_after_init": 0}, res
    text = "\n".join(m for _, m in res["messages"])
    for needle in ("fmi2DoStep: not allowed while instance 'misused' is instantiated",
                   "fmi2SetReal: vr[] is NULL (with 2 elements)",
                   "fmi2ExitInitializationMode: not allowed while instance 'misused' is stepping",
                   "fmi2SetString: value[0] (value reference", "fmi2SetReal: not allowed while instance 'misused' "
                   "is terminated", "fmi2GetDirectionalDerivative: not supported"):
        assert needle in text, needle
    assert "fmi2DoStep: called with a NULL fmi2Component" in res["_stderr"]


ECHO_SLAVE = """
from pythonfmu import Fmi2Causality, Fmi2Slave, Real
from pythonfmu.enums import Fmi2Status


class Echo(Fmi2Slave):
    \"\"\"Logs an ok and a warning message every step, a discard while x > 10, and raises
    while x < 0.\"\"\"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.x = 0.0
        self.register_variable(Real("x", causality=Fmi2Causality.input))

    def do_step(self, current_time, step_size):
        self.log(f"ok message: 100% of the step at t = {current_time}")
        self.log("a warning", Fmi2Status.warning)
        if self.x > 10:
            self.log(f"x = {self.x} is too large", Fmi2Status.discard)
        if self.x < 0:
            raise RuntimeError(f"x = {self.x} is negative")
        return True
"""


@pytest.fixture(scope="session")
def echo_fmu(tmp_path_factory) -> Path:
    """A small pythonfmu FMU (the slave above) packaged with the shim like the rotor FMU."""
    folder = tmp_path_factory.mktemp("echo")
    return Path(host("build_echo", {"dest": str(folder / "Echo.fmu")}, folder)["fmu"])


@pytest.mark.parametrize("logging", ["off", "on", "warnings only"])
def test_logging_and_statuses_follow_what_the_slave_logged(echo_fmu, logging, tmp_path):
    res = host("echo", {"fmu": str(echo_fmu), "logging": logging}, tmp_path)
    assert res["step"] == 1 and res["discard_step"] == 2, res  # fmi2Warning, fmi2Discard
    ok = ["ok message: 100%% of the step at t = 0.0"]  # a message is a format string: '%' doubled
    expect = {"off": [], "on": ok, "warnings only": []}[logging]
    assert res["messages"] == [["ok", m] for m in expect] + [["warning", "a warning"]], res
    assert res["after_discard"][-1] == ["discard", "x = 20.0 is too large"], res
    assert ["ok", "ok message: 100%% of the step at t = 0.1"] in res["after_discard"] or logging != "on"


# -- a host without Python ------------------------------------------------------------------------

C_HOST = r"""
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    printf("LOG %s %d %s %s\n", (const char *)env, (int)status, category, message);
}

int main(int argc, char **argv)
{
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        printf("DLOPEN %s\n", dlerror());
        return 2;
    }
    fmi2InstantiateTYPE *instantiate = (fmi2InstantiateTYPE *)dlsym(lib, "fmi2Instantiate");
    fmi2GetVersionTYPE *version = (fmi2GetVersionTYPE *)dlsym(lib, "fmi2GetVersion");
    fmi2GetTypesPlatformTYPE *platform = (fmi2GetTypesPlatformTYPE *)dlsym(lib, "fmi2GetTypesPlatform");
    fmi2DoStepTYPE *step = (fmi2DoStepTYPE *)dlsym(lib, "fmi2DoStep");
    fmi2FreeInstanceTYPE *release = (fmi2FreeInstanceTYPE *)dlsym(lib, "fmi2FreeInstance");
    printf("VERSION %s %s\n", version(), platform());
    printf("NULL_STEP %d\n", (int)step(NULL, 0.0, 0.1, fmi2True));
    for (int i = 3; i < argc; i++) {
        fmi2CallbackFunctions cb = {logger, calloc, free, NULL, argv[i]};
        fmi2Component c = instantiate("c-host", fmi2CoSimulation, argv[2], argv[i], &cb, fmi2False, fmi2False);
        printf("INSTANCE %s %s\n", argv[i], c ? "non-NULL" : "NULL");
        release(c);
    }
    return 0;
}
"""


@pytest.fixture(scope="session")
def c_host(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("c-host")
    (folder / "host.c").write_text(C_HOST)
    exe = folder / "host"
    proc = subprocess.run([shim.find_compiler(), "-std=c99", f"-I{shim.headers_dir()}", str(folder / "host.c"),
                           "-o", str(exe), "-ldl"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return exe


def run_c_host(c_host: Path, fmu_dir: Path, guid: str, locations: list[str], cwd: Path) -> dict:
    lib = fmu_dir / "binaries" / "linux64" / "HeliRotor_forward_flight.so"
    proc = subprocess.run([str(c_host), str(lib), guid, *locations], cwd=cwd, capture_output=True, timeout=60)
    assert proc.returncode == 0, (proc.returncode, proc.stdout, proc.stderr)
    out = proc.stdout.decode("utf-8", "replace")
    logs = {loc: [line[len(f"LOG {loc} "):] for line in out.splitlines() if line.startswith(f"LOG {loc} ")]
            for loc in locations}
    return {"out": out, "logs": logs}


def _guid(fmu_dir: Path) -> str:
    return ElementTree.parse(fmu_dir / "modelDescription.xml").getroot().get("guid")


def test_a_host_without_python_gets_null_and_a_message(fmu_path, c_host, tmp_path):
    fmu_dir = unzip(fmu_path, tmp_path / ODD_FOLDER)
    location = (fmu_dir / "resources").as_uri()  # percent-escaped: a%23b%26c%25d%20%C3%BC
    res = run_c_host(c_host, fmu_dir, _guid(fmu_dir), [location], tmp_path)
    assert "VERSION 2.0 default" in res["out"] and "NULL_STEP 3" in res["out"]
    assert f"INSTANCE {location} NULL" in res["out"]
    [message] = res["logs"][location]
    assert message.startswith("3 logStatusError fmi2Instantiate: instance 'c-host': this FMU runs its model in "
                              "Python and needs a Python host process with numpy"), message
    assert "undefined symbol: _Py" in message and "heli fmu build --native" in message


def test_resource_locations_are_decoded_and_checked(fmu_path, c_host, tmp_path):
    """The location checks come before pythonfmu is loaded: in a host without Python, a good
    location ends at the message about Python, a bad one at a message about the location."""
    fmu_dir = unzip(fmu_path, tmp_path / ODD_FOLDER)
    resources = fmu_dir / "resources"
    (tmp_path / "x%20y").mkdir()
    quoted = resources.as_uri()[len("file://"):]
    good = [f"file://{quoted}", f"file:{quoted}", f"file://localhost{quoted}", f"file://{quoted}/", str(resources)]
    bad = {f"file://{tmp_path.as_posix()}/x%2520y": "contains the characters %%20",
           f"file://{quoted}%2Fmissing": "does not exist",
           "file:///tmp/%zz": "invalid percent escape",
           "file:///tmp/%00": "invalid percent escape",
           "http://example.org/resources": "is not a local file URI",
           "file:///tmp/%FF": "is not valid UTF-8"}
    res = run_c_host(c_host, fmu_dir, _guid(fmu_dir), good + list(bad), tmp_path)
    for location in good:
        [message] = res["logs"][location]
        assert "needs a Python host process" in message, (location, message)
    for location, needle in bad.items():
        [message] = res["logs"][location]
        assert needle in message and "needs a Python" not in message, (location, message)
    assert f"the resources folder '{tmp_path.as_posix()}/x%%20y' contains" in res["logs"][list(bad)[0]][0]


# -- packaging -------------------------------------------------------------------------------------

def test_only_linux64_binaries_with_the_shim_in_front(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        binaries = sorted(n for n in z.namelist() if n.startswith("binaries/"))
        xml = z.read("modelDescription.xml").decode()
        front = z.read("binaries/linux64/HeliRotor_forward_flight.so")
    assert binaries == ["binaries/linux64/HeliRotor_forward_flight.so",
                        "binaries/linux64/pythonfmu/HeliRotor_forward_flight.so"]
    assert b"pythonfmu reported fmi2Fatal" in front  # the shim, not pythonfmu's library
    for other in ("win32", "win64", "darwin", "linux32", ".dll", ".dylib"):
        assert other not in xml
    from fmpy import supported_platforms

    assert supported_platforms(str(fmu_path)) == ["linux64"]


def test_fmpy_validate_is_clean(fmu_path, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "fmpy.cli", "validate", str(fmu_path)], cwd=tmp_path,
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "No problems found" in proc.stdout, proc.stdout + proc.stderr


def test_relocate_moves_pythonfmus_library_and_drops_other_platforms():
    lib = "binaries/linux64/M.so"
    assert shim.relocate(lib, b"inner", b"shim") == [("binaries/linux64/pythonfmu/M.so", b"inner"), (lib, b"shim")]
    assert shim.relocate("binaries/win64/M.dll", b"x", b"shim") == []
    assert shim.relocate("resources/a.py", b"x", b"shim") == [("resources/a.py", b"x")]


def test_building_without_a_compiler_says_so(monkeypatch, tmp_path):
    monkeypatch.setenv("CC", "no-such-cc")
    with pytest.raises(shim.ShimBuildError, match="needs a C compiler.*no-such-cc"):
        shim.compile_shim(tmp_path / "shim.so", "{12345678-1234-5678-1234-567812345678}")


def test_building_the_fmu_without_a_compiler_fails_at_once_with_that_message(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "fmu.build", "--dest", str(tmp_path / "x.fmu")], cwd=tmp_path,
                          capture_output=True, text=True, env={**os.environ, "CC": "no-such-cc"}, timeout=300)
    assert proc.returncode != 0 and not (tmp_path / "x.fmu").exists()
    assert "ShimBuildError: building the FMU needs a C compiler" in proc.stderr, proc.stderr[-2000:]


def test_the_shim_compiles_cleanly(tmp_path):
    out = shim.compile_shim(tmp_path / "shim.so", "{12345678-1234-5678-1234-567812345678}")
    proc = subprocess.run(["nm", "-D", "--defined-only", str(out)], capture_output=True, text=True)
    if proc.returncode:
        pytest.skip("nm is not available")
    exported = {line.split()[-1] for line in proc.stdout.splitlines()}
    assert exported == FMI2_CS_FUNCTIONS


FMI2_CS_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate", "fmi2FreeInstance",
    "fmi2SetupExperiment", "fmi2EnterInitializationMode", "fmi2ExitInitializationMode", "fmi2Terminate",
    "fmi2Reset", "fmi2GetReal", "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal",
    "fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate",
    "fmi2FreeFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
    "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus"}


# -- the fresh-process side (run as a script) ----------------------------------------------------

_status = hosts.call_status  # the status of one FMI call (fmpy raises on errors)


def _instance(a: dict, name: str = "instance", logging_on: bool = True, unzipdir: str | None = None):
    from fmu.hosts import Instance

    return Instance(a["fmu"], name, unzipdir=unzipdir or a.get("unzipdir"), logging_on=logging_on)


def _mode_steps(a: dict) -> dict:
    inst = _instance(a)
    inst.initialise()
    statuses, outputs = [], []
    for k in range(a["steps"]):
        statuses.append(inst.step(k * a["dt"], a["dt"]))
        outputs.append(inst.get(a["names"]))
    inst.free()
    return {"statuses": statuses, "outputs": outputs, "messages": inst.messages}


def _mode_simulate(a: dict) -> dict:
    from fmpy import simulate_fmu

    res = simulate_fmu(a["fmu"], stop_time=a["stop"], output_interval=a["dt"], output=a["names"])
    return {"time": res["time"].tolist(), **{n: res[n].tolist() for n in a["names"]}}


def _mode_refused(a: dict) -> dict:
    inst = _instance(a, "refusing")
    inst.initialise()
    nan = [_status(inst.set, {"collective": float("nan")}) for _ in range(10)]
    out = {"nan": nan, "step_after_nan": inst.step(0.0, a["dt"])}
    inst.set({"collective": 0.25})
    out["recovered"] = inst.step(0.0, a["dt"])
    return {**out, "messages": inst.messages}


def _mode_unknown_vr(a: dict) -> dict:
    inst = _instance(a, "unknown")
    inst.initialise()
    statuses = [_status(inst.slave.setReal, [987654], [1.0]) for _ in range(10)]
    return {"statuses": statuses, "step": inst.step(0.0, a["dt"]), "messages": inst.messages}


def _mode_fatal(a: dict) -> dict:
    inst = _instance(a, "dying")
    inst.initialise()
    inst.set({"x": -1.0})
    out = {"fatal_step": inst.step(0.0, a["dt"])}
    calls = [lambda: inst.step(0.0, a["dt"]), lambda: _status(inst.get, ["x"]),
             lambda: _status(inst.set, {"x": 1.0}), lambda: _status(inst.slave.terminate)]
    out["after"] = [calls[k % len(calls)]() for k in range(10)]
    inst.slave.freeInstance()
    out["freed"] = True
    second = _instance(a, "second", unzipdir=inst.unzipdir)
    second.initialise()
    out["second_step"] = second.step(0.0, a["dt"])
    second.free()
    return {**out, "messages": inst.messages}


def _mode_quiet(a: dict) -> dict:
    inst = _instance(a, "quiet", logging_on=False)
    inst.initialise()
    inst.step(0.0, a["dt"])
    out = {"set": _status(inst.set, {"collective": float("nan")}), "step": inst.step(a["dt"], a["dt"])}
    return {**out, "messages": inst.messages}


def _mode_misuse(a: dict) -> dict:
    inst = _instance(a, "misused")
    s, c, vr = inst.slave, inst.slave.component, inst.vr
    out = {"step_before_init": inst.step(0.0, a["dt"]),
           "null_arrays": _status(s.fmi2SetReal, c, None, 2, None),
           "null_component": _status(s.fmi2DoStep, None, 0.0, a["dt"], 1)}
    inst.initialise()
    out["exit_twice"] = _status(s.exitInitializationMode)
    out["step_after_init"] = inst.step(0.0, a["dt"])
    from fmpy.fmi2 import fmi2String, fmi2ValueReference

    out["null_string"] = _status(s.fmi2SetString, c, (fmi2ValueReference * 1)(vr["scene"]), 1, (fmi2String * 1)())
    out["unsupported"] = _status(s.fmi2GetDirectionalDerivative, c, None, 0, None, 0, None, None)
    s.terminate()
    out["set_after_terminate"] = _status(inst.set, {"collective": 0.2})
    s.freeInstance()
    return {"statuses": out, "messages": inst.messages}


def _mode_build_echo(a: dict) -> dict:
    from pythonfmu import FmuBuilder

    script = Path("echo.py")
    script.write_text(ECHO_SLAVE)
    built = FmuBuilder.build_FMU(script, dest="out")
    from fmpy import read_model_description

    build._recompress(built, Path(a["dest"]), build.compiled_shim(read_model_description(str(built)).guid))
    return {"fmu": a["dest"]}


def _mode_echo(a: dict) -> dict:
    inst = _instance(a, "echo", logging_on=a["logging"] != "off")
    if a["logging"] == "warnings only":
        inst.slave.setDebugLogging(True, ["logStatusWarning", "logStatusDiscard"])
    inst.initialise()
    s, c = inst.slave, inst.slave.component
    out = {"step": s.fmi2DoStep(c, 0.0, 0.1, 1), "messages": list(inst.messages)}
    inst.set({"x": 20.0})
    out["discard_step"] = _status(s.fmi2DoStep, c, 0.1, 0.1, 1)
    out["after_discard"] = inst.messages[len(out["messages"]):]
    inst.free()
    return out


MODES = {"steps": _mode_steps, "simulate": _mode_simulate, "refused": _mode_refused, "unknown_vr": _mode_unknown_vr,
         "fatal": _mode_fatal, "quiet": _mode_quiet, "misuse": _mode_misuse, "build_echo": _mode_build_echo,
         "echo": _mode_echo}


if __name__ == "__main__":
    mode, args_path = sys.argv[1], sys.argv[2]
    print(json.dumps(MODES[mode](json.loads(Path(args_path).read_text()))))
    hosts.finish(0)
