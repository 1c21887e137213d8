"""The flight envelope the model covers: the flight speeds and climb rates that the commands
(:mod:`mbs.arguments`) and the run inputs (:mod:`mbs.inputs`) accept. SI units."""

SPEED_RANGE = (-20.0, 90.0)
"""Flight speeds (m/s) the commands accept: rearward flight to 175 kt, beyond every packaged
aircraft's never-exceed speed (the FMU's ``initial_forward_speed`` has the same range)."""
CLIMB_RANGE = (-20.0, 20.0)
"""Climb rates (m/s, up positive) the commands accept: about 4000 ft/min either way."""
