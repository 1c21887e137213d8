"""Where a run starts: its scene's periodic trim (stored, or computed and stored on first use)
or the scene's own initial state; either way said on stderr and recorded in ``run.json``
(``"initial_state"``: where it came from and every state by name)."""
from __future__ import annotations

import numpy as np

from mbs.trims import store
from mbs.trims.entry import TOLERANCE, entry_of, residual, scene_identity

TRIM, SCENE = "trim", "scene"


def default_start(scene) -> str:
    """``trim`` for a trimmable scene whose fuselage flies free (forward-flight, hover and the
    swashplate scenes) and for one whose engines govern a rotor speed that is a state (the engine
    failures, hover-engines), ``scene`` otherwise."""
    from mbs.analysis.trim import trimmable

    return TRIM if _flies(scene) and (trimmable(scene) or governed(scene)) else SCENE


def governed(scene) -> bool:
    """Whether ``scene``'s rotor speed is a state held by its engines' governor: its steady state
    is a trim at the nominal rotor speed with the governor's reference solved for."""
    return "governor_speed" in scene.model().parameters


def check(start: str, scene) -> None:
    """Refuse ``--start trim`` for a scene that has no periodic solution, saying why."""
    from mbs.analysis.trim import trimmable

    if start != TRIM or trimmable(scene) or (governed(scene) and _flies(scene)):
        return
    if scene.options.get("drive_train", getattr(getattr(scene.builder, "config", None), "drive_train", None)):
        raise ValueError(f"--start trim: scene {scene.name!r} turns its rotors at a speed that is a state without an "
                         "engine governing it: its steady state is an autorotation ('heli autorotation' trims it); "
                         "it starts from its own initial state: drop --start or give --start scene")
    raise ValueError(f"--start trim: scene {scene.name!r} has no periodic trim (it has no controls or no rotor "
                     f"aerodynamics); it starts from its own initial state: drop --start or give --start scene")


def _flies(scene) -> bool:
    return any(type(b.joint).__name__ == "FreeJoint" for b in scene.model().bodies.values())


def from_trim(run, speed: float | None, log=print, progress=None) -> None:
    """Start ``run`` (a :class:`mbs.simulate.Run`) from the periodic trim of its scene at
    ``speed`` (m/s; default the scene's) and its ``--set`` parameters other than controls:
    the stored trim of that model when one holds (checked by running it over its period), else
    trimmed now and stored in :func:`mbs.trims.store.default_file`. The trim is RK4's at the
    scene's steps per revolution (a run at another step starts from it with a discretisation
    error of that order). The ``--set`` controls then replace the trim's from t = 0. ``log``:
    one-line messages."""
    scene, system = run.scene, _float64(run)
    controls = [q["name"] for q in system.info.parameters if q.get("control")]
    fixed = {k: v for k, v in run.settings.items() if k not in controls and k != "speed"}
    speed = _scene_speed(system) if speed is None else float(speed)
    ident = scene_identity(scene, fixed, speed, 0.0, "rk4", scene.steps_per_rev)  # the accurate step, whatever the run's
    system = _with(system, fixed)
    what = _what(scene, speed, fixed)
    path, name, entry, check_r, computed = _stored(scene, system, ident, what, log)
    if entry is None:
        path, name, entry = _computed(scene, system, ident, what, log, progress, run.system.backend)
        check_r, computed = residual(entry, system, scene), True
    run.x0 = np.array([entry["state"][n] for n in run.system.info.state_names])
    given = {k: v for k, v in run.settings.items() if k in controls}
    run.p = run.system.params({**entry["controls"], **fixed, **given})
    run.start = {"from": "periodic trim", "computed_now": computed, "file": str(path) if path else None, "key": name,
                 "speed": entry["speed"], "climb_rate": entry["climb_rate"], "method": entry["method"],
                 "steps_per_rev": entry["steps_per_rev"], "parameters": entry["parameters"],
                 "controls": entry["controls"], "controls_set": given, "roll_deg": float(np.degrees(entry["roll"])),
                 "pitch_deg": float(np.degrees(entry["pitch"])), "max_abs_residual": entry["max_abs_residual"],
                 "check_residual": check_r}
    if given:
        log("  the --set " + ", ".join(f"{k}={v:g}" for k, v in given.items()) + " replace the trim's "
            + ", ".join(f"{k} {entry['controls'][k]:.5g}" for k in given) + " rad from t = 0: a step from the trim")


def _stored(scene, system, ident, what, log):
    """``(file, name, entry, residual, False)`` of a stored trim that holds, else Nones."""
    files = _files(scene)
    found = store.find(files, ident)
    if found is None:
        return None, None, None, None, False
    path, name, entry = found
    r = residual(entry, system, scene)
    if r > TOLERANCE:
        log(f"heli simulate: the stored trim {name!r} in {path} no longer holds for this model (periodicity "
            f"residual {r:.3g} > {TOLERANCE:g}: the program changed since); trimming again")
        return None, None, None, None, False
    log(f"heli simulate: starting from the periodic trim of {what}, stored in {path}")
    return path, name, entry, r, False


def _computed(scene, system, ident, what, log, progress, backend):
    """Trim now, store the result and return ``(file, name, entry)``; ValueError when the trim
    does not converge."""
    from mbs.analysis.trim import trim
    from mbs.cli import warn

    craft = scene.aircraft
    earlier = store.earlier_versions(_files(scene), ident, str(craft.path.resolve())) if craft is not None else []
    why = f" (the stored one is of an earlier version of {craft.path})" if earlier else ""
    log(f"heli simulate: no stored periodic trim of {what}{why}; trimming it now (for a new aircraft about a "
        "minute, most of it compiling the model's AD step) and storing it; --start scene starts from the scene's "
        "own state instead")
    if governed(scene):
        entry, path = _governed_entry(scene, ident, what, progress), store.default_file()
        took = entry.pop("wall_s")
    else:
        res = trim(scene, speed=ident["speed"], method=ident["method"], steps_per_rev=ident["steps_per_rev"],
                   backend=backend or "compiled", system=system, progress=progress)
        if not res.converged:
            raise ValueError(f"no periodic trim of {what}: {res.reason}; 'heli trim {scene.name} --speed "
                             f"{ident['speed']:g}' shows the iterations; --start scene starts from the scene's own "
                             "state (with a transient)")
        entry, path = entry_of(res, scene, ident["parameters"]), store.default_file()
        took = res.wall_s + res.setup_s
    try:
        name = store.write(path, entry)
    except (OSError, ValueError) as exc:
        warn(f"the trim could not be stored in {path} ({getattr(exc, 'strerror', None) or exc}): the next run trims "
             "again; set XDG_DATA_HOME to a writable folder")
        return None, store.key(entry), entry
    log(f"heli simulate: trimmed in {took:.1f} s; stored in {path} (later runs start from it)")
    return path, name, entry


def _governed_entry(scene, ident: dict, what: str, progress=None) -> dict:
    """The stored form of the trim of a scene whose engines govern its rotor speed: the rotor at
    its nominal speed, the governor's reference solved for (:mod:`mbs.analysis.rotor_speed_trim`)."""
    import time

    from mbs.analysis.period import periodic_scene, scene_period
    from mbs.analysis.rotor_speed_trim import rotor_speed_trim
    from mbs.analysis.trim import evaluators

    start = time.perf_counter()
    system, stepper = evaluators(scene)
    system = _with(system, ident["parameters"])
    res = rotor_speed_trim(scene, ident["speed"], extra="governor_speed", steps_per_rev=ident["steps_per_rev"],
                           system=system, stepper=stepper, progress=progress)
    if not res.converged:
        raise ValueError(f"no periodic trim of {what} (its rotor speed held by the governor): {res.reason}; "
                         "--start scene starts from the scene's own state (with a transient)")
    controls = [q["name"] for q in system.info.parameters if q.get("control") and not q["name"].endswith("_throttle")]
    craft = scene.aircraft
    about = {"aircraft": craft.name, "aircraft_file": str(craft.path.resolve())} if craft is not None else {}
    entry = {"scene": ident["scene"], **about, **ident, "shooting_revs": scene_period(periodic_scene(scene), system).revs,
             "controls": {**{c: float(res.unknowns[c]) for c in controls},
                          "governor_speed": float(res.unknowns["governor_speed"])},
             "roll": float(res.unknowns["roll"]), "pitch": float(res.unknowns["pitch"]),
             "max_abs_residual": float(res.residual),
             "state": dict(zip(system.info.state_names, map(float, res.x0)))}
    entry["wall_s"] = time.perf_counter() - start
    return entry


def _files(scene) -> list:
    craft = scene.aircraft
    return ([store.beside(craft)] if craft is not None else []) + [store.default_file()]


def _float64(run):
    """The run's system, or its float64 twin (a trim is computed and checked in float64)."""
    if run.system.dtype == np.float64:
        return run.system
    return run.scene.system(run.system.backend if run.system.backend in ("compiled", "vm") else "compiled")


def _with(system, fixed: dict):
    if not fixed:
        return system
    from mbs.analysis.fanplot import WithParameters

    return WithParameters(system, **fixed)


def _scene_speed(system) -> float:
    """The scene's own flight speed (m/s): that of its initial state's free fuselage (0 without)."""
    from mbs.inputs import initial_speed

    speed = initial_speed(system.info, system.x0())
    return 0.0 if speed is None else round(speed, 6)


def _what(scene, speed: float, fixed: dict) -> str:
    """``forward-flight at 10 m/s of the My helicopter (my_helicopter.toml)``, with the parameters."""
    craft = f" of the {scene.aircraft.name} ({scene.aircraft.path.name})" if scene.aircraft is not None else ""
    with_ = ", " + ", ".join(f"{k} = {v:g}" for k, v in fixed.items()) if fixed else ""
    return f"{scene.name} at {speed:g} m/s{craft}{with_}"


def scene_record(run) -> dict:
    """What ``run.json`` says of a run that starts from the scene's own initial state:
    ``estimate`` is true when that is the closed-form trim estimate, not a stored trim."""
    what, estimate = _scene_origin(run.scene)
    return {"from": "scene", "what": what, "estimate": estimate}


def _scene_origin(scene) -> tuple[str, bool]:
    if scene.aircraft is None:
        return "the scene's initial state", False
    from mbs.models.helicopter import stored_trim
    from mbs.models.helicopter.config import config_of

    cfg = config_of(scene)
    if stored_trim(scene.aircraft, cfg.trim, cfg.speed):
        return (f"the scene's initial state: controls, attitude and inflow of the trim stored in "
                f"{store.beside(scene.aircraft).name}, blades at the estimated coning and flapping with zero lag"), False
    if cfg.rotors == "driven" and cfg.pitch_hinge:
        return ("the scene's initial state: controls, attitude and flapping of the closed-form trim estimate "
                "(momentum and blade-element theory), not a trim"), True
    return "the scene's initial state", False


def untrimmed_warning(run) -> str | None:
    """A warning when a free-flying trimmable scene starts from the closed-form estimate."""
    if default_start(run.scene) != TRIM or not run.start.get("estimate"):
        return None
    return (f"--start scene: scene {run.scene.name!r} of the {run.scene.aircraft.name} starts from the closed-form "
            "trim estimate, not a trim, so it starts with a transient; without --start scene it starts from its "
            "periodic trim")


def estimate_warning(scene, who: str) -> str | None:
    """A warning for ``who`` (a command that runs the scene from its own initial state) when
    that state is the closed-form estimate of a free-flying trimmable scene."""
    if default_start(scene) != TRIM or not _scene_origin(scene)[1]:
        return None
    return (f"{who} starts scene {scene.name!r} of the {scene.aircraft.name} from its own initial state, the "
            "closed-form trim estimate, not a trim: expect a start-up transient ('heli simulate' starts from the "
            "periodic trim)")
