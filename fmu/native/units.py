"""Units of the native FMU's variables with their SI base units, for FMI 2.0 and 3.0
(``<UnitDefinitions>``), including the units of the state derivatives (a unit per second)."""
from __future__ import annotations

from xml.etree import ElementTree as ET


def per_second(unit: str | None) -> str:
    """The unit of a derivative: ``rad`` -> ``rad/s``, ``rad/s`` -> ``rad/s2``, ``1`` -> ``1/s``."""
    if not unit or unit == "1":
        return "1/s"
    return unit[:-2] + "/s2" if unit.endswith("/s") else unit + "/s"


def base_units(unit: str) -> dict[str, int] | None:
    """Exponents of the SI base units of ``unit`` (None for a unit not known here)."""
    from fmu.pythonfmu.units import BASE_UNITS

    if unit in BASE_UNITS:
        return BASE_UNITS[unit]
    for stem, extra in (("/s2", -2), ("/s", -1)):
        if unit.endswith(stem) and (unit[:-len(stem)] or "1") in BASE_UNITS:
            exps = dict(BASE_UNITS[unit[:-len(stem)] or "1"])
            exps["s"] = exps.get("s", 0) + extra
            return {k: e for k, e in exps.items() if e}
    return None


def unit_definitions(units) -> ET.Element:
    """``<UnitDefinitions>`` of the ``units`` used (each with its ``<BaseUnit>`` when known)."""
    defs = ET.Element("UnitDefinitions")
    for u in sorted(set(units) - {None}):
        unit = ET.SubElement(defs, "Unit", name=u)
        exps = base_units(u)
        if exps is not None:
            ET.SubElement(unit, "BaseUnit", {k: str(e) for k, e in exps.items()})
    return defs
