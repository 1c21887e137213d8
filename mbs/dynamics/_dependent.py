"""Dependent coordinates: joint coordinates that are functions of the others.

A model may declare a one-axis coordinate ``c_d = f(s, t, p)`` of the remaining coordinates
``s`` (:meth:`mbs.tree.Model.add_dependent`): a tail rotor geared to the main rotor's azimuth,
a blade's cyclic pitch following its hub's azimuth. The tree is built with every coordinate
free (the full layout: ``s_f``, ``u_f``); the state keeps the independent ones. Their map is

    u_f = G u + g,   G = ∂u_f/∂u,   u'_f = G u' + γ,   γ = ∂u_f/∂(s, t) · (s', 1)

with the dependent rates ``∂f/∂(s, t) · (s', 1)`` and ``γ`` by forward-mode AD. The full
equations ``Mt_f u'_f = ht_f`` (plus the constraint loads, which do no work) projected on the
independent rates give

    Gᵀ Mt_f G u' = Gᵀ (ht_f − Mt_f γ):

a generalized force on a dependent coordinate (an engine torque on a geared shaft, a spring)
reaches the state through ``Gᵀ``; energies, poses and outputs are the full model's at
``s_f(s)``, ``u_f``; joint reactions read ``u'_f``. Nothing is written by hand. The composite
path forms ``Mt_f``; the articulated recursion does not take a map ``G``.
"""
from __future__ import annotations

import casadi as ca

from mbs.backends.info import StateSizes
from mbs.dynamics._spatial import symmetric
from mbs.joints import Params


class DependentLayout(StateSizes):
    """The state of a model with dependent coordinates: the independent ``q_names``,
    ``v_names``, ``z_names``; ``bodies`` and ``full`` (the tree's :class:`Layout`)."""

    def __init__(self, full, dependent):
        self.full, self.bodies = full, full.bodies
        self.dependent = list(dependent)
        rates = {f"{n}_rate" for n in self.dependent}
        self.q_names = [n for n in full.q_names if n not in dependent]
        self.v_names = [n for n in full.v_names if n not in rates]
        self.z_names = list(full.z_names)

    def sections(self) -> dict:
        return self.full.sections()


def check(model, full) -> None:
    """ValueError naming a dependent coordinate that is not a one-axis coordinate of the tree."""
    for name in model.dependent:
        if name not in full.q_names or f"{name}_rate" not in full.v_names:
            raise ValueError(f"dependent coordinate {name!r} is not a one-axis joint coordinate of model "
                             f"{model.name!r} (its coordinates: {', '.join(full.q_names)})")


class _Coordinates:
    """Read-only coordinates by name for the dependent functions."""

    def __init__(self, values: dict):
        self._values = values

    def __getitem__(self, name: str):
        if name not in self._values:
            raise KeyError(f"unknown or not yet defined coordinate {name!r}; known: {sorted(self._values)}")
        return self._values[name]


def embedding(model, full_sym) -> tuple[ca.Function, DependentLayout]:
    """``embed(x, t, p) -> (x_f, G, gamma, s')`` (SX): the full state of the independent one,
    the rate map and the velocity-product accelerations of the full rates, the independent
    positions' rates."""
    full = full_sym.layout
    lay = DependentLayout(full, model.dependent)
    x, t, p = ca.SX.sym("x", lay.nx), ca.SX.sym("t"), ca.SX.sym("p", len(model.parameters))
    s, u, z = x[:lay.nq], x[lay.nq:lay.nq + lay.nv], x[lay.nq + lay.nv:]
    params = Params(list(model.parameters), p)
    values = {n: s[i] for i, n in enumerate(lay.q_names)}
    for name, fn in model.dependent.items():
        values[name] = fn(_Coordinates(dict(values)), t, params)
    s_f = ca.vertcat(*[values[n] for n in full.q_names])
    rates = {n: u[i] for i, n in enumerate(lay.v_names)}
    zero_dependent = ca.vertcat(*[rates.get(n, 0) for n in full.v_names])
    sdot_f = full_sym["parts"](ca.vertcat(s_f, zero_dependent, z), t, p)[0]
    sdot = ca.vertcat(*[sdot_f[full.q_names.index(n)] for n in lay.q_names])
    along = ca.vertcat(s, t), ca.vertcat(sdot, 1)
    for name in model.dependent:
        rates[f"{name}_rate"] = ca.jtimes(values[name], *along)
    u_f = ca.vertcat(*[rates[n] for n in full.v_names])
    g, gamma = ca.jacobian(u_f, u), ca.jtimes(u_f, *along)
    fn = ca.Function("embed", [x, t, p], [ca.vertcat(s_f, u_f, z), g, gamma, sdot], ["x", "t", "p"],
                     ["x_full", "G", "gamma", "sdot"])
    return fn, lay


def reduced_parts(full_sym, embed: ca.Function, lay: DependentLayout, n_params: int) -> ca.Function:
    """``parts(x, t, p) -> (s', Mt, ht, z')`` of the independent state: ``Gᵀ Mt_f G`` and
    ``Gᵀ (ht_f − Mt_f γ)``."""
    x, t, p = ca.SX.sym("x", lay.nx), ca.SX.sym("t"), ca.SX.sym("p", n_params)
    x_f, g, gamma, sdot = embed(x, t, p)
    _, mt_f, ht_f, zdot = full_sym["parts"](x_f, t, p)
    mt = symmetric(ca.mtimes([g.T, mt_f, g]))
    ht = ca.mtimes(g.T, ht_f - ca.mtimes(mt_f, gamma))
    return ca.Function("parts", [x, t, p], [sdot, ca.sparsify(mt), ht, zdot], ["x", "t", "p"],
                       ["sdot", "Mt", "ht", "zdot"])


def reduced_functions(full_sym, embed: ca.Function, lay: DependentLayout, rhs: ca.Function) -> dict:
    """``energy``, ``poses``, ``outputs``, ``project`` and ``kin`` of the independent state: the
    full model's at ``x_f`` (outputs with the full accelerations ``G u' + γ``, ``J_u`` times
    ``G`` and ``H + J_u γ``)."""
    f = full_sym.functions
    nx, n_params = lay.nx, f["parts"].size1_in(2)
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", n_params)
    x_f, g, gamma, _ = embed(x, t, p)
    udot = rhs(x, t, p)[lay.nq:lay.nq + lay.nv]
    v, j_f, h_f = f["kin"](x_f, t, p)
    keep = [full_sym.layout.q_names.index(n) for n in lay.q_names]
    full_nq = full_sym.layout.nq
    xs = ca.MX.sym("x", nx)
    projected = f["project"](embed(xs, 0, ca.DM.zeros(n_params))[0])
    rest = projected[full_nq:]
    free_rates = [full_sym.layout.v_names.index(n) for n in lay.v_names]
    names = ["x", "t", "p"]
    return {
        "energy": ca.Function("energy", [x, t, p], [f["energy"](x_f, t, p)], names, ["energy"]),
        "poses": ca.Function("poses", [x, t, p], [f["poses"](x_f, t, p)], names, ["poses"]),
        "outputs": ca.Function("outputs", [x, t, p], [f["outputs_at"](x_f, t, p, ca.mtimes(g, udot) + gamma)],
                               names, ["y"]),
        "project": ca.Function("project", [xs], [ca.vertcat(projected[keep], rest[free_rates],
                                                            rest[full_sym.layout.nv:])], ["x"], ["x_projected"]),
        "kin": ca.Function("kin", [x, t, p], [v, ca.mtimes(j_f, g), h_f + ca.mtimes(j_f, gamma)], names,
                           ["V", "Ju", "H"]),
    }
