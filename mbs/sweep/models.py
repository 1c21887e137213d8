"""The compiled models of a sweep: built once in the client, loaded from the cache by workers.

The client calls :func:`loaded` before any task is submitted, which generates and compiles
the model (and, for trims and Floquet analyses, its tangent-step library) into the
compiled-model cache (``$MBS_CACHE_DIR`` or ``~/.cache/mbs``). Each worker process calls it
again on its first task with the client's cache folder: the generated source hashes to the
folder the client built, so the worker loads the library from there and compiles nothing.
Built models are kept per process, so later tasks on that worker reuse them. A sweep's
parallelism is its processes: the tangent stepper of a trim runs its blocks in one thread.
"""
from __future__ import annotations

import inspect
import json
import os

KINDS = ("trim", "simulate", "floquet")
_LOADED: dict[str, object] = {}


def loaded(kind: str, scene: str, options: dict, cache_dir: str = ""):
    """The built evaluators of ``kind`` for ``scene`` in this process (built on first use):
    trim: ``(system, tangent stepper)``; simulate: the system; floquet: a
    :class:`mbs.analysis.fanplot.FanPlotAnalysis`. ``cache_dir`` (when given) becomes
    ``$MBS_CACHE_DIR`` of this process first."""
    key = json.dumps([kind, scene, _model_options(kind, options)], sort_keys=True)
    if key not in _LOADED:
        if cache_dir:
            os.environ["MBS_CACHE_DIR"] = cache_dir
        _LOADED[key] = build(kind, scene, options)
    return _LOADED[key]


def _model_options(kind: str, options: dict) -> dict:
    """The options that change the built evaluators (not those of a single point)."""
    names = {"trim": ("backend", "method"), "simulate": ("backend", "dtype"),
             "floquet": ("backend", "method", "steps_per_rev", "settings", "frame")}[kind]
    return {n: options.get(n) for n in (*names, "aircraft", "environment")}


def scene_of(scene: str, options: dict):
    """The scene ``scene`` of the sweep's aircraft (``options["aircraft"]``: file and SHA-256, or
    absent for the Bo105) in its air (``options["environment"]``: the scene options of
    :func:`mbs.models.helicopter.air_options.environment_record`, e.g. ``{"atmosphere": "isa"}`` or
    ``{"turbulence": "dryden"}``); ValueError when the file has changed since the sweep began."""
    from mbs import aircraft, scenes
    from mbs.models.helicopter.air_options import environment_of_record

    recorded = options.get("aircraft")
    craft = aircraft.load(recorded["file"]) if recorded else None
    if craft is not None and craft.digest != recorded["sha256"]:
        raise ValueError(f"the aircraft file {recorded['file']} has changed since the sweep began")
    sc = scenes.get(scene, aircraft=craft)
    return environment_of_record(sc, options["environment"]) if options.get("environment") else sc


def aircraft_option(craft) -> dict:
    """``options["aircraft"]`` of a sweep of ``craft`` (an :class:`mbs.aircraft.Aircraft`)."""
    return {"file": str(craft.path.resolve()), "sha256": craft.digest}


def build(kind: str, scene: str, options: dict):
    """Build (compile, or load from the cache) what a point of ``kind`` needs."""
    if kind not in KINDS:
        raise ValueError(f"sweep kind {kind!r} unknown; choose one of {', '.join(KINDS)}")
    sc, backend = scene_of(scene, options), options.get("backend", "compiled")
    if kind == "simulate":
        return sc.system(backend, options.get("dtype", "float64"))
    if kind == "trim":
        return _trim_evaluators(sc, backend, options.get("method", "rk4"))
    from mbs.analysis.fanplot import FanPlotAnalysis

    ana = FanPlotAnalysis(sc, options.get("settings") or {}, options.get("method", "rk4"),
                          options.get("steps_per_rev"), backend, options.get("frame", "fixed") != "rotating")
    ana.stepper = _stepper(ana.scene, options.get("method", "rk4"), backend)
    return ana


def _trim_evaluators(sc, backend: str, method: str):
    """The system and tangent stepper of a trimmable scene (ValueError naming the scene otherwise)."""
    from mbs.analysis.trim import _check_scene

    sc = _check_scene(sc)
    return sc.system(backend), _stepper(sc, method, backend)


def _stepper(sc, method: str, backend: str):
    """The scene's tangent stepper, running its blocks of directions in one thread (where it can
    use more): a sweep's parallelism is its worker processes."""
    from mbs.analysis.monodromy import TangentStepper

    threads = {"workers": 1} if "workers" in inspect.signature(TangentStepper).parameters else {}
    return TangentStepper(sc.model(), method, backend, **threads)


def check_axes(kind: str, scene: str, options: dict, names: list[str]) -> None:
    """Refuse axis names that are not inputs of ``kind`` (ValueError naming them and the known
    ones), from the scene's symbolic model: nothing is compiled."""
    model = scene_of(scene, options).model()
    params = list(model.parameters)
    if kind == "trim":
        controls = [n for n, p in model.parameters.items() if p.control]
        free = any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())  # a flight speed needs one
        params = ["speed", "climb_rate"] * free + [p for p in params if p not in controls]
    bad = [n for n in names if n not in params]
    if bad:
        why = " (it has no free fuselage: no flight speed)" if kind == "trim" and not free else ""
        raise ValueError(f"cannot sweep {', '.join(map(repr, bad))} in a {kind} sweep of {scene!r}{why}; "
                         f"sweepable: {', '.join(params) or 'nothing'}")
