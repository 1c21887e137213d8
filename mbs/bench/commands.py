"""Benchmark subcommands: ``heli bench speed`` (``heli bench scaling`` lives in mbs.bench.scaling)."""
from __future__ import annotations

from mbs.cli import add_json, emit


def _scene_lines(res: dict) -> list[str]:
    lines = [f"Bo105 scenes (compiled C, float64; RK4 at {res['steps_per_rev']} steps per main-rotor revolution):",
             f"  {'scene':15} {'DOF':>4} {'states':>6} {'rhs µs':>8} {'RK4 µs':>8} {'RK4 µs in run':>13} "
             f"{'real time x':>11}"]
    for r in res["bo105"]:
        lines.append(f"  {r['scene']:15} {r['dof']:4d} {r['nx']:6d} {r['rhs_us']:8.2f} {r['rk4_step_us']:8.2f} "
                     f"{r['rk4_step_in_run_us']:13.2f} {r['real_time_factor']:11.1f}")
    lines.append("  (rhs and RK4: one raw call from Python; in run: per step inside a 200-step C loop, "
                 "which sets the real-time factor)")
    t = res.get("tables")
    if t:
        lines.append(f"  {t['scene']}: the rotors' sections as C81 tables, {t['real_time_factor_cpu']:.1f}x real time "
                     f"in CPU time against {t['analytic_real_time_factor_cpu']:.1f}x analytic: RK4 step "
                     f"x{t['ratio_rk4_step_to_analytic']:.2f}; trim {t['trim_s']:.1f} s against "
                     f"{t['analytic_trim_s']:.1f} s (Newton, {t['trim_iterations']} and {t['analytic_trim_iterations']} "
                     f"iterations): x{t['ratio_trim_to_analytic']:.2f}, with its set-up {t['trim_with_setup_s']:.1f} s "
                     f"against {t['analytic_trim_with_setup_s']:.1f} s: x{t['ratio_trim_with_setup_to_analytic']:.2f} "
                     f"(medians of {t['repeats']} interleaved runs)")
    return lines


def _engine_line(label: str, us: float | None, ratio: float | None, diff: float | None) -> str:
    us_s = f"{us:9.2f}" if us is not None else f"{'-':>9}"
    ratio_s = f"{ratio:13.2f}" if ratio is not None else f"{'':13}"
    diff_s = f"{diff:15.1e}" if diff is not None else ""
    return f"  {label:36} {us_s} {ratio_s} {diff_s}"


def _tree_lines(c: dict, what: str) -> list[str]:
    lines = [f"{what} {c['model']} ({c['nv']} DOF, no springs), one forward dynamics call:",
             f"  {'engine':36} {'µs':>9} {'ours / them':>13} {'max rel. diff':>15}",
             _engine_line("ours, compiled C (raw ctypes call)", c["compiled_rhs_us"], None, None),
             _engine_line("ours, compiled C (bound call)", c.get("compiled_rhs_bound_us"), None, None),
             _engine_line("ours, compiled C via System.rhs", c["compiled_rhs_checked_us"], None, None),
             _engine_line("ours, CasADi virtual machine", c["vm_rhs_us"], None, None)]
    for key, name, fn in (("pinocchio_aba", "pinocchio", "pinocchio.aba"),
                          ("mujoco_forward", "mujoco", "mujoco.mj_forward")):
        label = f"{fn} {c[name]}" if f"max_rel_diff_to_{key}" in c else fn
        lines.append(_engine_line(label, c.get(f"{key}_us"), c.get(f"ratio_rhs_to_{key}"),
                                  c.get(f"max_rel_diff_to_{key}")))
        if f"max_rel_diff_to_{key}" not in c:
            lines.append(f"    {fn}: {c[name]}")
        elif f"{key}_error" in c:
            lines.append(f"    {fn}: {c[f'{key}_error']}")
    lines.append(f"  RK4 step, ours: {c['compiled_rk4_step_us']:.2f} µs (one call), "
                 f"{c['compiled_rk4_step_in_run_us']:.2f} µs inside a 1000-step run")
    if "mujoco_rk4_step_us" in c:
        lines.append(f"  RK4 step, MuJoCo: {c['mujoco_rk4_step_us']:.2f} µs (one mj_step), "
                     f"{c['mujoco_rk4_step_in_run_us']:.2f} µs inside mj_step(nstep=1000); ours / MuJoCo "
                     f"{c['ratio_rk4_step_to_mujoco']:.2f} and {c['ratio_rk4_step_in_run_to_mujoco']:.2f}")
    if "scene_real_time_factor" in c:
        lines.append(f"  the scene with aerodynamics, RK4 at {c['steps_per_rev']} steps/rev: rhs {c['scene_rhs_us']:.2f} µs, "
                     f"{c['scene_rk4_step_in_run_us']:.2f} µs per step in a run, {c['scene_real_time_factor']:.1f}x real time "
                     f"({c['scene_real_time_factor_cpu']:.1f}x in CPU time)")
    lines.append(f"  {c.get('dynamics', '?')} path, {c.get('operations', 0)} operations; first build: "
                 f"code generation {c.get('codegen_s') or 0:.1f} s, compile {c.get('compile_s') or 0:.1f} s")
    return lines


def cmd_bench_speed(args) -> int:
    from mbs._progress import Progress
    from mbs.bench import speed

    res = speed.run(Progress("speed"))
    m = res["machine"]
    lines = [f"machine: {m['cpu']}, {m['cores']} cores; python {m['python']}, numpy {m['numpy']}, "
             f"casadi {m['casadi']}, {m['cc']}", *_scene_lines(res),
             *_tree_lines(res["conservative_tree"], "conservative tree"),
             *_tree_lines(res["bo105_tree"], "Bo105 structural tree"),
             *[line for c in res.get("trees", []) for line in _tree_lines(c, c["row"])]]
    emit(res, args.json, lines)
    return 0


def register(sub, bench) -> None:
    p = bench.add_parser("speed", help="Bo105 scenes, and one tree against Pinocchio and MuJoCo")
    add_json(p)
    p.set_defaults(fn=cmd_bench_speed)
