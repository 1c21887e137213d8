"""The native FMU's model exchange and its exact derivatives, from the model's CasADi functions.

- Continuous states: the primary scene's states ``x`` in its order (``me_states``); their
  derivatives ``der(<state>)`` are ``rhs(x, t, p)``, the core's right-hand side.
- ``ad_fwd(x, t, p, dx, dp) -> J (dx, dp)`` and ``ad_adj(x, t, p, b) -> Jᵀ b``: CasADi's forward
  and reverse mode of ``(rhs, fmu_outputs)`` (rows: ``x'`` then every computed variable;
  columns: ``x`` then the model parameters ``p``, the inputs among them). The FMU answers
  ``fmiXGetDirectionalDerivative`` with one ``ad_fwd`` and ``fmi3GetAdjointDerivative`` with one
  ``ad_adj``: exact to round-off, never differences.
- ``ModelStructure`` of model exchange from the same functions' symbolic Jacobians: outputs and
  derivatives on the continuous states and inputs where the partial derivative is not the
  constant 0 (``dependenciesKind`` ``constant`` where it is another constant), the initial
  unknowns on the parameters that choose the start (:mod:`fmu.structure`).
"""
from __future__ import annotations

import numpy as np

from fmu import structure


def ad_functions(rhs, fmu_outputs) -> dict:
    """``{"ad_fwd", "ad_adj"}`` of the model ``rhs(x, t, p)`` and ``fmu_outputs(x, t, p)``."""
    import casadi as ca

    nx, n_p = rhs.size1_in(0), rhs.size1_in(2)
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", n_p)
    dx, dp = ca.MX.sym("dx", nx), ca.MX.sym("dp", n_p)
    f, z = ca.vertcat(rhs(x, t, p), fmu_outputs(x, t, p)), ca.vertcat(x, p)
    b = ca.MX.sym("b", f.numel())
    return {"ad_fwd": ca.Function("ad_fwd", [x, t, p, dx, dp], [ca.jtimes(f, z, ca.vertcat(dx, dp))],
                                  ["x", "t", "p", "dx", "dp"], ["d"]),
            "ad_adj": ca.Function("ad_adj", [x, t, p, b], [ca.jtimes(f, z, b, True)], ["x", "t", "p", "b"], ["bz"])}


def me_states(spec: dict, groups: dict) -> list[str]:
    """The continuous states: the primary scene's states in its order (each is a variable)."""
    vm = groups[spec["scenes"][spec["primary"]]["group"]][0]
    names = {v["name"] for v in spec["variables"]}
    missing = [s for s in vm.info.state_names if s not in names]
    if missing:
        raise ValueError(f"states {missing} of scene {spec['primary']!r} are not variables of the FMU")
    return list(vm.info.state_names)


def derivative_name(state: str) -> str:
    return f"der({state})"


def covers(vm, states: list[str]) -> bool:
    """Whether every state of the model ``vm`` is one of the continuous states."""
    return set(vm.info.state_names) <= set(states)


def _kinds(f) -> tuple[np.ndarray, np.ndarray]:
    """(pattern, varies) of ``f(x, t, p)`` with respect to ``(x, p)``, from its symbolic Jacobian
    (``f`` expanded to scalar expressions): an entry is a dependency unless it is the constant 0
    (CasADi folds ``d/dx ((x + a) - x)`` to 0, which sparsity propagation would still count: the
    fuselage position, on which nothing depends), and ``constant`` where it is a constant."""
    import casadi as ca

    try:
        f = f if f.is_a("SXFunction") else f.expand()
    except RuntimeError:  # a linear solve that has no scalar form: the propagated sparsity (a superset)
        return _propagated_kinds(f)
    x, t, p = f.sx_in()
    jac = ca.jacobian(f(x, t, p), ca.vertcat(x, p))
    pattern, varies = np.zeros(jac.shape, dtype=bool), np.zeros(jac.shape, dtype=bool)
    rows, cols = jac.sparsity().get_triplet()
    for r, c, entry in zip(rows, cols, jac.nonzeros()):
        pattern[r, c] = not entry.is_zero()
        varies[r, c] = not entry.is_constant()
    return pattern, varies


def _propagated_kinds(f) -> tuple[np.ndarray, np.ndarray]:
    """(pattern, varies) by sparsity propagation through ``f`` and its Jacobian."""
    import casadi as ca

    x, t, p = f.mx_in()
    jac = ca.jacobian(f(x, t, p), ca.vertcat(x, p))
    second = ca.Function("d_dz", [x, t, p], [jac])
    rows, cols = jac.shape
    varies = np.zeros(rows * cols, dtype=bool)
    for k in range(3):
        varies |= structure._pattern(second.sparsity_jac(k, 0)).any(axis=1)
    return structure._pattern(jac.sparsity()), varies.reshape(cols, rows).T


def _add(deps: dict, name: str, known: str, varies: bool) -> None:
    kind = "dependent" if varies else "constant"
    deps.setdefault(name, {})
    deps[name][known] = "dependent" if "dependent" in (deps[name].get(known), kind) else kind


def me_structure(spec: dict, groups: dict) -> dict:
    """``{"outputs", "derivatives", "initial_states"}``, each ``{name: [[known, kind], ...]}``:
    the outputs and state derivatives on the continuous states and inputs (union over the
    family's models), and the initial dependencies of the derivatives and of the states that
    are no outputs (the states that are outputs are in ``spec["structure"]["initial"]``)."""
    states = me_states(spec, groups)
    inputs = {v["name"] for v in spec["variables"] if v["causality"] == "input"}
    computed = [v["name"] for v in spec["variables"] if v["causality"] in ("output", "local")]
    outputs = [v["name"] for v in spec["variables"] if v["causality"] == "output"]
    direct: dict = {n: {} for n in outputs}
    direct.update({derivative_name(s): {} for s in states})
    for vm, functions in groups.values():
        info = vm.info
        knowns = list(info.state_names) + [p["name"] for p in info.parameters]
        for rows, f in ((computed, functions["fmu_outputs"]), ([derivative_name(s) for s in info.state_names],
                                                                 vm.functions["rhs"])):
            pattern, varies = _kinds(f)
            for i, j in zip(*np.nonzero(pattern)):
                if rows[i] in direct and (knowns[j] in inputs or j < info.nx):
                    _add(direct, rows[i], knowns[j], varies[i, j])
    order = {v["name"]: k for k, v in enumerate(spec["variables"])}
    ordered = lambda d: sorted(([n, k] for n, k in d.items()), key=lambda e: order[e[0]])  # noqa: E731
    return {"outputs": {n: ordered(direct[n]) for n in outputs},
            "derivatives": {s: ordered(direct[derivative_name(s)]) for s in states},
            "initial_states": _initial_states(spec, groups, states),
            "states": states}


def _initial_states(spec: dict, groups: dict, states: list[str]) -> dict:
    """Initial dependencies of every derivative and of the states that are no outputs: the
    parameters and inputs they read, and those that choose the initial state."""
    computed = [v for v in spec["variables"] if v["causality"] in ("output", "local")]
    locals_ = [s for s in states if next(v for v in spec["variables"] if v["name"] == s)["causality"] == "local"]
    direct = {n: {} for n in [*locals_, *map(derivative_name, states)]}
    initial = {n: {} for n in direct}
    for vm, functions in groups.values():
        as_outputs = [{**v, "causality": "output"} for v in computed]
        structure._add_group(structure.sparsities(functions["fmu_outputs"]), vm.info, as_outputs, spec, direct, initial)
        rows = [{"name": derivative_name(s), "causality": "output"} for s in vm.info.state_names]
        structure._add_group(structure.sparsities(vm.functions["rhs"]), vm.info, rows, spec, direct, initial)
    order = {v["name"]: k for k, v in enumerate(spec["variables"])}
    return {n: sorted(([k, "dependent"] for k in d), key=lambda e: order[e[0]]) for n, d in initial.items()}
