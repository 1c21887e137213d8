"""Generic conservative trees for tests and benchmarks (not helicopter data)."""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.joints import DrivenHinge, Fixed, FreeJoint, Hinge, Serial
from mbs.scenes import Scene, register
from mbs.tree import Model


def _rod_inertia(mass: float, length: float, width: float) -> np.ndarray:
    """Inertia about the centre of a slender box along x, kg m^2."""
    return mass / 12 * np.diag([2 * width**2, length**2 + width**2, length**2 + width**2])


def spinning_rotor(n_blades: int = 4, free_fuselage: bool = True, omega: float = 44.4,
                   radius: float = 4.9, name: str | None = None) -> Model:
    """A fuselage (free if ``free_fuselage``) carrying a free-spinning hub with ``n_blades``
    blades on flap and lag hinges with springs: conservative, no driven joints.

    The hub turns at ``omega`` (rad/s) initially; blades start with small flap and lag angles.
    DOF: 6 (if free) + 1 + 2 n_blades.
    """
    m = Model(name or f"rotor{n_blades}{'-free' if free_fuselage else ''}")
    root = "world"
    if free_fuselage:
        m.add_body("fuselage", "world", FreeJoint(), mass=2000.0, com=(0.0, 0.0, 0.2),
                   inertia=[[1400.0, 0, -600], [0, 4900, 0], [-600, 0, 4000]],
                   shape={"kind": "box", "size": [4.0, 1.5, 1.5]})
        m.set_initial(**{"fuselage.u": 10.0})
        root = "fuselage"
    m.add_body("hub", root, Hinge(axis=(0, 0, -1), name="azimuth"), mass=30.0,
               inertia=np.diag([40.0, 40.0, 60.0]), at=(0.0, 0.0, -1.5),
               shape={"kind": "cylinder", "radius": 0.3, "length": 0.3, "axis": [0, 0, 1]})
    m.set_initial(**{"hub.azimuth_rate": omega})
    blade_mass, e = 28.0, 0.3
    for k in range(n_blades):
        psi = 2 * np.pi * k / n_blades
        frame = [[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0], [0, 0, 1]]
        joint = Serial(Hinge(axis=(0, -1, 0), name="flap", stiffness=1.1e5),
                       Hinge(axis=(0, 0, 1), name="lag", stiffness=2.0e5))
        b = f"blade{k + 1}"
        m.add_body(b, "hub", joint, mass=blade_mass, com=(radius / 2, 0.0, 0.0),
                   inertia=_rod_inertia(blade_mass, radius, 0.27), at=e * np.array(frame)[:, 0],
                   frame=frame, shape={"kind": "box", "size": [radius, 0.27, 0.05], "offset": [radius / 2, 0, 0]})
        m.set_initial(**{f"{b}.flap": 0.02 * (k + 1), f"{b}.lag": -0.01 * k})
    return m


def driven_rotor(n_blades: int = 3) -> Model:
    """Free fuselage; hub driven at ``omega``; blades with swashplate-driven pitch, flap
    spring, lag damper. Controls ``collective``, ``lateral_cyclic``, ``longitudinal_cyclic``
    (rad) are run-time inputs. Outputs: azimuth and each blade's flap and lag angle."""
    m = Model("demo-driven")
    m.add_parameter("omega", 44.4, "rad/s", "rotor speed")
    m.add_parameter("collective", 0.1, "rad", "collective pitch", control=True, low=-0.2, high=0.4)
    m.add_parameter("lateral_cyclic", 0.0, "rad", "lateral cyclic pitch", control=True, low=-0.2, high=0.2)
    m.add_parameter("longitudinal_cyclic", -0.05, "rad", "longitudinal cyclic pitch", control=True,
                    low=-0.2, high=0.2)
    m.add_body("fuselage", "world", FreeJoint(), mass=2000.0, com=(0.1, 0, 0.3),
               inertia=[[1400.0, 0, -600], [0, 4900, 0], [-600, 0, 4000]], shape={"kind": "box", "size": [4.0, 1.5, 1.5]})
    m.add_body("hub", "fuselage", DrivenHinge((0, 0.05, -1), lambda t, p: p["omega"] * t, name="azimuth"),
               mass=30.0, inertia=np.diag([40.0, 40.0, 60.0]), at=(0, 0, -1.5),
               shape={"kind": "cylinder", "radius": 0.3, "length": 0.3, "axis": [0, 0, 1]})
    for k in range(n_blades):
        psi = 2 * np.pi * k / n_blades

        def pitch_law(t, p, psi=psi):
            azimuth = p["omega"] * t + psi
            return p["collective"] + p["lateral_cyclic"] * ca.cos(azimuth) + p["longitudinal_cyclic"] * ca.sin(azimuth)

        joint = Serial(DrivenHinge((1, 0, 0), pitch_law, name="pitch"),
                       Hinge((0, -1, 0), name="flap", stiffness=1e5),
                       Fixed(at=(0.2, 0, 0)), Hinge((0, 0, 1), name="lag", damping=700.0))
        b = f"blade{k + 1}"
        m.add_body(b, "hub", joint, mass=28.0, com=(2.4, 0.02, 0), inertia=np.diag([1, 56, 57.0]),
                   at=(0.3 * np.cos(psi), 0.3 * np.sin(psi), 0),
                   frame=[[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0], [0, 0, 1]],
                   shape={"kind": "box", "size": [4.9, 0.27, 0.05], "offset": [2.45, 0, 0]})
    m.add_output("azimuth", lambda s: s.p["omega"] * s.t, "rad", "rotor azimuth")
    return m


register(Scene("demo-rotor", "generic conservative rotor tree: free fuselage, free hub, 4 blades "
               "on flap and lag springs (no helicopter data)", spinning_rotor, omega=44.4, conservative=True,
               plots={"flap (rad)": [f"blade{k}.flap" for k in range(1, 5)],
                      "lag (rad)": [f"blade{k}.lag" for k in range(1, 5)]}))
register(Scene("demo-driven", "generic driven rotor: free fuselage, hub at constant speed, 3 blades with "
               "swashplate pitch inputs, flap springs, lag dampers (no aerodynamics, no helicopter data)",
               driven_rotor, omega=44.4,
               plots={"flap (rad)": [f"blade{k}.flap" for k in range(1, 4)],
                      "lag (rad)": [f"blade{k}.lag" for k in range(1, 4)]}))
