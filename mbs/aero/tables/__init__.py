"""Airfoil tables: C81 files read as printed (:mod:`~mbs.aero.tables.c81`), their smooth
interpolants with exact derivatives in the generated code (:mod:`~mbs.aero.tables.interpolant`)
and the section loads of a blade whose segments each have their airfoil
(:mod:`~mbs.aero.tables.airfoil`)."""
from mbs.aero.tables.airfoil import AirfoilSegment, BladeAirfoils, TableAirfoil, table_section_loads
from mbs.aero.tables.c81 import C81, C81Error, CoefficientTable, parse_c81, read_c81
from mbs.aero.tables.interpolant import HermiteTable, TableSpline

__all__ = ["C81", "AirfoilSegment", "BladeAirfoils", "C81Error", "CoefficientTable", "HermiteTable", "TableAirfoil", "TableSpline",
           "parse_c81", "read_c81", "table_section_loads"]
