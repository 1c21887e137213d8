"""Validation against published data: trims, stability and control derivatives and eigenvalues
against speed, read from a file with units, sources and tolerances (:mod:`mbs.validate.data`; a
TOML or CSV file, packaged or a path: :mod:`mbs.validate.files`), compared with the model run at
the same speeds (:mod:`mbs.validate.ours`), shown as tables
(:mod:`mbs.validate.report`) and charts (:mod:`mbs.validate.charts`); ``heli validate``
(:mod:`mbs.validate.commands`). The packaged data (``mbs/validate/data``): the Puma against
Padfield's Helisim and the Bo105 against Helisim and its flight test.
"""
from mbs.validate.data import Validation, ValidationError
from mbs.validate.files import load, packaged
from mbs.validate.runner import Result, validate

__all__ = ["Validation", "ValidationError", "Result", "load", "packaged", "validate"]
