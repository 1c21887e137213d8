"""``heli bench modal``: the elastic rotor with modal blades against the segmented chain.

Four Bo105 rotors on a driven hub with blade-element aerodynamics (the ``elastic-rotor``
family): rigid blades (reference), blades of 8 rigid segments (``elastic-rotor``, RK4 at its
300 steps per revolution), modal blades with one mode per direction (first frequencies as
accurate as the chain's or better, at 100 steps) and the ``elastic-rotor-modal`` scene (two
per direction, 120 steps). Per rotor: degrees of freedom, operations of one right-hand side,
the first flap, lag and torsion frequency errors against the continuous blade, the RK4 step
inside a 200-step C run (wall and CPU time), the real-time factor at its own steps per
revolution and at the chain's, the model's compile at its first build (``--fresh``: in an empty
cache folder, so this run compiles everything), and the wall time of the periodic trim (set-up:
building the model and its tangent step, compiled unless cached; solve) and of the Floquet
analysis at it.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from mbs.bench.timing import machine, median_time

CASES = (("rigid", "elastic-rotor", {"blade_segments": 0}, 100),
         ("chain-8", "elastic-rotor", {}, 300),
         ("modal-1-1-1", "elastic-rotor-modal", {"blade_modes": (1, 1, 1)}, 100),
         ("modal-2-2-2", "elastic-rotor-modal", {}, 120))
"""(row, scene, options, RK4 steps per revolution)."""


def _row(name: str, scene_name: str, options: dict, steps_per_rev: int) -> dict:
    from mbs import scenes
    from mbs.analysis.floquet import floquet
    from mbs.analysis.trim import evaluators, trim

    sc = scenes.get(scene_name)
    sc = replace(sc, name=f"{scene_name}-{name}", options={**sc.options, **options}, steps_per_rev=steps_per_rev)
    start = time.perf_counter()
    system, stepper = evaluators(sc)
    build_s = time.perf_counter() - start
    info, h = system.info, sc.revolution() / steps_per_rev
    x = system.x0()
    wall = median_time(lambda: system.run(x, 0.0, h, 200, every=200)) / 200
    cpu = median_time(lambda: system.run(x, 0.0, h, 200, every=200), clock=time.thread_time) / 200
    res = trim(sc, system=system, stepper=stepper)
    start = time.perf_counter()
    fl = floquet(sc, system=system, stepper=stepper)
    floquet_s = time.perf_counter() - start
    return {"rotor": name, "scene": scene_name, "options": {k: list(v) if isinstance(v, tuple) else v
                                                              for k, v in options.items()},
            "dof": info.nv, "operations": info.extra["operations"][info.extra["dynamics"]],
            "steps_per_rev": steps_per_rev, "rk4_step_us": 1e6 * wall, "rk4_step_cpu_us": 1e6 * cpu,
            "real_time_factor": h / wall, "real_time_factor_cpu": h / cpu,
            "real_time_factor_at_300": sc.revolution() / 300 / wall,
            "compile_s": info.extra.get("compile_s"), "trim_setup_s": build_s,
            "trim_solve_s": res.wall_s, "trim_iterations": res.iterations,
            "thrust": res.thrust, "floquet_s": floquet_s,
            "largest_multiplier": float(max(abs(m.multiplier) for m in fl.modes))}


def run() -> dict:
    """Every row of :data:`CASES` and the ratios to the chain's."""
    from mbs import aircraft
    from mbs.analysis.blade_modes import modal_frequencies, segmented_frequencies
    from mbs.flexible.uniform_blade import DIRECTIONS

    d = aircraft.load().data
    omega = d["main_rotor"]["omega"]
    targets = {k: d["elastic_blade"][f"{k}_frequency"] * omega for k in DIRECTIONS}
    rows = []
    for name, scene_name, options, steps in CASES:
        row = _row(name, scene_name, options, steps)
        if name.startswith("chain"):
            found = segmented_frequencies(8, d)
        elif name.startswith("modal"):
            found = modal_frequencies(options.get("blade_modes", (2, 2, 2)), d)
        else:
            found = {}
        row["frequency_errors"] = {k: found[k] / targets[k] - 1 for k in found}
        rows.append(row)
    chain = next(r for r in rows if r["rotor"].startswith("chain"))
    for r in rows:
        r["real_time_factor_over_chain"] = r["real_time_factor"] / chain["real_time_factor"]
        r["step_over_chain"] = r["rk4_step_us"] / chain["rk4_step_us"]
    return {"machine": machine(), "rows": rows}


def _lines(res: dict) -> list[str]:
    m = res["machine"]
    chain = next(r for r in res["rows"] if r["rotor"].startswith("chain"))["real_time_factor_cpu"]
    out = [f"machine: {m['cpu']}, {m['cores']} cores; python {m['python']}, casadi {m['casadi']}",
           "Bo105 elastic rotor, 4 blades, blade elements, uniform inflow (compiled C, float64):",
           f"  {'rotor':12} {'DOF':>4} {'ops':>6} {'first-frequency errors (flap, lag, torsion)':>44} "
           f"{'steps/rev':>9} {'RK4 µs':>8} {'RT x':>6} {'RT x/chain':>10} {'build s':>8} {'trim s':>12} "
           f"{'Floquet s':>9}"]
    for r in res["rows"]:
        err = r["frequency_errors"]
        errors = ", ".join(f"{100 * err[k]:+.2f} %" for k in ("flap", "lag", "torsion")) if err else "(rigid)"
        build = r["compile_s"]
        out.append(f"  {r['rotor']:12} {r['dof']:4d} {r['operations']:6d} {errors:>44} {r['steps_per_rev']:9d} "
                   f"{r['rk4_step_us']:8.2f} {r['real_time_factor']:6.1f} {r['real_time_factor_over_chain']:10.1f} "
                   f"{build if build is not None else float('nan'):8.1f} "
                   f"{r['trim_setup_s']:5.1f}+{r['trim_solve_s']:<6.1f} {r['floquet_s']:9.1f}")
    out.append("  (RT x: real-time factor at the rotor's steps per revolution, wall time of a step inside a 200-step "
               "C run; build: compile of the model at its first build; trim: set-up (the model and its tangent step, "
               "compiled unless cached) + solve; Floquet: trim and monodromy with both built)")
    out.append("  in CPU time: " + ", ".join(
        f"{r['rotor']} {r['rk4_step_cpu_us']:.1f} µs, {r['real_time_factor_cpu']:.1f}x real time "
        f"({r['real_time_factor_cpu'] / chain:.1f}x the chain's)" for r in res["rows"]))
    return out


def cmd_bench_modal(args) -> int:
    import os
    import tempfile

    from mbs.cli import emit

    if args.fresh:
        os.environ["MBS_CACHE_DIR"] = tempfile.mkdtemp(prefix="mbs-bench-modal-")
    res = run()
    res["fresh"] = bool(args.fresh)
    emit(res, args.json, _lines(res))
    return 0


def register(sub, bench) -> None:
    from mbs.cli import add_json

    p = bench.add_parser("modal", help="elastic rotor: modal blades against the 8-segment chain (step, real-time "
                                       "factor, build, trim and Floquet times, first-frequency errors)")
    p.add_argument("--fresh", action="store_true", help="compile every model and tangent step again in an empty "
                                                        "cache folder, so that build times are measured (minutes)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_modal)
