"""Benchmark subcommands: ``heli bench speed`` (and more to come)."""
from __future__ import annotations

from mbs.cli import add_json, emit


def cmd_bench_speed(args) -> int:
    from mbs.bench import speed

    res = speed.run()
    c = res["conservative_tree"]
    lines = [f"conservative tree {c['model']} ({c['nv']} DOF):",
             f"  compiled rhs          {c['compiled_rhs_us']:8.2f} µs (raw ctypes call)",
             f"  compiled rhs, checked {c['compiled_rhs_checked_us']:8.2f} µs (System.rhs)",
             f"  compiled RK4 step     {c['compiled_rk4_step_us']:8.2f} µs (one call), "
             f"{c['compiled_rk4_step_in_run_us']:.2f} µs inside a 1000-step run",
             f"  virtual machine rhs   {c['vm_rhs_us']:8.2f} µs"]
    if "pinocchio_aba_us" in c:
        lines += [f"  pinocchio.aba         {c['pinocchio_aba_us']:8.2f} µs",
                  f"  ratio rhs / aba       {c['ratio_rhs_to_aba']:8.2f}"]
    else:
        lines.append(f"  pinocchio: {c['pinocchio']}")
    emit(res, args.json, lines)
    return 0


def register(sub, bench) -> None:
    p = bench.add_parser("speed", help="right-hand side and RK4 step against Pinocchio")
    add_json(p)
    p.set_defaults(fn=cmd_bench_speed)
