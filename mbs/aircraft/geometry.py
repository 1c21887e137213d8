"""Where the rotors sit and which way they turn, from the aircraft data (no model needed).

Body axes at the aircraft's centre of gravity: x forward, y starboard, z down. Each rotor has
a hub frame (right-handed; its joints turn about its z axis): the main rotor's x aft, y
starboard, z up the shaft; the tail rotor's x up, z its thrust axis. Blade azimuths are
counted in the sense of rotation from blade 1.
"""
from __future__ import annotations

import numpy as np


def rz(angle: float) -> np.ndarray:
    """Rotation (3, 3) by ``angle`` (rad) about z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def main_sense(d) -> int:
    """+1 for a main rotor turning counter-clockwise seen from above (about its thrust axis, up)."""
    return 1 if d["main_rotor"]["rotation"] == "counter-clockwise" else -1


def shaft_frame(tilt: float) -> np.ndarray:
    """Main-rotor hub frame in body axes: columns x (aft), y (starboard), z (shaft, up)."""
    return np.array([[-np.cos(tilt), 0, np.sin(tilt)], [0, 1.0, 0], [-np.sin(tilt), 0, -np.cos(tilt)]])


def tail_frame(d) -> np.ndarray:
    """Tail-rotor hub frame in body axes: x up, z the thrust (against the main rotor's torque:
    starboard under a counter-clockwise main rotor), y = z × x."""
    z = np.array([0.0, main_sense(d), 0.0])
    x = np.array([0.0, 0.0, -1.0])
    return np.column_stack([x, np.cross(z, x), z])


def tail_sense(d) -> int:
    """+1 when the tail rotor turns about its thrust axis: its upper blade then moves along the
    tail hub frame's y."""
    forward_is_y = tail_frame(d)[0, 1] > 0
    moves_forward = d["tail_rotor"]["upper_blade"] == "forward"
    return 1 if forward_is_y == moves_forward else -1


def main_hub_position(d) -> np.ndarray:
    """Main-rotor hub (m, body axes from the CG)."""
    return np.array([d["main_rotor"]["hub_x"], 0.0, d["main_rotor"]["hub_z"]])


def tail_hub_position(d) -> np.ndarray:
    """Tail-rotor hub (m, body axes from the CG)."""
    tr = d["tail_rotor"]
    return np.array([tr["hub_x"], tr["hub_y"], tr["hub_z"]])


def blade_azimuths(n_blades: int) -> np.ndarray:
    """Azimuth of each blade at ψ = 0 of blade 1 (rad, in the sense of rotation)."""
    return 2 * np.pi * np.arange(n_blades) / n_blades
