"""The work of one sweep point, run on a Dask worker (or in-process for a plain loop).

Every point starts from the same state whatever the schedule: a trim from the built-in
closed-form estimate at its own speed (no warm start from a neighbour), a simulation from the
scene's initial state, a Floquet analysis from its own periodic solution. So a point's result
depends only on its inputs, never on which worker ran it or what ran before.

A point whose model fails (no trim, divergence, a parameter outside its range) returns a row
with status ``"failed"`` and the message; only unexpected exceptions escape (the runner
records them as ``"error"``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from mbs.sweep import models

ENVELOPE = {"min": np.min, "max": np.max, "mean": np.mean}
MODEL_ERRORS = (ValueError, RuntimeError, FloatingPointError, ArithmeticError, np.linalg.LinAlgError)


@dataclass(frozen=True)
class Task:
    """One point: the sweep ``kind`` (trim, simulate, floquet), ``scene``, ``inputs`` (axis
    name -> value, SI units), fixed ``options`` and the compiled-model cache folder."""

    kind: str
    scene: str
    inputs: dict
    options: dict = field(default_factory=dict)
    cache_dir: str = ""


def run_task(task: Task) -> dict:
    """The table row of ``task``: inputs, outputs, ``status``, ``message`` and ``wall_s`` (s)."""
    compute = {"trim": trim_point, "simulate": simulate_point, "floquet": floquet_point}[task.kind]
    built = models.loaded(task.kind, task.scene, task.options, task.cache_dir)
    start = time.perf_counter()
    try:
        outputs, status, message = compute(built, task.scene, task.inputs, task.options)
    except MODEL_ERRORS as exc:
        outputs, status, message = {}, "failed", f"{type(exc).__name__}: {exc}"
    return {**task.inputs, **outputs, "status": status, "message": message,
            "wall_s": time.perf_counter() - start}


def _parameters(inputs: dict, skip: tuple[str, ...]) -> dict[str, float]:
    """The run-time parameter values among ``inputs`` (the others are not parameters)."""
    return {k: v for k, v in inputs.items() if k not in skip}


def trim_point(built, scene: str, inputs: dict, options: dict) -> tuple[dict, str, str]:
    """Trim at ``inputs["speed"]`` (m/s), ``climb_rate`` (m/s) and any run-time parameters; its
    message carries the trim's warnings (:func:`mbs.analysis.trim_checks.warnings`)."""
    from mbs.analysis.fanplot import WithParameters
    from mbs.analysis.trim import trim

    system, stepper = built
    system = WithParameters(system, **_parameters(inputs, ("speed", "climb_rate")))
    res = trim(models.scene_of(scene, options), speed=inputs.get("speed", options.get("speed")),
               climb_rate=inputs.get("climb_rate", options.get("climb_rate", 0.0)),
               method=options.get("method", "rk4"), steps_per_rev=options.get("steps_per_rev"),
               tol=options.get("tol", 1e-10), max_iterations=options.get("iterations", 20),
               system=system, stepper=stepper)
    work = {"iterations": res.iterations, "max_abs_residual": float(np.abs(res.residual).max())}
    if not res.converged:  # the last iterate is no trim: only the work is reported
        return work, "failed", res.reason
    said = "; ".join([res.reason, *(f"warning: {w}" for w in getattr(res, "warnings", []))])
    return {**res.controls, "roll": res.roll, "pitch": res.pitch, "thrust": res.thrust, **res.output_means,
            **work}, "ok", said


def simulate_point(built, scene: str, inputs: dict, options: dict) -> tuple[dict, str, str]:
    """Run ``options["revs"]`` revolutions with the run-time parameters ``inputs``; the output
    is the envelope (min, max, mean) of every plotted coordinate and model output."""
    from mbs.simulate import simulate

    sim = simulate(models.scene_of(scene, options), options.get("revs", 1.0), options.get("steps_per_rev"),
                   params=dict(inputs),
                   system=built, method=options.get("method", "rk4"))
    if not sim.traj.ok:
        return {}, "failed", sim.traj.message
    cols = sim.columns()
    out = {f"{n}.{s}": float(f(cols[n])) for n in envelope_names(sim, cols) for s, f in ENVELOPE.items()}
    return out, "ok", sim.traj.message


def envelope_names(sim, cols: dict) -> list[str]:
    """The coordinates the scene plots and the model outputs other than azimuths (in ``cols``)."""
    plotted = [n for names in sim.scene.plots.values() for n in names]
    outputs = [n for n in sim.system.info.output_names if not n.endswith(".azimuth")]
    return [n for n in dict.fromkeys(plotted + outputs) if n in cols]


def floquet_point(built, scene: str, inputs: dict, options: dict) -> tuple[dict, str, str]:
    """Floquet analysis at the run-time parameters ``inputs`` (e.g. ``omega``, rad/s): per mode
    (least damped first) its name, frequency (Hz), ``Re λ`` (1/s), damping ratio, |multiplier|."""
    p = built.at(**inputs)
    if not p.floquet:
        return {}, "failed", p.status
    modes = p.floquet.modes
    out = {"stable": not p.unstable, "max_multiplier": max(abs(m.multiplier) for m in modes),
           "mode": list(p.names), "frequency_hz": [m.frequency_hz for m in modes],
           "real_per_s": [m.exponent.real for m in modes], "damping_ratio": [m.damping_ratio for m in modes],
           "multiplier_modulus": [abs(m.multiplier) for m in modes]}
    return out, "ok", p.status


def warm(kind: str, scene: str, options: dict, cache_dir: str) -> None:
    """Load the models of a sweep in this worker process before its first task."""
    models.loaded(kind, scene, options, cache_dir)
