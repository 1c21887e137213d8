"""Write an SSP 1.0 file (System Structure and Parameterization: a ``.ssp`` zip with
``SystemStructure.ssd`` and the FMUs under ``resources/``) for a system of FMUs connected
output to input, with start values as inline parameter sets."""
from __future__ import annotations

import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
TYPES = {float: "Real", str: "String", int: "Integer", bool: "Boolean"}


def _q(ns: str, tag: str) -> str:
    return f"{{{ns}}}{tag}"


def _connectors(parent: ET.Element, inputs: list[str], outputs: list[str]) -> None:
    box = ET.SubElement(parent, _q(SSD, "Connectors"))
    for kind, names in (("input", inputs), ("output", outputs)):
        for name in names:
            ET.SubElement(ET.SubElement(box, _q(SSD, "Connector"), name=name, kind=kind), _q(SSC, "Real"))


def _parameters(parent: ET.Element, name: str, values: dict) -> None:
    binding = ET.SubElement(ET.SubElement(parent, _q(SSD, "ParameterBindings")), _q(SSD, "ParameterBinding"))
    pset = ET.SubElement(ET.SubElement(binding, _q(SSD, "ParameterValues")), _q(SSV, "ParameterSet"),
                         version="1.0", name=name)
    params = ET.SubElement(pset, _q(SSV, "Parameters"))
    for key, value in values.items():
        kind = TYPES[type(value)]
        text = repr(float(value)) if kind == "Real" else str(value).lower() if kind == "Boolean" else str(value)
        ET.SubElement(ET.SubElement(params, _q(SSV, "Parameter"), name=key), _q(SSV, kind), value=text)


def system_structure(name: str, components: dict, connections: list, stop: float) -> bytes:
    """``SystemStructure.ssd``: ``components[name] = {"fmu": file name in resources/, "inputs",
    "outputs", "parameters"}``; ``connections``: ``(from component, output, to component, input)``."""
    for prefix, ns in (("ssd", SSD), ("ssc", SSC), ("ssv", SSV)):
        ET.register_namespace(prefix, ns)
    root = ET.Element(_q(SSD, "SystemStructureDescription"), version="1.0", name=name)
    system = ET.SubElement(root, _q(SSD, "System"), name=name)
    elements = ET.SubElement(system, _q(SSD, "Elements"))
    for cname, c in components.items():
        comp = ET.SubElement(elements, _q(SSD, "Component"), name=cname, type="application/x-fmu-sharedlibrary",
                             source=f"resources/{c['fmu']}")
        _connectors(comp, c["inputs"], c["outputs"])
        if c.get("parameters"):
            _parameters(comp, f"{cname}-start", c["parameters"])
    wires = ET.SubElement(system, _q(SSD, "Connections"))
    for a, out, b, inp in connections:
        ET.SubElement(wires, _q(SSD, "Connection"), startElement=a, startConnector=out, endElement=b,
                      endConnector=inp)
    ET.SubElement(root, _q(SSD, "DefaultExperiment"), startTime="0.0", stopTime=repr(float(stop)))
    ET.indent(root, "  ")
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n"


def write_ssp(dest: Path, name: str, components: dict, connections: list, stop: float) -> Path:
    """The ``.ssp`` file ``dest``: ``SystemStructure.ssd`` and each component's FMU (``c["path"]``)."""
    dest.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", system_structure(name, components, connections, stop))
        for c in components.values():
            z.write(c["path"], f"resources/{c['fmu']}")
    return dest
