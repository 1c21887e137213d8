"""The FMI 3.0 description of the native FMU: the same model and library as the FMI 2.0 one,
its variables with arrays where they belong and the FMI 3.0 ``modelDescription.xml``.

Arrays: the scalar variables ``<part><k>.<rest>`` for ``k = 1 .. N`` (N >= 2, all present, the
same causality, variability and unit), e.g. ``blade1.flap`` ... ``blade4.flap``, are one array
variable ``<part>.<rest>`` of N elements (``blade.flap``, element k the blade k's); the same for
their derivatives (``der(blade.flap)``). Inputs and parameters stay scalars. Value reference 0
is the independent variable ``time``; the others follow in the order of the FMI 2.0 variables.
Each FMI 3.0 variable lists its *slots*, the FMI 2.0 value references of its elements, which is
how the library's FMI 3.0 interface reaches the model core.
"""
from __future__ import annotations

import re
from xml.etree import ElementTree as ET

from fmu.native.c_literals import c_string
from fmu.native.units import unit_definitions

ELEMENT = re.compile(r"^(der\()?([A-Za-z_]+?)(\d+)\.(.+?)(\))?$")
PLATFORMS = {"linux64": "x86_64-linux", "win64": "x86_64-windows", "aarch64-linux": "aarch64-linux"}


def _array_key(v: dict):
    m = ELEMENT.match(v["name"])
    if not m or v["causality"] in ("input", "parameter") or v["type"] != "Real" or bool(m[1]) != bool(m[5]):
        return None
    name = f"{m[2]}.{m[4]}"
    return (f"der({name})" if m[1] else name, v["causality"], v["variability"], v.get("unit")), int(m[3])


def variables3(scalars: list[dict]) -> list[dict]:
    """The FMI 3.0 variables of the FMI 2.0 ones ``scalars`` (in value-reference order): dicts of
    the first element's fields with ``name``, ``slots`` and ``dims`` (``None`` for a scalar)."""
    members: dict = {}
    for slot, v in enumerate(scalars):
        key = _array_key(v)
        if key:
            members.setdefault(key[0], {})[key[1]] = slot
    arrays = {key: [m[k] for k in range(1, len(m) + 1)] for key, m in members.items()
              if len(m) >= 2 and sorted(m) == list(range(1, len(m) + 1))}
    first = {slots[0]: key for key, slots in arrays.items()}
    taken = {s for slots in arrays.values() for s in slots}
    out = [{"name": "time", "causality": "independent", "variability": "continuous", "type": "Real", "unit": "s",
            "description": "simulation time", "slots": [-1], "dims": None}]
    for slot, v in enumerate(scalars):
        if slot in first:
            key = first[slot]
            out.append({**v, "name": key[0], "slots": arrays[key], "dims": len(arrays[key]),
                        "description": _array_description(v["description"], key[0])})
        elif slot not in taken:
            out.append({**v, "slots": [slot], "dims": None})
    return out


def _array_description(text: str, name: str) -> str:
    """The description of an array from its first element's: ``blade1``/``blade 1`` become ``blade k``,
    and element k is said to be blade k's; a derivative's names its array (``der(blade.flap)``)."""
    part = (name[4:] if name.startswith("der(") else name).split(".")[0]
    if name.startswith("der("):
        return f"time derivative of {name[4:-1]}; element k is {part} k's (model exchange)"
    return re.sub(rf"\b{re.escape(part)} ?1\b", f"{part} k", text) + f"; element k is {part} k's"


def me_order(vars3: list[dict], state_slots: list[int], n_variables: int) -> list[int]:
    """FMI 3.0 continuous state k is the FMI 2.0 state ``me_order(...)[k]``: the derivatives in
    the order of the FMI 3.0 variables, arrays element by element."""
    out = []
    for v in vars3:
        if v["name"].startswith("der("):
            out += [s - n_variables for s in v["slots"]]
    if sorted(out) != list(range(len(state_slots))):
        raise ValueError("the FMI 3.0 derivatives do not cover the continuous states once each")
    return out


def c_tables(vars3: list[dict], order: list[int]) -> str:
    """C tables of ``heli_data.c`` for the FMI 3.0 interface (see ``heli_model.h``)."""
    rows = [f"static const int slots3_{k}[{len(v['slots'])}] = {{{', '.join(map(str, v['slots']))}}};\n"
            for k, v in enumerate(vars3)]
    rows.append("static const heli_variable3 variables3[] = {\n"
                + ",\n".join(f"  {{{c_string(v['name'])}, {len(v['slots'])}, slots3_{k}}}" for k, v in enumerate(vars3))
                + "\n};\n")
    rows.append(f"static const int me_order3[{max(len(order), 1)}] = {{{', '.join(map(str, order)) or '0'}}};\n")
    return "".join(rows)


# -- modelDescription.xml --------------------------------------------------------------------------

def _variable(v: dict, vr: int, start) -> ET.Element:
    tag = "String" if v["type"] == "String" else "Float64"
    el = ET.Element(tag, name=v["name"], valueReference=str(vr), description=v["description"],
                    causality=v["causality"], variability=v["variability"])
    if v["causality"] in ("output", "local"):
        el.set("initial", "calculated")
    if tag == "Float64":
        for key in ("unit", "min", "max"):
            if v.get(key) is not None:
                el.set(key, v[key] if key == "unit" else f"{float(v[key]):.16g}")
        if start is not None:
            el.set("start", start)
    elif start is not None:
        ET.SubElement(el, "Start", value=start)
    if v["dims"]:
        ET.SubElement(el, "Dimension", start=str(v["dims"]))
    return el


def _interfaces(identifier: str) -> list[ET.Element]:
    common = {"modelIdentifier": identifier, "canGetAndSetFMUState": "true", "canSerializeFMUState": "true",
              "providesDirectionalDerivatives": "true", "providesAdjointDerivatives": "true",
              "canBeInstantiatedOnlyOncePerProcess": "false", "needsExecutionTool": "false"}
    me = ET.Element("ModelExchange", {**common, "needsCompletedIntegratorStep": "true",
                                      "providesEvaluateDiscreteStates": "false"})
    cs = ET.Element("CoSimulation", {**common, "canHandleVariableCommunicationStepSize": "true",
                                     "providesIntermediateUpdate": "false", "canReturnEarly": "false",
                                     "hasEventMode": "false"})
    return [me, cs]


def _dependencies(el: ET.Element, deps: list, vr_of_scalar: dict) -> None:
    """Dependencies on FMI 3.0 variables (an array once, its kind the worst of its elements')."""
    merged: dict = {}
    for name, kind in deps:
        vr = vr_of_scalar[name]
        merged[vr] = "dependent" if "dependent" in (merged.get(vr), kind) else kind
    el.set("dependencies", " ".join(map(str, merged)))
    el.set("dependenciesKind", " ".join(merged.values()))


def model_description(spec: dict, guid: str, scalars: list[dict], vars3: list[dict], me: dict,
                      starts: dict) -> bytes:
    """FMI 3.0 ``modelDescription.xml``: model exchange and co-simulation, ``vars3`` with their
    ``starts`` (name -> text), ModelStructure from ``spec["structure"]`` and ``me``
    (:func:`fmu.native.derivatives.me_structure`)."""
    root = ET.Element("fmiModelDescription", fmiVersion="3.0", modelName=spec["model_identifier"],
                      instantiationToken=guid, description=spec["description"], author="rotor-mbs",
                      version=spec["version"], license="MIT", generationTool="rotor-mbs fmu.native",
                      variableNamingConvention="structured")
    root.extend(_interfaces(spec["model_identifier"]))
    root.append(unit_definitions(v.get("unit") for v in vars3))
    cats = ET.SubElement(root, "LogCategories")
    for name in ("logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal", "logAll"):
        ET.SubElement(cats, "Category", name=name)
    ex = spec["default_experiment"]
    ET.SubElement(root, "DefaultExperiment", startTime=repr(float(ex["start"])), stopTime=repr(float(ex["stop"])),
                  stepSize=repr(float(ex["step"])))
    vr_of_scalar = {scalars[s]["name"]: k for k, v in enumerate(vars3) for s in v["slots"] if s >= 0}
    state_vr = {s: vr_of_scalar[s] for s in me["states"]}
    variables = ET.SubElement(root, "ModelVariables")
    for k, v in enumerate(vars3):
        el = _variable(v, k, starts.get(v["name"]))
        if v.get("derivative_of"):
            el.set("derivative", str(state_vr[v["derivative_of"]]))
        variables.append(el)
    root.append(_model_structure(spec, scalars, vars3, me, vr_of_scalar))
    ET.indent(root, "\t")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def _model_structure(spec: dict, scalars: list[dict], vars3: list[dict], me: dict, vr_of_scalar: dict) -> ET.Element:
    root = ET.Element("ModelStructure")
    deps_of = {**me["outputs"], **{f"der({s})": d for s, d in me["derivatives"].items()}}
    initial = {**spec["structure"]["initial"], **me["initial_states"]}
    for tag, kinds in (("Output", ("output",)), ("ContinuousStateDerivative", ("der",)),
                       ("InitialUnknown", ("output", "der", "state"))):
        for k, v in enumerate(vars3):
            kind = "der" if v["name"].startswith("der(") else v["causality"]
            names = [scalars[s]["name"] for s in v["slots"] if s >= 0]
            if kind == "local" and names and names[0] in me["states"]:
                kind = "state"
            if kind not in kinds:
                continue
            el = ET.SubElement(root, tag, valueReference=str(k))
            table = initial if tag == "InitialUnknown" else deps_of
            _dependencies(el, [d for n in names for d in table.get(n, [])], vr_of_scalar)
    return root


def build_description(identifier: str, sources: list[str]) -> bytes:
    """``sources/buildDescription.xml``: one build configuration of every C file."""
    root = ET.Element("fmiBuildDescription", fmiVersion="3.0")
    config = ET.SubElement(root, "BuildConfiguration", modelIdentifier=identifier)
    files = ET.SubElement(config, "SourceFileSet", language="C99")
    for name in sources:
        ET.SubElement(files, "SourceFile", name=name)
    ET.indent(root, "\t")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"
