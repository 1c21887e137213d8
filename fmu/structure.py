"""The FMUs' ``ModelStructure`` from the sparsity of the generated functions, never by hand.

Every output of the FMUs is ``fmu_outputs(x, t, p)`` (:func:`fmu.build.fmu_outputs`), with the
inputs (the four pitch controls) among the model parameters ``p``:

- ``<Outputs>``: output k depends directly on input j when ``d fmu_outputs[k] / d p[j]`` is
  structurally non-zero in any model of the family (CasADi's Jacobian sparsity); a state,
  an Euler angle or the energy depends on no input (``dependencies=""``), so a feedback loop
  through them is no algebraic loop. ``dependenciesKind`` is ``constant`` when that partial
  derivative itself depends on nothing (its row of the second-derivative sparsity is empty),
  else ``dependent``.
- ``<InitialUnknowns>``: every output at initialisation, ``fmu_outputs(x0, t0, p)``: the inputs
  and Real parameters in ``p`` it depends on (same sparsity), and, when it reads the state, the
  parameters that choose the initial state ``x0`` (``scene``, ``initial_state``; and
  ``initial_forward_speed`` when it reads the free body's velocity); ``dependent``.
"""
from __future__ import annotations

import numpy as np

START_CHOOSERS = ("scene", "initial_state")  # String parameters that select x0 (all of it)


def _pattern(sparsity) -> np.ndarray:
    """A CasADi sparsity as a dense boolean matrix."""
    out = np.zeros(sparsity.shape, dtype=bool)
    rows, cols = sparsity.get_triplet()
    out[rows, cols] = True
    return out


def sparsities(fmu_outputs) -> dict[str, np.ndarray]:
    """Boolean patterns of ``fmu_outputs(x, t, p)``: ``dp`` (ny, np), ``dx`` (ny, nx) and
    ``dp_varies`` (ny, np): where ``d y / d p`` itself depends on x, t or p."""
    import casadi as ca

    x, t, p = fmu_outputs.mx_in()
    jac = ca.jacobian(fmu_outputs(x, t, p), p)
    second = ca.Function("d_dp", [x, t, p], [jac])
    ny, n_p = jac.shape
    varies = np.zeros(ny * n_p, dtype=bool)
    for k in range(3):
        varies |= _pattern(second.sparsity_jac(k, 0)).any(axis=1)
    return {"dp": _pattern(fmu_outputs.sparsity_jac(2, 0)), "dx": _pattern(fmu_outputs.sparsity_jac(0, 0)),
            "dp_varies": varies.reshape(n_p, ny).T}  # CasADi vectorises column by column


def structure(spec: dict, groups: dict) -> dict:
    """``{"outputs": {name: [[input, kind], ...]}, "initial": {name: [[known, kind], ...]}}`` for
    every output of ``spec`` (a plan of :func:`fmu.build.plan`), over every model group
    ``groups[g] = (vm, functions)``; knowns in the order of the variables."""
    computed = [v for v in spec["variables"] if v["causality"] in ("output", "local")]
    order = {v["name"]: i for i, v in enumerate(spec["variables"])}
    direct: dict[str, dict] = {v["name"]: {} for v in computed if v["causality"] == "output"}
    initial: dict[str, dict] = {name: {} for name in direct}
    for vm, functions in groups.values():
        pattern = sparsities(functions["fmu_outputs"])
        _add_group(pattern, vm.info, computed, spec, direct, initial)
    by_order = lambda deps: sorted(([n, k] for n, k in deps.items()), key=lambda d: order[d[0]])  # noqa: E731
    return {"outputs": {n: by_order(d) for n, d in direct.items()},
            "initial": {n: by_order(d) for n, d in initial.items()}}


def _add_group(pattern: dict, info, computed: list[dict], spec: dict, direct: dict, initial: dict) -> None:
    """Add one model group's dependencies (``pattern`` of :func:`sparsities`) to ``direct`` and
    ``initial`` (name -> {known: kind})."""
    kinds = {v["name"]: v["causality"] for v in spec["variables"]}
    params = [p["name"] for p in info.parameters]
    velocity = _free_velocity(info)
    for k, v in enumerate(computed):
        name = v["name"]
        if name not in direct:
            continue
        for j in np.flatnonzero(pattern["dp"][k]):
            kind = "dependent" if pattern["dp_varies"][k, j] else "constant"
            if kinds.get(params[j]) == "input":
                direct[name][params[j]] = _worse(direct[name].get(params[j]), kind)
            if params[j] in kinds:
                initial[name][params[j]] = "dependent"
        reads = np.flatnonzero(pattern["dx"][k])
        for chooser in START_CHOOSERS if reads.size else ():
            if chooser in kinds:
                initial[name][chooser] = "dependent"
        if velocity & set(reads.tolist()) and "initial_forward_speed" in kinds:
            initial[name]["initial_forward_speed"] = "dependent"


def _worse(a: str | None, b: str) -> str:
    return "dependent" if "dependent" in (a, b) else b


def _free_velocity(info) -> set[int]:
    """Indices in x of the free body's linear velocity (what initial_forward_speed sets)."""
    free = [b for b in info.bodies if b["joint"] == "FreeJoint"]
    return {info.state_names.index(n) for b in free for n in b["v_names"][:3]}


def model_structure_xml(spec: dict):
    """``<ModelStructure>`` of the FMUs from ``spec["structure"]`` (indices: 1-based positions
    of the variables, which both FMUs write in the spec's order)."""
    from xml.etree import ElementTree as ET

    index = {v["name"]: str(k + 1) for k, v in enumerate(spec["variables"])}
    root = ET.Element("ModelStructure")
    for tag, key in (("Outputs", "outputs"), ("InitialUnknowns", "initial")):
        group = ET.SubElement(root, tag)
        for name, deps in spec["structure"][key].items():
            ET.SubElement(group, "Unknown", index=index[name], dependencies=" ".join(index[n] for n, _ in deps),
                          dependenciesKind=" ".join(kind for _, kind in deps))
    return root
