"""The lag damper as published: a strut between the hub and each blade with its force curve.

The aircraft file's ``[lag_damper]`` gives the damper's two ends (distance from the rotor axis,
towards the leading edge, up; m) and its force against the rate of extension (a table; N against
m/s), optionally a stiffness along its line (N/m). Each blade gets one :class:`mbs.forces.Strut`
from the hub to the blade (which moves with flap, lag and pitch); the AD turns its force into the
generalized forces of every coordinate. A rotor with such a damper may also keep a rotational
``lag_damping`` on the hinge (structural damping): ``heli aircraft check`` says so.
"""
from __future__ import annotations

import numpy as np

from mbs.forces import Strut


def has_damper(d) -> bool:
    """Whether the aircraft data ``d`` give a ``[lag_damper]``."""
    return bool(d.get("lag_damper", {}).get("force_curve"))


def force_curve(d):
    """The damper's force (N) as a function of its rate of extension (m/s): a natural cubic spline."""
    from mbs.aero.interpolation import Spline

    rows = np.array(d["lag_damper"]["force_curve"], dtype=float)
    return Spline(rows[:, 0], rows[:, 1])


def ends(d, sense: int) -> tuple[np.ndarray, np.ndarray]:
    """The damper's ends at zero azimuth: on the hub (hub frame) and on the blade (blade frame, whose
    origin is the flap hinge; y towards the leading edge for ``sense`` +1, the trailing edge for -1)."""
    ld, e = d["lag_damper"], d["main_rotor"]["flap_hinge_offset"]
    flip = np.array([1.0, sense, 1.0])
    return np.asarray(ld["hub_point"]) * flip, (np.asarray(ld["blade_point"]) - [e, 0.0, 0.0]) * flip


def add_lag_damper(m, d, blade: str, frame: np.ndarray, sense: int) -> None:
    """The damper of ``blade`` (a body on ``main_hub``; ``frame`` its azimuth frame in the hub's)."""
    hub_end, blade_end = ends(d, sense)
    rest = float(np.linalg.norm(np.asarray(d["lag_damper"]["blade_point"]) - d["lag_damper"]["hub_point"]))
    m.add_force(Strut(f"{blade} lag damper", "main_hub", frame @ hub_end, blade, blade_end,
                      d["lag_damper"]["stiffness"], rest, force_curve(d)))
