"""Core subcommands of ``heli``: scenes, simulate, trim, figures (``heli demo`` is in :mod:`fmu.commands`)."""
from __future__ import annotations

import re
import sys
from pathlib import Path

from mbs import arguments as A
from mbs.envelope import CLIMB_RANGE, SPEED_RANGE
from mbs.cli import add_json, emit, say

FIXED_METHODS = ("euler", "rk4", "rk8")  # mbs.integrators.FIXED_STEP, named here to keep casadi out of start-up


def cmd_scenes(args) -> int:
    from mbs import scenes

    if args.markdown and args.json:
        raise ValueError("--markdown and --json: the Markdown table is text; give one of them")
    rows = [scene_row(sc) for sc in scenes.all_scenes().values()]
    if args.markdown:
        print(scene_table(rows))
        return 0
    lines = []
    for row in rows:
        extra = f" + {_extra(row)} ({', '.join(row['extra_states'])})" if row["extra_states"] else ""
        lines += [f"{row['scene']}: {row['description']}",
                  f"  {len(row['bodies'])} bodies: {', '.join(row['bodies'])}",
                  f"  {row['dof']} degrees of freedom{extra}",
                  f"  {len(row['coordinates'])} position coordinates: {', '.join(row['coordinates'])}",
                  f"  {len(row['velocities'])} velocities: {', '.join(row['velocities'])}",
                  f"  force elements: {', '.join(row['forces']) or 'none'} (+ gravity)",
                  f"  {'conservative' if row['conservative'] else 'not conservative'}", ""]
    emit({"scenes": rows}, args.json, lines)
    return 0


def scene_row(sc) -> dict:
    """What ``heli scenes`` says of the scene ``sc``."""
    from mbs.dynamics import state_layout

    model = sc.model()
    lay = state_layout(model)
    return {"scene": sc.name, "description": sc.description, "bodies": [b.name for b in lay.bodies],
            "dof": lay.nv, "position_coordinates": lay.nq, "coordinates": lay.q_names, "velocities": lay.v_names,
            "extra_states": lay.z_names, "conservative": sc.conservative, "forces": [f.name for f in model.forces],
            "parameters": {p.name: p.default for p in model.parameters.values()}}


def _extra(row: dict) -> str:
    n = len(row["extra_states"])
    return f"{n} extra state{'s' if n != 1 else ''}"


def scene_table(rows: list[dict]) -> str:
    """The docs' scene table (docs/method/helicopter-model.md, Markdown) from the rows of :func:`scene_row`."""
    lines = ["| scene | what it models | degrees of freedom |", "|---|---|---|"]
    for r in rows:
        extra = f" + {_extra(r)}" if r["extra_states"] else ""
        lines.append(f"| `{r['scene']}` | {r['description']} | {r['dof']}{extra} |")
    return "\n".join(lines)


def _scene(args):
    """The scene named on the command line, of the ``--aircraft`` (when given), with exactly the
    ``--aero`` switches on (when given)."""
    from mbs import scenes
    from mbs.models.helicopter import with_aero

    try:
        scene = scenes.get(args.scene, aircraft=getattr(args, "aircraft", None))
    except ValueError as exc:
        raise ValueError(f"--aircraft {args.aircraft.path}: {exc}") from None
    if getattr(args, "aero", None) is not None:
        try:
            scene = with_aero(scene, args.aero)
        except ValueError as exc:
            raise ValueError(f"--aero {args.aero!r}: {exc}") from None
    return _in_air(scene, args)


def _in_air(scene, args):
    """``scene`` in the ``--altitude``, ``--temperature-offset`` and ``--wind`` of ``args``."""
    from mbs.models.helicopter.air_options import with_environment

    keys = ("altitude", "temperature_offset", "wind", "turbulence", "gust", "ground_effect")
    given = {k: getattr(args, k, None) for k in keys}
    if not any(given.values()) and all(given[k] is None for k in keys[:3]):
        return scene
    if scene.aircraft is None:
        raise ValueError(f"--altitude, --temperature-offset, --wind, --turbulence, --gust and --ground-effect apply "
                         f"to the helicopter scenes; scene {scene.name!r} has no air")
    try:
        return with_environment(scene, given["altitude"], given["temperature_offset"],
                                None if given["wind"] is None else wind_components(given["wind"]), given["turbulence"],
                                bool(given["gust"]), bool(given["ground_effect"]))
    except ValueError as exc:
        raise ValueError(f"scene {scene.name!r}: {exc}") from None


def cmd_simulate(args) -> int:
    from mbs._progress import Progress
    from mbs.run_cost import check_size
    from mbs.simulate import prepare
    from mbs.trims import start as begin

    scene = _scene(args)
    _check_revs(args.revs, args.steps_per_rev or scene.steps_per_rev, args.every)
    if args.dtype == "float32" and args.backend == "vm":
        raise ValueError("--dtype float32 needs --backend compiled: the virtual machine computes in float64 only")
    settings = dict(_settings(args.set))
    speed = settings.pop("speed", None)
    start = args.start or begin.default_start(scene)
    if start.startswith("periodic"):
        return _simulate_from(_periodic_start(args, scene), args, scene, settings, speed)
    begin.check(start, scene)
    if speed is not None and start == begin.TRIM:
        from mbs.inputs import check_settings

        check_settings({"speed": speed}, {}, scene.name, _model_facts(scene)[1])
    run = prepare(scene, args.revs, args.steps_per_rev, args.dtype, args.backend, params=settings, every=args.every,
                  method=args.method, inputs=args.inputs, speed=None if start == begin.TRIM else speed)
    cost = run.cost()  # time and size first: a run too large is refused before a trim is computed for it
    check_size(cost, args.max_gb)
    if start == begin.TRIM:
        begin.from_trim(run, speed, log=say, progress=Progress(f"trim {scene.name}", not args.quiet))
        run.settings.update({} if speed is None else {"speed": speed})
    else:
        run.start = begin.scene_record(run)
        run.warnings += [w for w in [begin.untrimmed_warning(run)] if w]
    return _execute(run, args, scene, cost)


def _execute(run, args, scene, cost) -> int:
    """Check the step of the prepared ``run``, run it, write its files and report."""
    from mbs._progress import Progress
    from mbs.cli import warn
    from mbs.simulate import write

    for text in run.warnings:
        warn(text)
    step = run.check_step(args.step_tol)
    if not step.ok or step.ratio is None:
        warn(step.message())
    if cost.worth_saying():
        say(f"heli simulate: {cost.message()}")
    show, slow = not args.quiet, cost.rows * cost.row_s > 2.0
    sim = run.execute(Progress(f"simulate {scene.name}", show), Progress("outputs and energies", show and slow))
    sim.step_error = step
    paths = write(sim, Path(args.out), Progress("writing results.csv", show and slow))
    res = {**sim.summary(), "files": {k: str(v) for k, v in paths.items()}, "warnings": run.warnings,
           "cost": cost.summary()}
    lines = [f"{sim.title()}: {sim.revs:g} revolutions, {res['steps']} {sim.method} steps ({sim.system.dtype}, "
             f"{sim.system.backend}) in {sim.traj.wall_s:.3f} s, {res['realtime_factor']:.1f}x real time",
             f"start: {start_words(run.start)}",
             f"result: {sim.traj.message}" + ("" if step.ok else " (but the step is too coarse: see the warning)"),
             f"step check ({1e3 * step.wall_s:.0f} ms): {step.message()}"]
    if "max_rel_energy_error" in res:
        lines.append(f"max relative energy error: {res['max_rel_energy_error']:.3e}")
    if "rotor_speed" in res:
        from mbs.drivetrain.report import pilot_line

        lines.append(pilot_line(res["rotor_speed"]))
    lines += [f"wrote {p}" for p in paths.values()]
    emit(res, args.json, lines)
    return 0 if sim.traj.ok else 1


def start_words(start: dict) -> str:
    """Where a run started (:mod:`mbs.trims.start`), in words."""
    if start.get("from") == "periodic trim":
        where = f"trimmed now and stored in {start['file']}" if start["computed_now"] else f"stored in {start['file']}"
        return f"the periodic trim at {start['speed']:g} m/s ({where}; roll {start['roll_deg']:+.3f} deg, pitch " \
               f"{start['pitch_deg']:+.3f} deg)"
    return start.get("what", "the scene's initial state")


def _periodic_start(args, scene):
    """The start ``--start periodic[:V]``: the periodic trim computed now (:mod:`mbs.starts`), as
    ``heli fly``'s page starts."""
    from mbs import starts
    from mbs.analysis.trim import trimmable

    if trimmable(scene):  # else the trim refuses the scene, naming the trimmable ones
        say(f"heli simulate: trimming {scene.name} for the start {args.start} ...")
    return starts.start(args.start, scene, scene.system("compiled"), args.steps_per_rev or scene.steps_per_rev)


def _parse_start(text: str) -> str:
    """``trim``, ``scene``, ``periodic`` or ``periodic:V``; ValueError naming them otherwise."""
    from mbs import starts

    if text == "trim":
        return text
    try:
        starts.parse(text)
    except ValueError as exc:
        raise ValueError(f"{exc}; or trim (the stored periodic trim)") from None
    return text


def _simulate_from(fixed, args, scene, settings: dict, speed) -> int:
    """``heli simulate`` from the start ``fixed`` (:class:`mbs.starts.Start`): its controls held
    (but those the input table gives), its state."""
    from mbs.run_cost import check_size
    from mbs.simulate import prepare

    table = set(args.inputs.names) if args.inputs else set()
    trimmed = {n: v for n, v in fixed.controls.items() if n not in table}  # the table's columns are its own
    run = prepare(scene, args.revs, args.steps_per_rev, args.dtype, args.backend, params={**trimmed, **settings},
                  every=args.every, method=args.method, inputs=args.inputs, speed=speed, x0=fixed.x0)

    run.settings["start"] = args.start
    run.start = {"from": args.start, "speed": fixed.speed, "residual": fixed.residual,
                 "what": f"the periodic trim at {fixed.speed:g} m/s computed now (--start {args.start}; max scaled "
                         f"residual {fixed.residual:.1e})"}
    cost = run.cost()
    check_size(cost, args.max_gb)
    return _execute(run, args, scene, cost)


def _check_revs(revs: float, steps_per_rev: int, every: int = 1) -> None:
    """Refuse a ``--revs`` shorter than one step, and an ``--every`` longer than the run."""
    steps = round(revs * steps_per_rev)
    if steps < 1:
        raise ValueError(f"--revs {revs:g} is less than one step ({steps_per_rev} steps per revolution): give "
                         f"--revs {1 / steps_per_rev:g} or more")
    if every > steps > 1:
        raise ValueError(f"--every {every} is more than the run's {steps} steps: results.csv would hold its first and "
                         f"last rows only; give --every {max(1, steps // 10)} or less, or more --revs")


def _settings(items: list[str] | None) -> dict[str, float]:
    """The ``--set NAME=VALUE`` values; a name given twice is refused."""
    from mbs.analysis.fanplot import parse_settings

    names = [item.partition("=")[0].strip() for item in items or []]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"--set {twice[0]} is given more than once; give each name once")
    return parse_settings(items)


def _model_facts(scene) -> tuple[dict, bool]:
    """Parameters (name -> :class:`mbs.tree.Parameter`) of ``scene``'s model and whether its
    fuselage flies free; symbolic only, so callers check options before anything is compiled."""
    model = scene.model()
    return model.parameters, any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())


def _check_speed(args, scene) -> None:
    """Refuse ``--speed`` and ``--climb-rate`` on a scene whose fuselage does not fly (clamped or
    none): they would be ignored."""
    given = [(f, v) for f, v in (("--speed", getattr(args, "speed", None)),
                                 ("--climb-rate", getattr(args, "climb_rate", 0.0) or None),
                                 ("--bank", getattr(args, "bank", None)),
                                 ("--turn-rate", getattr(args, "turn_rate", 0.0) or None)) if v is not None]
    if given and not _model_facts(scene)[1]:
        flag, value = given[0]
        raise ValueError(f"{flag} {value:g}: scene {scene.name!r} has no free fuselage, so no flight speed or climb "
                         "(its rotor turns in still air); give it for forward-flight or hover")


def _check_floquet_settings(scene, settings: dict, sweep: tuple | None) -> None:
    """Refuse ``--set``/``--sweep`` names that are no parameters, ``--set`` values out of range (a
    sweep's are rows with their status), a name both set and swept, and a control of a
    free-flying scene (its trim sets the controls). ``sweep``: ``(name, values)`` of ``--sweep``,
    or None."""
    from mbs.inputs import check_settings

    swept = sweep[0] if sweep else None
    option = {**{n: "--set" for n in settings}, **({swept: "--sweep"} if swept else {})}
    if not option:
        return
    if swept in settings:
        raise ValueError(f"--set {swept}=... and --sweep {swept}=...: the sweep sets {swept}; drop one of them")
    parameters, free = _model_facts(scene)
    for name, flag in option.items():
        if name not in parameters:
            hint = "; the flight speed is --speed" if name == "speed" else ""
            raise ValueError(f"{flag} {name}: {name!r} is not a parameter of scene {scene.name!r} "
                             f"(it has: {', '.join(parameters) or 'none'}){hint}")
        if free and parameters[name].control:
            others = ", ".join(n for n, q in parameters.items() if not q.control) or "none"
            raise ValueError(f"{flag} {name}: the trim sets the controls of scene {scene.name!r} (its fuselage flies "
                             f"free), so {name} given here would be overridden; set a parameter that is not a control "
                             f"({others}), or use a scene with a clamped fuselage (ground-run)")
    limits = {n: {"low": q.low, "high": q.high, "unit": q.unit} for n, q in parameters.items()}
    check_settings(settings, limits, scene.name, free)  # a sweep's values beyond the range are failed rows


def cmd_trim(args) -> int:
    from mbs._progress import Progress
    from mbs.trim import trim

    scene = _scene(args)
    _check_speed(args, scene)
    if args.write and (args.turn_rate or args.bank is not None):
        raise ValueError("--write stores trims of straight flight at zero sideslip, the ones 'heli simulate' starts "
                         "from; a trim with --bank or --turn-rate is not stored: leave --write out (--json gives it)")
    res = trim(scene, speed=args.speed, climb_rate=args.climb_rate, method=args.method,
               steps_per_rev=args.steps_per_rev, backend=args.backend, tol=args.tol,
               max_iterations=args.iterations, progress=Progress(f"trim {args.scene}", not args.quiet),
               turn_rate=args.turn_rate, bank=args.bank)
    out, lines = res.summary(), _trim_lines(res)
    if args.write and res.converged:
        from mbs.trims import entry_of, store

        key = store.write(args.write, entry_of(res, scene))
        out.update(written=str(args.write), key=key)
        lines.append(f"stored as {key!r} in {args.write}: " + _who_starts(args, scene, res))
    elif args.write:
        lines.append(f"{args.write} not written: the trim did not converge")
    elif res.converged:
        lines.append(f"not stored (--write stores it; 'heli simulate {scene.name}' starts from a stored trim of the "
                     "same aircraft file, scene and speed, or trims on first use)")
    emit(out, args.json, lines)
    return 0 if res.converged else 1


def _who_starts(args, scene, res) -> str:
    """Which ``heli simulate`` starts from a stored trim ``res``, or why none does (it looks up
    level flight trimmed by RK4 at the scene's steps per revolution)."""
    if res.climb_rate or res.method != "rk4" or res.steps_per_rev != scene.steps_per_rev:
        return (f"'heli simulate' starts from level-flight trims by rk4 at {scene.steps_per_rev} steps per revolution "
                f"(this one: climb {res.climb_rate:g} m/s, {res.method} at {res.steps_per_rev}), so not from this one")
    craft = getattr(args, "aircraft", None)
    options = ("" if craft is None else f" --aircraft {craft.key if craft.packaged else craft.path}") + \
        ("" if getattr(args, "speed", None) is None else f" --set speed={args.speed:g}") + \
        ("" if getattr(args, "aero", None) is None else f" --aero {args.aero}")
    from mbs.trims.store import beside

    read = [user_trims().resolve(), beside(scene.aircraft).resolve()] if scene.aircraft else [user_trims().resolve()]
    if Path(args.write).resolve() not in read:
        return (f"'heli simulate' does not read this file: it reads {user_trims()} (--write without PATH) and "
                "<aircraft stem>_trim.toml beside the aircraft file")
    return f"'heli simulate {scene.name}{options}' starts from it"


def _trim_lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.trim.trim`."""
    import numpy as np

    per = res.period
    flip = f", the tail rotor's teeter reversed; period {per.full_revs} revolutions" if per.flip else ""
    flip += f", tail blades exchanged; period {per.full_revs} revolutions" if per.source else ""
    lines = [f"{res.scene}{_of(res)} at {res.speed:g} m/s, climb {res.climb_rate:g} m/s: periodic shooting over {per.revs} "
             f"main-rotor revolution(s){flip}; {res.method}, {res.steps_per_rev} steps/rev",
             *gear_lines(res),
             *[f"  iteration {k + 1}: max |scaled residual| {it.residual:.3e}, step {it.step:g}"
               for k, it in enumerate(res.history)],
             f"  final:       max |scaled residual| {np.abs(res.residual).max():.3e}",
             *([] if res.converged else [f"  NOT A TRIM: the values below are the "
                                         f"{'last Newton iterate' if res.iterations else 'starting estimate'}, "
                                         "balancing nothing (the reason is on the last line)"]),
             *[f"  {k:20s} {v:+.6f} rad ({np.degrees(v):+.4f} deg)" for k, v in
               [*res.controls.items(), ("roll", res.roll), ("pitch", res.pitch),
                *([("sideslip", res.sideslip)] if res.flight.bank is not None else [])]]]
    if res.flight.bank is not None or res.flight.turn_rate:
        lines.append(f"  flight: {res.flight.constraint}, turn rate {res.flight.turn_rate:g} rad/s")
    changed = {k: v for k, v in res.published.items() if v != res.controls.get(k)}
    if changed:
        lines.append("  as published (the aircraft's conventions): "
                     + ", ".join(f"{k} {np.degrees(v):+.4f} deg" for k, v in changed.items()))
    if res.pilot:
        lines.append("  pilot controls: " + ", ".join(f"{k} {v:.4g} {res.pilot_units[k]}" for k, v in res.pilot.items()))
    lines += [f"  {k:28s} {v:.6g} {res.output_units.get(k, '')} (period mean)".replace(" 1 (", " (")
              for k, v in res.output_means.items() if not OTHER_BLADES.match(k)]
    if res.flapping:
        lines.append("  flapping (rad, relative to the shaft, beta = beta0 + beta1c cos psi + beta1s sin psi): "
                     + ", ".join(f"{k} {v:+.5f} ({np.degrees(v):+.3f} deg)" for k, v in res.flapping.items()
                                 if k.startswith("beta")))
    if "bar1c" in res.flapping:
        lines.append("  stabilizer bar tilt (rad, relative to the shaft, its plane at azimuth psi = bar1c cos psi + "
                     "bar1s sin psi): " + ", ".join(f"{k} {res.flapping[k]:+.5f} ({np.degrees(res.flapping[k]):+.3f} "
                                                    "deg)" for k in ("bar1c", "bar1s")))
    if res.rotor:
        lines.append("  main rotor: " + ", ".join(f"{k} {v:.5g}" for k, v in res.rotor.items()))
    verdict = "converged" if res.converged else "NOT CONVERGED"
    lines += [f"  warning: {w}" for w in res.warnings]
    return lines + [f"  {res.summary()['note']}",
                    f"{verdict}: {res.reason}; {res.iterations} Newton iterations, {res.n_jacobian} Jacobians, "
                    f"{res.n_residual} residual runs, {res.wall_s:.2f} s (+ {res.setup_s:.2f} s set-up)"]


def gear_lines(res) -> list[str]:
    """The tail-rotor gear ratio of a periodic solution when the analyses replaced it, with the
    estimated error of the tail collective (:attr:`mbs.analysis.trim.Trim.tail_collective_error`)."""
    import numpy as np

    gear = res.period.gear
    if gear is None or gear.exact:
        return []
    err = res.tail_collective_error
    estimate = f"; estimated error of the tail collective {np.degrees(err):+.2g} deg" if err is not None else ""
    return [f"  approximation: {gear.text()}{estimate}"]


OTHER_BLADES = re.compile(r"blade([2-9]|\d{2,})\.")
"""Outputs of main-rotor blades other than blade 1 (left out of the trim's report: in a trim
they repeat blade 1's; ``--json`` has them all)."""


def cmd_floquet(args) -> int:
    from mbs.analysis.fanplot import WithParameters, parse_sweep
    from mbs.analysis.floquet import check_scene, floquet
    from mbs.analysis.trim import evaluators

    scene = _scene(args)
    _check_speed(args, scene)
    settings = _settings(args.set)
    _check_floquet_settings(scene, settings, parse_sweep(args.sweep) if args.sweep else None)
    if args.sweep:
        return _floquet_sweep(args, scene)
    sc = scene
    check_scene(scene)
    system, stepper = evaluators(scene, args.method, args.backend)
    if settings:
        system = WithParameters(system, **settings)
        system.params()
    res = floquet(sc, speed=args.speed, method=args.method, steps_per_rev=args.steps_per_rev,
                  backend=args.backend, system=system, stepper=stepper, frame=args.frame)
    out, lines = res.summary(), _floquet_lines(res)
    if args.out:
        out["files"] = _floquet_files(res, Path(args.out))
        lines += [f"wrote {f}" for f in out["files"]]
    emit(out, args.json, lines)
    return 0


def _floquet_lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.analysis.floquet.floquet`."""
    from mbs.analysis.flight_modes import zeta_text

    return [f"{res.scene}{_of(res)} at {res.speed:g} m/s: Floquet analysis over {res.period_revs} main-rotor revolutions "
            f"(monodromy over {res.interval_revs}; periodic solution in {res.trim.iterations} Newton iterations; "
            f"analysis {res.wall_s:.2f} s); rotor-mode frequencies in the {res.frame} frame",
            *gear_lines(res.trim),
            f"  {'mode':30s} {'Re λ 1/s':>10s} {'Im λ rad/s':>11s} {'Hz':>8s} {'/rev':>7s} {'ζ':>7s} {'|μ|':>9s}",
            *[f"  {m.name:30s} {m.exponent.real:+10.4f} {m.exponent.imag:11.4f} {m.frequency_hz:8.4f} "
              f"{m.per_rev:7.4f} {zeta_text(m.damping_ratio)} {abs(m.multiplier):9.3e}" for m in res.modes],
            f"{'stable' if res.stable else 'UNSTABLE'}: largest |multiplier| "
            f"{max(abs(m.multiplier) for m in res.modes):.6f} over the period"]


def _floquet_files(res, out: Path) -> list[str]:
    """``floquet_<scene>.png`` (exponents and multipliers) and ``.csv`` (one row per mode) in ``out``."""
    from mbs.analysis import floquet_plot

    stem = out / f"floquet_{res.scene}"
    return [str(floquet_plot.write_csv(res, stem.with_suffix(".csv"))),
            str(floquet_plot.figure(res, stem.with_suffix(".png"), _of(res)))]


def _floquet_sweep(args, scene) -> int:
    """``heli floquet SCENE --sweep NAME=LO:HI:N``: the fan plot (PNG) and its table (CSV)."""
    import time

    from mbs._progress import Progress
    from mbs.analysis import fanplot as fp

    start = time.perf_counter()
    name, values = fp.parse_sweep(args.sweep)
    ana = fp.FanPlotAnalysis(scene, fp.parse_settings(args.set), args.method, args.steps_per_rev,
                             args.backend, fixed_frame=args.frame != "rotating")
    setup_s = time.perf_counter() - start
    points = fp.sweep(ana, name, values, Progress(f"floquet sweep {args.scene}", not args.quiet))
    sweep_s = time.perf_counter() - start - setup_s
    bands = fp.unstable_bands(points, lambda v: ana.at(**{name: v}))
    out = Path(args.out or "out/floquet")
    stem = f"fanplot_{args.scene}"
    files = [fp.write_csv(fp.rows(points, name), out / f"{stem}.csv"),
             fp.figure(points, name, bands, out / f"{stem}.png", _fan_title(args, ana))]
    res = {"scene": args.scene, "parameter": name, "values": values.tolist(), "settings": ana.settings,
           "frame": "rotating" if args.frame == "rotating" else "fixed (multi-blade)",
           "points": [_sweep_point(p) for p in points], "unstable_bands": bands,
           "files": [str(f) for f in files], "setup_s": setup_s, "sweep_s": sweep_s,
           "wall_s": time.perf_counter() - start}
    emit(res, args.json, _sweep_lines(res, points))
    return 0 if any(p.floquet for p in points) else 1


def _fan_title(args, ana) -> str:
    settings = ", ".join(f"{k} = {v:g}" for k, v in ana.settings.items())
    frame = "rotating-frame" if args.frame == "rotating" else "fixed-frame"
    craft = f" of the {args.aircraft.name}" if getattr(args, "aircraft", None) else " of the MBB Bo105"
    return f"{args.scene}{craft}: fan plot ({frame} frequencies{'; ' + settings if settings else ''})"


def _of(res) -> str:
    """`` of the MBB Bo105``: the aircraft of a result (its own, or that of the trim it rests on)."""
    name = getattr(res, "aircraft", None) or getattr(getattr(res, "trim", None), "aircraft", None)
    return f" of the {name}" if isinstance(name, str) else ""


def _sweep_point(p) -> dict:
    modes = [{**m.summary(), "name": n} for m, n in zip(p.floquet.modes, p.names)] if p.floquet else []
    return {"value": p.value, "status": p.status, "stable": not p.unstable if p.floquet else None,
            "modes": modes, "wall_s": p.wall_s}


def _sweep_lines(res: dict, points) -> list[str]:
    failed = [p for p in points if not p.floquet]
    bands = "; ".join(f"{lo:.4g} to {hi:.4g}" for lo, hi in res["unstable_bands"]) or "none"
    return [f"{res['scene']}: Floquet sweep of {res['parameter']} over {len(points)} points "
            f"({res['frame']} frequencies) in {res['sweep_s']:.2f} s (+ {res['setup_s']:.2f} s set-up)",
            *[f"  {res['parameter']} = {p.value:g}: {p.status}" for p in failed],
            f"unstable {res['parameter']} band(s): {bands}", *[f"wrote {f}" for f in res["files"]]]


def cmd_derivatives(args) -> int:
    from mbs.analysis.derivatives import derivatives, write_matrices

    scene = _scene(args)
    _check_speed(args, scene)
    res = derivatives(scene, speed=args.speed, method=args.method, steps_per_rev=args.steps_per_rev,
                      backend=args.backend)
    out, lines = res.summary(), _derivative_lines(res)
    if args.mat:
        out["written"] = write_matrices(res, args.mat)
        lines.append(f"wrote {out['written']}")
    emit(out, args.json, lines)
    return 0


def _derivative_lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.analysis.derivatives.derivatives`."""
    import numpy as np

    from mbs.analysis.derivatives import CONTROL_SYMBOLS, FORCES, VELOCITIES

    ref = res.reference
    syms = [CONTROL_SYMBOLS.get(c, c) for c in res.controls]
    lines = [f"{res.scene}{_of(res)} at {res.speed:g} m/s: derivatives with the rotor in its periodic equilibrium "
             f"(quasi-static rotor, implicit-function theorem on the trim; {res.wall_s:.2f} s)",
             f"  reference: U_e {ref['U_e']:.3f}, V_e {ref['V_e']:.3f}, W_e {ref['W_e']:.3f} m/s, "
             f"Theta_e {np.degrees(ref['Theta_e']):+.3f} deg, Phi_e {np.degrees(ref['Phi_e']):+.3f} deg",
             *(gear_lines(res.trim) if res.trim is not None else []),
             "  forces per unit mass (X, Y, Z), moments per unit inertia (L, M, N; primed), per m/s, rad/s, rad:",
             "  " + " " * 4 + "".join(f"{v:>11s}" for v in [*VELOCITIES, *syms])]
    for f in FORCES:
        row = [res.table[f"{f}_{v}"] for v in [*VELOCITIES, *syms]]
        lines.append(f"  {f:4s}" + "".join(f"{x:+11.4g}" for x in row))
    lines += matrix_lines("A", res.A, res.states, res.states) + matrix_lines("B", res.B, res.states, syms)
    flipped = {k: v for k, v in res.published.items() if v != res.table.get(k)}
    if flipped:
        lines.append("  per published control angle (the aircraft's conventions): "
                     + ", ".join(f"{k} {v:+.4g}" for k, v in flipped.items()))
    if res.B_pilot is not None:
        lines += matrix_lines("B per pilot position (SI: m, rad or fraction of travel)", res.B_pilot, res.states,
                              list(PILOT_LABELS))
        lines += pilot_derivative_lines(res)
    held_bar = any(w.startswith("stabilizer bar:") for w in res.warnings)
    note = ["  (NOT the aircraft's modes with its stabilizer bar: these hold the bar in its periodic equilibrium; "
            "heli floquet gives the modes with the bar as states)"] if held_bar else []
    return lines + mode_lines(res.modes) + note + [f"  warning: {w}" for w in res.warnings]


PILOT_LABELS = ("lever", "lon stick", "lat stick", "pedals")
"""Column heads of the pilot controls (:data:`mbs.aircraft.rigging.PILOT` order)."""


def pilot_derivative_lines(res) -> list[str]:
    """The control derivatives per pilot control in the aircraft file's units of each control (per
    inch of stick, per % of lever), as reports print them; none without the file's units."""
    from mbs.aircraft import units
    from mbs.aircraft.rigging import PILOT
    from mbs.analysis.derivatives import FORCES

    if not res.pilot_file_units:
        return []
    per = {p: units.parse(u).factor for p, u in res.pilot_file_units.items()}
    labels = dict(zip(PILOT, PILOT_LABELS))
    head = [f"{labels[p]} (/{res.pilot_file_units[p]})" for p in PILOT]
    out = ["  control derivatives per pilot control in the file's units (X, Y, Z in m/s^2, L, M, N in rad/s^2):",
           "  " + " " * 4 + "".join(f"{h:>16s}" for h in head)]
    for f in FORCES:
        out.append(f"  {f:4s}" + "".join(f"{res.pilot[f'{f}_{p}'] * per[p]:+16.4g}" for p in PILOT))
    return out


def mode_lines(modes) -> list[str]:
    """The table of flight modes (:class:`mbs.analysis.flight_modes.FlightMode`), with a note when
    a complex pair is named as a subsidence."""
    from mbs.analysis.flight_modes import OVERDAMPED, zeta_text

    lines = [f"  {'mode':22s} {'Re λ 1/s':>10s} {'Im λ rad/s':>11s} {'ζ':>7s} {'period s':>9s}"]
    for m in modes:
        period = f"{m.period_s:9.2f}" if m.period_s else " " * 9
        lines.append(f"  {m.name:22s} {m.eigenvalue.real:+10.4f} {m.eigenvalue.imag:11.4f} "
                     f"{zeta_text(m.damping_ratio)} {period}")
    if any(m.eigenvalue.imag and m.name.endswith(("subsidence", "divergence")) for m in modes):
        lines.append(f"  (a complex pair damped at {100 * OVERDAMPED:g} % of critical or more is named as a subsidence: "
                     "it dies out within one swing)")
    return lines


SYMBOLS = {"theta": "θ", "phi": "φ"}


def matrix_lines(name: str, m, rows: list[str], columns: list[str]) -> list[str]:
    """``m`` printed with its labels: a row per state (the derivative of), a column per state or
    control (per unit of); Greek symbols for the Euler angles."""
    label = lambda s: SYMBOLS.get(s, s)  # noqa: E731
    return [f"  {name} (row: time derivative of the state; column: per unit of the state or control):",
            "    " + " " * 6 + "".join(f"{label(c):>10s}" for c in columns),
            *[f"    {'d' + label(r) + '/dt':6s}" + "".join(f"{x:+10.4f}" for x in row) for r, row in zip(rows, m)]]


def cmd_figures(args) -> int:
    from mbs._progress import Progress
    from mbs.figures import make_all

    res = make_all(Path(args.out), progress=Progress("figures", not args.quiet), aircraft=args.aircraft)
    f3 = res["fig3"]
    lines = [f"Fig. 3 max relative energy error: float64 {f3['float64']['max_rel_energy_error']:.2e}, "
             f"float32 {f3['float32']['max_rel_energy_error']:.2e} "
             f"(plain summation {f3['float32_plain']['max_rel_energy_error']:.2e})",
             *[f"wrote {p}" for p in res["files"]]]
    emit(res, args.json, lines)
    return 0


def user_trims() -> Path:
    """The user's trim file, ``$XDG_DATA_HOME/rotor-mbs/trims.toml`` (default
    ``~/.local/share/rotor-mbs/trims.toml``): where ``heli trim --write`` stores a trim and
    ``heli simulate`` finds it (:mod:`mbs.trims`)."""
    from mbs.trims.store import default_file

    return default_file()


def trim_file(text: str) -> Path:
    """Argument type of ``trim --write``: a writable ``.toml`` file outside the installed package."""
    path, package = A.output_file(".toml")(text), Path(__file__).resolve().parent
    if path.resolve().is_relative_to(package):
        raise A.Bad(f"{text!r} is inside the installed package ({package}); give a file of your own "
                    f"(without PATH: {user_trims()})")
    if path.exists():  # its other entries are kept: a file that cannot be read would fail after the trim
        tomllib = __import__("tomllib" if sys.version_info >= (3, 11) else "tomli")
        try:
            tomllib.loads(path.read_text())
        except (ValueError, OSError, UnicodeDecodeError) as exc:
            raise A.Bad(f"{text!r} exists and is not a TOML file whose entries could be kept ({exc}); give another "
                        "file or repair it") from None
    return path


def _setting(text: str) -> dict:
    from mbs.analysis.fanplot import parse_settings

    return parse_settings([text])


def _sweep(text: str):
    from mbs.analysis.fanplot import parse_sweep

    return parse_sweep(text)


def _add_periodic_arguments(p) -> None:
    """The arguments of the analyses at a periodic solution (trim, Floquet, derivatives)."""
    A.add_scene(p, nargs="?", default="forward-flight", what="scene (default forward-flight)")
    A.add_aircraft(p)
    p.add_argument("--speed", type=A.flight_speed, default=None,
                   help=f"flight speed in m/s, {SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g}, or with a unit: 60kt, "
                        "100km/h, ft/s, mph (default: the scene's)")
    p.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    _steps_per_rev(p)
    _backend(p)


def _steps_per_rev(p) -> None:
    p.add_argument("--steps-per-rev", type=A.positive_int, default=None,
                   help="fixed steps per main-rotor revolution (default: the scene's, 100 for the Bo105 scenes)")


def _backend(p) -> None:
    p.add_argument("--backend", choices=("compiled", "vm"), default="compiled",
                   help="evaluator: generated C compiled by the machine's compiler (default) or CasADi's "
                        "virtual machine (no compiler needed, slower)")


def _aero(p) -> None:
    from mbs.models.helicopter import AERO_SWITCHES

    p.add_argument("--aero", metavar="SWITCHES", default=None,
                   help="aerodynamics switches that are on (the helicopter scenes, of any aircraft), the others off: "
                        f"comma-separated {', '.join(AERO_SWITCHES)}; or full (every switch the scene models, the default) or "
                        "none (the paper's model: uniform inflow, free-stream airframe)")


def _air(p) -> None:
    from mbs.environment import atmosphere as isa

    low, high = isa.ALTITUDE_RANGE
    p.add_argument("--altitude", type=A.checked_by(_altitude), default=None, metavar="M",
                   help=f"fly in the ISA at this pressure altitude in m ({low:g} to {high:g}; the run-time parameter "
                        "'altitude'); default: the aircraft file's density and speed of sound")
    p.add_argument("--temperature-offset", type=A.checked_by(_offset), default=None, metavar="K",
                   help="ISA temperature offset in K (ISA+20: 20; the parameter 'temperature_offset'); implies the ISA")
    p.add_argument("--wind", type=A.checked_by(wind_components), default=None, metavar="N,E,D",
                   help="steady wind: the air's velocity north, east, down in m/s (the parameters wind_north, "
                        "wind_east, wind_down); a headwind of a north-flying aircraft is negative north")
    p.add_argument("--turbulence", choices=("dryden", "von-karman"), default=None,
                   help="continuous turbulence of MIL-F-8785C's form (free flight; its intensity, seed and the height "
                        "above the ground are the parameters turbulence_intensity, turbulence_seed, height)")
    p.add_argument("--gust", action="store_true", help="a discrete 1 - cosine gust (free flight; the parameters "
                   "gust_north, gust_east, gust_down, gust_start, gust_length, gust_hold)")
    p.add_argument("--ground-effect", action="store_true",
                   help="the main rotor's inflow in ground effect (the ground at the parameter height below the start)")


def _altitude(text: str) -> float:
    from mbs.environment import atmosphere as isa

    value = float(text)
    isa.check(value)
    return value


def _offset(text: str) -> float:
    from mbs.environment import atmosphere as isa

    value = float(text)
    isa.check(0.0, value)
    return value


def wind_components(text: str) -> tuple[float, float, float]:
    """``N,E,D`` (m/s) as three finite numbers within the wind's range."""
    import math

    from mbs.models.helicopter.environment import WIND_LIMIT

    parts = [t.strip() for t in str(text).split(",")]
    try:
        values = tuple(float(t) for t in parts)
    except ValueError:
        raise ValueError(f"{text!r} is not three numbers N,E,D (m/s)") from None
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise ValueError(f"{text!r} is not three finite numbers N,E,D (m/s)")
    if max(abs(v) for v in values) > WIND_LIMIT:
        raise ValueError(f"{text!r}: each component within ±{WIND_LIMIT:g} m/s")
    return values


def _quiet(p, what: str = "no progress bar") -> None:
    p.add_argument("--quiet", action="store_true", help=what)


def register(sub, bench) -> None:
    p = sub.add_parser("figures", help="regenerate the paper's Fig. 2 and Fig. 3")
    p.add_argument("--out", type=A.output_folder, default="out/figures",
                   help="output folder (default out/figures)")
    A.add_aircraft(p)
    _quiet(p)
    add_json(p)
    p.set_defaults(fn=cmd_figures)

    p = sub.add_parser("trim", help="periodic trim: controls, attitude and periodic rotor states by Newton "
                       "with the exact AD Jacobian of the period map")
    _add_periodic_arguments(p)
    p.add_argument("--climb-rate", type=A.climb_rate, default=0.0,
                   help=f"climb rate in m/s, up positive, {CLIMB_RANGE[0]:g} to {CLIMB_RANGE[1]:g} (default 0)")
    p.add_argument("--bank", type=A.within(-1.2, 1.2, "rad", "the bank angles a trim holds"), default=None,
                   help="hold this roll angle in rad (right wing down positive) and trim the sideslip instead "
                        "(--bank 0: a zero-bank trim); default: zero sideslip, the roll trimmed")
    p.add_argument("--turn-rate", type=A.within(-1.0, 1.0, "rad/s", "the turn rates a trim holds"), default=0.0,
                   help="steady turn: the heading's rate in rad/s, right positive (default 0: straight flight)")
    p.add_argument("--tol", type=A.tolerance, default=1e-10,
                   help="max |scaled residual| to reach, at most 1e-3 (default 1e-10)")
    p.add_argument("--iterations", type=A.positive_int, default=20,
                   help="most Newton iterations before giving up (default 20)")
    p.add_argument("--write", metavar="PATH", nargs="?", const=str(user_trims()), default=None,
                   type=trim_file, help="store the converged trim in the TOML file PATH (other trims kept), keyed by "
                   "the aircraft file (its SHA-256), scene, aerodynamics switches, speed, climb rate, method and steps "
                   f"per revolution; without PATH in {user_trims()}. 'heli simulate' starts from a stored trim of the "
                   "same model found there or in <aircraft stem>_trim.toml beside the aircraft file")
    _aero(p)
    _air(p)
    _quiet(p)
    add_json(p)
    p.set_defaults(fn=cmd_trim)

    p = sub.add_parser("floquet", help="Floquet stability at the periodic trim: multipliers, exponents, modes")
    _add_periodic_arguments(p)
    p.add_argument("--set", action="append", metavar="NAME=VALUE", type=A.checked_by(_setting),
                   help="run-time parameter value, e.g. lag_damping=50 (repeatable)")
    p.add_argument("--sweep", metavar="NAME=LO:HI:N", default=None, type=A.checked_by(_sweep),
                   help="fan plot: analyse at N values of a run-time parameter, e.g. omega=20:60:30; writes "
                        "fanplot_SCENE.png and .csv into --out")
    p.add_argument("--frame", choices=("fixed", "rotating"), default="fixed",
                   help="rotor-mode frequencies and names in the fixed frame (multi-blade coordinates, default) "
                        "or per blade (rotating)")
    p.add_argument("--out", type=A.output_folder, default=None, help="output folder: writes floquet_SCENE.png and "
                   ".csv (default: print only); with --sweep the fan plot's files (default out/floquet)")
    _quiet(p)
    add_json(p)
    _aero(p)
    _air(p)
    p.set_defaults(fn=cmd_floquet)

    p = sub.add_parser("derivatives", help="stability and control derivatives at trim (quasi-static rotor in its "
                       "periodic equilibrium), the A and B matrices and the flight modes")
    _add_periodic_arguments(p)
    p.add_argument("--mat", metavar="FILE", default=None, type=A.matrix_file,
                   help="write A, B and the mode names to FILE (.mat for MATLAB, or .npz)")
    _quiet(p, "no build messages")
    add_json(p)
    _aero(p)
    _air(p)
    p.set_defaults(fn=cmd_derivatives)

    p = sub.add_parser("scenes", help="list the scenes: bodies, degrees of freedom, force elements")
    p.add_argument("--markdown", action="store_true", help="print the scene table of docs/method/helicopter-model.md instead")
    add_json(p)
    p.set_defaults(fn=cmd_scenes)

    p = sub.add_parser("simulate", help="run a scene and write results.csv, run.json and plots")
    A.add_scene(p)
    A.add_aircraft(p)
    p.add_argument("--revs", type=A.positive, default=1.0, help="main-rotor revolutions (default 1)")
    _steps_per_rev(p)
    p.add_argument("--method", choices=FIXED_METHODS, default="rk4",
                   help="fixed-step method of the generated driver (default rk4, the paper's)")
    p.add_argument("--dtype", choices=("float64", "float32"), default="float64",
                   help="floating-point precision of the compiled code (default float64; float32 needs "
                        "--backend compiled)")
    _backend(p)
    p.add_argument("--every", type=A.positive_int, default=1, help="record every N-th step (default 1: all)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", type=A.checked_by(_setting),
                   help="a control (collective, lateral_cyclic, longitudinal_cyclic, tail_collective; rad), another "
                        "run-time parameter (e.g. omega=40) or speed=V, the initial forward speed in m/s of a free "
                        "fuselage (level flight at the start's attitude); repeatable; 'heli scenes --json' lists "
                        "each scene's parameters")
    p.add_argument("--inputs", metavar="FILE", type=A.input_table, default=None,
                   help="input table: a CSV file with a 'time' column (s) and columns named after parameters (the "
                        "FMU demo's and fmpy's format); linear between rows, a time written twice is a jump, each "
                        "step holds the values at its start; written into results.csv as columns")
    p.add_argument("--start", type=A.checked_by(_parse_start), default=None, metavar="START",
                   help="initial state: trim, the scene's periodic trim at the run's speed and parameters (stored for "
                        "the aircraft file, or trimmed on first use and stored; the default for the scenes that fly: "
                        "forward-flight, hover and the swashplate scenes); scene, the scene's own initial state (the "
                        "default for the others); periodic or periodic:V, the periodic trim at the scene's speed or "
                        "at V m/s computed now at the run's steps per revolution (as 'heli fly' starts its page, so "
                        "that a flight replays from the same state); run.json records it")
    p.add_argument("--step-tol", type=A.fraction, default=0.01, metavar="FRACTION",
                   help="largest step error allowed, as a fraction of each state's range over the first revolution "
                        "(default 0.01): a step-doubling check (three revolutions' worth of steps) warns above it "
                        "with the --steps-per-rev that would do")
    p.add_argument("--max-gb", type=A.positive, default=1.0, metavar="GB",
                   help="refuse a run whose results.csv would exceed this size (default 1 GB; the estimate and the "
                        "run's time are printed first for long runs); --every N records fewer rows")
    p.add_argument("--out", type=A.output_folder, default="out/simulate", help="output folder (default out/simulate)")
    _aero(p)
    _air(p)
    _quiet(p)
    add_json(p)
    p.set_defaults(fn=cmd_simulate)
