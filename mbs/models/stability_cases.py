"""Models for the stability benchmark (``heli bench stability``): cases where a method fails.

* :func:`tail_rotor_rig`: Bo105 on the ground rig (fuselage clamped, both hubs driven at
  constant speed, no aerodynamics, no dampers). The teetering tail rotor turns 5.25 times
  faster than the main rotor, so its 1/rev teeter mode sets RK4's step limit; without the
  tail rotor the main-rotor flap and lag modes allow a step about four times larger.
* :func:`stiff_damper_rotor`: Bo105 main rotor on a free hub (no fuselage, no aerodynamics)
  with the lead-lag dampers made ``factor`` times stiffer: a fast, strongly damped real
  eigenvalue that limits explicit methods although it carries no interesting motion.
* :func:`tumbling_body`: a free rigid body with the Bo105 airframe's mass and inertia,
  tumbling nose over tail (pitching through +-90 deg) in free fall: conservative, and an
  attitude that Euler angles cannot describe at the pitch singularity.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from mbs.joints import FreeJoint
from mbs import aircraft
from mbs.models import helicopter
from mbs.tree import Model

RIG = helicopter.Config(fuselage="clamped", rotors="driven", rotor_aero=False, airframe_aero=False,
                        dampers=False, speed=0.0)
DAMPER = helicopter.Config(fuselage="none", rotors="free", tail_rotor=False, rotor_aero=False,
                           airframe_aero=False, dampers=True, shaft_tilt=False, pitch_hinge=False, speed=0.0)


def tail_rotor_rig(tail_rotor: bool = True, teeter: float = 0.02) -> Model:
    """Clamped Bo105 with driven rotors and no aerodynamics; the seesaw starts at ``teeter``
    (rad) so that the tail rotor's teeter mode is excited (it is otherwise at rest)."""
    name = "bo105-rig" if tail_rotor else "bo105-rig-no-tail"
    m = helicopter.build(replace(RIG, tail_rotor=tail_rotor), name=name)
    if tail_rotor:
        m.set_initial(**{"seesaw.teeter": teeter})
    return m


def stiff_damper_rotor(factor: float = 10.0) -> Model:
    """Bo105 main rotor on a free hub with ``factor`` times the lag damping of the data
    file (700 N m s/rad); the hub spins at the nominal speed initially."""
    if not (np.isfinite(factor) and factor > 0):
        raise ValueError(f"damper factor {factor} must be positive and finite")
    d = aircraft.Data(aircraft.load().data)
    d["main_rotor"] = {**d["main_rotor"], "lag_damping": factor * d["main_rotor"]["lag_damping"]}
    m = helicopter.build(DAMPER, d, name=f"bo105-damper-x{factor:g}")
    for k in range(d["main_rotor"]["n_blades"]):
        m.set_initial(**{f"blade{k + 1}.lag": 0.01})
    return m


def tumbling_body(rates=(0.01, 2.0, 0.0)) -> Model:
    """Rigid body with the Bo105's mass and airframe inertia (``aircraft`` section of the
    data), free, starting level at 20 m/s with body rates ``rates`` = (p, q, r) in rad/s: with
    q dominant it pitches nose over tail, the nose passing close to the vertical (+-90 deg
    pitch) every half turn."""
    d = aircraft.load().data["aircraft"]
    m = Model("tumbling-body", gravity=(0.0, 0.0, 9.80665))
    inertia = [[d["Ixx"], 0, -d["Ixz"]], [0, d["Iyy"], 0], [-d["Ixz"], 0, d["Izz"]]]
    m.add_body("fuselage", "world", FreeJoint(), mass=d["mass"], inertia=inertia,
               shape={"kind": "box", "size": [3.6, 1.5, 1.4]})
    m.set_initial(**{"fuselage.p": rates[0], "fuselage.q": rates[1], "fuselage.r": rates[2],
                     "fuselage.u": 20.0})
    return m

