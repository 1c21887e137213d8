"""``heli autorotation``: the steady autorotation of a scene whose rotor speed is a state, trimmed
at several forward speeds (:mod:`mbs.analysis.rotor_speed_trim`)."""
from __future__ import annotations

from mbs import arguments as A
from mbs.cli import add_json, emit

FT_PER_MIN = 196.850394  # per m/s


AUTOROTATION_SPEED = A.Within(5.0, 90.0, "m/s", "the speeds of a steady autorotation (below 5 m/s the wake is in "
                              "the vortex ring state, which the inflow models do not cover)", units=A.SPEED_UNITS)


def speed_list(text: str) -> list[float]:
    """``20,30,40`` (m/s) or ``50kt,70kt``: speeds from 5 to 90 m/s."""
    items = [t for t in str(text).split(",") if t.strip()]
    if not items:
        raise ValueError(f"{text!r} is not a comma-separated list of speeds (m/s, or with a unit: 50kt,70kt)")
    try:
        return [AUTOROTATION_SPEED(t) for t in items]
    except A.Bad as exc:
        raise ValueError(f"{text!r}: {exc}") from None


def cmd_autorotation(args) -> int:
    from mbs.analysis.period import periodic_scene, scene_period
    from mbs.analysis.rotor_speed_trim import descent_estimate, rotor_speed_trim
    from mbs.analysis.trim import evaluators
    from mbs.commands import _scene

    sc = _scene(args)
    _check(sc)
    sc = periodic_scene(sc)  # a tail rotor that does not repeat soon turns at the nearest ratio that does
    speeds = speed_list(args.speeds)
    omega = rotor_speed(args.rotor_speed, sc.aircraft.data["main_rotor"])  # checked before the model is built
    system, stepper = evaluators(sc)
    rows, lines = [], [f"{sc.name}: steady autorotation at the rotor's nominal speed (descent rate solved for)"]
    gear = scene_period(sc, system).gear
    approximation = gear.text() if gear is not None and not gear.exact else None
    lines += [f"  approximation: {approximation}"] if approximation else []
    if omega is not None:
        lines[0] = lines[0].replace("at the rotor's nominal speed", f"at {omega:.4g} rad/s")
    for v in speeds:
        res = rotor_speed_trim(sc, v, steps_per_rev=args.steps_per_rev, system=system, stepper=stepper, omega=omega)
        row = {"speed": v, "converged": res.converged, "reason": res.reason, "iterations": res.iterations,
               "climb_rate": res.climb_rate, "descent_rate": -res.climb_rate,
               "energy_method_descent_rate": -descent_estimate(sc, v), "controls":
               {k: res.unknowns[k] for k in ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective")
                if k in res.unknowns}, "mean_aerodynamic_torque": res.mean_torque,
               "torque_balance": res.torque_balance, "wall_s": res.wall_s}
        rows.append(row)
        lines.append(f"  {v:5.1f} m/s: " + (f"descent {-res.climb_rate:6.2f} m/s ({-res.climb_rate * FT_PER_MIN:5.0f} "
                                          f"ft/min; energy method {row['energy_method_descent_rate']:.2f} m/s), "
                                          f"collective {row['controls']['collective']:.4f} rad, {res.iterations} "
                                          "Newton iterations" if res.converged else f"no trim: {res.reason}"))
    emit({"scene": sc.name, "trims": rows, "approximation": approximation}, args.json, lines)
    return 0 if all(r["converged"] for r in rows) else 1


def rotor_speed(text: str | None, mr: dict) -> float | None:
    """``--rotor-speed``: rad/s, ``400rpm``, or ``90%`` of the nominal speed (None: nominal);
    ValueError outside the rotor's omega_min..omega_max."""
    if text is None:
        return None
    t = str(text).strip().lower().replace(" ", "")
    try:
        if t.endswith("%"):
            omega = float(t[:-1]) / 100 * mr["omega"]
        elif t.endswith("rpm"):
            omega = float(t[:-3]) * 2 * 3.141592653589793 / 60
        else:
            omega = float(t.removesuffix("rad/s"))
    except ValueError:
        raise ValueError(f"--rotor-speed {text!r}: give rad/s, rpm (400rpm) or a percentage of the nominal speed "
                         "(90%)") from None
    if not mr["omega_min"] <= omega <= mr["omega_max"]:
        raise ValueError(f"--rotor-speed {text!r} ({omega:.4g} rad/s) is outside the rotor's omega_min..omega_max, "
                         f"{mr['omega_min']:.4g} to {mr['omega_max']:.4g} rad/s")
    return omega


def _check(sc) -> None:
    """ValueError unless ``sc`` turns its rotors on a free-wheeling rigid drive train in free flight."""
    from mbs import scenes
    from mbs.models.helicopter.config import config_of

    cfg = config_of(sc)
    options = {**{k: getattr(cfg, k) for k in ("drive_train", "engines", "fuselage")}, **sc.options}
    ok = ", ".join(n for n, s in scenes.all_scenes().items() if s.aircraft is not None
                   and getattr(s.builder.config, "drive_train", None) == "rigid" and not s.builder.config.engines)
    if options["drive_train"] != "rigid" or options["engines"] or options["fuselage"] != "free":
        raise ValueError(f"scene {sc.name!r} cannot autorotate: the trim needs a free fuselage and the rotor speed as "
                         f"a state on a rigid drive train without engines (scenes: {ok})")


def register(sub, bench) -> None:
    from mbs.commands import _air, _quiet, _steps_per_rev

    p = sub.add_parser("autorotation", help="steady autorotation: periodic trims with the rotor speed a state, no "
                       "engine torque, the descent rate solved for")
    A.add_scene(p, nargs="?", default="autorotation", what="scene (default autorotation)")
    A.add_aircraft(p)
    p.add_argument("--speeds", default="20,30,40", type=A.checked_by(speed_list), metavar="V1,V2,...",
                   help="forward speeds in m/s, 5 to 90 (a steady autorotation), or with a unit: 50kt,70kt "
                        "(default 20,30,40)")
    p.add_argument("--rotor-speed", default=None, metavar="OMEGA",
                   help="the rotor speed held: rad/s, rpm (400rpm) or a percentage of the nominal (90%%); "
                        "default the nominal speed")
    _steps_per_rev(p)
    _air(p)
    _quiet(p, "no build messages")
    add_json(p)
    p.set_defaults(fn=cmd_autorotation)
