"""Stored periodic trims: what a run starts from.

A helicopter that flies free starts ``heli simulate`` from its periodic trim, so that no
start-up transient hides the response: the trim stored for exactly that model (aircraft file
by SHA-256, scene, aerodynamics switches, parameters, speed, method and steps per revolution)
and still periodic for it, or else one trimmed on first use and stored.

- :mod:`mbs.trims.store`: the TOML files of trims and their keys (``heli trim --write``).
- :mod:`mbs.trims.entry`: a trim as stored data, and the check that it still holds.
- :mod:`mbs.trims.start`: the start of a run, said on stderr and recorded in ``run.json``.
"""
from mbs.trims.entry import entry_of, residual
from mbs.trims.store import default_file, find, write

__all__ = ["default_file", "entry_of", "find", "residual", "write"]
