"""The model's symbolic functions, and the choice between the two forward-dynamics paths."""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs import tree as _tree
from mbs.dynamics._articulated import articulated
from mbs.dynamics._composite import composite, ldl_operations, solve
from mbs.dynamics._flexible import flexible_spatials
from mbs.dynamics._kinematics import Kinematics, kinematics, poses
from mbs.dynamics._layout import Layout
from mbs.dynamics._loads import applied, energy, mass_times, state_view
from mbs.dynamics._reactions import Reactions
from mbs.dynamics._spatial import body_spatial
from mbs.joints import Params

PATHS = {
    "composite": "Mt = J_uᵀ M J_u summed over subtrees, then CasADi's sparse LDL: O(n²) to O(n³) on a "
                 "chain, cheapest on shallow trees",
    "articulated": "articulated-body recursion over the AD's motion subspaces and velocity products: "
                   "O(n) for any tree",
}
"""The forward-dynamics paths (name -> description); :func:`symbolic` picks the one with
fewer operations unless told."""


@dataclass
class Symbolic:
    """The model's CasADi functions (all inputs dense column vectors).

    ``rhs(x, t, p) -> x'`` by ``path`` (a key of :data:`PATHS`),
    ``parts(x, t, p) -> (s', Mt, ht, z')`` (the composite path's ``Mt u' = ht``),
    ``kin(x, t, p) -> (V, J_u, H)``,
    ``energy(x, t, p) -> (T_trans, T_rot, V_grav, V_spring, E)`` in J,
    ``poses(x, t, p) -> (nb*12,)``: per body origin (3, m) and rotation matrix (9, row major),
    ``project(x) -> x`` back onto the manifold (unit quaternions),
    ``outputs(x, t, p) -> (n_outputs,)`` the model's named outputs.
    ``operations``: per path the floating-point operations of one right-hand side.
    """

    model: _tree.Model
    layout: Layout
    functions: dict[str, ca.Function]
    path: str = "composite"
    operations: dict[str, int] = field(default_factory=dict)

    def __getitem__(self, name: str) -> ca.Function:
        return self.functions[name]


def _ancestry(lay) -> np.ndarray:
    """(nb, nb): 1 where body ``j`` is body ``i`` or one of its ancestors."""
    index = {b.name: i for i, b in enumerate(lay.bodies)}
    out = np.zeros((len(index), len(index)))
    for i, b in enumerate(lay.bodies):
        name = b.name
        while name in index:
            out[i, index[name]] = 1.0
            name = lay.bodies[index[name]].parent
    return out


def _kin(lay, args, names, kin: Kinematics, spatial: dict) -> ca.Function:
    """``kin``: ``V`` and ``H`` from the AD and ``J_u`` (6 nb, nv) from each rate's twist:
    block ``(i, k)`` is body ``i``'s state map times ``ξ_k`` when ``b_k`` is ``b_i`` or one of
    its ancestors, formed by sparse products (compact code for any depth)."""
    maps = ca.diagcat(*[spatial[b.name].to_body_state for b in lay.bodies])
    twists = _placed(lay, spatial) if lay.sections() else ca.diagcat(*[spatial[b.name].twist for b in lay.bodies])
    blocks = ca.Function("kin_blocks", args, [kin.V, kin.H, maps, twists], names, ["V", "H", "maps", "twists"])
    mx = [ca.MX.sym(n, a.sparsity()) for n, a in zip(names, args)]
    v, h, m, xi = blocks(*mx)
    spread = ca.sparsify(ca.DM(np.kron(_ancestry(lay), np.eye(6))))
    return ca.Function("kin", mx, [v, ca.densify(ca.mtimes(m, ca.mtimes(spread, xi))), h], names, ["V", "Ju", "H"])


def choose(operations: dict[str, int], path: str | None) -> str:
    """``path`` when given (checked), else the path with fewer operations."""
    if path is None:
        return min(operations, key=operations.get)
    if path not in PATHS:
        raise ValueError(f"unknown dynamics path {path!r}; choose one of {', '.join(PATHS)}")
    return path


def symbolic(model: _tree.Model, path: str | None = None) -> Symbolic:
    """Build the symbolic equations of motion of ``model``; ``path`` forces one of
    :data:`PATHS` (default: the one with fewer operations). A model with dependent coordinates
    (:meth:`mbs.tree.Model.add_dependent`) takes the composite path on its full tree and keeps
    the independent coordinates (:mod:`mbs.dynamics._dependent`)."""
    if model.dependent:
        return _with_dependent(model, path)
    return _tree_symbolic(model, path)


def _with_dependent(model: _tree.Model, path: str | None) -> Symbolic:
    from mbs.dynamics import _dependent as dep

    if path == "articulated":
        raise ValueError(f"model {model.name!r} has dependent coordinates ({', '.join(model.dependent)}): the "
                         "articulated path takes no coordinate map; use the composite path")
    full = _tree_symbolic(model, "composite", full=True)
    dep.check(model, full.layout)
    embed, lay = dep.embedding(model, full)
    parts = dep.reduced_parts(full, embed, lay, len(model.parameters))
    rhs = solve(parts, lay.nx, len(model.parameters))
    fns = {"parts": parts, **dep.reduced_functions(full, embed, lay, rhs), "rhs": rhs}
    operations = {"composite": int(parts.n_instructions()) + ldl_operations(parts.sparsity_out(1))}
    return Symbolic(model, lay, fns, "composite", operations)


def _tree_symbolic(model: _tree.Model, path: str | None = None, full: bool = False) -> Symbolic:
    """The equations of the tree with every coordinate free; ``full``: the composite path and,
    besides, ``outputs_at(x, t, p, udot)`` whose reactions read given accelerations."""
    lay = Layout.of(model)
    x, t, p = ca.SX.sym("x", lay.nx), ca.SX.sym("t"), ca.SX.sym("p", len(model.parameters))
    s, u, z = x[:lay.nq], x[lay.nq:lay.nq + lay.nv], x[lay.nq + lay.nv:]
    params = Params(list(model.parameters), p)
    kin = kinematics(lay, s, u, t, params)
    state = state_view(lay, s, u, z, t, params, kin.motions, model.air)
    state.energy = energy(lay, model, state, kin.V)
    h, q, zdot = applied(lay, model, state)
    g = h - mass_times(lay, kin.H)
    r0 = kin.motions[lay.bodies[0].name].position
    spatial = {b.name: body_spatial(b, kin.motions[b.name], kin.own.get(b.name, ca.SX(6, 0)), g[kin.rows(i)], r0)
               for i, b in enumerate(lay.bodies)}
    args, names = [x, t, p], ["x", "t", "p"]
    mt, jtg = composite(lay, {**spatial, **flexible_spatials(lay, kin, spatial, g, u, r0)})
    parts = ca.Function("parts", args, [kin.sdot, mt, jtg + q, zdot], names, ["sdot", "Mt", "ht", "zdot"])
    operations = {"composite": int(parts.n_instructions()) + ldl_operations(mt.sparsity())}
    flexible = bool(lay.sections())  # their sections share rates, which the recursion does not take
    if flexible or full:
        udot = ca.SX.sym("udot", lay.nv)
        path = choose(operations, _rigid_only(path, model))
    else:
        udot = articulated(lay, spatial, q)
        recursion = ca.Function("rhs", args, [ca.vertcat(kin.sdot, udot, zdot)], names, ["xdot"])
        operations["articulated"] = int(recursion.n_instructions())
        path = choose(operations, path)
    rhs = recursion if path == "articulated" else solve(parts, lay.nx, len(model.parameters))
    project = ca.vertcat(*[b.joint.project(s[lay.q_slices[b.name]]) for b in lay.bodies], ca.SX(0, 1), u, z)
    state.reactions = Reactions(lay, spatial, udot, kin.motions, r0, s, u, t, params)
    outputs = ca.vertcat(*[o.fn(state) for o in model.outputs.values()], ca.SX(0, 1))
    fns = {
        "parts": parts,
        "kin": _kin(lay, args, names, kin, spatial),
        "energy": ca.Function("energy", args, [state.energy], names, ["energy"]),
        "outputs": _outputs(args, names, outputs, udot, rhs, lay) if flexible or full else
        ca.Function("outputs", args, [outputs], names, ["y"]),
        "poses": ca.Function("poses", args, [poses(lay, kin.motions)], names, ["poses"]),
        "project": ca.Function("project", [x], [project], ["x"], ["x_projected"]),
        "rhs": rhs,
    }
    if full:
        fns["outputs_at"] = ca.Function("outputs_at", args + [udot], [outputs], names + ["udot"], ["y"])
    return Symbolic(model, lay, fns, path, operations)


def _rigid_only(path: str | None, model) -> str | None:
    if path == "articulated":
        raise ValueError(f"model {model.name!r} has flexible bodies, whose sections share their modal rates: "
                         "the articulated path takes rigid bodies only; use the composite path")
    return path


def _placed(lay, spatial: dict) -> ca.SX:
    """Each body's twist (6, nk) in its rows and in the columns of the rates that move it
    (6 nb, nv): a section's in its flexible body's modal columns."""
    out = ca.SX(6 * len(lay.bodies), lay.nv)
    for i, b in enumerate(lay.bodies):
        if spatial[b.name].twist.shape[1]:
            out[6 * i:6 * i + 6, lay.v_slices[b.name]] = spatial[b.name].twist
    return out


def _outputs(args, names, outputs: ca.SX, udot: ca.SX, rhs: ca.Function, lay) -> ca.Function:
    """``outputs(x, t, p)`` whose joint reactions read the accelerations ``udot`` (a symbol)
    from the right-hand side (code-generatable)."""
    inner = ca.Function("outputs_at", args + [udot], [outputs])
    mx = [ca.MX.sym(n, a.sparsity()) for n, a in zip(names, args)]
    accelerations = rhs(*mx)[lay.nq:lay.nq + lay.nv]
    return ca.Function("outputs", mx, [inner(*mx, accelerations)], names, ["y"])
