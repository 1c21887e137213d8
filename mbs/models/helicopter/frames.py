"""Where the rotors sit and which way they turn, from the aircraft data.

Body axes at the aircraft's centre of gravity: x forward, y starboard, z down. Each rotor has
a hub frame (right-handed; its joints turn about its z axis) and an *azimuth frame*: x at
azimuth ψ = 0, y at ψ = 90° (ψ counted in the sense of rotation), z the thrust axis. The two
coincide for a rotor that turns about its thrust axis (sense +1: the Bo105's main rotor,
counter-clockwise seen from above); for one that turns against it (sense -1: a clockwise main
rotor) the azimuth frame's y axis is the hub frame's -y (a left-handed frame, used only for
coordinates in the disc). In blade frames x runs along the span and z is the lift direction
at zero pitch; y is the leading edge for sense +1 and the trailing edge for sense -1.
"""
from __future__ import annotations

import numpy as np

from mbs.aircraft.geometry import (blade_azimuths, delta3_axis, main_hub_position, main_sense,  # noqa: F401
                                   precone_frame, rx, rz, shaft_frame, tail_frame, tail_hub_position, tail_sense)


def azimuth_frame(hub_frame: np.ndarray, sense: int) -> np.ndarray:
    """The azimuth frame (x at ψ = 0, y at ψ = 90°, z thrust) of a hub frame and its sense."""
    return hub_frame * np.array([1.0, sense, 1.0])
