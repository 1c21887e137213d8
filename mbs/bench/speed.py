"""``heli bench speed``: the Bo105 scenes, and two conservative trees in three engines.

All figures are medians of raw calls in µs (see :func:`mbs.bench.timing.median_time`),
measured in one run. The conservative trees (the demo rotor and the Bo105 structural tree,
both without springs) are also built in Pinocchio (``pinocchio.aba``) and MuJoCo
(``mj_forward``); each reference is timed only after its accelerations were checked
against ours.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

import mbs
from mbs.bench.timing import machine, median_time
from mbs.models.demo import spinning_rotor
from mbs.tree import Model

BO105_SCENES = ("structural", "forward-flight", "hover", "ground-run", "single-blade")
STEPS_PER_REV = 100
AGREEMENT = 1e-8  # largest relative acceleration difference accepted before timing a reference


def _rel_diff(ours: np.ndarray, theirs: np.ndarray) -> float:
    return float(np.abs(ours - theirs).max() / np.abs(theirs).max())


def _pinocchio_aba(model, system, x):
    """``(call, version)``; ``call`` is None with the reason in ``version`` when unavailable."""
    try:
        import pinocchio as pin

        from mbs.bench.pinocchio_ref import to_pinocchio
    except ImportError:
        return None, "pinocchio not installed (pip install pin)"
    pm, conv = to_pinocchio(model)
    data, q, v = pm.createData(), conv(x[:system.info.nq]), x[system.info.nq:].copy()
    tau = np.zeros(pm.nv)
    return (lambda: pin.aba(pm, data, q, v, tau)), pin.__version__


def _mujoco_forward(model, x):
    """``(tree, version)`` with the state set; ``tree`` is None with the reason when unavailable."""
    try:
        import mujoco

        from mbs.bench.mujoco_ref import MujocoTree
    except ImportError as exc:
        return None, f"mujoco not importable ({exc}); pip install mujoco"
    tree = MujocoTree(model)
    tree.set_state(x)
    return tree, mujoco.__version__


def _add_reference(out: dict, key: str, call, accel: np.ndarray, ours: np.ndarray) -> None:
    """Check ``accel`` against ``ours``; time ``call`` only if they agree to ``AGREEMENT``."""
    diff = _rel_diff(ours, accel)
    out[f"max_rel_diff_to_{key}"] = diff
    if diff > AGREEMENT:
        out[f"{key}_error"] = f"accelerations differ by {diff:.1e} (relative) from ours: not timed"
        return
    out[f"{key}_us"] = 1e6 * median_time(call)
    out[f"ratio_rhs_to_{key}"] = out["compiled_rhs_us"] / out[f"{key}_us"]


def _ours(model, h: float) -> tuple[dict, object]:
    compiled, vm = mbs.build(model, "compiled"), mbs.build(model, "vm")
    x, t, p = compiled.x0(), np.zeros(1), compiled.params()
    rhs_raw, rk4_raw = compiled.function("rhs"), compiled.function("step_rk4")
    out = {"model": model.name, "nv": compiled.info.nv, "nx": compiled.info.nx,
           "compiled_rhs_us": 1e6 * median_time(lambda: rhs_raw(x, t, p)),
           "compiled_rhs_checked_us": 1e6 * median_time(lambda: compiled.rhs(x)),
           "compiled_rk4_step_us": 1e6 * median_time(lambda: rk4_raw(x, t, h, p)),
           "compiled_rk4_step_in_run_us": 1e6 * median_time(lambda: compiled.run(x, 0.0, h, 1000, every=1000)) / 1000,
           "vm_rhs_us": 1e6 * median_time(lambda: vm.functions["rhs"](x, 0.0, p)),
           "compile_s": compiled.info.extra.get("compile_s")}
    return out, compiled


def demo_tree(n_blades: int = 4) -> Model:
    """The demo rotor (free fuselage, free hub, flap and lag hinges) without its springs."""
    model = spinning_rotor(n_blades=n_blades, free_fuselage=True)
    model.forces.clear()  # the references get no joint torques: compare the bare tree
    return model


def bo105_tree() -> Model:
    """The Bo105 ``structural`` scene's tree (every joint free) without its springs."""
    from mbs import scenes

    model = scenes.get("structural").model()
    model.forces.clear()
    model.name += "-bare"
    return model


def conservative_tree_speed(model: Model | None = None, omega: float = 44.4) -> dict:
    """Medians (µs) of one right-hand side and one RK4 step (``STEPS_PER_REV`` steps per
    revolution at ``omega`` rad/s) on a conservative tree without force elements (default
    :func:`demo_tree`), and of the same tree's forward dynamics in Pinocchio (ABA) and
    MuJoCo (``mj_forward``), each checked against ours first."""
    model = demo_tree() if model is None else model
    if model.forces:
        raise ValueError(f"model {model.name!r} has force elements; the references need a bare tree")
    out, compiled = _ours(model, 2 * np.pi / omega / STEPS_PER_REV)
    x = compiled.x0()
    ours = compiled.rhs(x)[compiled.info.nq:]
    aba, out["pinocchio"] = _pinocchio_aba(model, compiled, x)
    if aba is not None:
        _add_reference(out, "pinocchio_aba", aba, aba(), ours)
    tree, out["mujoco"] = _mujoco_forward(model, x)
    if tree is not None:
        _add_reference(out, "mujoco_forward", tree.forward, tree.accelerations(x), ours)
    return out


def scene_speed(name: str, steps_per_rev: int = STEPS_PER_REV, run_steps: int = 200) -> dict:
    """One Bo105 scene, compiled, float64: DOF, rhs and RK4 step medians (µs) and the
    real-time factor (simulated time / wall time) at ``steps_per_rev`` steps per revolution,
    from the step time inside a C run of ``run_steps`` steps."""
    from mbs import scenes

    scene = scenes.get(name)
    system = scene.system("compiled")
    x, p, t = system.x0(), system.params(), np.zeros(1)
    h = scene.revolution(system, p) / steps_per_rev
    rhs_raw, rk4_raw = system.function("rhs"), system.function("step_rk4")
    traj = system.run(x, 0.0, h, run_steps, every=run_steps, p=p)
    if not traj.ok:
        raise RuntimeError(f"scene {name}: {traj.message}")
    in_run = median_time(lambda: system.run(x, 0.0, h, run_steps, every=run_steps, p=p)) / run_steps
    return {"scene": name, "dof": system.info.nv, "nx": system.info.nx, "h_s": h,
            "rhs_us": 1e6 * median_time(lambda: rhs_raw(x, t, p)),
            "rk4_step_us": 1e6 * median_time(lambda: rk4_raw(x, t, h, p)),
            "rk4_step_in_run_us": 1e6 * in_run, "real_time_factor": h / in_run}


def toolchain() -> dict:
    """Versions beyond :func:`mbs.bench.timing.machine`: the C compiler and the reference engines."""
    import importlib
    import subprocess

    from mbs.backends.compiled import CompilerNotFound, find_compiler

    out = {}
    try:
        cc = find_compiler()
        out["cc"] = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    except (CompilerNotFound, OSError, IndexError) as exc:
        out["cc"] = f"unavailable ({exc})"
    for name in ("pinocchio", "mujoco"):
        try:
            out[name] = importlib.import_module(name).__version__
        except ImportError:
            out[name] = "not installed"
    return out


def run(progress: Callable[[int, int], None] | None = None) -> dict:
    """Every measurement of ``heli bench speed`` in one run; ``progress(done, total)``."""
    rows, total = [], len(BO105_SCENES) + 2
    for i, name in enumerate(BO105_SCENES):
        rows.append(scene_speed(name))
        if progress:
            progress(i + 1, total)
    tree = conservative_tree_speed()
    if progress:
        progress(total - 1, total)
    bo105 = conservative_tree_speed(bo105_tree(), _bo105_omega())
    if progress:
        progress(total, total)
    return {"benchmark": "speed", "machine": {**machine(), **toolchain()}, "steps_per_rev": STEPS_PER_REV,
            "bo105": rows, "conservative_tree": tree, "bo105_tree": bo105}


def _bo105_omega() -> float:
    from mbs import scenes

    return scenes.get("structural").omega
