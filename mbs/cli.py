"""The ``heli`` command (also ``python -m mbs``).

Every subcommand prints human-readable lines; with ``--json`` the last line on stdout is
one JSON object with the figures. Progress bars go to stderr.
"""
from __future__ import annotations

import argparse
import json
import sys
from typing import Callable

COMMANDS: dict[str, Callable] = {}


def _emit(result: dict, as_json: bool, lines: list[str]) -> None:
    for line in lines:
        print(line)
    if as_json:
        print(json.dumps(result, default=float))


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
    _emit(res, args.json, lines)
    return 0


def cmd_demo(args) -> int:
    import numpy as np

    import mbs
    from mbs._progress import Progress
    from mbs.models.demo import spinning_rotor

    system = mbs.build(spinning_rotor(), args.backend)
    h = 2 * np.pi / 44.4 / 100
    traj = system.run(system.x0(), 0.0, h, 100 * args.revs, every=10, progress=Progress("demo", not args.json))
    e = np.array([system.energy(x)[-1] for x in traj.x])
    err = float(np.abs(e / e[0] - 1).max())
    res = {"model": system.info.name, "revs": args.revs, "steps": 100 * args.revs, "wall_s": traj.wall_s,
           "realtime_factor": traj.t[-1] / traj.wall_s, "max_rel_energy_error": err, "result": traj.result.name}
    _emit(res, args.json, [f"{system.info.name}: {args.revs} revolutions, RK4 at 100 steps/rev, "
                           f"{traj.wall_s:.3f} s wall ({res['realtime_factor']:.0f}x real time)",
                           f"max relative energy error {err:.2e}"])
    return 0 if traj.ok else 1


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="heli", description="Rotor multibody simulation (Bo105).")
    sub = ap.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="short simulation of a conservative demo rotor tree")
    demo.add_argument("--revs", type=int, default=10)
    demo.add_argument("--backend", choices=["compiled", "vm"], default="compiled")
    demo.add_argument("--json", action="store_true", help="print one JSON object last")
    demo.set_defaults(fn=cmd_demo)
    bench = sub.add_parser("bench", help="benchmarks").add_subparsers(dest="bench", required=True)
    speed = bench.add_parser("speed", help="right-hand side and RK4 step against Pinocchio")
    speed.add_argument("--json", action="store_true", help="print one JSON object last")
    speed.set_defaults(fn=cmd_bench_speed)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.fn(args)
    except (ValueError, RuntimeError, FileNotFoundError) as exc:
        print(f"heli: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
