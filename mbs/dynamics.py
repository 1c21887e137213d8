"""Equations of motion in minimal coordinates with forward-mode AD (the paper's method).

State ``x = (s, u, z)``: ``s`` (nq,) joint positions, ``u`` (nv,) joint rates, ``z`` (nz,)
extra first-order states of force elements (e.g. induced inflow; usually none). Body states
``V`` stack, per body, the centre-of-mass velocity (world components, m/s) and the
angular velocity (body components, rad/s), so that ``M = blockdiag(m I, J_c)``.

* ``J_u = dV/du`` from ``nv`` forward directional derivatives (one per rate);
* ``H = dV/ds F + dV/dt`` from ONE forward directional derivative along ``(F, 1)``
  (it carries the rates and accelerations of driven joints: they are functions of t);
* ``Mt = J_uᵀ M J_u``, ``ht = J_uᵀ (h - M H) + Q``; ``u' = Mt⁻¹ ht`` by sparse LDL;
  ``s' = F(s, u)``. The two products are summed over subtrees (:func:`_composite`): the
  same sums, in O(n²) operations for a chain of n bodies instead of O(n³).

No Jacobian is written by hand: each joint states only its relative kinematics.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from mbs import tree as _tree
from mbs.backends.info import StateSizes
from mbs.forces import Loads, State
from mbs.joints import Params, Relative, compose


@dataclass
class Layout(StateSizes):
    """Where each body's coordinates live in ``s`` and ``u``; numeric data only."""

    bodies: list
    q_slices: dict[str, slice] = field(default_factory=dict)
    v_slices: dict[str, slice] = field(default_factory=dict)
    q_names: list[str] = field(default_factory=list)
    v_names: list[str] = field(default_factory=list)
    z_names: list[str] = field(default_factory=list)

    @classmethod
    def of(cls, model: _tree.Model) -> "Layout":
        lay = cls(model.order())
        for b in lay.bodies:
            lay.q_slices[b.name] = slice(len(lay.q_names), len(lay.q_names) + b.joint.nq)
            lay.v_slices[b.name] = slice(len(lay.v_names), len(lay.v_names) + b.joint.nv)
            lay.q_names += [f"{b.name}.{n}" for n in b.joint.q_names]
            lay.v_names += [f"{b.name}.{n}" for n in b.joint.v_names]
        lay.z_names = list(model.states)
        return lay


def _placement(body) -> Relative:
    z = ca.SX.zeros(3)
    return Relative(ca.DM(body.at), ca.DM(body.frame), z, z)


def traverse(lay: Layout, s, u, t, p: Params) -> dict[str, Relative]:
    """Absolute motion of every body frame, root to leaves (the paper's traversal)."""
    z = ca.SX.zeros(3)
    world = Relative(z, ca.SX.eye(3), z, z)
    motions: dict[str, Relative] = {}
    for b in lay.bodies:
        parent = motions.get(b.parent, world)
        rel = b.joint.relative(s[lay.q_slices[b.name]], u[lay.v_slices[b.name]], t, p)
        motions[b.name] = compose(compose(parent, _placement(b)), rel)
    return motions


def body_states(lay: Layout, motions) -> ca.SX:
    """``V``: per body (centre-of-mass velocity in world, angular velocity in body), (6 nb,)."""
    parts = []
    for b in lay.bodies:
        m = motions[b.name]
        parts += [m.velocity + ca.mtimes(m.rotation, ca.cross(m.omega, ca.DM(b.com))), m.omega]
    return ca.vertcat(*parts)


@dataclass
class Symbolic:
    """The model's CasADi functions (all inputs dense column vectors).

    ``parts(x, t, p) -> (s', Mt, ht)``, ``rhs(x, t, p) -> x'``, ``kin(x, t, p) -> (V, J_u, H)``,
    ``energy(x, t, p) -> (T_trans, T_rot, V_grav, V_spring, E)`` in J,
    ``poses(x, t, p) -> (nb*12,)``: per body origin (3, m) and rotation matrix (9, row major),
    ``project(x) -> x`` back onto the manifold (unit quaternions),
    ``outputs(x, t, p) -> (n_outputs,)`` the model's named outputs.
    """

    model: _tree.Model
    layout: Layout
    functions: dict[str, ca.Function]

    def __getitem__(self, name: str) -> ca.Function:
        return self.functions[name]


def _state_view(lay, s, u, z, t, p, motions) -> State:
    coords = {n: s[i] for i, n in enumerate(lay.q_names)}
    rates = {n: u[i] for i, n in enumerate(lay.v_names)}
    extra = {n: z[i] for i, n in enumerate(lay.z_names)}
    v_index = {n: i for i, n in enumerate(lay.v_names)}
    return State(t, p, motions, coords, rates, v_index, extra)


def _applied_h(lay, model, state: State) -> tuple[ca.SX, ca.SX, ca.SX]:
    """Applied body loads ``h`` (6 nb,) including gyroscopic terms, generalized ``Q`` (nv,)
    and the rates of the extra states (nz,)."""
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


def _mass_times(lay, a: ca.SX) -> ca.SX:
    """``M a`` for the block-diagonal body mass matrix; ``a`` has 6 nb rows."""
    rows = []
    for i, b in enumerate(lay.bodies):
        rows += [b.mass * a[6 * i:6 * i + 3, :], ca.mtimes(ca.DM(b.inertia), a[6 * i + 3:6 * i + 6, :])]
    return ca.vertcat(*rows)


def _skew(c) -> ca.SX:
    """``skew(c) @ w = c × w``."""
    return ca.vertcat(ca.horzcat(0, -c[2], c[1]), ca.horzcat(c[2], 0, -c[0]), ca.horzcat(-c[1], c[0], 0))


def _body_spatial(lay, motions, Ju, g, i, b, r0):
    """Body ``b`` (index ``i``) about the reference point ``r0``, world components, ordered
    (angular, linear): the twists (6, nk) of its own rates (columns of ``J_u``), its spatial
    inertia (6, 6) and the wrench (6,) of its load ``g`` (force in world, torque in body)."""
    m = motions[b.name]
    c = m.position + ca.mtimes(m.rotation, ca.DM(b.com)) - r0
    cx, rows = _skew(c), slice(6 * i, 6 * i + 6)
    own = Ju[rows, lay.v_slices[b.name]]
    w = ca.mtimes(m.rotation, own[3:, :])
    twist = ca.vertcat(w, own[:3, :] + ca.mtimes(cx, w))
    j_world = ca.mtimes([m.rotation, ca.DM(b.inertia), m.rotation.T])
    inertia = ca.blockcat([[j_world + b.mass * ca.mtimes(cx.T, cx), b.mass * cx],
                           [b.mass * cx.T, b.mass * ca.SX.eye(3)]])
    gf, gt = g[6 * i:6 * i + 3], g[6 * i + 3:6 * i + 6]
    return twist, inertia, ca.vertcat(ca.cross(c, gf) + ca.mtimes(m.rotation, gt), gf)


def _composite(lay, motions, Ju, g) -> tuple[ca.SX, ca.SX]:
    """``Mt = J_uᵀ M J_u`` and ``J_uᵀ g`` (g: (6 nb,) body loads), summed over subtrees.

    A unit rate ``u_k`` moves the whole subtree of its body ``b_k`` rigidly, with one twist
    ``ξ_k`` (the body's own columns of ``J_u``, as a world twist about the first body's
    origin: any common point would do, one near the bodies keeps float32 accurate when the
    aircraft is far from the world origin). So ``(J_uᵀ M J_u)_jk = Σ_i ξ_jᵀ I_i ξ_k = ξ_jᵀ Ic(b_k) ξ_k`` when ``b_j`` is
    ``b_k`` or one of its ancestors (zero otherwise) and ``(J_uᵀ g)_k = ξ_kᵀ Wc(b_k)``, with
    ``Ic``, ``Wc`` the spatial inertias and wrenches summed over the subtree: the same sums as
    the plain product, in O(n²) operations for a chain where the product takes O(n³).
    """
    r0 = motions[lay.bodies[0].name].position
    twist, inertia, wrench = {}, {}, {}
    for i, b in enumerate(lay.bodies):
        twist[b.name], inertia[b.name], wrench[b.name] = _body_spatial(lay, motions, Ju, g, i, b, r0)
    parent = {b.name: b.parent for b in lay.bodies}
    for b in reversed(lay.bodies):
        if b.parent in inertia:
            inertia[b.parent] += inertia[b.name]
            wrench[b.parent] += wrench[b.name]
    moving = [b.name for b in lay.bodies if b.joint.nv]
    blocks = {}
    for k in moving:
        f, a = ca.mtimes(inertia[k], twist[k]), k
        while a in parent:  # b_k and its ancestors
            if twist[a].shape[1]:
                blocks[(a, k)] = ca.mtimes(twist[a].T, f)
            a = parent[a]
    rows = [[blocks[(a, k)] if (a, k) in blocks else blocks[(k, a)].T if (k, a) in blocks
             else ca.SX(twist[a].shape[1], twist[k].shape[1]) for k in moving] for a in moving]
    ht = ca.vertcat(*[ca.mtimes(twist[k].T, wrench[k]) for k in moving], ca.SX(0, 1))
    return (ca.blockcat(rows) if moving else ca.SX(0, 0)), ht


def _energy(lay, model, state: State, V) -> ca.SX:
    t_tr = t_rot = v_grav = 0
    for i, b in enumerate(lay.bodies):
        vc, w = V[6 * i:6 * i + 3], V[6 * i + 3:6 * i + 6]
        t_tr += 0.5 * b.mass * ca.dot(vc, vc)
        t_rot += 0.5 * ca.dot(w, ca.mtimes(ca.DM(b.inertia), w))
        v_grav -= b.mass * ca.dot(ca.DM(model.gravity), state.point_position(b.name, b.com))
    v_spring = sum((f.potential(state) for f in model.forces), ca.SX(0))
    return ca.vertcat(t_tr, t_rot, v_grav, v_spring, t_tr + t_rot + v_grav + v_spring)


def _poses(lay, motions) -> ca.SX:
    return ca.vertcat(*[ca.vertcat(motions[b.name].position, ca.reshape(motions[b.name].rotation.T, 9, 1))
                        for b in lay.bodies])


def symbolic(model: _tree.Model) -> Symbolic:
    """Build the symbolic equations of motion of ``model`` (the one orchestrating function)."""
    lay = Layout.of(model)
    x = ca.SX.sym("x", lay.nq + lay.nv + lay.nz)
    t = ca.SX.sym("t")
    p = ca.SX.sym("p", len(model.parameters))
    s, u, z = x[:lay.nq], x[lay.nq:lay.nq + lay.nv], x[lay.nq + lay.nv:]
    params = Params(list(model.parameters), p)
    motions = traverse(lay, s, u, t, params)
    V = body_states(lay, motions)
    F = ca.vertcat(*[b.joint.qdot(s[lay.q_slices[b.name]], u[lay.v_slices[b.name]]) for b in lay.bodies],
                   ca.SX(0, 1))
    Ju = ca.jtimes(V, u, ca.SX.eye(lay.nv))
    H = ca.jtimes(V, ca.vertcat(s, t), ca.vertcat(F, 1))
    state = _state_view(lay, s, u, z, t, params, motions)
    state.energy = _energy(lay, model, state, V)
    h, Q, zdot = _applied_h(lay, model, state)
    Mt, ht = _composite(lay, motions, Ju, h - _mass_times(lay, H))
    Mt, ht = ca.sparsify(Mt), ht + Q
    project = ca.vertcat(*[b.joint.project(s[lay.q_slices[b.name]]) for b in lay.bodies], ca.SX(0, 1), u, z)
    args, names = [x, t, p], ["x", "t", "p"]
    fns = {
        "parts": ca.Function("parts", args, [F, Mt, ht, zdot], names, ["sdot", "Mt", "ht", "zdot"]),
        "kin": ca.Function("kin", args, [V, Ju, H], names, ["V", "Ju", "H"]),
        "energy": ca.Function("energy", args, [state.energy], names, ["energy"]),
        "outputs": ca.Function("outputs", args, [ca.vertcat(*[o.fn(state) for o in model.outputs.values()],
                                                            ca.SX(0, 1))], names, ["y"]),
        "poses": ca.Function("poses", args, [_poses(lay, motions)], names, ["poses"]),
        "project": ca.Function("project", [x], [project], ["x"], ["x_projected"]),
    }
    fns["rhs"] = _rhs(fns["parts"], lay.nq + lay.nv + lay.nz, len(model.parameters))
    return Symbolic(model, lay, fns)


def _rhs(parts: ca.Function, nx: int, np_: int) -> ca.Function:
    """MX wrapper solving ``Mt u' = ht`` with CasADi's sparse LDL (code-generatable)."""
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", np_)
    sd, Mt, ht, zd = parts(x, t, p)
    return ca.Function("rhs", [x, t, p], [ca.vertcat(sd, ca.solve(Mt, ht, "ldl"), zd)],
                       ["x", "t", "p"], ["xdot"])
