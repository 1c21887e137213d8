"""The model's side of a validation: periodic trims, and stability and control derivatives with
their eigenvalues, at the published speeds, from one build of the scene.

Each speed is trimmed from the closed-form estimate (with the trim's own continuation in speed
when Newton from it fails); the derivatives follow from the trim by the quasi-static rotor
(:func:`mbs.analysis.derivatives.linearise`). A speed that does not trim is kept, with the
reason, and its comparisons read "no trim".
"""
from __future__ import annotations

from dataclasses import dataclass, field

from mbs.analysis.derivatives import Derivatives, in_pilot_controls, linearise, model_warnings


@dataclass
class Point:
    """The model at one speed (m/s): its trim, and its derivatives when they were asked for
    (None when the trim failed or they were not)."""

    speed: float
    trim: object
    derivatives: Derivatives | None = None
    problem: str = ""
    condition: str = ""  # its mass, altitude and CG where the data give them

    @property
    def ok(self) -> bool:
        return not self.problem


@dataclass
class Model:
    """The model's points by speed (m/s) and the work done."""

    scene: str
    aircraft: str
    points: dict[float, Point] = field(default_factory=dict)
    wall_s: float = 0.0
    controls: str = ""  # the conventions of the model's control angles and pilot controls, in words

    def at(self, speed: float, mass: float | None = None, altitude: float | None = None,
           cg_x: float | None = None) -> Point:
        """The point at ``speed`` (m/s) and, where the data give them, ``mass`` (kg), ``altitude``
        (m) and ``cg_x`` (m forward of the aircraft file's CG)."""
        from mbs.validate.data import condition_key

        return self.points[condition_key(speed, mass, altitude, cg_x)]


def scene_of(validation, aircraft=None, aero: str | None = None):
    """The scene of ``validation`` built with ``aircraft`` (an :class:`mbs.aircraft.Aircraft`;
    default the aircraft the file names, packaged or a path relative to the file)."""
    from mbs import aircraft as craft
    from mbs import scenes

    if aircraft is None:
        name = validation.aircraft
        near = validation.path.parent / name
        aircraft = craft.load(str(near) if near.suffix == ".toml" and near.is_file() else name)
    scene = scenes.get(validation.scene, aircraft=aircraft)
    if aero is not None:
        from mbs.models.helicopter import with_aero

        try:
            scene = with_aero(scene, aero)
        except ValueError as exc:
            raise ValueError(f"--aero {aero!r}: {exc}") from None
    return scene


def run(scene, trim_speeds: list, derivative_speeds: list, method: str = "rk4",
        steps_per_rev: int | None = None, backend: str = "compiled", progress=None, check=None) -> Model:
    """Trims at ``trim_speeds`` and derivatives at ``derivative_speeds`` of ``scene``: speeds (m/s)
    or flight conditions ``(speed m/s, mass kg, altitude m, cg_x m)`` (None: the aircraft file's),
    a mass as a weight added at the CG (the run-time ``payload``), an altitude in the ISA, a CG
    forward of the file's as the weight's point (``cg_x``); ``check(info)`` is called with the
    built system's description before the first trim."""
    import time

    from mbs.analysis.fanplot import WithParameters
    from mbs.analysis.held import HeldStepper
    from mbs.analysis.period import periodic_scene
    from mbs.analysis.trim import evaluators, periodic_solution
    from mbs.validate.compare import describe_condition
    from mbs.validate.data import condition, condition_key

    trims, derivatives = ([condition(c) for c in points] for points in (trim_speeds, derivative_speeds))
    scene = _in_conditions(scene, trims + derivatives)
    start, scene = time.perf_counter(), periodic_scene(scene)  # the tail rotor at a ratio that repeats
    system, stepper = evaluators(scene, method, backend)
    if check is not None:
        check(system.info)
    held = HeldStepper(scene.model(), method, backend) if derivatives else None
    conditions = sorted(set(trims) | set(derivatives), key=lambda c: tuple(x or 0.0 for x in c))
    out = Model(scene.name, scene.aircraft.name if scene.aircraft else "",
                controls=controls_convention(scene.aircraft.data) if scene.aircraft else "")
    base = scene.aircraft.data["aircraft"]["mass"] if scene.aircraft else 0.0
    for k, (v, mass, altitude, cg_x) in enumerate(conditions):
        values = {name: value for name, value in (("payload", None if mass is None else mass - base),
                                                  ("altitude", altitude), ("cg_x", cg_x)) if value is not None}
        at = WithParameters(system, **values) if values else system
        sol = periodic_solution(scene, v, method=method, steps_per_rev=steps_per_rev, backend=backend,
                                system=at, stepper=stepper)
        point = _point(v, sol, at, held, (v, mass, altitude, cg_x) in derivatives, scene.aircraft)
        point.condition = describe_condition(mass, altitude, cg_x)
        out.points[condition_key(v, mass, altitude, cg_x)] = point
        if progress:
            progress(k + 1, len(conditions))
    out.wall_s = time.perf_counter() - start
    return out


def _in_conditions(scene, conditions: list[tuple]):
    """``scene`` with the run-time ``payload`` when a condition gives a mass, in the ISA when one
    gives an altitude, with the CG's ``cg_x`` when one gives a CG (ValueError: a scene without air)."""
    from mbs.models.helicopter.air_options import environment_of_record

    record = {**({"payload": 0.0} if any(c[1] is not None for c in conditions) else {}),
              **({"atmosphere": "isa"} if any(c[2] is not None for c in conditions) else {}),
              **({"cg_shift": True} if any(c[3] is not None for c in conditions) else {})}
    if record and scene.aircraft is None:
        raise ValueError(f"scene {scene.name!r} has no aircraft: the points' mass, altitude and CG need one")
    return environment_of_record(scene, record)


def controls_convention(d) -> str:
    """How the model states its controls for the comparison: the aircraft file's ``[conventions]``
    (defaults included) and whether a rigging gives the pilot's controls."""
    from mbs.aircraft import rigging

    c = d.get("conventions", {})
    cyclic = c.get("cyclic_pitch", "theta_1c, theta_1s")
    out = (f"blade angles in the aircraft file's conventions: tail_collective positive "
           f"{c.get('tail_collective_positive', 'anti-torque')}, collective at r/R = {c.get('collective_radius', 0.0):g}, "
           f"cyclic as {cyclic}")
    rig = rigging.rigging(d)
    return out + ("; pilot controls through its rigging ([controls])" if rig is not None else "; no rigging")


def _point(speed: float, sol, system, held, with_derivatives: bool, aircraft=None) -> Point:
    """The trim at ``speed`` and, when asked, its derivatives (per published control angle and per
    pilot position too, with ``aircraft``'s conventions and rigging)."""
    if not sol.converged:
        return Point(speed, sol, problem=f"no trim: {sol.reason}")
    if not with_derivatives:
        return Point(speed, sol)
    try:
        res = linearise(sol, system, held, sol.radius)
    except RuntimeError as exc:
        return Point(speed, sol, problem=f"no derivatives: {exc}")
    if aircraft is not None:
        in_pilot_controls(res, aircraft.data)
    res.warnings += model_warnings(res, aircraft.data if aircraft is not None else None)
    return Point(speed, sol, res)
