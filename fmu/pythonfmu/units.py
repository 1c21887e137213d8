"""SI units of the FMU's variables: the base-unit exponents of ``<UnitDefinitions>`` (also used by
the native and controller FMUs)."""
from __future__ import annotations

# SI base-unit exponents for <UnitDefinitions>; unknown units are declared by name only.
BASE_UNITS = {"rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1},
              "s": {"s": 1}, "J": {"kg": 1, "m": 2, "s": -2}, "N": {"kg": 1, "m": 1, "s": -2},
              "N m": {"kg": 1, "m": 2, "s": -2}, "W": {"kg": 1, "m": 2, "s": -3}, "1": {}}


def unit_definitions(root, units) -> None:
    """Insert ``<UnitDefinitions>`` of ``units`` (names) after ``<CoSimulation>`` of the model description
    ``root``, each with its SI base-unit exponents where :data:`BASE_UNITS` knows them."""
    from xml.etree.ElementTree import Element, SubElement

    defs = Element("UnitDefinitions")
    for u in sorted(units):
        unit = SubElement(defs, "Unit", name=u)
        if u in BASE_UNITS:
            SubElement(unit, "BaseUnit", {k: str(e) for k, e in BASE_UNITS[u].items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, defs)
