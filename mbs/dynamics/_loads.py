"""What force elements see and add: the symbolic state view, body loads ``h`` (with the
gyroscopic terms), generalized forces ``Q``, extra-state rates and the energies."""
from __future__ import annotations

import casadi as ca

from mbs.forces import Loads, State


def state_view(lay, s, u, z, t, p, motions, air=None) -> State:
    """The :class:`mbs.forces.State` of the symbolic state (coordinates and rates by name)."""
    coords = {n: s[i] for i, n in enumerate(lay.q_names)}
    rates = {n: u[i] for i, n in enumerate(lay.v_names)}
    extra = {n: z[i] for i, n in enumerate(lay.z_names)}
    v_index = {n: i for i, n in enumerate(lay.v_names)}
    return State(t, p, motions, coords, rates, v_index, extra, air)


def applied(lay, model, state: State) -> tuple[ca.SX, ca.SX, ca.SX]:
    """Applied body loads ``h`` (6 nb,): per body the force at the centre of mass (N, world)
    with gravity and the torque about it (N m, body) with the gyroscopic term; generalized
    forces ``Q`` (nv,) and the rates of the extra states (nz,)."""
    loads = Loads(lay.bodies, lay.nv, state.v_index, lay.z_names)
    for element in model.forces:
        element.apply(state, loads)
    missing = [n for n, r in loads.rates.items() if r is None]
    if missing:
        raise ValueError(f"no force element sets the rate of extra states {missing}")
    parts = []
    g = ca.DM(model.gravity)
    for b in lay.bodies:
        w, j = state.body(b.name).omega, ca.DM(b.inertia)
        parts += [loads.force[b.name] + b.mass * g, loads.torque[b.name] - ca.cross(w, ca.mtimes(j, w))]
    zdot = ca.vertcat(*loads.rates.values(), ca.SX(0, 1))
    return ca.vertcat(*parts), loads.generalized, zdot


def mass_times(lay, a: ca.SX) -> ca.SX:
    """``M a`` for the block-diagonal body mass matrix; ``a`` has 6 nb rows."""
    rows = []
    for i, b in enumerate(lay.bodies):
        rows += [b.mass * a[6 * i:6 * i + 3, :], ca.mtimes(ca.DM(b.inertia), a[6 * i + 3:6 * i + 6, :])]
    return ca.vertcat(*rows)


def energy(lay, model, state: State, V) -> ca.SX:
    """(translational kinetic, rotational kinetic, gravity, spring, total) in J, (5,)."""
    t_tr = t_rot = v_grav = 0
    for i, b in enumerate(lay.bodies):
        vc, w = V[6 * i:6 * i + 3], V[6 * i + 3:6 * i + 6]
        t_tr += 0.5 * b.mass * ca.dot(vc, vc)
        t_rot += 0.5 * ca.dot(w, ca.mtimes(ca.DM(b.inertia), w))
        v_grav -= b.mass * ca.dot(ca.DM(model.gravity), state.point_position(b.name, b.com))
    v_spring = sum((f.potential(state) for f in model.forces), ca.SX(0))
    return ca.vertcat(t_tr, t_rot, v_grav, v_spring, t_tr + t_rot + v_grav + v_spring)
