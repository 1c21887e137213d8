"""``heli bench speed``: the project's evaluators against Pinocchio's ABA on one tree."""
from __future__ import annotations

import numpy as np

import mbs
from mbs.bench.timing import machine, median_time
from mbs.models.demo import spinning_rotor


def _pinocchio_aba(model, system, x):
    try:
        import pinocchio as pin

        from mbs.bench.pinocchio_ref import to_pinocchio
    except ImportError:
        return None, "pinocchio not installed (pip install pin)"
    pm, conv = to_pinocchio(model)
    data, q, v = pm.createData(), conv(x[:system.info.nq]), x[system.info.nq:].copy()
    tau = np.zeros(pm.nv)
    return (lambda: pin.aba(pm, data, q, v, tau)), pin.__version__


def conservative_tree_speed(n_blades: int = 4) -> dict:
    """Medians (µs) of one right-hand side and one RK4 step on a conservative rotor tree."""
    model = spinning_rotor(n_blades=n_blades, free_fuselage=True)
    model.forces.clear()  # Pinocchio's ABA gets no joint torques: compare the bare tree
    compiled, vm = mbs.build(model, "compiled"), mbs.build(model, "vm")
    x, h = compiled.x0(), 2 * np.pi / 44.4 / 100
    t, p = np.zeros(1), compiled.params()
    rhs_raw = compiled.function("rhs")
    rk4_raw = compiled.function("step_rk4")
    out = {"model": model.name, "nv": compiled.info.nv, "nx": compiled.info.nx,
           "compiled_rhs_us": 1e6 * median_time(lambda: rhs_raw(x, t, p)),
           "compiled_rhs_checked_us": 1e6 * median_time(lambda: compiled.rhs(x)),
           "compiled_rk4_step_us": 1e6 * median_time(lambda: rk4_raw(x, t, h, p)),
           "compiled_rk4_step_in_run_us": 1e6 * median_time(lambda: compiled.run(x, 0.0, h, 1000, every=1000)) / 1000,
           "vm_rhs_us": 1e6 * median_time(lambda: vm.functions["rhs"](x, 0.0, p)),
           "compile_s": compiled.info.extra.get("compile_s")}
    aba, version = _pinocchio_aba(model, compiled, x)
    if aba is not None:
        out["pinocchio_aba_us"] = 1e6 * median_time(aba)
        out["ratio_rhs_to_aba"] = out["compiled_rhs_us"] / out["pinocchio_aba_us"]
        accel = aba()
        out["max_rel_diff_to_pinocchio"] = float(np.abs(compiled.rhs(x)[compiled.info.nq:] - accel).max()
                                                 / np.abs(accel).max())
    out["pinocchio"] = version
    return out


def run() -> dict:
    return {"benchmark": "speed", "machine": machine(), "conservative_tree": conservative_tree_speed()}
