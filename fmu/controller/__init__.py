"""The hover-hold controller FMU: a stability augmentation with attitude, velocity and position
hold for the helicopter FMU, designed from our own linearisation at the hover trim.

Design (:func:`design`): the 8-state flight-mechanics model ``ẋ = A x + B δ`` of
:func:`mbs.analysis.derivatives.derivatives` at the hover trim (quasi-static rotor in its
periodic equilibrium; Padfield's ``x = (u, w, q, θ, v, p, φ, r)``, ``δ = (θ0, θ1s, θ1c, θ0T)``),
extended by the position north, east, down in the trim heading's axes and the heading ψ
(their kinematics linearised at the trim attitude), and a linear-quadratic regulator on it
(:func:`scipy.linalg.solve_continuous_are`) with Bryson's weights: each state and control is
divided by the deviation it may reach (:data:`MAX_STATE`, :data:`MAX_CONTROL`). So the gains
say, e.g., how many radians of longitudinal cyclic a metre per second of forward speed costs.

The FMU (``HoverHold``, FMI 2.0 co-simulation, C: ``controller_fmi2.c`` with the generated
``hover_hold_data.h``): inputs are the helicopter FMU's fuselage outputs (``fuselage.x`` ...
``fuselage.r``, same names), outputs its four pitch inputs
``δ = δ_trim − gain_scale · K e`` (``e``: the inputs minus the trim, positions turned into the
trim heading's axes, heading taken nearest the trim heading by one ``remainder()``, so any finite
heading costs the same and one beyond ±2³³ rad, which a double no longer resolves, is discarded;
outputs clamped to the helicopter's input ranges). Libraries for the native FMU's platforms
(``linux64``, ``win64``, and ``sources/`` for ARM Linux, which FMI 2.0 has no folder for).
The controller samples: ``fmi2DoStep`` computes the outputs from the inputs averaged over the
last 1/N_b revolution (which removes the rotor harmonics at N_b/rev and its multiples, all
the fuselage feels in steady flight, and which the quasi-static design leaves out: fed back, they
drove the cyclic to its stops; a whole revolution's average delayed the loop into a roll limit
cycle); no direct
feedthrough, so a loop with the helicopter FMU, whose fuselage outputs are states, is no
algebraic loop; before the first step the outputs are the trim controls.
``gain_scale = 0`` leaves the loop open (the trim controls, held).

This package: the design, the generated data header and the build here; the FMU's C
(``controller_fmi2.c``) and its WebAssembly entry points for the flight page
(``controller_wasm.c``, built by :mod:`fmu.native.wasm`).
"""
from __future__ import annotations

import hashlib
import importlib.metadata
import json
import math
import os
import shutil
import subprocess
import tempfile
import time
import uuid
import zipfile
from pathlib import Path

import numpy as np

from fmu.native import platforms

HERE = Path(__file__).resolve().parent
NAME = "hover-hold"
IDENTIFIER = "HoverHold"
SCENE = "hover"
SOURCE = "controller_fmi2.c"
INPUTS = ("fuselage.x", "fuselage.y", "fuselage.z", "fuselage.roll", "fuselage.pitch", "fuselage.yaw",
          "fuselage.u", "fuselage.v", "fuselage.w", "fuselage.p", "fuselage.q", "fuselage.r")
INPUT_UNITS = ("m",) * 3 + ("rad",) * 3 + ("m/s",) * 3 + ("rad/s",) * 3
OUTPUTS = ("collective", "longitudinal_cyclic", "lateral_cyclic", "tail_collective")
STATES = ("u", "w", "q", "theta", "v", "p", "phi", "r", "north", "east", "down", "psi")
"""The regulator's state: Padfield's 8 (derivatives' order), then position in the trim heading's
axes (m) and heading (rad)."""
MAX_STATE = {"u": 2.0, "w": 1.0, "v": 2.0, "p": 0.15, "q": 0.1, "r": 0.3, "theta": 0.009, "phi": 0.01,
             "north": 2.0, "east": 2.0, "down": 2.0, "psi": 0.1}
"""Bryson's rule: the deviation (m/s, rad/s, rad, m) at which each state costs 1. Attitude and
its rates weigh most: the 1 m/s disturbance peaks at 1.87° of attitude (2.14° with 0.012 rad and
0.3 rad/s); a tighter pitch (0.008 rad) meets the quarter-revolution average's delay in a limit
cycle."""
MAX_CONTROL = 0.01  # rad: the pitch deviation at which each control costs 1
FROM_INPUT = {"u": "fuselage.u", "w": "fuselage.w", "q": "fuselage.q", "theta": "fuselage.pitch",
              "v": "fuselage.v", "p": "fuselage.p", "phi": "fuselage.roll", "r": "fuselage.r",
              "north": "fuselage.x", "east": "fuselage.y", "down": "fuselage.z", "psi": "fuselage.yaw"}


# -- design ------------------------------------------------------------------------------------

def augmented(a: np.ndarray, b: np.ndarray, phi: float, theta: float) -> tuple[np.ndarray, np.ndarray]:
    """``A`` (12, 12), ``B`` (12, 4) in :data:`STATES` order: Padfield's ``a`` (8, 8), ``b`` (8, 4)
    with d(north, east, down)/dt = R(φ, θ, 0) (u, v, w) and dψ/dt = (q sin φ + r cos φ) / cos θ
    at the trim roll ``phi`` and pitch ``theta`` (rad)."""
    import casadi as ca

    from mbs._rotation import euler_to_quat, quat_to_matrix

    big, bb = np.zeros((12, 12)), np.zeros((12, 4))
    big[:8, :8], bb[:8] = a, b
    idx = {s: i for i, s in enumerate(STATES)}
    rot = np.array(ca.DM(quat_to_matrix(ca.DM(euler_to_quat(phi, theta, 0.0)))))  # body to world
    for i, pos in enumerate(("north", "east", "down")):
        for j, vel in enumerate(("u", "v", "w")):
            big[idx[pos], idx[vel]] = rot[i, j]
    big[idx["psi"], idx["q"]] = math.sin(phi) / math.cos(theta)
    big[idx["psi"], idx["r"]] = math.cos(phi) / math.cos(theta)
    return big, bb


def lqr(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Gains ``K`` (4, 12): δ − δ_trim = −K (z − z_trim) minimises ∫ zᵀQz + δᵀRδ dt with Bryson's
    weights ``Q = diag(1 / MAX_STATE²)``, ``R = I / MAX_CONTROL²``."""
    from scipy.linalg import solve_continuous_are

    q = np.diag([1.0 / MAX_STATE[s] ** 2 for s in STATES])
    r = np.eye(b.shape[1]) / MAX_CONTROL ** 2
    p = solve_continuous_are(a, b, q, r)
    return np.linalg.solve(r, b.T @ p)


def design(log=None, aircraft=None) -> dict:
    """The controller at the hover trim of the helicopter FMU's default family of ``aircraft``
    (default the Bo105): gains by input name, trim values of the inputs and outputs, output
    ranges, the open- and closed-loop eigenvalues of the linear model."""
    from mbs import scenes
    from mbs.analysis.derivatives import derivatives

    from fmu import build as pybuild

    craft = pybuild.load_aircraft(aircraft)
    if log:
        log(f"designing the {NAME} controller of the {craft.name}: derivatives at the {SCENE} trim ...")
    d = derivatives(scenes.get(SCENE, craft))
    if list(d.controls) != list(OUTPUTS):
        raise RuntimeError(f"derivatives gave controls {d.controls}, expected {list(OUTPUTS)}")
    ref = d.reference
    a, b = augmented(d.A, d.B, ref["Phi_e"], ref["Theta_e"])
    k = lqr(a, b)
    spec = _helicopter_spec(pybuild, craft)
    trim = _trim_inputs(spec, ref, craft)
    gains = np.zeros((4, len(INPUTS)))
    for j, s in enumerate(STATES):
        gains[:, INPUTS.index(FROM_INPUT[s])] = k[:, j]
    scene = spec["scenes"][SCENE]
    controls = {c: float(scene["periodic"]["defaults"][c]) for c in OUTPUTS}
    ranges = {c: scene["ranges"][c] for c in OUTPUTS}
    blades = craft.data["main_rotor"]["n_blades"]
    window = scene["revolution"] / blades  # the fuselage feels the rotor's harmonics at N_b/rev and multiples
    return {"aircraft": craft.name, "gains": gains.tolist(), "trim_inputs": trim, "revolution": scene["revolution"], "window": window, "trim_controls": controls, "ranges": ranges,
            "heading": trim["fuselage.yaw"], "A": a.tolist(), "B": b.tolist(), "K_states": k.tolist(),
            "open_loop": _eigenvalues(a), "closed_loop": _eigenvalues(a - b @ k),
            "reference": {key: float(v) for key, v in ref.items()}, "states": list(STATES)}


def _eigenvalues(m: np.ndarray) -> list[list[float]]:
    lam = np.linalg.eigvals(m)
    return [[float(z.real), float(z.imag)] for z in sorted(lam, key=lambda z: (-z.real, z.imag))]


def _helicopter_spec(pybuild, aircraft=None) -> dict:
    """The spec of the helicopter FMU (default family) from its build (the shipped spec.json)."""
    return json.loads(zipfile.ZipFile(_pybuild_fmu(aircraft)).read("resources/heli_models/spec.json"))


def _trim_inputs(spec: dict, ref: dict, aircraft=None) -> dict:
    """The controller's input values at the trim: position and heading of the periodic hover
    start, period-mean attitude, velocities and rates of the linearisation (m, rad, m/s, rad/s)."""
    from mbs._rotation import quat_to_euler

    scene = spec["scenes"][SCENE]
    info = json.loads(zipfile.ZipFile(_pybuild_fmu(aircraft)).read(f"resources/heli_models/{scene['group']}/info.json"))
    x0 = dict(zip(info["q_names"] + info["v_names"] + info.get("z_names", []), scene["periodic"]["x0"]))
    yaw = float(quat_to_euler([x0[f"fuselage.q{c}"] for c in "wxyz"])[2])
    return {"fuselage.x": x0["fuselage.x"], "fuselage.y": x0["fuselage.y"], "fuselage.z": x0["fuselage.z"],
            "fuselage.roll": ref["Phi_e"], "fuselage.pitch": ref["Theta_e"], "fuselage.yaw": yaw,
            "fuselage.u": ref["U_e"], "fuselage.v": ref["V_e"], "fuselage.w": ref["W_e"],
            "fuselage.p": ref["P_e"], "fuselage.q": ref["Q_e"], "fuselage.r": ref["R_e"]}


def _pybuild_fmu(aircraft=None) -> Path:
    from fmu import build as pybuild

    return pybuild.ensure_fmu(pybuild.DEFAULT_SCENES, aircraft=aircraft)[0]


# -- the FMU -------------------------------------------------------------------------------------

def c_data(dsg: dict, guid: str) -> str:
    """``hover_hold_data.h``: the design as C constants."""
    from fmu.native.c_literals import c_real, c_reals, c_string

    rows = ",\n  ".join(c_reals(r) for r in dsg["gains"])
    low = [dsg["ranges"][c][0] for c in OUTPUTS]
    high = [dsg["ranges"][c][1] for c in OUTPUTS]
    return ("/* The hover-hold controller's design (generated at build time by fmu/controller). */\n"
            f"#define HH_GUID {c_string(guid)}\n#define HH_NIN {len(INPUTS)}\n#define HH_NOUT {len(OUTPUTS)}\n"
            f"static const double GAINS[HH_NOUT][HH_NIN] = {{\n  {rows}}};\n"
            f"static const double TRIM_IN[HH_NIN] = {c_reals([dsg['trim_inputs'][n] for n in INPUTS])};\n"
            f"static const double TRIM_OUT[HH_NOUT] = {c_reals([dsg['trim_controls'][c] for c in OUTPUTS])};\n"
            f"static const double LOW[HH_NOUT] = {c_reals(low)};\nstatic const double HIGH[HH_NOUT] = {c_reals(high)};\n"
            f"static const double WINDOW = {c_real(dsg['window'])}; /* averaging window (s) */\n"
            f"static const double COS_HEADING = {c_real(math.cos(dsg['heading']))};\n"
            f"static const double SIN_HEADING = {c_real(math.sin(dsg['heading']))};\n"
            f"static const char* const NAMES[HH_NIN + HH_NOUT + 1] = {{{', '.join(map(c_string, INPUTS + OUTPUTS))}, "
            '"gain_scale"};\n')


def model_description(dsg: dict, guid: str, step: float) -> bytes:
    """``modelDescription.xml`` of the controller FMU."""
    from xml.etree import ElementTree as ET

    from fmu.pythonfmu.units import BASE_UNITS

    root = ET.Element("fmiModelDescription", fmiVersion="2.0", modelName=IDENTIFIER, guid=guid,
                      description="hover hold for the heli rotor FMU: LQR at the hover trim from the model's own "
                                  "stability and control derivatives (fmu/controller)", author="rotor-mbs",
                      version=_version(), license="MIT", generationTool="rotor-mbs fmu.controller",
                      variableNamingConvention="structured", numberOfEventIndicators="0")
    cs = ET.SubElement(root, "CoSimulation", modelIdentifier=IDENTIFIER, needsExecutionTool="false",
                       canHandleVariableCommunicationStepSize="true", canInterpolateInputs="false",
                       maxOutputDerivativeOrder="0", canRunAsynchronuously="false",
                       canBeInstantiatedOnlyOncePerProcess="false", canNotUseMemoryManagementFunctions="true",
                       canGetAndSetFMUstate="false", canSerializeFMUstate="false",
                       providesDirectionalDerivative="false")
    files = ET.SubElement(cs, "SourceFiles")
    ET.SubElement(files, "File", name=SOURCE)
    units = ET.SubElement(root, "UnitDefinitions")
    for u in ("1", "m", "m/s", "rad", "rad/s"):
        ET.SubElement(ET.SubElement(units, "Unit", name=u), "BaseUnit", {k: str(e) for k, e in BASE_UNITS[u].items()})
    cats = ET.SubElement(root, "LogCategories")
    for name in ("logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal", "logAll"):
        ET.SubElement(cats, "Category", name=name)
    ET.SubElement(root, "DefaultExperiment", startTime="0.0", stopTime="60.0", stepSize=repr(step))
    variables = ET.SubElement(root, "ModelVariables")
    for k, (name, unit) in enumerate(zip(INPUTS, INPUT_UNITS)):
        sv = ET.SubElement(variables, "ScalarVariable", name=name, valueReference=str(k), causality="input",
                           variability="continuous", description=f"helicopter {name} (its output)")
        ET.SubElement(sv, "Real", start=repr(float(dsg["trim_inputs"][name])), unit=unit)
    for k, name in enumerate(OUTPUTS):
        sv = ET.SubElement(variables, "ScalarVariable", name=name, valueReference=str(len(INPUTS) + k),
                           causality="output", variability="continuous", initial="calculated",
                           description=f"helicopter {name} pitch (its input): trim minus the gains times the "
                                       "deviation, sampled at each step")
        ET.SubElement(sv, "Real", unit="rad", min=repr(dsg["ranges"][name][0]), max=repr(dsg["ranges"][name][1]))
    sv = ET.SubElement(variables, "ScalarVariable", name="gain_scale", valueReference=str(len(INPUTS) + 4),
                       causality="parameter", variability="fixed", description="1: closed loop; 0: open loop "
                       "(the trim controls held)")
    ET.SubElement(sv, "Real", start="1.0", unit="1", min="0.0", max="1.0")
    structure = ET.SubElement(root, "ModelStructure")
    for tag in ("Outputs", "InitialUnknowns"):
        group = ET.SubElement(structure, tag)
        for k in range(len(OUTPUTS)):  # sampled: no direct feedthrough; the trim before the first step
            ET.SubElement(group, "Unknown", index=str(len(INPUTS) + k + 1), dependencies="", dependenciesKind="")
    ET.indent(root, "\t")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def _version() -> str:
    try:
        return importlib.metadata.version("rotor-mbs")
    except importlib.metadata.PackageNotFoundError:
        return "0"


def default_step(spec: dict | None = None, aircraft=None) -> float:
    """The co-simulation's communication step: 1/100 revolution in whole nanoseconds (s)."""
    spec = spec or _helicopter_spec(__import__("fmu.build").build, aircraft)
    return round(spec["scenes"][SCENE]["revolution"] / spec["scenes"][SCENE]["steps_per_rev"] * 1e9) / 1e9


def build_controller(dest: Path, log=None, aircraft=None) -> dict:
    """Design, generate, compile and zip the controller FMU of ``aircraft`` into ``dest``;
    returns the design."""
    from fmu.native.build import fmi_headers_dir

    dsg = design(log, aircraft)
    guid = "{" + str(uuid.UUID(bytes=hashlib.sha256(json.dumps(dsg, sort_keys=True).encode()).digest()[:16],
                                version=5)) + "}"
    with tempfile.TemporaryDirectory(prefix="heli-controller-") as tmp:
        root = Path(tmp)
        src = root / "sources"
        src.mkdir()
        shutil.copy2(HERE / SOURCE, src / SOURCE)
        (src / "hover_hold_data.h").write_text(c_data(dsg, guid))
        for h in ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"):
            shutil.copy2(fmi_headers_dir() / h, src / h)
        for platform in platforms.available():
            if platform.fmi2:  # FMI 2.0 has no folder for ARM Linux: sources/ serve it, as in the native FMU
                compile_library(src, root / "binaries" / platform.fmi2 / f"{IDENTIFIER}{platform.suffix}", platform)
        if log and platforms.missing():
            log("controller FMU: no binaries for " + ", ".join(p.fmi3 for p in platforms.missing()))
        (root / "modelDescription.xml").write_bytes(model_description(dsg, guid, default_step(aircraft=aircraft)))
        (root / "resources").mkdir()
        (root / "resources" / "design.json").write_text(json.dumps(dsg, indent=1))
        dest.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as z:
            for path in sorted(p for p in root.rglob("*") if p.is_file()):
                z.write(path, path.relative_to(root).as_posix())
    return dsg


def compile_library(sources: Path, out: Path, platform) -> Path:
    """The controller's shared library ``out`` from ``sources/`` for ``platform`` (a
    :class:`fmu.native.platforms.Platform`): no fused multiply-adds, so every platform gives the
    same bits where the C runtime's functions do."""
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [platforms.compiler(platform), "-shared", "-O2", "-ffp-contract=off", "-fvisibility=hidden", *platform.cflags,
           "-I", str(sources), str(sources / SOURCE), "-o", str(out), *platform.ldflags]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling the controller FMU for {platform.fmi3} failed:\n{proc.stderr[-3000:]}")
    return out


def cache_key(aircraft=None) -> str:
    """Hash of what the controller is designed and built from (the core, the aircraft, the FMU code)."""
    from fmu import build as pybuild

    h = hashlib.sha256(pybuild.cache_key(pybuild.DEFAULT_SCENES, aircraft).encode())
    for name in ("__init__.py", SOURCE):
        h.update((HERE / name).read_bytes())
    h.update(os.environ.get("CC", "").encode())
    h.update(json.dumps(platforms.key()).encode())
    return h.hexdigest()[:20]


def ensure_controller_fmu(force: bool = False, log=None, aircraft=None) -> tuple[Path, float]:
    """The cached controller FMU of ``aircraft`` (default the Bo105; built if absent or not
    intact); (path, build seconds)."""
    from mbs.backends.cache import record, writable_dir
    from mbs.backends.compiled import cache_dir

    from fmu.build import fmu_problem

    path = cache_dir() / "fmu-controller" / cache_key(aircraft) / f"{IDENTIFIER}.fmu"
    if not force and fmu_problem(path) is None:
        return path, 0.0
    writable_dir(path.parent, "FMU cache")
    start = time.perf_counter()
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        build_controller(tmp, log, aircraft)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    tmp.replace(path)
    record(path)
    return path, time.perf_counter() - start


def read_design(fmu: Path) -> dict:
    """The design shipped in the controller FMU (``resources/design.json``)."""
    return json.loads(zipfile.ZipFile(fmu).read("resources/design.json"))
