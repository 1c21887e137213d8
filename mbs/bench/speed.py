"""``heli bench speed``: the Bo105 scenes, and conservative trees in three engines.

All figures are medians of raw calls in µs (see :func:`mbs.bench.timing.median_time`),
measured in one run. The conservative trees, shallow (the demo rotor and the Bo105
structural tree, both without springs), deep (:data:`DEEP_TREES`: chains of 40 and 100
links) and the elastic rotor's (:func:`elastic_rotor_speed`), are also built in Pinocchio (``pinocchio.aba``) and MuJoCo (``mj_forward``, and its
RK4 step); each reference is timed only after its accelerations were checked against ours.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

import time

import numpy as np

from mbs.bench.timing import machine, median_time, toolchain
from mbs.models.demo import spinning_rotor
from mbs.tree import Model

BO105_SCENES = ("structural", "forward-flight", "hover", "ground-run", "single-blade")
STEPS_PER_REV = 100
AGREEMENT = 1e-8  # largest relative acceleration difference accepted before timing a reference
DEEP_TREES = {"chain40": 40, "chain100": 100}
"""Rows of deep trees: name -> links of :func:`mbs.bench.scaling.chain`."""
CHAIN_STEP = 1e-3  # s, the RK4 step of the chains, ours and MuJoCo's
RUN_STEPS = 1000  # steps of one C run (ours) and of one mj_step call (MuJoCo)


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


def _mujoco_tree(model, x):
    """``(tree, version)`` with the state set; ``tree`` is None with the reason when unavailable."""
    try:
        import mujoco

        from mbs.bench.mujoco_ref import MujocoTree
    except ImportError as exc:
        return None, f"mujoco not importable ({exc}); pip install mujoco"
    tree = MujocoTree(model)
    tree.set_state(x)
    return tree, mujoco.__version__


def _add_reference(out: dict, key: str, call, accel: np.ndarray, ours: np.ndarray) -> bool:
    """Check ``accel`` against ``ours``; time ``call`` only if they agree to ``AGREEMENT``."""
    diff = _rel_diff(ours, accel)
    out[f"max_rel_diff_to_{key}"] = diff
    if not diff <= AGREEMENT:  # NaN included
        out[f"{key}_error"] = f"accelerations differ by {diff:.1e} (relative) from ours: not timed"
        return False
    out[f"{key}_us"] = 1e6 * median_time(call)
    out[f"ratio_rhs_to_{key}"] = out["compiled_rhs_us"] / out[f"{key}_us"]
    out[f"ratio_bound_rhs_to_{key}"] = out["compiled_rhs_bound_us"] / out[f"{key}_us"]
    return True


def _add_mujoco_rk4(out: dict, tree, x, h: float) -> None:
    """MuJoCo's RK4 step at ``h`` from our state ``x``: per step of ``mj_step(nstep=RUN_STEPS)``
    and of one ``mj_step``, against ours inside a C run and in one call."""
    tree.use_rk4(h)

    def run():
        tree.set_state(x)
        tree.mj.mj_step(tree.m, tree.d, RUN_STEPS)
    out["mujoco_rk4_step_in_run_us"] = 1e6 * median_time(run) / RUN_STEPS
    tree.set_state(x)
    out["mujoco_rk4_step_us"] = 1e6 * median_time(tree.step)
    out["ratio_rk4_step_in_run_to_mujoco"] = out["compiled_rk4_step_in_run_us"] / out["mujoco_rk4_step_in_run_us"]
    out["ratio_rk4_step_to_mujoco"] = out["compiled_rk4_step_us"] / out["mujoco_rk4_step_us"]


def _build(model) -> tuple[object, object, float]:
    """``(compiled, vm, codegen_s)``: symbolic build and C generation timed; the compile is
    cached (its time, measured at the first build, is the library's ``compile_s``)."""
    from mbs.backends.compiled import CompiledSystem, compile_source, generate
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic

    start = time.perf_counter()
    vm = VMSystem(symbolic(model))
    source = generate(vm.functions, vm.info, "float64")
    codegen_s = time.perf_counter() - start
    return CompiledSystem(compile_source(source, vm.info)), vm, codegen_s


def _ours(model, h: float) -> tuple[dict, object]:
    compiled, vm, codegen_s = _build(model)
    x, t, p = compiled.x0(), np.zeros(1), compiled.params()
    rhs_raw, rk4_raw, bound = compiled.function("rhs"), compiled.function("step_rk4"), compiled.bind("rhs")
    for buf, v in zip(bound.inputs, (x, t, p)):
        buf[:] = v
    info = compiled.info.extra
    out = {"model": model.name, "nv": compiled.info.nv, "nx": compiled.info.nx, "dynamics": info["dynamics"],
           "operations": info["operations"][info["dynamics"]],
           "compiled_rhs_us": 1e6 * median_time(lambda: rhs_raw(x, t, p)),
           "compiled_rhs_bound_us": 1e6 * median_time(bound),
           "compiled_rhs_checked_us": 1e6 * median_time(lambda: compiled.rhs(x)),
           "compiled_rk4_step_us": 1e6 * median_time(lambda: rk4_raw(x, t, h, p)),
           "compiled_rk4_step_in_run_us": 1e6 * median_time(
               lambda: compiled.run(x, 0.0, h, RUN_STEPS, every=RUN_STEPS)) / RUN_STEPS,
           "vm_rhs_us": 1e6 * median_time(lambda: vm.functions["rhs"](x, 0.0, p)),
           "h_s": h, "codegen_s": codegen_s, "compile_s": info.get("compile_s"), "cflags": info.get("cflags")}
    return out, compiled


def demo_tree(n_blades: int = 4) -> Model:
    """The demo rotor (free fuselage, free hub, flap and lag hinges) without its springs."""
    model = spinning_rotor(n_blades=n_blades, free_fuselage=True)
    model.forces.clear()  # the references get no joint torques: compare the bare tree
    return model


def bo105_tree() -> Model:
    """The Bo105 ``structural`` scene's tree (every joint free) without its springs, its fuselage
    carrying the published whole-aircraft inertia: the airframe left after the rotors breaks the
    triangle inequality by 372 kg m² (``aircraft check`` warns of it), and MuJoCo refuses a body
    that does."""
    from mbs import scenes
    from mbs.aircraft import mass

    model = scenes.get("structural").model()
    model.forces.clear()
    model.bodies["fuselage"].inertia = mass.published_inertia(scenes.get("structural").aircraft.data)
    model.name += "-bare"
    return model


def conservative_tree_speed(model: Model | None = None, omega: float = 44.4, h: float | None = None) -> dict:
    """Medians (µs) of one right-hand side and one RK4 step (step ``h``, default
    ``STEPS_PER_REV`` steps per revolution at ``omega`` rad/s) on a conservative tree without
    force elements (default :func:`demo_tree`), and of the same tree's forward dynamics in
    Pinocchio (ABA) and MuJoCo (``mj_forward``, and MuJoCo's RK4 step), each checked against
    ours first."""
    model = demo_tree() if model is None else model
    if model.forces:
        raise ValueError(f"model {model.name!r} has force elements; the references need a bare tree")
    out, compiled = _ours(model, 2 * np.pi / omega / STEPS_PER_REV if h is None else h)
    x = compiled.x0()
    ours = compiled.rhs(x)[compiled.info.nq:]
    aba, out["pinocchio"] = _pinocchio_aba(model, compiled, x)
    if aba is not None:
        _add_reference(out, "pinocchio_aba", aba, aba(), ours)
    tree, out["mujoco"] = _mujoco_tree(model, x)
    if tree is not None and _add_reference(out, "mujoco_forward", tree.forward, tree.accelerations(x), ours):
        _add_mujoco_rk4(out, tree, x, out["h_s"])
    return out


def elastic_rotor_speed(steps_per_rev: int = 200) -> dict:
    """Row ``elastic-rotor``: the scene (4 blades of 8 segments, aerodynamics on) at
    ``steps_per_rev`` RK4 steps per revolution (``scene_`` entries, its real-time factor),
    and its tree with free hub and pitch hinges, without springs and aerodynamics, in the
    three engines (:func:`conservative_tree_speed` at the same step; no pitch hinge: a free one
    would turn about the root torsion hinge's axis)."""
    from dataclasses import replace

    from mbs.models import helicopter
    from mbs.models.helicopter.scenes import ELASTIC_ROTOR

    bare = helicopter.build(replace(ELASTIC_ROTOR, rotors="free", pitch_hinge=False, rotor_aero=False),
                            name="elastic-rotor-bare")
    bare.forces.clear()
    scene = scene_speed("elastic-rotor", steps_per_rev)
    tree = conservative_tree_speed(bare, h=scene["h_s"])
    return {"row": "elastic-rotor", **tree, "steps_per_rev": steps_per_rev,
            **{f"scene_{k}": v for k, v in scene.items() if k not in ("scene", "h_s")}}


def deep_tree_speed(name: str) -> dict:
    """One row of :data:`DEEP_TREES` (:func:`conservative_tree_speed` of the chain, RK4 at
    ``CHAIN_STEP``), named ``row``."""
    from mbs.bench.scaling import chain

    return {"row": name, **conservative_tree_speed(chain(DEEP_TREES[name]), h=CHAIN_STEP)}


def fuselage_tables_speed() -> dict:
    """:func:`scene_speed` of forward flight with the Bo105's fuselage polynomials sampled as
    tables every 5 deg over ±90 deg (:func:`mbs.aircraft.template.with_polynomial_tables`)."""
    import tempfile

    from mbs import scenes
    from mbs.aircraft.template import with_polynomial_tables

    with tempfile.TemporaryDirectory() as tmp:
        scene = scenes.get("forward-flight").with_aircraft(str(with_polynomial_tables("bo105", tmp)))
        return {**scene_speed(scene), "scene": "forward-flight, fuselage tables"}


def scene_speed(name, steps_per_rev: int = STEPS_PER_REV, run_steps: int = 200) -> dict:
    """One Bo105 scene, compiled, float64: DOF, rhs and RK4 step medians (µs) and the
    real-time factor (simulated time / wall time) at ``steps_per_rev`` steps per revolution,
    from the step time inside a C run of ``run_steps`` steps; ``_cpu``: the same from the
    CPU time of the run (other jobs on the machine do not count)."""
    from mbs import scenes

    scene = scenes.get(name) if isinstance(name, str) else name
    name = scene.name
    system = scene.system("compiled")
    x, p, t = system.x0(), system.params(), np.zeros(1)
    h = scene.revolution(system, p) / steps_per_rev
    rhs_raw, rk4_raw = system.function("rhs"), system.function("step_rk4")
    traj = system.run(x, 0.0, h, run_steps, every=run_steps, p=p)
    if not traj.ok:
        raise RuntimeError(f"scene {name}: {traj.message}")
    def run():
        system.run(x, 0.0, h, run_steps, every=run_steps, p=p)
    in_run, in_run_cpu = (median_time(run, clock=c) / run_steps for c in (time.perf_counter, time.thread_time))
    return {"scene": scene.name, "dof": system.info.nv, "nx": system.info.nx, "h_s": h,
            "compile_s": system.info.extra.get("compile_s"), "rhs_us": 1e6 * median_time(lambda: rhs_raw(x, t, p)),
            "rk4_step_us": 1e6 * median_time(lambda: rk4_raw(x, t, h, p)),
            "rk4_step_in_run_us": 1e6 * in_run, "real_time_factor": h / in_run,
            "rk4_step_in_run_cpu_us": 1e6 * in_run_cpu, "real_time_factor_cpu": h / in_run_cpu}


TABLES_REPEATS = 3
"""Runs of each variant in the row ``forward-flight-tables``, interleaved (tables, analytic, ...)."""


def tables_speed(repeats: int = TABLES_REPEATS) -> dict:
    """Row ``forward-flight-tables``: the forward-flight scene of a Bo105 whose rotors' sections
    are C81 tables (91 angles x 12 Mach numbers, sampled from its analytic sections with their
    compressibility corrections; :func:`mbs.aero.tables.sample.with_sampled_tables`) against the
    analytic scene, both measured here, interleaved ``repeats`` times (other jobs on the machine
    then load both alike): the tables' :func:`scene_speed` of the median run, its RK4 step and
    real-time factor over the analytic scene's (CPU time, medians), and the trims' times (s, wall,
    medians, :func:`_trim_times`: Newton alone and with the set-up) and their ratios."""
    import tempfile
    from pathlib import Path

    from mbs import aircraft, scenes
    from mbs.aero.tables.sample import with_sampled_tables

    base = scenes.get("forward-flight")
    with tempfile.TemporaryDirectory() as folder:
        craft = with_sampled_tables(aircraft.load(), Path(folder))
        tabled = replace(base.with_aircraft(craft), name="forward-flight-tables")
        runs = [[scene_speed(sc) for sc in (tabled, base)] for _ in range(repeats)]
        trims = _trim_times((tabled, base), repeats)
    step = [float(np.median([r[k]["rk4_step_in_run_cpu_us"] for r in runs])) for k in range(2)]
    tables = sorted((r[0] for r in runs), key=lambda r: r["rk4_step_in_run_cpu_us"])[len(runs) // 2]
    h = float(tables["h_s"])
    return {**tables, "rk4_step_in_run_cpu_us": step[0], "real_time_factor_cpu": h / step[0] * 1e6,
            "analytic_rk4_step_in_run_cpu_us": step[1], "ratio_rk4_step_to_analytic": step[0] / step[1],
            "analytic_real_time_factor_cpu": h / step[1] * 1e6, "repeats": repeats,
            "trim_s": trims[0]["newton_s"], "analytic_trim_s": trims[1]["newton_s"],
            "ratio_trim_to_analytic": trims[0]["newton_s"] / trims[1]["newton_s"],
            "trim_with_setup_s": trims[0]["total_s"], "analytic_trim_with_setup_s": trims[1]["total_s"],
            "ratio_trim_with_setup_to_analytic": trims[0]["total_s"] / trims[1]["total_s"],
            "trim_iterations": trims[0]["iterations"], "analytic_trim_iterations": trims[1]["iterations"]}


def _trim_times(scenes: tuple, repeats: int) -> list[dict]:
    """For each scene, medians over ``repeats`` trims (the scenes' trims interleaved): the wall time
    (s) of the Newton iterations and of the whole trim with its set-up (the evaluators built from
    the scene, their libraries found in the cache), and the iterations of the last. Each scene's
    libraries are built (compiled when not cached) once before, not counted."""
    from mbs.analysis.trim import evaluators, trim

    for sc in scenes:
        evaluators(sc)
    times: list[dict] = [{"newton_s": [], "total_s": []} for _ in scenes]
    last = [None] * len(scenes)
    for _ in range(repeats):
        for k, sc in enumerate(scenes):
            start = time.perf_counter()
            system, stepper = evaluators(sc)
            last[k] = trim(sc, system=system, stepper=stepper)
            if not last[k].converged:
                raise RuntimeError(f"scene {sc.name}: the trim did not converge: {last[k].reason}")
            times[k]["newton_s"].append(last[k].wall_s)
            times[k]["total_s"].append(time.perf_counter() - start)
    return [{**{key: float(np.median(v)) for key, v in t.items()}, "iterations": r.iterations}
            for t, r in zip(times, last)]


def run(progress: Callable[[int, int], None] | None = None) -> dict:
    """Every measurement of ``heli bench speed`` in one run; ``progress(done, total)``."""
    jobs = [*((lambda n=n: scene_speed(n)) for n in BO105_SCENES), fuselage_tables_speed, conservative_tree_speed,
            lambda: conservative_tree_speed(bo105_tree(), _bo105_omega()),
            *((lambda n=n: deep_tree_speed(n)) for n in DEEP_TREES), elastic_rotor_speed, tables_speed]
    done = []
    for job in jobs:
        done.append(job())
        if progress:
            progress(len(done), len(jobs))
    n = len(BO105_SCENES) + 1
    return {"benchmark": "speed", "machine": {**machine(), **toolchain()}, "steps_per_rev": STEPS_PER_REV,
            "bo105": done[:n], "conservative_tree": done[n], "bo105_tree": done[n + 1], "trees": done[n + 2:-1],
            "tables": done[-1]}


def _bo105_omega() -> float:
    from mbs import scenes

    return scenes.get("structural").omega
