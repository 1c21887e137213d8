"""Build the FMU of a scene family: plan the variables, compile the models, stage a clean
copy of the slave and of the core's run-time files, and call pythonfmu's builder.

``ensure_fmu(scenes)`` returns a cached ``.fmu`` (``<cache>/fmu/<key>/<identifier>.fmu``,
keyed by the sources of ``mbs`` and ``fmu``, the scenes, ``$CC``, CasADi and pythonfmu),
building it in a fresh interpreter (``python -m fmu.build``) when absent or when it fails
its recorded digest. The staged code lives in a package named ``heli_rotor_<digest>``
(digest of the staged code) with every ``import mbs...`` rewritten to it, and the slave's
helpers (:mod:`fmu.pythonfmu`) in its subpackage ``slave``, so the shipped copy never mixes
with an ``mbs`` or ``fmu`` that the host process imported, nor with another build of this FMU
loaded in the same process.
"""
from __future__ import annotations

import argparse
import hashlib
import importlib.metadata
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
import uuid
import zipfile
from pathlib import Path

import numpy as np

from fmu import DEFAULT_SCENES

HERE = Path(__file__).resolve().parent
SLAVE = "heli_rotor_slave"  # the entry module (fmu/pythonfmu/slave.py) in the FMU: <SLAVE>_<digest>.py
SLAVE_DIR = HERE / "pythonfmu"
RUNTIME = ["backends/__init__.py", "backends/info.py", "backends/system.py", "backends/closure.py",
           "backends/compiled.py", "backends/vm.py", "backends/cache.py", "integrators/*.py"]
VM_FUNCTIONS = ("incr_rk4", "incr_rk8", "project", "fmu_outputs")
MODELS_FOLDER = "heli_models"  # resources/heli_models/ of the pythonfmu FMU
_IMPORT = re.compile(r"^(\s*)(from|import)\s+mbs(?=[\s.])", re.MULTILINE)
_SLAVE_IMPORT = re.compile(r"^(\s*)(from|import)\s+fmu\.pythonfmu(?=[\s.])", re.MULTILINE)
# Ranges shared by every scene (and by the native FMU, which reads spec.json).
# max_step: with RK4 (the default integrator) over 20 revolutions at the trim, the hinge
# amplitudes of every scene are those of small steps (0.049-0.051 rad) up to 0.012 s; at
# 0.013-0.014 s RK4 amplifies them 2.5-6x, at 0.015 s hover diverges, at 0.02 s every scene.
# Beyond the bound (e.g. 0.05 s) is refused; inside it, extreme inputs at the largest omega
# can still diverge: doStep then undoes the step (limits.hinge_angle).
MAX_STEP_RANGE = (1e-6, 0.012)  # s
FORWARD_SPEED_RANGE = (-20.0, 90.0)  # m/s
LIMITS = {"max_substeps": 1_000_000, "hinge_angle": math.pi / 2}  # sub-steps per doStep; rad


def mbs_dir() -> Path:
    import mbs

    return Path(mbs.__file__).resolve().parent


def identifier(scenes, aircraft=None) -> str:
    """Model identifier (also the FMU's file name) of a family: ``HeliRotor_<primary>`` for the
    Bo105, ``HeliRotor_<aircraft>_<primary>`` for another aircraft (its file's stem)."""
    craft = load_aircraft(aircraft)
    prefix = "" if craft.packaged and craft.key == "bo105" else f"{craft.key}_"
    return "HeliRotor_" + re.sub(r"\W", "_", prefix + scenes[0])


def load_aircraft(aircraft=None):
    """The aircraft of an FMU family: a loaded :class:`mbs.aircraft.Aircraft`, a packaged name,
    a file path, or None for the Bo105."""
    from mbs import aircraft as ac

    return aircraft if isinstance(aircraft, ac.Aircraft) else ac.load(aircraft or ac.DEFAULT)


# -- planning (needs the core and CasADi) ---------------------------------------------------

def plan(scene_names, aircraft=None) -> tuple[dict, dict]:
    """The FMU's spec (variables, scenes) and, per model group, ``(vm, functions)``: the
    functions to generate, the core's plus ``fmu_outputs(x, t, p)``, which computes every
    output and local variable of the FMU in generated code.

    Scenes whose generated code is identical (e.g. hover and forward flight, which differ in
    initial state and trim only) share one model (``group``). Raises ValueError when a scene
    cannot provide the primary scene's variables.
    """
    from mbs import scenes as registry
    from mbs.backends import build
    from mbs.backends.compiled import generate

    from fmu import periodic, structure

    groups, per_scene, starts = {}, {}, {}
    craft = load_aircraft(aircraft)
    for name in scene_names:
        scene = registry.get(name, aircraft=craft)
        model = scene.model()
        vm = build(model, "vm")
        key = hashlib.sha256(generate(vm.functions, vm.info, "float64").encode()).hexdigest()
        groups.setdefault(key, (re.sub(r"\W", "_", name), vm))
        per_scene[name] = (scene, model, vm, groups[key][0])
        starts[name] = periodic.start(scene, vm, log=lambda m: print(m, file=sys.stderr, flush=True))
    primary = per_scene[scene_names[0]]
    variables = _variables(primary, scene_names, periodic_start=any(starts.values()))
    _note_missing_outputs(variables, per_scene)
    computed = [v for v in variables if v["causality"] in ("output", "local")]
    spec = {"model_identifier": identifier(scene_names, craft), "primary": scene_names[0], "family": list(scene_names),
            "aircraft": {"name": craft.name, "file": craft.path.name, "sha256": craft.digest},
            "description": f"{craft.name}: {primary[0].description} (scenes: {', '.join(scene_names)})",
            "version": _version(), "variables": variables, "n_computed": len(computed),
            "default_experiment": _default_experiment(primary), "limits": dict(LIMITS),
            "scenes": {n: _scene_spec(per_scene[n], variables, starts[n]) for n in scene_names}}
    _add_starts(variables, spec["scenes"][spec["primary"]], spec["primary"])
    functions = {g: (vm, {**vm.functions, "fmu_outputs": fmu_outputs(vm, computed)}) for g, vm in groups.values()}
    spec["structure"] = structure.structure(spec, functions)  # ModelStructure from the functions' sparsity
    return spec, functions


def _note_missing_outputs(variables: list[dict], per_scene: dict) -> None:
    """Say in its description which scenes of the family do not model an output or state of
    the primary scene (there it is 0)."""
    for v in variables:
        lacking = [n for n, (_, _, vm, _) in per_scene.items()
                   if v["causality"] in ("output", "local") and not _modelled(vm.info, v)]
        if lacking:
            v["description"] += f" (0 in {', '.join(lacking)}: not modelled there)"


def _version() -> str:
    try:
        return importlib.metadata.version("rotor-mbs")
    except importlib.metadata.PackageNotFoundError:
        return "0"


def _revolution(scene, vm) -> float:
    return scene.revolution(vm, vm.params())


def _default_experiment(primary) -> dict:
    scene, _, vm, _ = primary
    rev = _revolution(scene, vm)
    return {"start": 0.0, "stop": 10 * rev, "step": rev / scene.steps_per_rev}


def _add_starts(variables: list[dict], primary: dict, primary_name: str) -> None:
    """Give every input and parameter its ``start``: its value in the primary scene. The FMU uses
    the start of every value the master does not set, in every scene (no start depends on another
    variable: FMI 2.0 section 2.2.7)."""
    for v in variables:
        if v["causality"] in ("input", "parameter"):
            v["start"] = scene_value(v["name"], primary, primary_name)


def scene_value(name: str, scene: dict, scene_name: str, periodic: bool = False):
    """The value of the input or parameter ``name`` in the scene ``scene`` (a scene spec) by itself,
    from its own start (``periodic``: its periodic trim): rad, rad/s, s, m/s as declared."""
    start = scene["periodic"] if periodic and scene.get("periodic") else scene
    omega = scene["defaults"].get("omega", scene["omega"])
    speed = (trim_speed(start) if start is not scene else start["forward_speed"]["default"]) \
        if scene["forward_speed"] else 0.0
    fixed = {"scene": scene_name, "evaluator": "compiled", "integrator": "rk4",
             "initial_state": "periodic" if start is not scene else "scene",
             "max_step": 2 * math.pi / abs(omega) / scene["steps_per_rev"],  # 1/steps_per_rev of a revolution
             "initial_forward_speed": speed}
    return fixed[name] if name in fixed else float(start["defaults"][name])


def trim_speed(periodic: dict) -> float:
    """The flight speed (m/s) of a scene's periodic trim: the ``initial_forward_speed`` that starts
    from the trim's own state (whose velocity differs from it by the trim's residual)."""
    return float(periodic["trim"]["speed"])


SCENE_STARTS = "scene_start_values.json"
"""The FMU's resource that lists, per scene of the family, the start values a master writes to run
it (:func:`scene_start_values`; its ``periodic`` entry for ``initial_state = "periodic"``)."""


def scene_starts_table(spec: dict) -> dict:
    """``{scene: {"scene": values, "periodic": values or None}}`` of :func:`scene_start_values`."""
    return {s: {"scene": scene_start_values(spec, s),
                "periodic": scene_start_values(spec, s, True) if spec["scenes"][s].get("periodic") else None}
            for s in spec["scenes"]}


def start_values_of(fmu: str | Path, scene: str, periodic: bool = False) -> dict:
    """The start values to write to run ``scene`` of the family FMU ``fmu`` (either FMU kind) as the
    FMU built for that scene alone would start (from its periodic trim with ``periodic``), read from
    the FMU's resources: e.g. ``simulate_fmu(fmu, start_values=start_values_of(fmu, "hover"))``."""
    with zipfile.ZipFile(fmu) as z:
        name = next((n for n in z.namelist() if n.endswith(f"resources/{SCENE_STARTS}") or
                     n.endswith(f"resources/{MODELS_FOLDER}/{SCENE_STARTS}")), None)
        if name is None:
            raise ValueError(f"{fmu} lists no start values of its scenes (no resources/{SCENE_STARTS})")
        table = json.loads(z.read(name))
    if scene not in table:
        raise ValueError(f"scene {scene!r} is not one of the FMU's: {', '.join(table)}")
    values = table[scene]["periodic" if periodic else "scene"]
    if values is None:
        raise ValueError(f"scene {scene!r} has no periodic start (it cannot be trimmed)")
    return {**values, **({"initial_state": "periodic"} if periodic else {})}


def scene_start_values(spec: dict, scene: str, periodic: bool = False) -> dict:
    """The start values a master writes to run ``scene`` (from its periodic trim with ``periodic``)
    in the family FMU of ``spec`` as the FMU built for that scene alone starts: ``scene``, and every
    input or parameter whose value in that scene differs from its XML start (the primary scene's)."""
    sc = spec["scenes"][scene]
    names = [v["name"] for v in spec["variables"] if v["causality"] in ("input", "parameter")]
    starts = {v["name"]: v["start"] for v in spec["variables"] if "start" in v}
    own = {n: scene_value(n, sc, scene, periodic) for n in names if n not in ("evaluator", "integrator")}
    return {n: value for n, value in own.items() if value != starts.get(n) or n == "scene"}


def _var(name, causality, variability, description, unit=None, **extra) -> dict:
    return {"name": name, "causality": causality, "variability": variability, "type": "Real",
            "description": description, "unit": unit, **extra}


def _finite(value):
    return float(value) if value is not None and np.isfinite(value) else None


def _variables(primary, scene_names, periodic_start: bool = False) -> list[dict]:
    scene, model, vm, _ = primary
    info = vm.info
    out = [_var(p["name"], "input", "continuous", p["description"], p["unit"] or None,
                min=_finite(p["low"]), max=_finite(p["high"])) for p in info.parameters if p["control"]]
    out.append({**_var("scene", "parameter", "fixed", "scene of this FMU's family: " + ", ".join(scene_names)),
                "type": "String", "allowed": list(scene_names)})
    out.append({**_var("evaluator", "parameter", "fixed", "compiled: the shipped C library (numpy only); "
                       "vm: CasADi's virtual machine (needs casadi on the host)"),
                "type": "String", "allowed": ["compiled", "vm"]})
    out.append({**_var("integrator", "parameter", "fixed", "fixed-step method of the shipped driver: rk4 "
                       "(classical, the default) or rk8 (Dormand-Prince 8th-order weights, 12 stages)"),
                "type": "String", "allowed": ["rk4", "rk8"]})
    if periodic_start:
        out.append({**_var("initial_state", "parameter", "fixed", "start of the run: scene (the scene's initial "
                           "state, every blade released at zero flap and lag; the default) or periodic (the scene's "
                           "periodic trim: controls, attitude, velocities and rotor states; with the trim inputs held "
                           "the run is periodic from its first step)"),
                    "type": "String", "allowed": ["scene", "periodic"]})
    out.append(_var("max_step", "parameter", "tunable", "largest internal integrator step; each "
                    "communication step is split into equal sub-steps no longer than this; default 1/100 "
                    "revolution", "s", min=MAX_STEP_RANGE[0], max=MAX_STEP_RANGE[1]))
    out += [_var(p["name"], "parameter", "fixed", p["description"], p["unit"] or None,
                 min=_finite(p["low"]), max=_finite(p["high"])) for p in info.parameters if not p["control"]]
    free = [b for b in info.bodies if b["joint"] == "FreeJoint"]
    if free:
        out.append(_var("initial_forward_speed", "parameter", "fixed",
                        f"initial {free[0]['name']} speed north (world x) at the scene's initial attitude; "
                        "default: the scene's", "m/s", min=FORWARD_SPEED_RANGE[0], max=FORWARD_SPEED_RANGE[1]))
    return out + _computed_variables(model, info, free)


def _computed_variables(model, info, free) -> list[dict]:
    hinges = [b for b in info.bodies if b["joint"] != "FreeJoint"]
    out = [_var(q, "output", "continuous", f"{q.replace('.', ' ')} angle (hinge coordinate)", "rad", kind="state")
           for b in hinges for q in b["q_names"]]
    out += [_var(v, "output", "continuous", f"{v.replace('.', ' ').replace('_rate', '')} angular rate", "rad/s",
                 kind="state") for b in hinges for v in b["v_names"]]
    out += [_var(o["name"], "output", "continuous", o["description"], o["unit"] or None, kind="output")
            for o in info.outputs]
    for b in free:
        out += _free_body_variables(b)
    out.append(_var("total_energy", "output", "continuous", "total energy: kinetic + gravity + spring "
                    "potential (J)", "J", kind="energy"))
    taken = {v["name"] for v in out}
    for name in info.state_names:
        if name not in taken:
            unit = model.states[name].unit if name in model.states else "1"
            out.append(_var(name, "local", "continuous", f"state {name} (for recording)", unit or None, kind="state"))
    for k, v in enumerate(out):
        v["position"] = k
    return out


def _free_body_variables(b: dict) -> list[dict]:
    name, q, v = b["name"], b["q_names"], b["v_names"]
    axes = ("north (world x)", "east (world y)", "down (world z)")
    out = [_var(q[i], "output", "continuous", f"{name} position {axes[i]}", "m", kind="state", body=name)
           for i in range(3)]
    out += [_var(f"{name}.{a}", "output", "continuous", f"{name} {a} angle (aerospace z-y-x Euler angles)", "rad",
                 kind="euler", body=name, axis=i) for i, a in enumerate(("roll", "pitch", "yaw"))]
    out += [_var(v[i], "output", "continuous", f"{name} velocity along body {'xyz'[i]}", "m/s", kind="state",
                 body=name) for i in range(3)]
    out += [_var(v[i], "output", "continuous", f"{name} angular velocity about body {'xyz'[i - 3]}", "rad/s",
                 kind="state", body=name) for i in range(3, 6)]
    return out


def _scene_spec(entry, variables, start: dict | None = None) -> dict:
    scene, _, vm, group = entry
    info = vm.info
    names = {v["name"] for v in variables}
    missing = [p for p in info.param_names if p not in names]
    if missing:
        raise ValueError(f"scene {scene.name!r} has parameters {missing} that the primary scene lacks")
    free = [b for b in info.bodies if b["joint"] == "FreeJoint"]
    x0 = np.array(info.x0)
    out = {"group": group, "x0": info.x0, "omega": scene.omega, "steps_per_rev": scene.steps_per_rev,
           "revolution": _revolution(scene, vm), "parameter_order": info.param_names,
           "defaults": {p["name"]: p["default"] for p in info.parameters},
           "ranges": {**{p["name"]: [_finite(p["low"]), _finite(p["high"])] for p in info.parameters},
                      "max_step": list(MAX_STEP_RANGE), "initial_forward_speed": list(FORWARD_SPEED_RANGE)},
           "hinge_states": _hinge_states(info), "plots": scene.plots, "description": scene.description,
           "forward_speed": _forward_speed(info, free[0], x0) if free else None}
    out["periodic"] = _periodic_spec(start, out, info, free) if start else None
    return out


def _periodic_spec(start: dict, scene: dict, info, free) -> dict:
    """The periodic start of a scene in the form of the scene's own start (``x0``,
    ``defaults``, ``forward_speed``), with the trim's figures and provenance (``trim``)."""
    x0 = np.array([start["state"][n] for n in info.state_names])
    trim = {k: v for k, v in start.items() if k not in ("state", "controls")}
    return {"x0": x0.tolist(), "defaults": {**scene["defaults"], **start["controls"]},
            "forward_speed": _forward_speed(info, free[0], x0) if free else None, "trim": trim}


def _hinge_states(info) -> list[int]:
    """Indices in x of the hinge coordinates (flap, lag, teeter; rad): the ``q_names`` of
    every body that is neither free nor clamped (driven hinges have none), but a free rotor's
    azimuth and its transmission's angle, which turn on without bound."""
    turning = ("main_hub.azimuth", "tail_hub.azimuth", "transmission.angle")
    return [info.state_names.index(q) for b in info.bodies if b["joint"] != "FreeJoint" for q in b["q_names"]
            if q not in turning]


def _forward_speed(info, body: dict, x0: np.ndarray) -> dict:
    """The free body's velocity indices ``v``, the level-flight direction in body axes at the
    start's attitude (``direction = R(q0)^T e_x``: ``initial_forward_speed`` V gives the body
    velocity V·direction) and the start's own forward speed ``default`` (m/s)."""
    import casadi as ca

    from mbs._rotation import quat_to_matrix

    q = [info.state_names.index(n) for n in body["q_names"][3:7]]
    v = [info.state_names.index(n) for n in body["v_names"][:3]]
    r = np.array(ca.DM(quat_to_matrix(ca.DM(x0[q]))))
    return {"v": v, "direction": r[0].tolist(), "default": float(r[0] @ x0[v])}


def fmu_outputs(vm, computed):
    """CasADi function ``fmu_outputs(x, t, p)`` of every computed variable (in order) of the
    model ``vm``: a state, a model output, the total energy, Euler angles of a free body, or
    a constant for a body that this model clamps."""
    import casadi as ca

    from mbs._rotation import quat_to_euler

    info = vm.info
    x, t, p = ca.MX.sym("x", info.nx), ca.MX.sym("t"), ca.MX.sym("p", len(info.parameters))
    y, e = vm.functions["outputs"](x, t, p), vm.functions["energy"](x, t, p)
    values = []
    for v in computed:
        name = v["name"]
        if v["kind"] == "energy":
            values.append(e[e.numel() - 1])
        elif v["kind"] == "output" and name in info.output_names:
            values.append(y[info.output_names.index(name)])
        elif v["kind"] == "state" and name in info.state_names:
            values.append(x[info.state_names.index(name)])
        elif v["kind"] == "euler" and _is_free(info, v["body"]):
            q = [x[info.state_names.index(n)] for n in _body(info, v["body"])["q_names"][3:7]]
            values.append(_euler(*q)[v["axis"]])
        elif _modelled(info, v):
            values.append(_clamped_value(info.name, vm, v, quat_to_euler))
        else:
            values.append(0.0)  # not modelled in this member of the family (see the description)
    return ca.Function("fmu_outputs", [x, t, p], [ca.vertcat(*values)], ["x", "t", "p"], ["values"])


def _euler(w, x, y, z):
    """Aerospace Euler angles (roll, pitch, yaw) of a quaternion, as CasADi expressions
    (the convention of :func:`mbs._rotation.quat_to_euler`)."""
    import casadi as ca

    n = ca.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return (ca.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)),
            ca.asin(ca.fmin(1, ca.fmax(-1, 2 * (w * y - z * x)))),
            ca.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))


def _body(info, name: str) -> dict | None:
    return next((b for b in info.bodies if b["name"] == name), None)


def _modelled(info, v: dict) -> bool:
    """Whether the model ``info`` has the computed variable ``v``: as a state or output, as the
    energy, or as the fixed pose of a body it clamps."""
    name = v["name"]
    if v["kind"] in ("energy", "euler") or name in info.state_names or name in info.output_names:
        return True
    return v["kind"] == "state" and _body(info, v.get("body") or name.split(".")[0]) is not None


def _is_free(info, name: str) -> bool:
    b = _body(info, name)
    return b is not None and b["joint"] == "FreeJoint"


def _clamped_value(model: str, vm, v: dict, quat_to_euler) -> float:
    """Value of a free-body variable of the primary scene for a body clamped in ``vm``."""
    from mbs._rotation import matrix_to_quat

    body = v.get("body") or v["name"].split(".")[0]
    info = vm.info
    if _body(info, body) is None or v["kind"] == "output":
        raise ValueError(f"model {model!r} cannot provide the variable {v['name']!r}")
    pos, rot = vm.poses(vm.x0())
    i = info.body_names.index(body)
    if v["kind"] == "euler":
        return float(quat_to_euler(matrix_to_quat(rot[i]))[v["axis"]])
    coordinate = v["name"].split(".", 1)[1]
    values = dict(zip("xyz", pos[i]), **dict(zip(("qw", "qx", "qy", "qz"), matrix_to_quat(rot[i]))))
    return float(values.get(coordinate, 0.0))


# -- staging --------------------------------------------------------------------------------

def runtime_sources() -> dict[str, str]:
    """The core's run-time files the FMU ships (relative path -> text), before renaming."""
    root = mbs_dir()
    return {path.relative_to(root).as_posix(): path.read_text()
            for pattern in RUNTIME for path in sorted(root.glob(pattern))}


def slave_sources() -> dict[str, str]:
    """The slave's helper modules (:mod:`fmu.pythonfmu` but the entry ``slave.py``): file name -> text."""
    return {path.name: path.read_text() for path in sorted(SLAVE_DIR.glob("*.py"))
            if path.name not in ("__init__.py", "slave.py")}


def stage_code(stage: Path) -> tuple[str, Path]:
    """Write the entry module (the slave, with its class defined in it as pythonfmu expects)
    and the renamed core package, with the slave's helpers in its subpackage ``slave``, into
    ``stage``; returns (entry module name, package folder)."""
    files = runtime_sources()
    helpers = slave_sources()
    slave = (SLAVE_DIR / "slave.py").read_text()
    digest = hashlib.sha256(json.dumps([files, helpers, slave], sort_keys=True).encode()).hexdigest()[:12]
    package = f"heli_rotor_{digest}"
    folder = stage / package
    files["__init__.py"] = f'"""Run-time part of the core shipped in the heli rotor FMU (build {digest})."""\n'
    files.update({f"slave/{name}": text for name, text in helpers.items()})
    entry = f"{SLAVE}_{digest}"
    for path, text in [*((folder / rel, t) for rel, t in files.items()), (stage / f"{entry}.py", slave)]:
        renamed = _SLAVE_IMPORT.sub(rf"\1\2 {package}.slave", _IMPORT.sub(rf"\1\2 {package}", text))
        if re.search(r"^\s*(from|import)\s+(mbs|fmu)\b", renamed, re.MULTILINE):
            raise RuntimeError(f"staged {path.name} still imports mbs or fmu")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(renamed)
    for sub in {p.parent for p in folder.rglob("*.py")}:
        (sub / "__init__.py").touch()
    return entry, folder


def content_guid(spec: dict, code_digest: str, sources: dict[str, str]) -> str:
    """The FMU's GUID from its content: the spec (variables, scenes, starts), the staged code
    and the generated C of every model group; the same content gives the same GUID, any change
    another one."""
    h = hashlib.sha256(json.dumps([spec, code_digest, sources], sort_keys=True).encode())
    return "{" + str(uuid.UUID(bytes=h.digest()[:16], version=5)) + "}"


def stage_models(stage: Path, spec: dict, groups: dict, code_digest: str = "") -> Path:
    """Compile each model group (cached) and write ``heli_models/``: per group the library,
    ``info.json`` and the CasADi functions the virtual machine needs; ``spec.json`` gets the
    FMU's GUID (:func:`content_guid`)."""
    from mbs.backends.compiled import compile_source, generate

    root = stage / "heli_models"
    sources = {group: generate(functions, vm.info, "float64") for group, (vm, functions) in groups.items()}
    spec["guid"] = content_guid({k: v for k, v in spec.items() if k != "guid"}, code_digest, sources)
    for group, (vm, functions) in groups.items():
        folder = root / group
        (folder / "vm").mkdir(parents=True)
        compiled = compile_source(sources[group], vm.info)
        shutil.copy2(compiled / "model.so", folder / "model.so")
        (folder / "info.json").write_text(vm.info.to_json())
        for name in VM_FUNCTIONS:
            functions[name].save(str(folder / "vm" / f"{name}.casadi"))
    (root / "spec.json").write_text(json.dumps(spec, indent=1))
    (root / SCENE_STARTS).write_text(json.dumps(scene_starts_table(spec), indent=1))
    return root


def build_here(scene_names, dest: Path, aircraft=None) -> Path:
    """Plan, stage and build in this process (call it in a fresh interpreter: the builder
    imports the staged code). Writes ``dest`` (a ``.fmu`` path)."""
    from pythonfmu import FmuBuilder

    from fmu.pythonfmu import shim

    shim.find_compiler()  # first: without a C compiler this fails at once, clearly
    spec, groups = plan(list(scene_names), aircraft)
    with tempfile.TemporaryDirectory(prefix="heli-fmu-stage-") as tmp:
        stage = Path(tmp)
        entry, package = stage_code(stage)
        models = stage_models(stage, spec, groups, package.name)
        shim_library = compiled_shim(spec["guid"])
        sys.path.insert(0, str(stage))
        built = FmuBuilder.build_FMU(stage / f"{entry}.py", dest=stage / "out", project_files=[package, models],
                                     canGetAndSetFMUstate=True, canSerializeFMUstate=True)
        _recompress(built, Path(dest), shim_library, spec)
    return Path(dest)


def compiled_shim(guid: str) -> bytes:
    """The FMU's FMI front end (``fmu/pythonfmu/shim/fmi2_shim.c``) compiled for this machine with
    the FMU's GUID; raises :class:`fmu.pythonfmu.shim.ShimBuildError` (e.g. no C compiler)."""
    from fmu.pythonfmu import shim

    with tempfile.TemporaryDirectory(prefix="heli-fmu-shim-") as tmp:
        return shim.compile_shim(Path(tmp) / "shim.so", guid).read_bytes()


def _recompress(src: Path, dest: Path, shim_library: bytes | None = None, spec: dict | None = None) -> None:
    """pythonfmu stores files uncompressed; deflate them (the libraries shrink about 4x).
    With ``shim_library``, the FMI front end takes the place of pythonfmu's library, which
    moves to ``binaries/linux64/pythonfmu/``, and other platforms' binaries are dropped. With
    ``spec``, the model description gets its ``<ModelStructure>`` (:mod:`fmu.structure`)."""
    from fmu.pythonfmu.shim import relocate

    dest.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "modelDescription.xml" and spec:
                data = with_model_structure(data, spec)
            entries = relocate(item.filename, data, shim_library) if shim_library else [(item.filename, data)]
            for name, payload in entries:
                zout.writestr(name, payload)


def with_model_structure(xml: bytes, spec: dict) -> bytes:
    """The model description ``xml`` with its ``<ModelStructure>`` replaced by the spec's."""
    from xml.etree import ElementTree as ET

    from fmu.structure import model_structure_xml

    root = ET.fromstring(xml)
    old = root.find("ModelStructure")
    root.insert(list(root).index(old), model_structure_xml(spec))
    root.remove(old)
    ET.indent(root, "\t")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


# -- cache ----------------------------------------------------------------------------------

SOURCE_SUFFIXES = (".py", ".toml", ".json", ".c", ".h")
"""The files of ``mbs`` and ``fmu`` whose content keys the FMU cache (``.json``: the stored
periodic starts)."""


def cache_key(scene_names, aircraft=None) -> str:
    """Hash of everything the FMU is built from: the sources, the scenes and aircraft, CasADi and
    pythonfmu, the compiler flags, the compiler named by ``$CC`` (if set) and the platform.
    It needs no compiler, so a cached FMU is found on a machine without one."""
    from mbs.backends.compiled import CFLAGS  # numpy only

    h = hashlib.sha256()
    for root in (mbs_dir(), HERE):
        for path in sorted(p for p in root.rglob("*") if p.suffix in SOURCE_SUFFIXES and "__pycache__" not in p.parts):
            h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes())
    versions = [importlib.metadata.version(d) for d in ("casadi", "pythonfmu")]
    h.update(json.dumps([list(scene_names), load_aircraft(aircraft).digest, versions, os.environ.get("CC") or "",
                         CFLAGS, sys.platform, platform.machine()]).encode())
    return h.hexdigest()[:20]


def cached_path(scene_names, aircraft=None) -> Path:
    """Where the FMU of ``scene_names`` is cached: ``<cache>/fmu/<key>/<identifier>.fmu``
    (its digest file next to it)."""
    from mbs.backends.compiled import cache_dir

    return cache_dir() / "fmu" / cache_key(scene_names, aircraft) / f"{identifier(scene_names, aircraft)}.fmu"


def fmu_problem(path: Path) -> str | None:
    """Why the cached FMU ``path`` must not be used (missing, no digest, truncated or
    changed, or a member failing its zip CRC check), or None when it is intact."""
    from mbs.backends.cache import problem

    reason = problem(path)
    if reason:
        return reason
    try:
        with zipfile.ZipFile(path) as z:
            bad = z.testzip()
    except (OSError, zipfile.BadZipFile) as exc:
        return f"{path} is not a readable zip file ({exc})"
    return f"{path} has a corrupt member {bad}" if bad else None


def family_problem(scene_names, aircraft=None) -> str | None:
    """Why the scenes ``scene_names`` cannot share one FMU (a scene with a run-time parameter
    the first, primary scene lacks), found on their models before anything is compiled; None
    when they can."""
    from mbs import scenes as registry

    models = [registry.get(n, aircraft=load_aircraft(aircraft)).model() for n in scene_names]
    for name, model in zip(scene_names[1:], models[1:]):
        missing = [p for p in model.parameters if p not in models[0].parameters]
        if missing:
            return f"scene {name!r} has parameters {missing} that the primary scene lacks"
    return None


def ensure_fmu(scene_names=DEFAULT_SCENES, force: bool = False, log=None, aircraft=None) -> tuple[Path, float]:
    """The cached FMU of ``scene_names`` of ``aircraft`` (default the Bo105; built in a
    subprocess if absent or not intact);
    returns (path, build seconds, 0 if it came from the cache). The FMU's digest is recorded
    when it is built and checked (with the zip's CRCs) before a cached one is returned.
    Raises :class:`~mbs.backends.cache.CacheNotWritable` when a build is needed and the
    cache folder cannot be written, :class:`~mbs.backends.compiled.CompilerNotFound` when
    there is no C compiler."""
    from mbs.backends.cache import record, writable_dir
    from mbs.backends.compiled import find_compiler

    craft = load_aircraft(aircraft)
    path = cached_path(scene_names, craft)
    if not force:
        reason = fmu_problem(path)
        if reason is None:
            return path, 0.0
        if log and path.exists():
            log(f"rebuilding the cached FMU: {reason}")
    writable_dir(path.parent, "FMU cache")
    find_compiler()
    problem = family_problem(scene_names, craft)
    if problem:
        raise ValueError(f"cannot build the FMU of {', '.join(scene_names)}: {problem}")
    if log:
        log(f"building the FMU for {', '.join(scene_names)} (compiles the models once; cached) ...")
    start = time.perf_counter()
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with tempfile.TemporaryDirectory(prefix="heli-fmu-build-") as cwd:
        env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
        proc = subprocess.run([sys.executable, "-m", "fmu.build", "--scenes", ",".join(scene_names),
                               "--aircraft", str(craft.path.resolve()), "--dest", str(tmp)], cwd=cwd, env=env,
                              capture_output=True, text=True)
    if proc.returncode:
        tmp.unlink(missing_ok=True)
        if proc.returncode == 2:  # a bad family or setting: the builder's one-line message
            reason = proc.stderr.strip().splitlines()[-1]
            raise ValueError(f"cannot build the FMU of {', '.join(scene_names)}: {reason}")
        raise RuntimeError(f"building the FMU failed:\n{proc.stderr[-4000:]}")
    for line in proc.stderr.splitlines() if log else ():
        log(line)  # the build's notes (e.g. a periodic start trimmed again)
    tmp.replace(path)
    record(path)
    return path, time.perf_counter() - start


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="build the heli rotor FMU in this process (use ensure_fmu)")
    ap.add_argument("--scenes", default=",".join(DEFAULT_SCENES))
    ap.add_argument("--aircraft", default=None, help="aircraft file (default: the Bo105)")
    ap.add_argument("--dest", required=True)
    args = ap.parse_args(argv)
    try:
        build_here(args.scenes.split(","), Path(args.dest), args.aircraft)
    except ValueError as exc:  # a bad family or setting (CompilerNotFound included): one line for ensure_fmu
        print(" ".join(str(exc).split()), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
