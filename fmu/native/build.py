"""Build the native FMU of a scene family, for FMI 2.0 and FMI 3.0 from one build: C sources
generated from ``fmu.build.plan``, the model core and its FMI wrappers (``heli_core.c``,
``fmi2Functions.c``, ``fmi3Functions.c``), one shared library per platform (:mod:`fmu.native.platforms`:
the machine's own and the cross compilers found), and the model descriptions.

Layout of the FMI 2.0 ``.fmu`` (co-simulation and model exchange)::

    modelDescription.xml
    resources/scene_start_values.json         (what a master writes to run each scene of the family)
    binaries/linux64/<identifier>.so  binaries/win64/<identifier>.dll
    sources/heli_core.c heli_core.h fmi2Functions.c fmi3Functions.c heli_model.h heli_libm.[ch]
    sources/heli_config.h heli_data.c         (generated: sizes and tables from the spec)
    sources/heli_model_<group>.c              (generated: per model group, CasADi code + driver)
    sources/heli_ad_<group>.c                 (generated: its forward and reverse derivatives)
    sources/fmi2*.h fmi3*.h                   (the FMI headers of the installed fmpy)

The FMI 3.0 ``.fmu`` (``<identifier>.fmi3.fmu``) holds the same library under
``binaries/x86_64-linux``, ``x86_64-windows`` and ``aarch64-linux`` and ``sources/`` with
``buildDescription.xml``. Each group's files have their exported names prefixed ``heli_<group>_``
(the CasADi API and the driver by renaming, CasADi's internal helpers through its
``CODEGEN_PREFIX``) and hidden, so several groups link into one library that exports only the
``fmi2*`` and ``fmi3*`` functions.
"""
from __future__ import annotations

import argparse
import hashlib
import importlib.metadata
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import uuid
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

from fmu import build as pybuild
from fmu.native import derivatives as me_derivatives
from fmu.native import fmi3, platforms, units
from fmu.native.c_literals import c_array, c_real, c_reals, c_string

HERE = Path(__file__).resolve().parent
HAND_WRITTEN = ("heli_core.c", "heli_core.h", "heli_forward.h", "fmi2Functions.c", "fmi3Functions.c", "heli_model.h", "heli_libm.c",
                "heli_libm.h")
FMI_HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h", "fmi3Functions.h",
               "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")
FUNCTIONS = ("incr_rk4", "incr_rk8", "project", "energy", "fmu_outputs", "rhs")
AD_FUNCTIONS = ("ad_fwd", "ad_adj")
METHODS = ("rk4", "rk8")
CFLAGS = ["-O2", "-fno-math-errno", "-ffp-contract=off", "-fvisibility=hidden", "-DHELI_LIBM_LINKED"]
"""The shipped binary links libm and calls it directly (``heli_libm.h``); a rebuild from ``sources/``
without ``-DHELI_LIBM_LINKED`` (fmpy's, or a plain ``cc``) needs no ``-lm``."""
AD_OPTIMIZATION = {"x86_64-linux": "-O1"}
"""The derivative files (megabytes of straight-line code) compile at this level for the machine's
own platform (-O2 takes minutes); the cross builds at -O0 (seconds). The level changes no result
(no fused multiply-adds, no reassociation): only the derivatives' speed."""
HINGE = re.compile(r"\.(flap|lag|teeter)$")
_EXPORT = re.compile(r"^CASADI_SYMBOL_EXPORT\s+[\w\s\*]*?\b(\w+)\s*\(", re.MULTILINE)
DEFAULT_LIMITS = {"max_substeps": 1_000_000, "hinge_angle": math.pi / 2}  # when the spec has no "limits"


def identifier(scenes, aircraft=None) -> str:
    """Model identifier (and file name) of the native FMU: ``HeliRotorNative_<primary>``
    (``HeliRotorNative_<aircraft>_<primary>`` for another aircraft than the Bo105)."""
    return pybuild.identifier(scenes, aircraft).replace("HeliRotor_", "HeliRotorNative_", 1)


def fmi_headers_dir() -> Path:
    """The FMI 2.0 headers shipped with the installed fmpy (``<fmpy>/c-code``)."""
    import fmpy

    return Path(fmpy.__file__).resolve().parent / "c-code"


# -- C literals ------------------------------------------------------------------------------

# -- start values ----------------------------------------------------------------------------

def start_value(spec: dict, v: dict):
    """The XML start of an input or parameter: the spec's ``start`` if it has one, else the
    primary scene's default (a String's first allowed value for ``scene``)."""
    if "start" in v:
        return v["start"]
    primary = spec["scenes"][spec["primary"]]
    name = v["name"]
    if v["type"] == "String":
        return {"scene": spec["primary"], "evaluator": "compiled", "integrator": "rk4",
                "initial_state": "scene"}.get(name, v["allowed"][0])
    if name == "max_step":
        omega = primary["defaults"].get("omega", primary["omega"])
        return 2 * math.pi / abs(omega) / primary["steps_per_rev"]
    if name == "initial_forward_speed":
        return primary["forward_speed"]["default"] if primary["forward_speed"] else 0.0
    return primary["defaults"][name]


def start_text(spec: dict, v: dict) -> str:
    value = start_value(spec, v)
    return value if isinstance(value, str) else "%.17g" % float(value)


# -- generated C: the models -----------------------------------------------------------------

def model_source(group: str, functions: dict, nx: int, names=FUNCTIONS, driver: bool = True,
                 prefix: str | None = None) -> str:
    """C source of one model group: CasADi's code of ``names`` (by default :data:`FUNCTIONS`) and,
    with ``driver``, the core's fixed-step driver per method; every exported name prefixed
    ``prefix`` (default ``heli_<group>_``; each file of a group needs its own)."""
    prefix = prefix or f"heli_{group}_"
    import casadi as ca

    from mbs.backends.compiled import DRIVER, _REALS

    gen = ca.CodeGenerator("model.c", {"casadi_real": _REALS["float64"][0], "with_header": False})
    for name in names:
        gen.add(functions[name])
    body = gen.dump() + ("".join(DRIVER.format(m=m, nx=nx) for m in METHODS) if driver else "")
    exported = sorted(set(_EXPORT.findall(body)), key=len, reverse=True)
    body = re.sub(r"\b(" + "|".join(map(re.escape, exported)) + r")\b", rf"{prefix}\1", body)
    prologue = (f"/* Model group {group} of the native heli rotor FMU (generated at build time). */\n"
                "#include <math.h>\n#include <stdlib.h>\n#include <string.h>\n#include \"heli_libm.h\"\n"
                f"#define CASADI_CODEGEN_PREFIX\n#define CODEGEN_PREFIX {prefix}\n"
                "#define CASADI_SYMBOL_EXPORT\n#if defined(__GNUC__) && !defined(_WIN32)\n"
                "#pragma GCC visibility push(hidden)\n#endif\n")
    return prologue + body + "#if defined(__GNUC__) && !defined(_WIN32)\n#pragma GCC visibility pop\n#endif\n"


def _group_declarations(group: str) -> str:
    g = f"heli_{group}_"
    lines = [f"int {g}mbs_run_{m}(const double*, double, double, long long, long long, long long, const double*, "
             "double*, double*, int, long long*);" for m in METHODS]
    for f in ("incr_rk4", "incr_rk8", "energy", "fmu_outputs", "rhs", *(f"d_{a}" for a in AD_FUNCTIONS)):
        lines += [f"int {g}{f}(const double**, double**, long long*, double*, int);",
                  f"int {g}{f}_work(long long*, long long*, long long*, long long*);"]
    return "\n".join(lines) + "\n"


def _group_entry(group: str, vm, functions: dict, states: list[str]) -> str:
    g = f"heli_{group}_"
    return (f"  {{{c_string(group)}, {vm.info.nx}, {{{g}mbs_run_rk4, {g}mbs_run_rk8}}, "
            f"{{{g}incr_rk4, {g}incr_rk8}}, {{{g}incr_rk4_work, {g}incr_rk8_work}}, "
            f"{g}fmu_outputs, {g}fmu_outputs_work, {g}energy, {g}energy_work, {functions['energy'].numel_out(0)}, "
            f"{g}rhs, {g}rhs_work, {g}d_ad_fwd, {g}d_ad_fwd_work, {g}d_ad_adj, {g}d_ad_adj_work, "
            f"{int(me_derivatives.covers(vm, states))}, states_{group}, state_of_{group}}}")


def _state_of(variables: list[dict], vm) -> list[str]:
    """Per value reference, the index in x of a computed variable that is a state of this
    model (read from x directly), else -1 (evaluated by ``fmu_outputs``)."""
    names = vm.info.state_names
    return [str(names.index(v["name"])) if v["causality"] in ("output", "local") and v.get("kind") == "state"
            and v["name"] in names else "-1" for v in variables]


# -- generated C: the tables -----------------------------------------------------------------

CAUSALITY = {"input": "HELI_INPUT", "parameter": "HELI_PARAMETER", "output": "HELI_OUTPUT", "local": "HELI_LOCAL"}
VARIABILITY = {"fixed": "HELI_FIXED", "tunable": "HELI_TUNABLE", "continuous": "HELI_CONTINUOUS"}


def _variable_entry(spec: dict, k: int, v: dict) -> str:
    settable = v["causality"] in ("input", "parameter")
    string = v["type"] == "String"
    start = start_value(spec, v) if settable else None
    allowed = f"allowed_{k}" if string else "NULL"
    return (f"  {{{c_string(v['name'])}, {'HELI_STRING' if string else 'HELI_REAL'}, {CAUSALITY[v['causality']]}, "
            f"{VARIABILITY[v['variability']]}, {c_string(v.get('unit') or '')}, {c_real(_bound(v, 'min', -math.inf))}, "
            f"{c_real(_bound(v, 'max', math.inf))}, {c_real(None if string or start is None else float(start_text(spec, v)))}, "
            f"{c_string(start if string else None)}, {len(v.get('allowed', [])) if string else 0}, {allowed}, "
            f"{v.get('position', -1)}, {int(_is_hinge(v))}}}")


def _bound(v: dict, key: str, absent: float) -> float:
    return absent if v.get(key) is None else float(v[key])


def _is_hinge(v: dict) -> bool:
    return v["causality"] == "output" and v.get("unit") == "rad" and bool(HINGE.search(v["name"]))


def _scene_tables(spec: dict, name: str, k: int) -> str:
    sc, variables = spec["scenes"][name], spec["variables"]
    vr = {v["name"]: i for i, v in enumerate(variables)}
    defaults = [c_real(sc["defaults"].get(v["name"])) for v in variables]
    ranges = [sc["ranges"].get(v["name"], [v.get("min"), v.get("max")]) for v in variables]
    low = [c_real(-math.inf if r[0] is None else r[0]) for r in ranges]
    high = [c_real(math.inf if r[1] is None else r[1]) for r in ranges]
    out = (c_array("double", f"x0_{k}", [c_real(x) for x in sc["x0"]])
           + c_array("int", f"params_{k}", [str(vr[p]) for p in sc["parameter_order"]])
           + c_array("double", f"defaults_{k}", defaults) + c_array("double", f"low_{k}", low)
           + c_array("double", f"high_{k}", high))
    periodic = sc.get("periodic")
    if periodic:
        out += (c_array("double", f"periodic_x0_{k}", [c_real(x) for x in periodic["x0"]])
                + c_array("double", f"periodic_defaults_{k}",
                          [c_real(periodic["defaults"].get(v["name"])) for v in variables]))
    return out


def _scene_entry(spec: dict, name: str, k: int, group_index: dict) -> str:
    sc = spec["scenes"][name]
    fs, periodic = sc["forward_speed"], sc.get("periodic")
    v, direction = (fs["v"], fs["direction"]) if fs else ([0] * 3, [0.0] * 3)
    pfs = periodic["forward_speed"] if periodic else None
    p_direction = pfs["direction"] if pfs else [0.0] * 3
    tables = f"periodic_x0_{k}, periodic_defaults_{k}" if periodic else "NULL, NULL"
    return (f"  {{{c_string(name)}, {group_index[sc['group']]}, x0_{k}, {c_real(sc['omega'])}, {sc['steps_per_rev']}, "
            f"{len(sc['parameter_order'])}, params_{k}, defaults_{k}, low_{k}, high_{k}, {int(fs is not None)}, "
            f"{{{', '.join(map(str, v))}}}, {c_reals(direction)}, {c_real(fs['default'] if fs else 0.0)}, "
            f"{tables}, {c_reals(p_direction)}, {c_real(pybuild.trim_speed(periodic) if pfs else 0.0)}}}")



def data_source(spec: dict, groups: dict, guid: str) -> str:
    """``heli_data.c``: the variables, scenes and model groups of the family, the continuous
    states and the FMI 3.0 variables."""
    variables, names, states = spec["variables"], list(spec["scenes"]), spec["me"]["states"]
    group_index = {g: i for i, g in enumerate(groups)}
    vr = {v["name"]: i for i, v in enumerate(variables)}
    out = ["/* Tables of the native heli rotor FMU (generated at build time from the spec). */\n",
           '#include <math.h>\n#include <stddef.h>\n#include "heli_model.h"\n',
           "#if defined(__GNUC__)\n#pragma GCC visibility push(hidden)\n#endif\n"]
    out += [_group_declarations(g) for g in groups]
    for g, (vm, _) in groups.items():
        out.append(c_array("char* const", f"states_{g}", [c_string(s) for s in vm.info.state_names]))
        out.append(c_array("int", f"state_of_{g}", _state_of(variables, vm)))
    for k, v in enumerate(variables):
        if v["type"] == "String":
            out.append(c_array("char* const", f"allowed_{k}", [c_string(a) for a in v["allowed"]]))
    out += [_scene_tables(spec, n, k) for k, n in enumerate(names)]
    out.append("static const heli_variable variables[] = {\n"
               + ",\n".join(_variable_entry(spec, k, v) for k, v in enumerate(variables)) + "\n};\n")
    out.append("static const heli_scene scenes[] = {\n"
               + ",\n".join(_scene_entry(spec, n, k, group_index) for k, n in enumerate(names)) + "\n};\n")
    out.append("static const heli_group groups[] = {\n"
               + ",\n".join(_group_entry(g, vm, f, states) for g, (vm, f) in groups.items()) + "\n};\n")
    state_slots = [vr[n] for n in states]
    scalars = all_variables(spec)
    vars3 = fmi3.variables3(scalars)
    out.append(c_array("int", "me_state", [str(k) for k in state_slots]))
    out.append(fmi3.c_tables(vars3, fmi3.me_order(vars3, state_slots, len(variables))))
    limits = {**DEFAULT_LIMITS, **spec.get("limits", {})}
    special = [vr.get(n, -1) for n in ("scene", "evaluator", "integrator", "max_step", "omega", "initial_forward_speed",
                                           "total_energy", "initial_state")]
    out.append(f"const heli_model heli_model_data = {{{c_string(spec['model_identifier'])}, {c_string(guid)}, "
               f"{names.index(spec['primary'])}, {len(variables)}, variables, {len(names)}, scenes, {len(groups)}, "
               f"groups, {spec['n_computed']}, {c_real(limits['max_substeps'])}, {c_real(limits['hinge_angle'])}, "
               f"{', '.join(map(str, special))}, {len(states)}, me_state, {len(vars3)}, variables3, me_order3}};\n")
    out.append("#if defined(__GNUC__)\n#pragma GCC visibility pop\n#endif\n")
    return "".join(out)


def config_header(spec: dict, groups: dict) -> str:
    """``heli_config.h``: the sizes the wrapper's fixed buffers need."""
    nx = max(vm.info.nx for vm, _ in groups.values())
    n_energy = max(f["energy"].numel_out(0) for _, f in groups.values())
    n_params = max(len(s["parameter_order"]) for s in spec["scenes"].values())
    return ("/* Sizes of the native heli rotor FMU (generated at build time). */\n"
            "#ifndef HELI_CONFIG_H\n#define HELI_CONFIG_H\n"
            f"#define HELI_NV {len(spec['variables'])}\n#define HELI_NX {nx}\n#define HELI_NP {n_params}\n"
            f"#define HELI_NCOMPUTED {spec['n_computed']}\n#define HELI_NENERGY {n_energy}\n#endif\n")


# -- modelDescription.xml ----------------------------------------------------------------------

def _fmt16(x: float) -> str:
    return f"{x:.16g}"


def all_variables(spec: dict) -> list[dict]:
    """The FMI 2.0 variables in value-reference order: the spec's, then the derivative of each
    continuous state (``der(<state>)``, value reference ``len(spec["variables"]) + k``)."""
    by_name = {v["name"]: v for v in spec["variables"]}
    ders = [{"name": me_derivatives.derivative_name(s), "causality": "local", "variability": "continuous",
             "type": "Real", "unit": units.per_second(by_name[s].get("unit")), "derivative_of": s,
             "description": f"time derivative of {s} (model exchange)"} for s in spec["me"]["states"]]
    return spec["variables"] + ders


def _scalar_variable(spec: dict, k: int, v: dict, index: dict) -> ET.Element:
    sv = ET.Element("ScalarVariable", name=v["name"], valueReference=str(k), description=v["description"],
                    causality=v["causality"], variability=v["variability"])
    settable = v["causality"] in ("input", "parameter")
    if not settable:
        sv.set("initial", "calculated")
    child = ET.SubElement(sv, v["type"])
    if settable:
        child.set("start", start_text(spec, v))
    if v.get("derivative_of"):
        child.set("derivative", index[v["derivative_of"]])
    if v["type"] == "Real":
        for key in ("unit", "min", "max"):
            if v.get(key) is not None:
                child.set(key, v[key] if key == "unit" else _fmt16(v[key]))
    return sv


def _interfaces(identifier_: str, sources: list[str]) -> list[ET.Element]:
    common = {"modelIdentifier": identifier_, "needsExecutionTool": "false",
              "canBeInstantiatedOnlyOncePerProcess": "false", "canNotUseMemoryManagementFunctions": "true",
              "canGetAndSetFMUstate": "true", "canSerializeFMUstate": "true", "providesDirectionalDerivative": "true"}
    me = ET.Element("ModelExchange", {"modelIdentifier": identifier_, "needsExecutionTool": "false",
                                      "completedIntegratorStepNotNeeded": "false",
                                      **{k: v for k, v in common.items() if k not in ("modelIdentifier",
                                                                                      "needsExecutionTool")}})
    cs = ET.Element("CoSimulation", {**common, "canHandleVariableCommunicationStepSize": "true",
                                     "canInterpolateInputs": "false", "maxOutputDerivativeOrder": "0",
                                     "canRunAsynchronuously": "false"})
    for el in (me, cs):
        files = ET.SubElement(el, "SourceFiles")
        for name in sources:
            ET.SubElement(files, "File", name=name)
    return [me, cs]


def _unknowns(parent: ET.Element, tag: str, table: dict, index: dict) -> None:
    group = ET.SubElement(parent, tag)
    for name in sorted(table, key=lambda n: int(index[n])):
        deps = table[name]
        ET.SubElement(group, "Unknown", index=index[name], dependencies=" ".join(index[n] for n, _ in deps),
                      dependenciesKind=" ".join(kind for _, kind in deps))


def _model_structure(spec: dict, index: dict) -> ET.Element:
    """``<ModelStructure>`` from the generated functions' sparsity (:mod:`fmu.structure`,
    :mod:`fmu.native.derivatives`): outputs and derivatives on the continuous states and inputs."""
    me = spec["me"]
    root = ET.Element("ModelStructure")
    _unknowns(root, "Outputs", me["outputs"], index)
    _unknowns(root, "Derivatives", {me_derivatives.derivative_name(s): d for s, d in me["derivatives"].items()}, index)
    _unknowns(root, "InitialUnknowns", {**spec["structure"]["initial"], **me["initial_states"]}, index)
    return root


def model_description(spec: dict, guid: str, sources: list[str]) -> bytes:
    """FMI 2.0 ``modelDescription.xml`` (UTF-8): model exchange and co-simulation, the pythonfmu
    FMU's variables in its order, then the state derivatives."""
    variables_ = all_variables(spec)
    index = {v["name"]: str(k + 1) for k, v in enumerate(variables_)}
    root = ET.Element("fmiModelDescription", fmiVersion="2.0", modelName=spec["model_identifier"], guid=guid,
                      description=spec["description"], author="rotor-mbs", version=spec["version"],
                      license="MIT", generationTool="rotor-mbs fmu.native", variableNamingConvention="structured",
                      numberOfEventIndicators="0")
    root.extend(_interfaces(spec["model_identifier"], sources))
    root.append(units.unit_definitions(v.get("unit") for v in variables_))
    cats = ET.SubElement(root, "LogCategories")
    for name, what in (("logStatusWarning", "fmi2Warning"), ("logStatusDiscard", "fmi2Discard"),
                       ("logStatusError", "fmi2Error"), ("logStatusFatal", "fmi2Fatal"), ("logAll", "all")):
        ET.SubElement(cats, "Category", name=name, description=f"Log messages with {what} status."
                      if what != "all" else "Log all messages.")
    ex = spec["default_experiment"]
    ET.SubElement(root, "DefaultExperiment", startTime=repr(float(ex["start"])), stopTime=repr(float(ex["stop"])),
                  stepSize=repr(float(ex["step"])))
    listed = ET.SubElement(root, "ModelVariables")
    listed.extend(_scalar_variable(spec, k, v, index) for k, v in enumerate(variables_))
    root.append(_model_structure(spec, index))
    ET.indent(root, "\t")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def model_description3(spec: dict, guid: str) -> bytes:
    """FMI 3.0 ``modelDescription.xml`` (:mod:`fmu.native.fmi3`)."""
    scalars = all_variables(spec)
    vars3 = fmi3.variables3(scalars)
    starts = {v["name"]: start_text(spec, v) for v in spec["variables"] if v["causality"] in ("input", "parameter")}
    return fmi3.model_description(spec, guid, scalars, vars3, spec["me"], starts)


# -- sources, library, archive -----------------------------------------------------------------

def native_spec(scene_names, aircraft=None) -> tuple[dict, dict]:
    """``fmu.build.plan`` with this FMU's identifier and its model exchange (``spec["me"]``:
    :func:`fmu.native.derivatives.me_structure`)."""
    spec, groups = pybuild.plan(list(scene_names), aircraft)
    variables = [_native_variable(v) for v in spec["variables"]]
    spec = {**spec, "model_identifier": identifier(scene_names, aircraft), "variables": variables}
    for name, sc in spec["scenes"].items():
        if sc["group"] not in groups:
            raise ValueError(f"scene {name!r}: model group {sc['group']!r} was not planned")
    spec["me"] = me_derivatives.me_structure(spec, groups)
    return spec, groups


def _native_variable(v: dict) -> dict:
    """A variable of the plan as the native FMU offers it: its ``evaluator`` has no virtual machine."""
    if v["name"] != "evaluator":
        return v
    return {**v, "allowed": ["compiled"], "description": "compiled: the model compiled into this FMU's library "
            "(the only evaluator of the native FMU; the pythonfmu FMU also offers CasADi's virtual machine, vm)"}


def write_sources(folder: Path, spec: dict, groups: dict, guid: str) -> list[str]:
    """Write every C file of the library into ``folder``; returns the compiled ones (.c)."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in HAND_WRITTEN:
        shutil.copy2(HERE / name, folder / name)
    for name in FMI_HEADERS:
        shutil.copy2(fmi_headers_dir() / name, folder / name)
    (folder / "heli_config.h").write_text(config_header(spec, groups))
    (folder / "heli_data.c").write_text(data_source(spec, groups, guid))
    files = ["heli_core.c", "fmi2Functions.c", "fmi3Functions.c", "heli_libm.c", "heli_data.c"]
    for g, (vm, functions) in groups.items():
        (folder / f"heli_model_{g}.c").write_text(model_source(g, functions, vm.info.nx))
        ad = me_derivatives.ad_functions(vm.functions["rhs"], functions["fmu_outputs"])
        (folder / f"heli_ad_{g}.c").write_text(model_source(g, ad, vm.info.nx, AD_FUNCTIONS, False, f"heli_{g}_d_"))
        files += [f"heli_model_{g}.c", f"heli_ad_{g}.c"]
    return files


def _flags(platform, name: str) -> list[str]:
    flags = [*CFLAGS, *platform.cflags]
    level = AD_OPTIMIZATION.get(platform.fmi3, "-O0")
    return [level if f == "-O2" and name.startswith("heli_ad_") else f for f in flags]


def compile_libraries(folder: Path, files: list[str], outs: dict) -> None:
    """Compile ``files`` (in ``folder``) for every platform of ``outs`` (platform -> library path),
    all files of all platforms in parallel, and link each library."""
    procs = []
    for p in outs:
        cc = platforms.compiler(p)
        for f in files:
            obj = folder / f"{f}.{p.fmi3}.o"
            procs.append((p, f, obj, subprocess.Popen([cc, *_flags(p, f), "-I", str(folder), "-c", str(folder / f), "-o",
                                                       str(obj)], stderr=subprocess.PIPE, text=True)))
    errors = [f"{f} ({p.fmi3}):\n{proc.communicate()[1][-2000:]}" for p, f, _, proc in procs if proc.wait()]
    if errors:
        raise RuntimeError("compiling the native FMU failed:\n" + "\n".join(errors))
    for p, out in outs.items():
        objects = [str(obj) for q, _, obj, _ in procs if q is p]
        proc = subprocess.run([platforms.compiler(p), "-shared", "-o", str(out), *objects, *p.ldflags],
                              capture_output=True, text=True)
        for o in objects:
            os.unlink(o)
        if proc.returncode:
            raise RuntimeError(f"linking the native FMU for {p.fmi3} failed:\n{proc.stderr[-2000:]}")


def guid_of(key: str) -> str:
    """A GUID derived from the cache key: the same inputs give the same FMU."""
    return "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, "rotor-mbs/native-fmu/" + key)) + "}"


def fmi3_path(fmu2: Path) -> Path:
    """Where the FMI 3.0 FMU built with the FMI 2.0 FMU ``fmu2`` goes: ``<name>_fmi3.fmu`` beside it."""
    fmu2 = Path(fmu2)
    return fmu2.with_name(fmu2.name[:-len(".fmu")] + "_fmi3.fmu")


def build_native(scene_names, dest: Path, key: str | None = None, aircraft=None, log=None) -> tuple[Path, Path]:
    """Generate, compile and zip the native FMU of ``scene_names`` of ``aircraft``: FMI 2.0 into
    ``dest`` (.fmu), FMI 3.0 into :func:`fmi3_path` of it, one library per available platform
    (``log`` says which are missing). Returns both paths."""
    spec, groups = native_spec(scene_names, aircraft)
    guid = guid_of(key or cache_key(scene_names, aircraft))
    ident = spec["model_identifier"]
    if log and platforms.missing():
        log("no binaries for " + ", ".join(f"{p.fmi3} ({p.compiler} not found)" for p in platforms.missing()))
    with tempfile.TemporaryDirectory(prefix="heli-native-fmu-") as tmp:
        root2, root3 = Path(tmp) / "fmi2", Path(tmp) / "fmi3"
        files = write_sources(root2 / "sources", spec, groups, guid)
        libraries = {p: root3 / "binaries" / p.fmi3 / f"{ident}{p.suffix}" for p in platforms.available()}
        for lib in libraries.values():
            lib.parent.mkdir(parents=True)
        compile_libraries(root2 / "sources", files, libraries)
        for p, lib in libraries.items():
            if p.fmi2:
                (root2 / "binaries" / p.fmi2).mkdir(parents=True)
                shutil.copy2(lib, root2 / "binaries" / p.fmi2 / lib.name)
        shutil.copytree(root2 / "sources", root3 / "sources")
        (root3 / "sources" / "buildDescription.xml").write_bytes(fmi3.build_description(ident, files))
        (root2 / "modelDescription.xml").write_bytes(model_description(spec, guid, files))
        (root3 / "modelDescription.xml").write_bytes(model_description3(spec, guid))
        for root in (root2, root3):  # the start values of each scene of the family, for masters
            (root / "resources").mkdir()
            (root / "resources" / pybuild.SCENE_STARTS).write_text(json.dumps(pybuild.scene_starts_table(spec), indent=1))
        _zip(root2, Path(dest))
        _zip(root3, fmi3_path(dest))
    return Path(dest), fmi3_path(dest)


def _zip(root: Path, dest: Path) -> None:
    dest.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as z:
        for path in sorted(p for p in root.rglob("*") if p.is_file()):
            z.write(path, path.relative_to(root).as_posix())


# -- cache -------------------------------------------------------------------------------------

def cache_key(scene_names, aircraft=None) -> str:
    """Hash of everything the native FMU is built from; like :func:`fmu.build.cache_key` it
    needs no compiler (``$CC`` counts when set), so a cached FMU is found without one."""
    h = hashlib.sha256()
    root = pybuild.mbs_dir()
    files = [(p.relative_to(root).as_posix(), p) for p in sorted(root.rglob("*"))
             if p.suffix in pybuild.SOURCE_SUFFIXES and "__pycache__" not in p.parts]
    files += [(f"fmu/{p.name}", p) for p in (HERE.parent / "build.py", HERE.parent / "periodic.py",
                                             HERE.parent / "periodic_starts.json") if p.exists()]
    files += [(f"fmu/pythonfmu/{p.name}", p) for p in sorted((HERE.parent / "pythonfmu").glob("*.py"))]
    files += [(f"fmu/native/{name}", HERE / name) for name in ("build.py", "c_literals.py", "derivatives.py", "fmi3.py",
                                                                 "units.py", "platforms.py", *HAND_WRITTEN)]
    files += [("fmu/structure.py", HERE.parent / "structure.py")]
    for rel, path in files:
        h.update(rel.encode() + b"\0" + path.read_bytes())
    for name in FMI_HEADERS:
        h.update((fmi_headers_dir() / name).read_bytes())
    h.update(json.dumps([list(scene_names), pybuild.load_aircraft(aircraft).digest, importlib.metadata.version("casadi"),
                         os.environ.get("CC") or "", CFLAGS, AD_OPTIMIZATION, platforms.key(), sys.platform]).encode())
    return h.hexdigest()[:20]


def cached_path(scene_names, aircraft=None, fmi: int = 2) -> Path:
    """The cached FMI 2.0 FMU (``fmi=3``: the FMI 3.0 one built with it)."""
    from mbs.backends.compiled import cache_dir

    path = cache_dir() / "fmu-native" / cache_key(scene_names, aircraft) / f"{identifier(scene_names, aircraft)}.fmu"
    return fmi3_path(path) if fmi == 3 else path


def ensure_native_fmu(scene_names=pybuild.DEFAULT_SCENES, force: bool = False, log=None,
                      aircraft=None, fmi: int = 2) -> tuple[Path, float]:
    """The cached native FMU of ``scene_names`` for FMI ``fmi`` (2 or 3; both are built at once
    if either is absent or not intact); returns (path, build seconds, 0 if it came from the
    cache). Verified like the pythonfmu FMU (:func:`fmu.build.fmu_problem`): a truncated or
    changed cached FMU is rebuilt."""
    from mbs.backends.cache import record, writable_dir

    if fmi not in (2, 3):
        raise ValueError(f"FMI version {fmi!r} is not one of 2, 3")
    key, path = cache_key(scene_names, aircraft), cached_path(scene_names, aircraft)
    wanted = fmi3_path(path) if fmi == 3 else path
    if not force:
        reason = pybuild.fmu_problem(path) or pybuild.fmu_problem(fmi3_path(path))
        if reason is None:
            return wanted, 0.0
        if log and (path.exists() or fmi3_path(path).exists()):
            log(f"rebuilding the cached native FMU: {reason}")
    writable_dir(path.parent, "FMU cache")
    if log:
        log(f"building the native FMU (FMI 2.0 and 3.0) for {', '.join(scene_names)} (compiles the models once; "
            "cached) ...")
    start = time.perf_counter()
    tmp = path.with_name(f".{os.getpid()}.tmp.fmu")
    try:
        build_native(scene_names, tmp, key, aircraft, log)
    except BaseException:
        tmp.unlink(missing_ok=True)
        fmi3_path(tmp).unlink(missing_ok=True)
        raise
    for built, final in ((tmp, path), (fmi3_path(tmp), fmi3_path(path))):
        built.replace(final)
        record(final)
    return wanted, time.perf_counter() - start


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="build the native heli rotor FMU (FMI 2.0 at --dest, FMI 3.0 beside it)")
    ap.add_argument("--scenes", default=",".join(pybuild.DEFAULT_SCENES))
    ap.add_argument("--aircraft", default=None, help="aircraft file (default: the Bo105)")
    ap.add_argument("--dest", required=True)
    args = ap.parse_args(argv)
    build_native(args.scenes.split(","), Path(args.dest), aircraft=args.aircraft,
                 log=lambda m: print(m, file=sys.stderr))
    return 0


if __name__ == "__main__":
    sys.exit(main())
