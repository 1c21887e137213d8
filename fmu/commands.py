"""``heli`` subcommands of the FMU: ``fmu build``, ``demo`` and ``bench fmu``."""
from __future__ import annotations

import sys
from pathlib import Path

from mbs import arguments as A
from mbs import atomic
from mbs.cli import add_json, emit


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def cmd_fmu_build(args) -> int:
    from fmu import build

    if args.fmi and not args.native:
        raise ValueError(f"--fmi {args.fmi} needs --native: the pythonfmu FMU (and the controller FMU) is FMI 2.0 "
                         "co-simulation only")
    scenes = tuple(args.scenes.split(",")) if args.scenes else build.DEFAULT_SCENES
    if args.controller:
        from fmu.controller import NAME, ensure_controller_fmu

        scenes = (NAME,)
        path, seconds = ensure_controller_fmu(force=args.force, log=_log, aircraft=args.aircraft)
    elif args.native:
        from fmu.native.build import ensure_native_fmu

        path, seconds = ensure_native_fmu(scenes, force=args.force, log=_log, aircraft=args.aircraft, fmi=args.fmi or 2)
    else:
        path, seconds = build.ensure_fmu(scenes, force=args.force, log=_log, aircraft=args.aircraft)
    dest = args.out / path.name if args.out.suffix != ".fmu" else args.out
    try:
        atomic.copy(path, dest)
    except OSError as exc:
        raise ValueError(f"cannot write the FMU to {dest}: {dest.parent} is not a writable folder "
                         f"({exc.strerror or exc}); choose another --out") from None
    res = {"fmu": str(dest), "cached": str(path), "scenes": list(scenes),
           "aircraft": args.aircraft.name if args.aircraft else "MBB Bo105", "build_s": seconds,
           "size_bytes": dest.stat().st_size}
    how = f"built in {seconds:.1f} s" if seconds else "from the cache"
    emit(res, args.json, [f"{dest} ({dest.stat().st_size / 1e6:.2f} MB, scenes {', '.join(scenes)}; {how})"])
    return 0


def cmd_demo(args) -> int:
    from fmu import demo

    res = demo.run(Path(args.out), args.revs, log=_log, aircraft=args.aircraft)
    lines = [f"{res['scene']}: {res['revs']:g} revolutions through the FMU under fmpy from its periodic trim "
             f"(communication step {res['communication_step_s'] * 1e3:.3f} ms; {res['inputs_seen']})",
             f"FMU: {res['fmu_cached']} ({'built in %.1f s' % res['build_s'] if res['build_s'] else 'from the cache'})",
             f"fmpy run: {res['fmpy_wall_s']:.2f} s wall for {res['simulated_s']:.3f} s simulated "
             f"({res['realtime_factor']:.1f}x real time); total {res['total_s']:.1f} s",
             *[f"wrote {p}" for p in res["files"].values()]]
    emit(res, args.json, lines)
    return 0


def cmd_bench_fmu(args) -> int:
    from fmu.bench import speed

    res = speed.run(args.revs, args.repeats)
    us, usc = res["us_per_step"], res["us_per_step_cpu"]
    rows = [("fmpy.simulate_fmu", "fmpy"), ("  first call in process", "fmpy_cold"),
            ("fmpy loop (FMU2Slave)", "fmpy_loop"), ("core directly", "core"),
            ("native FMU, fmpy", "fmpy_native"), ("native FMU, C host", "c_host"),
            ("  reading hinge states", "c_host_states")]
    lines = [f"{res['scene']}: {res['revs']:g} revolutions, communication step 1/100 rev "
             f"({res['communication_step_s'] * 1e3:.3f} ms), median of {res['repeats']} fresh processes, "
             f"load average {res['load_average'][0]:.1f}",
             f"  {'':24s} {'real-time factor':>18s} {'µs/step':>9s}   (CPU time: factor, µs/step)"]
    lines += [f"  {label:24s} {res['realtime_factor_' + k]:17.1f}x {us[k]:9.1f}   "
              f"({res['realtime_factor_' + k + '_cpu']:.1f}x, {usc[k]:.1f})" for label, k in rows]
    lines += [f"  FMU overhead ratio (core / fmpy): {res['overhead_ratio']:.2f} (CPU time {res['overhead_ratio_cpu']:.2f})",
              f"  target fmpy >= 10x real time: {'met' if res['meets_target'] else 'NOT met'}",
              f"  native: C host / core time per step {res['c_host_over_core']:.2f} (CPU time "
              f"{res['c_host_over_core_cpu']:.2f}; hinge states only {res['c_host_states_over_core']:.2f})",
              f"  targets C host <= 1.2x core, fmpy >= 30x real time: "
              f"{'met' if res['meets_native_targets'] else 'NOT met'}"]
    emit(res, args.json, lines)
    return 0


def cmd_cosim(args) -> int:
    import math

    from fmu import cosim
    from mbs import aircraft

    step = 2 * math.pi / abs((args.aircraft or aircraft.load()).omega) / 100
    if args.stop < step:
        raise ValueError(f"--stop {args.stop:g} s is less than one communication step ({step * 1e3:.3g} ms, 1/100 of "
                         f"a revolution); give --stop {step:.3g} or more")
    res = cosim.run(Path(args.out), args.stop, log=_log, aircraft=args.aircraft)
    c, o = res["closed"], res["open"]

    def when(key: str) -> str:
        return f"at {o[key]:.2f} s" if o[key] is not None else f"not within the {res['stop_s']:g} s run"

    name = args.aircraft.name if args.aircraft else "MBB Bo105"
    lines = [f"{name}, hover, 1 m/s initial disturbance, {res['stop_s']:g} s in steps of {res['step_s'] * 1e3:.6f} ms "
             f"({res['steps']} steps)",
             f"closed loop: attitude within {c['max_attitude_deg']:.2f} deg of the trim (within 2 deg after "
             f"{c['attitude_within_2deg_after_s']:.2f} s), position within {c['max_drift_m']:.2f} m of the start",
             f"open loop: attitude beyond 2 deg {when('attitude_beyond_2deg_s')}, beyond 20 deg "
             f"{when('attitude_beyond_20deg_s')}; drift beyond 5 m {when('drift_beyond_5m_s')}",
             f"algebraic loops: {len(res['algebraic_loops'])} (with every output depending on every input, as "
             f"without ModelStructure dependencies: {res['algebraic_loops_without_dependencies']})",
             f"libcosim vs fmpy master: largest difference {res['libcosim_vs_fmpy_max_abs']:.3g}; wall time "
             f"libcosim {res['libcosim_wall_s']:.2f} s (recording), fmpy {res['fmpy_wall_s']:.2f} s",
             _fmpy_runner_line(res["fmpy_ssp_runner"]),
             *[f"wrote {p}" for p in res["files"].values()]]
    emit(res, args.json, lines)
    return 0


def _fmpy_runner_line(res: dict) -> str:
    if res["completed"]:
        return "fmpy's own SSP runner (fmpy.ssp.simulation.simulate_ssp): ran"
    why = res["refused"][0] if res["refused"] else res["error"]
    return f"fmpy's own SSP runner (fmpy.ssp.simulation.simulate_ssp) cannot run it, as documented: {why}"


def cmd_bench_cosim(args) -> int:
    from fmu import cosim

    r = cosim.bench(args.stop, args.repeats)
    lines = [f"closed-loop co-simulation, {r['stop_s']:g} s, step {r['step_s'] * 1e3:.6f} ms, median of {r['repeats']}",
             f"  libcosim (simulate_until): {r['libcosim_wall_s']:.2f} s wall, {r['libcosim_realtime_factor']:.1f}x "
             "real time",
             f"  fmpy master loop:          {r['fmpy_wall_s']:.2f} s wall, {r['fmpy_realtime_factor']:.1f}x real time",
             f"  helicopter fmi2DoStep:     {r['helicopter_dostep_s']:.2f} s = {100 * r['helicopter_share_fmpy']:.0f} % "
             f"of the fmpy loop, {100 * r['helicopter_share_libcosim']:.0f} % of libcosim's"]
    emit(r, args.json, lines)
    return 0


def fmu_destination(text: str) -> Path:
    """Argument type of ``fmu build --out``: a ``.fmu`` file, or else a folder, that can be written."""
    return A.output_file(".fmu")(text) if text.lower().endswith(".fmu") else A.output_folder(text)


def scene_family(text: str) -> str:
    """Argument type of ``fmu build --scenes``: comma-separated registered scenes, none twice."""
    names, known = [n.strip() for n in text.split(",")], A.scene_names()
    bad = [n for n in names if n not in known]
    if bad or len(set(names)) != len(names):
        raise A.Bad(f"{text!r}: " + (f"unknown scene {bad[0]!r}; known scenes: {', '.join(known)}" if bad
                                     else "a scene is named twice"))
    return ",".join(names)


MAX_DEMO_REVS = 10_000
"""Revolutions of an FMU run at most: its results.csv holds every communication step (about 1 GB
at this length); longer runs belong to heli simulate, which estimates their size first."""


def demo_revs(text: str) -> float:
    """Argument type of the FMU runs' ``--revs``: at least one communication step (1/100 rev),
    at most :data:`MAX_DEMO_REVS`."""
    revs = A.positive(text)
    if round(revs * 100) < 1:
        raise A.Bad(f"{text} is less than one communication step (0.01 revolutions)")
    if revs > MAX_DEMO_REVS:
        raise A.Bad(f"{text} revolutions would record {revs * 100:.3g} communication steps (results.csv of about "
                    f"{revs * 0.1 / 1e3:.3g} GB); give {MAX_DEMO_REVS} or fewer, or run long cases with 'heli simulate "
                    "--every N'")
    return revs


cosim_stop = A.positive_at_most(3600, lambda text, stop: f"{text} s is more than an hour of closed loop (the "
                                "hover-hold case settles within a minute); give 3600 or less")
"""Argument type of ``heli cosim --stop``: a simulated time in (0, 3600] s."""


def register(sub, bench) -> None:
    p = sub.add_parser("fmu", help="the FMUs: FMI 2.0 co-simulation (pythonfmu), native FMI 2.0/3.0 CS and ME")
    fsub = p.add_subparsers(dest="fmu_command", required=True, metavar="ACTION")
    b = fsub.add_parser("build", help="build the .fmu (cached; in a fresh interpreter from a staged copy)")
    b.add_argument("--out", type=fmu_destination, default="out/fmu",
                   help="output .fmu file or folder (default out/fmu/)")
    b.add_argument("--scenes", type=scene_family, default=None,
                   help="comma-separated scene family, the first one the default "
                        "(default forward-flight,hover,ground-run)")
    b.add_argument("--force", action="store_true", help="rebuild even if a cached FMU exists")
    b.add_argument("--native", action="store_true",
                   help="the native FMU (HeliRotorNative_<scene>.fmu): C only, no Python at run time; co-simulation "
                        "and model exchange, exact directional derivatives; Linux, Windows and ARM binaries")
    b.add_argument("--fmi", type=int, choices=[2, 3], default=None,
                   help="with --native: FMI version 2 (default) or 3 (HeliRotorNative_<scene>_fmi3.fmu: arrays, "
                        "adjoint derivatives); one build makes both")
    A.add_aircraft(b)
    b.add_argument("--controller", choices=["hover-hold"], default=None,
                   help="instead, the controller FMU hover-hold (HoverHold.fmu): LQR at the hover trim from the "
                        "model's own derivatives, for a closed loop with the helicopter FMU (see heli cosim)")
    add_json(b)
    b.set_defaults(fn=cmd_fmu_build)

    from fmu.derivative_commands import register as register_derivatives

    register_derivatives(fsub, bench)

    p = sub.add_parser("demo", help="the main job: build the FMU, run forward flight through fmpy, write "
                       "results.csv, hinge_angles.png, viewer.html")
    p.add_argument("--out", type=A.output_folder, default="out/demo", help="output folder (default out/demo)")
    p.add_argument("--revs", type=demo_revs, default=10.0,
                   help="main-rotor revolutions, at least one communication step of 1/100 (default 10)")
    A.add_aircraft(p)
    add_json(p)
    p.set_defaults(fn=cmd_demo)

    p = sub.add_parser("cosim", help="closed loop: helicopter FMU + hover-hold controller FMU in one SSP file, run "
                       "in libcosim and in an fmpy master loop; writes the .ssp files, hover_hold.png and .csv")
    p.add_argument("--out", type=A.output_folder, default="out/cosim", help="output folder (default out/cosim)")
    p.add_argument("--stop", type=cosim_stop, default=60.0, help="simulated time in s, at most 3600 (default 60)")
    A.add_aircraft(p)
    add_json(p)
    p.set_defaults(fn=cmd_cosim)

    p = bench.add_parser("cosim", help="closed-loop co-simulation: wall time in libcosim and in fmpy, share of "
                         "the helicopter FMU")
    p.add_argument("--stop", type=A.positive, default=60.0, help="simulated time in s (default 60)")
    p.add_argument("--repeats", type=A.positive_int, default=3, help="runs per master (median; default 3)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_cosim)

    p = bench.add_parser("fmu", help="FMU under fmpy against the core: real-time factors and overhead")
    p.add_argument("--revs", type=demo_revs, default=20.0, help="revolutions per run (default 20)")
    p.add_argument("--repeats", type=A.positive_int, default=3, help="fresh-process runs per kind (median; default 3)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_fmu)
