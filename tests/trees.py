"""Random trees and helpers shared by the tests."""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from mbs import Fixed, FreeJoint, Hinge, Model, Serial, SpringDamper


def random_inertia(rng) -> np.ndarray:
    """Full (rotated) inertia tensor; principal moments in [0.5, 1] satisfy the triangle rule."""
    r = Rotation.random(random_state=rng).as_matrix()
    return r @ np.diag(rng.uniform(0.5, 1.0, 3)) @ r.T


def random_tree(seed: int, n_bodies: int = 12, free_base: bool = True, serial: bool = True) -> Model:
    """A random tree: a chain of 4 (depth >= 4) then random attachments; random hinge axes,
    placements, masses, centres of mass, full inertias, springs and dampers."""
    rng = np.random.default_rng(seed)
    m = Model(f"random{seed}{'f' if free_base else ''}{'s' if serial else ''}", gravity=(0, 0, 9.81))
    names = []
    for i in range(n_bodies):
        parent = "world" if i == 0 else names[i - 1] if i < 4 else names[rng.integers(len(names))]
        if i == 0 and free_base:
            joint = FreeJoint()
        elif serial and i % 3 == 2:
            rot = Rotation.random(random_state=rng).as_matrix()
            joint = Serial(Hinge(rng.normal(size=3), name="a", stiffness=rng.uniform(0, 50)),
                           Fixed(at=tuple(rng.normal(size=3) * 0.3), frame=tuple(map(tuple, rot))),
                           Hinge(rng.normal(size=3), name="b", damping=rng.uniform(0, 2)))
        else:
            joint = Hinge(rng.normal(size=3), stiffness=rng.uniform(0, 50), damping=rng.uniform(0, 2),
                          rest_angle=rng.uniform(-0.3, 0.3))
        name = f"b{i}"
        m.add_body(name, parent, joint, mass=rng.uniform(0.5, 5.0), com=rng.normal(size=3) * 0.3,
                   inertia=random_inertia(rng), at=rng.normal(size=3) * 0.5,
                   frame=Rotation.random(random_state=rng).as_matrix())
        names.append(name)
    return m


def random_chain(seed: int, n_links: int, free_base: bool = False) -> Model:
    """``n_links`` bodies in series (the deepest tree): random hinge axes, placements, masses,
    centres of mass and full inertias; the first body on a free joint when ``free_base``."""
    rng = np.random.default_rng(seed)
    m = Model(f"chain{n_links}-{seed}{'f' if free_base else ''}", gravity=(0, 0, 9.81))
    parent = "world"
    for i in range(n_links):
        joint = FreeJoint() if i == 0 and free_base else Hinge(rng.normal(size=3))
        m.add_body(f"b{i}", parent, joint, mass=rng.uniform(0.5, 5.0), com=rng.normal(size=3) * 0.3,
                   inertia=random_inertia(rng), at=rng.normal(size=3) * 0.5 if i else np.zeros(3),
                   frame=Rotation.random(random_state=rng).as_matrix())
        parent = f"b{i}"
    return m


def random_state(system, seed: int, scale: float = 1.0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = system.x0()
    nq = system.info.nq
    x[:nq] += rng.normal(size=nq) * scale
    x[nq:] = rng.normal(size=system.info.nv) * scale
    return system.project(x)


def spring_forces(model: Model, system, x) -> np.ndarray:
    """Generalized spring-damper forces at ``x`` (for engines that take joint torques)."""
    info, tau = system.info, np.zeros(system.info.nv)
    for f in model.forces:
        if isinstance(f, SpringDamper):
            q = x[info.q_names.index(f.coordinate)]
            v = x[info.nq + info.v_names.index(f.coordinate + "_rate")]
            tau[info.v_names.index(f.coordinate + "_rate")] += -f.stiffness * (q - f.rest) - f.damping * v
    return tau


def depth(model: Model) -> int:
    return max(model.depth(n) for n in model.bodies)

