"""Aircraft as data: a TOML file of values with units and sources defines a single-main-rotor
helicopter; ``load(path)`` validates it, converts it to SI and computes what it derives.

    >>> from mbs import aircraft
    >>> lynx = aircraft.load("lynx")              # a packaged aircraft, or a path to your file
    >>> lynx.data["main_rotor"]["radius"]         # m

``check(path)`` returns the problems and the derived figures without raising; ``heli aircraft
check FILE`` prints them and ``heli aircraft new NAME`` writes a commented template.
"""
from mbs.aircraft._aircraft import DEFAULT, Aircraft, AircraftError, Data, load, packaged, resolve
from mbs.aircraft.report import Report, check
from mbs.aircraft.template import template

__all__ = ["Aircraft", "AircraftError", "Data", "DEFAULT", "Report", "check", "load", "packaged", "resolve",
           "template"]
