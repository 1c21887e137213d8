"""Generic conservative trees for tests and benchmarks (not helicopter data)."""
from __future__ import annotations

import numpy as np

from mbs.joints import FreeJoint, Hinge, Serial
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
                   inertia=[[1400.0, 0, -600], [0, 4900, 0], [-600, 0, 4000]])
        m.set_initial(**{"fuselage.u": 10.0})
        root = "fuselage"
    m.add_body("hub", root, Hinge(axis=(0, 0, -1), name="azimuth"), mass=30.0,
               inertia=np.diag([40.0, 40.0, 60.0]), at=(0.0, 0.0, -1.5))
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
                   frame=frame)
        m.set_initial(**{f"{b}.flap": 0.02 * (k + 1), f"{b}.lag": -0.01 * k})
    return m
