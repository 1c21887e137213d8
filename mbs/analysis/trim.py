"""Periodic trim by shooting: controls, attitude and periodic rotor states together.

A trim is a periodic solution of the driven-rotor model: every rotor state (flap, lag, teeter,
their rates, inflows) and the fuselage's velocities, rates and attitude return after the
period, while the aircraft advances along a straight path at the given speed and climb rate
(equations: :mod:`mbs.analysis.shooting`; period and tail-rotor symmetry:
:mod:`mbs.analysis.period`). The residual is evaluated by the model's generated fixed-step
driver, the same run a simulation makes; Newton's Jacobian is the exact derivative of that
discrete map from forward-mode AD (:mod:`mbs.analysis.monodromy`) chained with the AD
Jacobians of the small maps ``z -> x(0)`` and ``x(τ) -> r``. A backtracking line search makes
it robust far from the solution; near it the steps are full and convergence is quadratic.

Start: the closed-form estimate of :func:`mbs.models.helicopter.estimate_trim` at the requested
speed (momentum and blade-element theory), for helicopter scenes; the scene's defaults otherwise.
The trim reports the period means of the model's outputs (rotor thrust, aerodynamic shaft
torque and power, inflow ratios, and the loads of :mod:`mbs.loads`): the aerodynamic torque is
that of the blade-element forces about the shaft; the drive's torque (``<rotor>.shaft_torque``)
is the driven hub joint's reaction about its axis, which in a trim balances the aerodynamic
torque and the moment of the blades' weight about the shaft.
"""
from __future__ import annotations

import logging
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mbs.analysis.newton import Failure, Iteration, newton
from mbs.analysis.period import RotorPeriod, periodic_scene, scene_period
from mbs.analysis.shooting import FlightPath, TrimLayout, residual_function, residual_scales, start_function

TORQUE_NOTE = ("rotor torque and power: aerodynamic shaft torque of the blade-element forces (N m) and "
               "torque times rotor speed (W); shaft torque and power: the drive's (a joint reaction); engine power: "
               "shaft powers over the transmission efficiency plus accessories; period means")


@dataclass
class Trim:
    """A periodic trim. Angles in rad, speeds in m/s, ``x0`` (nx,) the state at ``t = 0``,
    ``params`` (np,) the parameters; ``residual`` the final scaled residual (per
    ``residual_names``); work: Newton iterations, Jacobians (tangent propagations), residual
    runs, right-hand sides (``nfev``) and directional derivatives (``nfwd``), wall times (s)."""

    scene: str
    speed: float
    climb_rate: float
    method: str
    steps_per_rev: int
    period: RotorPeriod
    controls: dict[str, float]
    roll: float
    pitch: float
    x0: np.ndarray
    params: np.ndarray
    state_names: list[str]
    converged: bool
    reason: str
    residual: np.ndarray
    residual_names: list[str]
    history: list[Iteration] = field(default_factory=list)
    n_jacobian: int = 0
    n_residual: int = 0
    nfev: int = 0
    nfwd: int = 0
    wall_s: float = 0.0
    setup_s: float = 0.0
    thrust: float | None = None
    output_means: dict[str, float] = field(default_factory=dict)
    radius: float = 1.0  # m: the length scaling position residuals (the main-rotor radius)
    aircraft: str | None = None  # the aircraft's name, for a helicopter scene
    flapping: dict[str, float] = field(default_factory=dict)  # rad: beta0, beta1c, beta1s (a bar's bar1c, bar1s)
    rotor: dict[str, float] = field(default_factory=dict)  # mu, C_T, C_T/sigma of the main rotor
    output_units: dict[str, str] = field(default_factory=dict)
    flight: FlightPath = field(default_factory=FlightPath)
    sideslip: float = 0.0  # rad: the track's sideslip at t = 0 (zero with the zero-sideslip constraint)
    pilot: dict[str, float] = field(default_factory=dict)  # pilot control positions of an aircraft with a rigging
    pilot_units: dict[str, str] = field(default_factory=dict)  # their units (the aircraft file's)
    published: dict[str, float] = field(default_factory=dict)  # the controls in the aircraft's published conventions
    warnings: list[str] = field(default_factory=list)
    tail_thrust_coefficient: tuple[float, float, float] | None = None  # tail C_T, sigma a, inflow ratio
    last_iterate_means: dict[str, float] = field(default_factory=dict)  # a failed trim's outputs where it stopped

    @property
    def iterations(self) -> int:
        return len(self.history)

    @property
    def residuals(self) -> list[float]:
        """Max-norm scaled residual at every iterate, the final one included."""
        return [it.residual for it in self.history] + [float(np.abs(self.residual).max())]

    @property
    def state(self) -> dict[str, float]:
        return dict(zip(self.state_names, map(float, self.x0)))

    def summary(self) -> dict:
        """Plain-data form (JSON)."""
        return {"scene": self.scene, "aircraft": self.aircraft, "speed": self.speed, "climb_rate": self.climb_rate,
                "method": self.method,
                "steps_per_rev": self.steps_per_rev, "converged": self.converged, "reason": self.reason,
                "controls": self.controls, "controls_deg": {k: float(np.degrees(v)) for k, v in self.controls.items()},
                "roll": self.roll, "pitch": self.pitch, "sideslip": self.sideslip, "state": self.state,
                "constraint": self.flight.constraint, "turn_rate": self.flight.turn_rate,
                "pilot_controls": self.pilot, "pilot_units": self.pilot_units, "published_controls": self.published, "warnings": self.warnings,
                "roll_deg": float(np.degrees(self.roll)), "pitch_deg": float(np.degrees(self.pitch)),
                "period": self.period_summary(),
                "max_abs_residual": float(np.abs(self.residual).max()), "residuals": self.residuals,
                "steps": [it.step for it in self.history], "iterations": self.iterations,
                "n_jacobian": self.n_jacobian, "n_residual": self.n_residual, "nfev": self.nfev, "nfwd": self.nfwd,
                "wall_s": self.wall_s, "setup_s": self.setup_s, "main_rotor_thrust": self.thrust,
                "outputs": self.output_means, "flapping": self.flapping, "rotor": self.rotor,
                "torque": self.output_means.get("main_rotor.torque"),
                "power": self.output_means.get("main_rotor.power"), "note": TORQUE_NOTE}


    def period_summary(self) -> dict:
        per = self.period
        out = {"revs": per.revs, "full_revs": per.full_revs, "duration_s": per.duration,
               "reversed": [self.state_names[i] for i in per.flip],
               "exchanged": {self.state_names[k]: self.state_names[i] for k, i in enumerate(per.source) if i != k}}
        if per.gear is not None:
            out.update(gear_ratio=per.gear.ratio, gear_ratio_used=per.gear.used, tail_speed_error=per.gear.speed_error,
                       tail_collective_error=self.tail_collective_error, gear_note=per.gear.text())
        return out

    @property
    def tail_collective_error(self) -> float | None:
        """Estimated error (rad) of the tail collective from the tail-rotor speed error of the
        periodic gear (:func:`mbs.analysis.period.tail_collective_error`); None without one."""
        from mbs.analysis.period import tail_collective_error

        gear = self.period.gear
        if gear is None or gear.exact or self.tail_thrust_coefficient is None:
            return None if gear is None or not gear.exact else 0.0
        return tail_collective_error(gear.speed_error, *self.tail_thrust_coefficient)


class ShootingProblem:
    """Residual and Jacobian of the trim equations for one system, method and flight path.

    system: the model's :class:`mbs.System`; stepper: its
    :class:`mbs.analysis.monodromy.TangentStepper`; path: target position (3,) at the end of the
    shooting interval (m); radius: reference length of the scaled residual (m); speed: m/s.
    """

    def __init__(self, system, stepper, period: RotorPeriod, steps_per_rev: int, flight: FlightPath, radius: float):
        info = system.info
        self.flight, self.speed, self.radius = flight, flight.speed, radius
        self.system, self.stepper, self.period = system, stepper, period
        self.lay = TrimLayout.of(info, sideslip=flight.bank is not None)
        self.h, self.n = period.revolution / steps_per_rev, period.revs * steps_per_rev
        self.path, self.p_base = flight.chord(period.duration), system.params()
        bank = flight.bank or 0.0
        self._start = start_function(self.lay, info.nx, len(self.p_base), bank)
        self._residual = residual_function(self.lay, info.nx, period.symmetry(info.nx),
                                           flight.turn_rate * period.duration, bank, period.permutation(info.nx))
        self.scale = residual_scales(self.lay.residual_names, period.omega, radius)
        self.nfwd = 0

    def start(self, z) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(x0 (nx,), p (np,), dx0/dz, dp/dz)``."""
        x0, p, dx0, dp = (np.asarray(a, dtype=float) for a in self._start(z, self.p_base))
        return x0.ravel(), p.ravel(), dx0, dp

    def run(self, z, every: int | None = None):
        """The model's fixed-step run over the shooting interval from the unknowns ``z``."""
        x0, p = self.start(z)[:2]
        try:
            traj = self.system.run(x0, 0.0, self.h, self.n, every=every or self.n, p=p, method=self.stepper.method)
        except ValueError as exc:  # a control outside its range
            raise Failure(str(exc)) from None
        if not traj.ok:
            raise Failure(traj.message)
        return traj

    def residual(self, z) -> np.ndarray:
        """Scaled residual (nr,) at ``z``."""
        return self._scaled(self._residual(self.run(z).x[-1], z, self.path)[0])

    def jacobian(self, z) -> np.ndarray:
        """Scaled ``dr/dz`` (nr, nz): AD of ``x(τ)`` along ``dx0/dz``, ``dp/dz``, chained."""
        x0, p, dx0, dp = self.start(z)
        sens = self.stepper.propagate(x0, p, dx0, dp, 0.0, self.h, self.n)
        self.nfwd += sens.nfwd
        _, dr_dx, dr_dz = self._residual(sens.x, z, self.path)
        return (np.asarray(dr_dx) @ sens.dx + np.asarray(dr_dz)) / self.scale[:, None]

    def _scaled(self, r) -> np.ndarray:
        return np.asarray(r, dtype=float).ravel() / self.scale


def evaluators(sc, method: str = "rk4", backend: str = "compiled"):
    """``(system, stepper)`` of the scene ``sc``: its :class:`mbs.System` and
    :class:`mbs.analysis.monodromy.TangentStepper`, from one symbolic model (built once)."""
    from mbs.analysis.monodromy import TangentStepper
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic

    model = periodic_scene(sc).model()
    sym = symbolic(model)
    stepper = TangentStepper(model, method, backend, sym=sym)
    vm = VMSystem(sym)
    if stepper.backend == "vm":
        return vm, stepper
    from mbs.backends import index
    from mbs.backends.compiled import CompiledSystem

    return CompiledSystem(index.system_library(vm)), stepper


def trimmable(scene) -> bool:
    """A scene can be trimmed when it has controls and rotor aerodynamics (an inflow state) and its
    rotors turn at a prescribed speed (a rotor speed that is a state: :mod:`mbs.analysis.rotor_speed_trim`;
    a stabilizer bar's mixer makes the blades' pitch dependent coordinates of its teeter, not of the
    hub's azimuth)."""
    from mbs.joints import DrivenHinge

    model = scene.model()
    hub = model.bodies.get("main_hub")
    return (any(p.control for p in model.parameters.values()) and any(n.endswith(".inflow") for n in model.states)
            and (hub is None or isinstance(hub.joint, DrivenHinge)))


def _check_scene(name):
    from mbs import scenes

    sc = scenes.get(name) if isinstance(name, str) else name
    if sc.options.get("drive_train", getattr(getattr(sc.builder, "config", None), "drive_train", None)):
        raise ValueError(f"scene {sc.name!r} turns its rotors at a speed that is a state: its periodic trim holds "
                         "the rotor speed with the descent rate or a drive parameter; use 'heli autorotation' "
                         "(mbs.analysis.rotor_speed_trim)")
    if not trimmable(sc):
        ok = sorted(n for n, s in scenes.all_scenes().items() if trimmable(s))
        raise ValueError(f"scene {sc.name!r} cannot be trimmed: it has no controls or no rotor aerodynamics; "
                         f"trimmable scenes: {', '.join(ok)}")
    return periodic_scene(sc)


def reference_radius(sc) -> float:
    """The length that scales position residuals (m): the main-rotor radius of a helicopter
    scene's aircraft, 1 otherwise."""
    return sc.aircraft.data["main_rotor"]["radius"] if getattr(sc, "aircraft", None) is not None else 1.0


def estimate(system, lay: TrimLayout, speed: float, climb_rate: float = 0.0, aircraft=None,
             bank: float | None = None) -> np.ndarray:
    """Starting unknowns ``z``: the closed-form estimate at ``speed`` for a free-flying
    helicopter of ``aircraft``, the model's initial state and parameters otherwise; with a given
    ``bank`` (rad) the roll is that and the sideslip starts at zero."""
    x, p = system.x0(), system.params()
    if lay.free and aircraft is not None:
        x, p = _aircraft_estimate(system, lay, speed, aircraft.data)
    if not lay.free:
        return x[lay.rotor]
    from mbs import _rotation as rot

    roll, pitch, _ = rot.quat_to_euler(x[lay.quaternion])
    roll = roll if bank is None else bank
    q = rot.euler_to_quat(roll, pitch, 0.0)
    body = np.r_[np.asarray(rot.quat_to_matrix(q)).T @ [speed, 0.0, -climb_rate], 0.0, 0.0, 0.0]
    return np.r_[p[lay.controls], roll if bank is None else 0.0, pitch, body, x[lay.rotor]]


def _aircraft_estimate(system, lay: TrimLayout, speed: float, d) -> tuple[np.ndarray, np.ndarray]:
    """Initial state and parameters from :func:`mbs.models.helicopter.estimate_trim` at ``speed``."""
    from mbs import _rotation as rot
    from mbs.models.helicopter import estimate_trim
    from mbs.models.helicopter.estimate import flap_start

    e, omega, names = estimate_trim(d, speed), d["main_rotor"]["omega"], system.info.state_names
    x = system.x0()
    x[lay.rotor] = 0.0
    x[lay.quaternion] = rot.euler_to_quat(e.roll, e.pitch, 0.0)
    for name, value in flap_start(d, int(d["main_rotor"]["n_blades"]), e.coning, e.a1s, omega).items():
        x[names.index(name)] = value
    for name, value in (("main_rotor.inflow", e.inflow_main), ("tail_rotor.inflow", e.inflow_tail)):
        if name in names:
            x[names.index(name)] = value
    ranges = {q["name"]: (q.get("low", -np.inf), q.get("high", np.inf)) for q in system.info.parameters}
    p = system.params({c: float(np.clip(getattr(e, c), *ranges[c])) for c in lay.control_names
                       if hasattr(e, c)})  # other controls (swashplate actuators) start at their defaults
    return x, p


def _beyond_range(system, speed: float, aircraft) -> str:
    """A note naming the controls whose closed-form estimate at ``speed`` lies outside their
    range (the likely reason a trim fails there), or ""."""
    if aircraft is None:
        return ""
    from mbs.models.helicopter import estimate_trim

    e = estimate_trim(aircraft.data, speed)
    out = [f"{q['name']} = {getattr(e, q['name']):.4f} rad outside its range [{q['low']}, {q['high']}]"
           for q in system.info.parameters if q.get("control") and hasattr(e, q["name"])
           and not q["low"] <= getattr(e, q["name"]) <= q["high"]]
    return f"; the closed-form estimate needs {', '.join(out)}: no trim within the control ranges" if out else ""


def _at_stops(system, lay: TrimLayout, z) -> str:
    """A note naming the controls at (within :data:`mbs.analysis.trim_checks.STOP_MARGIN` of) a
    range's end at the last iterate ``z`` of a failed trim (the trim likely needs more than the
    range), or ""."""
    from mbs.analysis.trim_checks import CONTROLS, near_stop

    out = []
    for i, name, value in zip(lay.controls, lay.control_names, z):
        q = system.info.parameters[i]
        stop = near_stop(value, q.get("low", -np.inf), q.get("high", np.inf))
        if stop:
            end = {"min": "low", "max": "high"}[stop]
            entry = f" ({CONTROLS[name][0]}.{CONTROLS[name][1]}_{stop})" if name in CONTROLS else ""
            out.append(f"{name} = {value:.4f} rad at its {end} stop {q[end]:g} rad{entry}")
    return (f"; at the last iterate {', '.join(out)}: the trim likely needs more than the control's range; widen "
            "the range if the aircraft has it, or check the flight condition") if out else ""


BALANCE = {"fuselage.u": "the forward force (drag against the rotor's forward tilt)",
           "fuselage.v": "the side force", "fuselage.w": "the vertical force (thrust against weight)",
           "fuselage.p": "the rolling moment", "fuselage.q": "the pitching moment", "fuselage.r": "the yawing moment"}
"""What a fuselage velocity's residual that stays large says is not balanced."""


def _unbalanced(lay: TrimLayout, r, aircraft=None) -> str:
    """A note naming what the last iterate of a failed trim leaves most unbalanced (the largest
    scaled residual of the fuselage's motion), or ""; for a moment and a teetering main rotor,
    what the rotor holds per degree of teeter (:func:`_teeter_capacity`)."""
    r = np.abs(np.asarray(r, dtype=float))
    fuselage = [k for k, n in enumerate(lay.residual_names) if n in BALANCE]
    if not fuselage or not np.all(np.isfinite(r)):
        return ""
    k = max(fuselage, key=lambda i: r[i])
    if r[k] < 0.1 * r.max():
        return ""
    name = lay.residual_names[k]
    teeter = _teeter_capacity(aircraft) if name in ("fuselage.p", "fuselage.q") else ""
    return (f"; at the last iterate {BALANCE[name]} stays unbalanced (scaled residual of "
            f"{name} {r[k]:.2g}): check what makes it (a surface at its stall or in the wake's edge, "
            f"a fuselage moment the rotor cannot hold{teeter}; the warnings of the last iterate say more)")


def _teeter_note(aircraft) -> str:
    """A failed trim of a teetering rotor with no other reason found: what the rotor holds."""
    text = _teeter_capacity(aircraft)
    return f"; a teetering rotor cannot hold every fuselage moment{text}" if text else ""


def _teeter_capacity(aircraft) -> str:
    """For a teetering main rotor (no hub moment but its spring's), the moment it holds per degree
    of teeter by tilting its thrust: ``W h + K`` per radian, ``h`` the hub above the CG; its pitch
    and roll move together, so a fuselage pitching moment beyond it can leave either unbalanced."""
    if aircraft is None or aircraft.data["main_rotor"]["hub_type"] != "teetering":
        return ""
    d = aircraft.data
    mr, weight = d["main_rotor"], d["aircraft"]["mass"] * d["environment"]["g"]
    per_degree = np.radians(1.0) * (weight * -mr["hub_z"] + mr["flap_stiffness"])
    return (f": a teetering rotor holds {per_degree:.4g} N m per degree of teeter (the weight's thrust "
            f"{weight:.4g} N over the hub {-mr['hub_z']:.3g} m above the CG, and its spring), tilting its thrust, "
            "and its pitch and roll go together, so compare the fuselage's pitching moment at this speed "
            "(fuselage_aero M) with a few degrees of it")


def _scene_speed(system, lay: TrimLayout) -> float:
    if not lay.free:
        return 0.0
    return round(float(np.linalg.norm(system.x0()[lay.body[:3]])), 6)


def trim(scene: str = "forward-flight", speed: float | None = None, climb_rate: float = 0.0,
         method: str = "rk4", steps_per_rev: int | None = None, backend: str = "compiled",
         tol: float = 1e-10, max_iterations: int = 20, system=None, stepper=None, progress=None, *,
         turn_rate: float = 0.0, bank: float | None = None) -> Trim:
    """Trim ``scene`` at ``speed`` (m/s, default the scene's) and ``climb_rate`` (m/s, up).

    method, steps_per_rev: the fixed-step method and step of the periodic solution (the trim
    is periodic for exactly this discretisation); tol: on the max-norm scaled residual.
    ``system``/``stepper`` reuse built evaluators (the scene's defaults otherwise).
    ``turn_rate`` (rad/s, right positive) trims a steady turn; ``bank`` None holds zero sideslip
    (the roll a trim unknown), a number (rad) holds that roll with the sideslip free (0: zero bank).
    """
    return periodic_solution(_check_scene(scene), speed, climb_rate, method, steps_per_rev, backend, tol,
                             max_iterations, system, stepper, progress, turn_rate=turn_rate, bank=bank)


def periodic_solution(sc, speed: float | None = None, climb_rate: float = 0.0, method: str = "rk4",
                      steps_per_rev: int | None = None, backend: str = "compiled", tol: float = 1e-10,
                      max_iterations: int = 20, system=None, stepper=None, progress=None, *,
                      turn_rate: float = 0.0, bank: float | None = None) -> Trim:
    """The periodic solution of the scene ``sc`` (a :class:`mbs.scenes.Scene`): a trim when its
    fuselage is free (flight path and constraint as :func:`trim`), the periodic rotor response at
    the given controls otherwise."""
    from mbs.analysis.monodromy import TangentStepper

    start, sc = time.perf_counter(), periodic_scene(sc)
    if system is None and stepper is None:
        system, stepper = evaluators(sc, method, backend)
    system = system or sc.system(backend)
    stepper = stepper or TangentStepper(sc.model(), method, backend)
    steps_per_rev = steps_per_rev or sc.steps_per_rev
    flight = FlightPath(0.0, climb_rate, turn_rate, bank)
    prob = _problem(system, stepper, sc, speed, flight, steps_per_rev)
    z0 = estimate(system, prob.lay, prob.speed, climb_rate, sc.aircraft, prob.flight.bank)
    if prob.period.revs > WARM_START_REVS and sc.aircraft is not None:
        z0 = _warm_start(sc, prob, flight, method, steps_per_rev, backend, tol, max_iterations, z0)
    setup_s, nfev0 = time.perf_counter() - start, system.nfev
    res = newton(prob.residual, prob.jacobian, z0, tol, max_iterations, progress=progress)
    if not res.converged and prob.lay.free and prob.speed > CONTINUATION_STEP:
        res = _continuation(system, stepper, sc, prob, steps_per_rev, tol, max_iterations, res)
    if not res.converged and prob.lay.free:
        res.reason += (_beyond_range(system, prob.speed, sc.aircraft) or _at_stops(system, prob.lay, res.z)
                       or _unbalanced(prob.lay, res.r, sc.aircraft) or _teeter_note(sc.aircraft))
    mr = sc.aircraft.data["main_rotor"] if getattr(sc, "aircraft", None) is not None else {}
    cone, tilt = mr.get("precone", 0.0), float(np.cos(mr.get("delta3", 0.0)))
    out = _result(sc.name, prob, res, steps_per_rev, setup_s, system.nfev - nfev0, cone, tilt)
    if sc.aircraft is not None:
        out.aircraft = sc.aircraft.name
        out.rotor = rotor_coefficients(sc.aircraft.data, out.thrust, out.speed, _air(system, out.params))
        out.tail_thrust_coefficient = _tail_coefficients(sc.aircraft.data, out.output_means)
        _pilot_figures(out, sc.aircraft.data, _air(system, out.params))
    return out


def _air(system, params) -> dict:
    """The ISA ``altitude`` and ``temperature_offset`` of a scene in the ISA ({} otherwise)."""
    names = [q["name"] for q in system.info.parameters]
    return {n: float(params[names.index(n)]) for n in ("altitude", "temperature_offset") if n in names}


def _pilot_figures(out: Trim, d, air: dict | None = None) -> None:
    """The trim's controls in the aircraft's published conventions and, with a rigging, as pilot
    positions; the warnings of :func:`mbs.analysis.trim_checks.warnings` (``air``: its ISA)."""
    from mbs.aircraft import rigging
    from mbs.analysis.trim_checks import warnings

    out.published = rigging.conventions(d).to_published(out.controls)
    rig = rigging.rigging(d)
    if rig is not None and all(k in out.controls for k in rigging.BLADE):
        si = rig.pilot(out.controls)
        out.warnings = warnings(out, d, si, air)
        out.pilot_units = {k: d.meta["controls"][k]["unit"] for k in si}
        out.pilot = {k: rig.in_file_unit(k, v, out.pilot_units[k]) for k, v in si.items()}
    else:
        out.warnings = warnings(out, d, air=air)


def _tail_coefficients(d, means: dict) -> tuple[float, float, float] | None:
    """The tail rotor's period-mean thrust coefficient, ``σ a`` and inflow ratio, or None without them."""
    if "tail_rotor.thrust" not in means:
        return None
    tr, rho = d["tail_rotor"], d["environment"]["rho"]
    tip = tr["gear_ratio"] * d["main_rotor"]["omega"] * tr["radius"]
    ct = means["tail_rotor.thrust"] / (rho * np.pi * tr["radius"] ** 2 * tip**2)
    sigma = tr["n_blades"] * tr["chord"] / (np.pi * tr["radius"])
    return ct, sigma * tr["lift_slope"], means.get("tail_rotor.inflow_ratio", 0.0)


def rotor_coefficients(d, thrust: float | None, speed: float, air: dict | None = None) -> dict[str, float]:
    """Advance ratio ``μ = V / (Ω R)``, thrust coefficient ``C_T = T / (ρ π R² (Ω R)²)`` and blade
    loading ``C_T/σ`` of the main rotor of the aircraft data ``d`` at its nominal speed, in the
    ISA at ``air``'s ``altitude`` and ``temperature_offset`` (:func:`_air`; none: the file's density)."""
    from mbs.environment import atmosphere

    mr = d["main_rotor"]
    rho = atmosphere.density(air["altitude"], air.get("temperature_offset", 0.0)) if air and "altitude" in air \
        else d["environment"]["rho"]
    tip = mr["omega"] * mr["radius"]
    sigma = mr["n_blades"] * mr["chord"] / (np.pi * mr["radius"])
    out = {"mu": speed / tip}
    if thrust is not None:
        ct = thrust / (rho * np.pi * mr["radius"] ** 2 * tip**2)
        out.update({"C_T": ct, "C_T/sigma": ct / sigma})
    return out


WARM_START_REVS = 6
"""A trim shooting over more main-rotor revolutions starts from the trim of the same aircraft with
the nearest tail-rotor gear ratio that repeats within two (:func:`_warm_start`)."""


_WARM_STARTS_SAID: set[tuple[str, str]] = set()
"""Scenes and aircraft files whose warm start was announced in this process (said once: a
validation or sweep trims the same aircraft at many speeds)."""


def _warm_start(sc, prob: ShootingProblem, flight: FlightPath, method: str, steps_per_rev: int, backend: str,
                tol: float, max_iterations: int, z0: np.ndarray) -> np.ndarray:
    """Unknowns of the trim of ``sc`` with its tail rotor turning at the nearest gear ratio that
    repeats within two main-rotor revolutions: over a long interval (the tail rotor repeating
    only after many) Newton from the closed-form estimate meets the aircraft's unstable motion
    growing over seconds; the near ratio's trim is within its small speed difference of the
    solution. ``z0`` when that trim fails."""
    near = periodic_scene(sc, max_revs=2)
    if near is sc:
        return z0
    said = (sc.name, str(getattr(sc.aircraft, "path", "")))
    logging.getLogger(__name__).log(
        logging.DEBUG if said in _WARM_STARTS_SAID else logging.INFO,
        "warm start: first a trim with the tail rotor at gear ratio %.8g (repeating within 2 revolutions), its "
        "own model (compiled once too: a second compiling line of the same name), then at %.8g",
        near.aircraft.data["tail_rotor"]["gear_ratio"], sc.aircraft.data["tail_rotor"]["gear_ratio"])
    _WARM_STARTS_SAID.add(said)
    sol = periodic_solution(near, prob.speed, flight.climb_rate, method, steps_per_rev, backend, tol, max_iterations,
                            turn_rate=flight.turn_rate, bank=flight.bank)
    if not sol.converged:
        return z0
    lay = prob.lay
    attitude = [sol.sideslip if lay.sideslip else sol.roll, sol.pitch] if lay.free else []
    return np.r_[[sol.controls[c] for c in lay.control_names], attitude,
                 sol.x0[lay.body], sol.x0[lay.rotor]]


CONTINUATION_STEP = 10.0
"""m/s: speed step of the continuation that takes over when Newton from the estimate fails."""


def _continuation(system, stepper, sc, prob: ShootingProblem, steps_per_rev: int, tol: float,
                  max_iterations: int, failed):
    """Newton from the estimate at ``prob.speed`` failed (``failed``): trim at speeds rising to
    it in steps of at most :data:`CONTINUATION_STEP`, each Newton solve starting from the
    previous solution. Returns the last solve with the work of all of them (the failed attempt
    included) counted, or ``failed`` when a step does not converge either."""
    speeds = np.linspace(0.0, prob.speed, int(np.ceil(prob.speed / CONTINUATION_STEP)) + 1)[1:]
    flight = prob.flight
    z, work = estimate(system, prob.lay, speeds[0], flight.climb_rate, sc.aircraft, flight.bank), [failed]
    for v in speeds:
        step = _problem(system, stepper, sc, v, flight, steps_per_rev)
        work.append(newton(step.residual, step.jacobian, z, tol, max_iterations))
        if not work[-1].converged:
            return failed
        z = work[-1].z
    res = work[-1]
    res.n_jacobian, res.n_residual = sum(w.n_jacobian for w in work), sum(w.n_residual for w in work)
    res.wall_s = sum(w.wall_s for w in work)
    res.reason += f" (by continuation in speed over {len(speeds)} steps: Newton from the estimate failed)"
    return res


def _problem(system, stepper, sc, speed, flight: FlightPath, steps_per_rev) -> ShootingProblem:
    """The trim problem at ``speed`` (m/s; None: the scene's) with ``flight``'s other settings."""
    from dataclasses import replace

    lay = TrimLayout.of(system.info)
    speed = _scene_speed(system, lay) if speed is None or not lay.free else float(speed)
    return ShootingProblem(system, stepper, scene_period(sc, system), steps_per_rev, replace(flight, speed=speed),
                           reference_radius(sc))


def _result(scene: str, prob: ShootingProblem, res, steps_per_rev, setup_s, nfev, cone: float = 0.0,
            tilt: float = 1.0) -> Trim:
    x0, p = prob.start(res.z)[:2]
    controls, attitude = prob.lay.split(res.z)[:2]
    flight = prob.flight
    roll, pitch = map(float, attitude) if prob.lay.free else (0.0, 0.0)
    sideslip, roll = (roll, flight.bank) if prob.lay.sideslip else (0.0, roll)
    out = Trim(scene, flight.speed, flight.climb_rate, prob.stepper.method, steps_per_rev, prob.period,
               dict(zip(prob.lay.control_names, map(float, controls))), roll, pitch, x0, p,
               prob.system.info.state_names, res.converged, res.reason, res.r, prob.lay.residual_names, res.history,
               res.n_jacobian, res.n_residual, nfev, prob.nfwd, res.wall_s, setup_s, radius=prob.radius,
               flight=flight, sideslip=sideslip)
    out.output_units = {o["name"]: o["unit"] for o in prob.system.info.outputs}
    if res.converged:
        out.output_means, out.flapping = _period_figures(prob, res.z, cone, tilt)
    elif prob.lay.free and np.all(np.isfinite(res.z)):
        out.last_iterate_means = _last_iterate_means(prob, res.z, cone)
    out.thrust = out.output_means.get("main_rotor.thrust")
    return out


def _last_iterate_means(prob: ShootingProblem, z, cone: float = 0.0) -> dict[str, float]:
    """The outputs' period means at a failed trim's last iterate ({} where they cannot be had)."""
    try:
        means = _period_figures(prob, z, cone)[0]
    except (ValueError, RuntimeError, FloatingPointError):
        return {}
    return means if all(np.isfinite(v) for v in means.values()) else {}


def _period_figures(prob: ShootingProblem, z, cone: float = 0.0,
                    tilt: float = 1.0) -> tuple[dict[str, float], dict[str, float]]:
    """The model's outputs averaged over the shooting interval (azimuths left out) and the
    main-rotor blades' flapping ``β = β0 + β1c cos ψ + β1s sin ψ`` (rad, relative to the shaft;
    ψ of each blade from the tail in the sense of rotation), averaged over the blades; a
    teetering rotor's blades flap by ± its teeter angle on its precone ``cone`` (rad); a hinge
    skewed by δ3 lifts the tip by its angle times ``tilt = cos δ3``."""
    from mbs.analysis.signals import azimuth_harmonics

    info = prob.system.info
    names = [n for n in info.output_names if not n.endswith(".azimuth")]
    if not info.output_names:
        return {}, {}
    traj = prob.run(z, every=1)
    y = prob.system.history("outputs", traj, prob.start(z)[1])[1:]
    means = {n: float(y[:, info.output_names.index(n)].mean()) for n in names}
    flaps = [traj.x[1:, i] for i, n in enumerate(info.state_names) if re.fullmatch(r"blade\d+\.flap", n)]
    if "main_seesaw.teeter" in info.state_names:  # blade 1 up by the teeter angle, blade 2 down, on the precone
        teeter = tilt * traj.x[1:, info.state_names.index("main_seesaw.teeter")]  # a skewed hinge: its tip's share
        coning = flaps or [0.0, 0.0]  # the coning hinges' angles about the precone, where the hub has them
        flaps = [cone + coning[0] + teeter, cone + coning[1] - teeter]
    elif tilt != 1.0:  # a flap hinge skewed by δ3 lifts the tip by its angle times cos δ3
        flaps = [tilt * f for f in flaps]
    if "main_rotor.azimuth" not in info.output_names or not flaps:
        return means, {}
    psi = y[:, info.output_names.index("main_rotor.azimuth")]
    rows = [azimuth_harmonics(psi + 2 * np.pi * k / len(flaps), flap) for k, flap in enumerate(flaps)]
    beta0, beta1c, beta1s = np.mean(rows, axis=0)
    out = {"beta0": float(beta0), "beta1c": float(beta1c), "beta1s": float(beta1s)}
    if "stabilizer_bar.teeter" in info.state_names:  # its lifted end 90 deg ahead of blade 1: the plane's tilt
        bar = traj.x[1:, info.state_names.index("stabilizer_bar.teeter")]
        out.update(zip(("bar1c", "bar1s"), map(float, azimuth_harmonics(psi + np.pi / 2, bar)[1:])))
    return means, out


def write_trim(result: Trim, path: Path, key: str | None = None) -> Path:
    """Store ``result`` under ``key`` (default the scene) in the TOML file ``path`` (other
    entries kept; the format of ``mbs/aircraft/data/bo105_trim.toml``; an aircraft file reads its stored trims from ``<stem>_trim.toml`` beside it)."""
    import sys

    tomllib = __import__("tomllib" if sys.version_info >= (3, 11) else "tomli")
    path = Path(path)
    entries = tomllib.loads(path.read_text()) if path.exists() else {}
    entries[key or result.scene] = {"speed": result.speed, **result.controls, "roll": result.roll,
                                    "pitch": result.pitch,
                                    **{k: v for k, v in result.state.items() if ".inflow" in k},
                                    "max_abs_residual": float(np.abs(result.residual).max())}
    lines = [f"# Periodic trims of the {result.aircraft or result.scene} model (DER): written by `heli trim SCENE --write PATH`",
             "# (mbs/analysis/trim.py). Angles in rad, speed and inflow in m/s, residual scaled (per R, rev).", ""]
    for name, e in sorted(entries.items()):
        lines += [f'["{name}"]'] + [f'"{k}" = {float(v)!r}' for k, v in e.items()] + [""]
    from mbs import atomic

    return atomic.write_text(path, "\n".join(lines))
