"""Stability and control derivatives at trim, with the rotor in its periodic equilibrium.

The quasi-static rotor (:mod:`mbs.analysis.held`): for held fuselage velocities, rates and
attitude and for given controls, the rotor settles on its periodic response, and the
fuselage feels the period-mean loads; divided by the aircraft's mass and inertia they are
the mean accelerations ``ā(u, v, w, p, q, r, φ, θ, controls)``. Their total derivatives,
the rotor's periodic orbit moving with each variable (implicit-function theorem on the
shooting equations, AD through the generated step), are the rows of Padfield's

    ẋ = A x + B δ,   x = (u, w, q, θ, v, p, φ, r),   δ = (θ0, θ1s, θ1c, θ0T)

(Helicopter Flight Dynamics, 2nd ed., ch. 4: the 8-state form; the heading ψ is left out,
nothing depends on it). Units: m/s, rad/s, rad; ``A`` in 1/s and its mixed units.

* Reference: the period mean of the periodic trim (:mod:`mbs.analysis.trim`) at the given
  speed: body velocities ``U_e, V_e, W_e``, rates (zero to round-off), roll ``Φ_e`` and pitch
  ``Θ_e``; controls of the trim. The rotor's periodic response with that motion held is
  solved afresh; ``ā`` there (``mean_acceleration_at_reference``) is not exactly zero, by the
  fuselage vibration that the held motion leaves out.
* Rows ``u̇, v̇, ẇ, ṗ, q̇, ṙ``: ``dā/d(·)``. They include the rigid-body kinematic terms (``−Q_e``
  in ``∂u̇/∂w``, ``U_e`` in ``∂ẇ/∂q`` ...) and, in the θ and φ columns, gravity (and the
  small change of the blades' weight loads with attitude); the moment rows use the inverse of
  the aircraft's full inertia matrix, so they are Padfield's primed derivatives ``L'``, ``N'``
  (product of inertia ``I_xz`` absorbed).
* Rows ``θ̇, φ̇``: the Euler-angle kinematics of the fuselage's quaternion rate, by AD.

The derivative table (:attr:`Derivatives.table`) follows Padfield's names: force derivatives
per unit mass ``X_u = ∂u̇/∂u`` … with the kinematic terms ``−ω × V`` removed (so ``Z_q`` is
``∂ẇ/∂q − U_e``), moment derivatives per unit inertia ``L_p = ∂ṗ/∂p`` … (primed), controls
``X_θ0``, ``M_θ1s``, ``L_θ1c``, ``N_θ0T`` … per rad.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs.analysis.flight_modes import LONGITUDINAL, STATES, FlightMode, flight_modes
from mbs.analysis.held import HELD, HeldRotor, HeldSolution, HeldStepper
from mbs.analysis.shooting import TrimLayout, euler_angles, quaternion

FORCES = ("X", "Y", "Z", "L", "M", "N")
VELOCITIES = ("u", "v", "w", "p", "q", "r")
CONTROL_SYMBOLS = {"collective": "θ0", "longitudinal_cyclic": "θ1s", "lateral_cyclic": "θ1c",
                   "tail_collective": "θ0T"}
CONTROL_ORDER = ("collective", "longitudinal_cyclic", "lateral_cyclic", "tail_collective")
ROW_SOURCE = {"u": ("a", 0), "w": ("a", 2), "q": ("a", 4), "theta": ("euler", 1), "v": ("a", 1),
              "p": ("a", 3), "phi": ("euler", 0), "r": ("a", 5)}
"""Where each row of ``A`` comes from: the mean accelerations (index into ``ā``) or the Euler rates."""
COLUMN = {s: HELD.index({"theta": "pitch", "phi": "roll"}.get(s, s)) for s in STATES}
"""Column of each state of ``A`` in the held variables ``b`` (:data:`mbs.analysis.held.HELD`)."""


@dataclass
class Derivatives:
    """``A`` (8, 8) in :data:`STATES` order and ``B`` (8, nc) in ``controls`` order (SI, rad),
    the named derivatives (:attr:`table`), the modes of ``A``, the reference flight condition
    and the work (wall time s, directional derivatives ``nfwd``)."""

    scene: str
    speed: float
    A: np.ndarray
    B: np.ndarray
    controls: list[str]
    reference: dict[str, float]
    mean_acceleration_at_reference: np.ndarray
    modes: list[FlightMode]
    held: HeldSolution
    rotor: HeldRotor | None = None
    trim: object = None
    table: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    wall_s: float = 0.0
    nfwd: int = 0
    published: dict[str, float] = field(default_factory=dict)  # control derivatives per published control angle
    pilot: dict[str, float] = field(default_factory=dict)  # control derivatives per pilot position (SI)
    pilot_units: dict[str, str] = field(default_factory=dict)  # their SI units ("1/s^2" per m of lever ...)
    pilot_file_units: dict[str, str] = field(default_factory=dict)  # each pilot control's unit in the file ("in")
    B_pilot: np.ndarray | None = None  # (8, 4): B per pilot position, PILOT order
    warnings: list[str] = field(default_factory=list)

    @property
    def states(self) -> list[str]:
        return list(STATES)

    def summary(self) -> dict:
        """Plain-data form (JSON)."""
        return {"scene": self.scene, "speed": self.speed, "states": self.states, "controls": self.controls,
                "control_symbols": [CONTROL_SYMBOLS.get(c, c) for c in self.controls],
                "A": self.A.tolist(), "B": self.B.tolist(), "derivatives": self.table, "units": self.units,
                "reference": self.reference,
                "mean_acceleration_at_reference": self.mean_acceleration_at_reference.tolist(),
                "eigenvalues": [m.summary() for m in self.modes],
                "rotor_periodicity_residual": self.held.residual, "wall_s": self.wall_s, "nfwd": self.nfwd,
                "control_derivatives_published": self.published, "control_derivatives_pilot": self.pilot,
                "control_derivatives_pilot_units": self.pilot_units,
                "B_pilot": None if self.B_pilot is None else self.B_pilot.tolist(),
                "period": self.trim.period_summary() if hasattr(self.trim, "period_summary") else None,
                "warnings": self.warnings,
                "convention": "Padfield 8-state x = (u, w, q, theta, v, p, phi, r), u = (theta0, theta1s, "
                              "theta1c, theta0T); forces per unit mass, moments per unit inertia (primed L, N); "
                              "quasi-static rotor in its periodic equilibrium"}


def euler_rate_function() -> ca.Function:
    """``euler_rates(b) -> (φ̇, θ̇) (2,), d/db (2, 8)``: the Euler-angle rates of a fuselage
    with held variables ``b`` (:data:`HELD`), from its quaternion rate, by AD."""
    from mbs import _rotation as rot

    b, q = ca.SX.sym("b", len(HELD)), ca.SX.sym("q", 4)
    along = ca.Function("e", [q, b], [ca.jtimes(euler_angles(q), q, rot.quat_rate(q, b[3:6]))[:2]])
    rates = along(quaternion(b[6], b[7]), b)
    return ca.Function("euler_rates", [b], [rates, ca.jacobian(rates, b)], ["b"], ["rates", "d_db"])


def kinematic_terms(b: np.ndarray) -> np.ndarray:
    """``d(−ω × V)/d(V, ω)`` (3, 6) at the held ``b``: the rigid-body part of the translational
    rows, removed from Padfield's force derivatives (AD of the cross product)."""
    v = ca.SX.sym("v", 6)
    k = ca.Function("k", [v], [ca.jacobian(-ca.cross(v[3:], v[:3]), v)])
    return np.asarray(k(b[:6]))


def assemble(dmean: np.ndarray, b: np.ndarray, n_controls: int) -> tuple[np.ndarray, np.ndarray]:
    """``A`` (8, 8) and ``B`` (8, nc) from ``dā/d(b, c)`` (6, 8 + nc) and the Euler kinematics."""
    euler = np.asarray(euler_rate_function()(b)[1])
    rows = {"a": np.asarray(dmean), "euler": np.hstack([euler, np.zeros((2, n_controls))])}
    full = np.array([rows[src][i] for src, i in (ROW_SOURCE[s] for s in STATES)])
    return full[:, [COLUMN[s] for s in STATES]], full[:, len(HELD):]


def derivative_table(dmean: np.ndarray, b: np.ndarray, controls: list[str]) -> tuple[dict, dict]:
    """Padfield's named derivatives (and their units) from ``dā/d(b, c)`` (6, 8 + nc)."""
    d = np.array(dmean[:, :6], dtype=float)
    d[:3] -= kinematic_terms(b)
    table, units = {}, {}
    for i, f in enumerate(FORCES):
        for j, v in enumerate(VELOCITIES):
            table[f"{f}_{v}"], units[f"{f}_{v}"] = float(d[i, j]), _unit(f, v)
        for j, c in enumerate(controls):
            name = f"{f}_{CONTROL_SYMBOLS.get(c, c)}"
            table[name], units[name] = float(dmean[i, len(HELD) + j]), _unit(f, "control")
    return table, units


def _unit(force: str, by: str) -> str:
    num = "m/s^2" if force in "XYZ" else "rad/s^2"
    den = {"u": "m/s", "v": "m/s", "w": "m/s", "control": "rad"}.get(by, "rad/s")
    simple = {("m/s^2", "m/s"): "1/s", ("rad/s^2", "rad/s"): "1/s", ("m/s^2", "rad/s"): "m/(s rad)",
              ("rad/s^2", "m/s"): "rad/(m s)", ("m/s^2", "rad"): "m/(s^2 rad)", ("rad/s^2", "rad"): "1/s^2"}
    return simple[(num, den)]


def pilot_unit(force: str, position: str) -> str:
    """SI unit of the derivative of ``force`` (X..N) per a pilot control's position in ``position``
    (m, rad, or "-" for a fraction of its travel)."""
    num = "m/s^2" if force in "XYZ" else "rad/s^2"
    if position == "rad":
        return _unit(force, "control")
    if position == "-":
        return num
    return "1/s^2" if force in "XYZ" else "rad/(s^2 m)"


def reference_condition(sol, system) -> np.ndarray:
    """Held variables ``b`` (8,): the period means over the trim's shooting interval of the body
    velocities and rates and of roll and pitch (from the quaternion)."""
    from mbs import _rotation as rot

    lay = TrimLayout.of(system.info)
    n = sol.period.revs * sol.steps_per_rev
    x = system.run(sol.x0, 0.0, sol.period.revolution / sol.steps_per_rev, n, every=1, p=sol.params,
                   method=sol.method).x[:-1]
    attitude = np.array([rot.quat_to_euler(q)[:2] for q in x[:, lay.quaternion]])
    return np.r_[x[:, lay.body].mean(axis=0), attitude.mean(axis=0)]


def _controls(lay: TrimLayout) -> list[int]:
    """Indices of the trim's controls in Padfield's order (θ0, θ1s, θ1c, θ0T), others after."""
    known = [c for c in CONTROL_ORDER if c in lay.control_names]
    return [lay.control_names.index(c) for c in known + [c for c in lay.control_names if c not in known]]


def at_trim(sol, system, held_stepper: HeldStepper, radius: float) -> tuple[HeldRotor, np.ndarray, np.ndarray]:
    """The held-rotor problem at the trim ``sol``: ``(rotor, b_e (8,), c_e (nc,))``, controls in
    the model's order."""
    lay = TrimLayout.of(system.info)
    rotor = HeldRotor(held_stepper, sol.period, sol.steps_per_rev, sol.params, radius)
    return rotor, reference_condition(sol, system), sol.params[lay.controls]


def derivatives(scene: str = "forward-flight", speed: float | None = None, method: str = "rk4",
                steps_per_rev: int | None = None, backend: str = "compiled", system=None, stepper=None,
                held_stepper=None) -> Derivatives:
    """Stability and control derivatives of ``scene`` (free-flying, trimmable) at ``speed`` m/s."""
    from mbs import scenes
    from mbs.analysis.monodromy import TangentStepper
    from mbs.analysis.trim import _check_scene, periodic_solution

    sc = _check_scene(scene)
    if not _flies_free(sc.model()):  # symbolic: before anything is compiled
        raise ValueError(f"scene {sc.name!r} has no free fuselage: derivatives need a free-flying scene; "
                         f"free-flying trimmable scenes: {', '.join(_free_scenes(scenes))}")
    system = system or sc.system(backend)
    stepper = stepper or TangentStepper(sc.model(), method, backend)
    start = time.perf_counter()
    sol = periodic_solution(sc, speed, method=method, steps_per_rev=steps_per_rev, system=system, stepper=stepper)
    if not sol.converged:
        raise RuntimeError(f"no trim of {sc.name!r} at {sol.speed:g} m/s: {sol.reason}")
    held_stepper = held_stepper or HeldStepper(sc.model(), method, backend)
    res = linearise(sol, system, held_stepper, sol.radius, start)
    if sc.aircraft is not None:
        in_pilot_controls(res, sc.aircraft.data)
        from mbs.aircraft.checks import inertia_warnings

        of_the_file = set(inertia_warnings(sc.aircraft.data))  # said by the check and the trim already
        res.warnings += [w for w in sol.warnings if w not in of_the_file]
    res.warnings += model_warnings(res, sc.aircraft.data if sc.aircraft is not None else None)
    return res


def model_warnings(res: Derivatives, d=None) -> list[str]:
    """What the derivatives of the aircraft data ``d`` (None: no aircraft) carry beyond the trim's
    warnings: a teetering rotor's and a stabilizer bar's limits of the quasi-static rotor, and a
    static instability in angle of attack."""
    return [*(teetering_warning(d) + stabilizer_bar_warning(d) if d is not None else []),
            *static_stability_warning(res)]


def static_stability_warning(res: Derivatives) -> list[str]:
    """A growing longitudinal mode where Padfield's short-period stability condition
    ``Z_w M_q - M_w U_e > 0`` fails: the aircraft is statically unstable in angle of attack
    (M_w > 0 beyond what the damping holds), which a new user should trace to its source."""
    t, speed = res.table, res.reference.get("U_e", 0.0)
    margin = t["Z_w"] * t["M_q"] - t["M_w"] * speed
    growing = [m for m in res.modes if m.eigenvalue.real > 0 and sum(m.participation[k] for k in LONGITUDINAL) >= 0.5]
    if margin >= 0 or not growing:
        return []
    modes = ", ".join(f"{m.name} {m.eigenvalue.real:+.3g}" + (f" ± {m.eigenvalue.imag:.3g}i" if m.eigenvalue.imag
                                                               else "") + " 1/s" for m in growing)
    return [f"statically unstable in angle of attack: M_w = {t['M_w']:+.4g} {res.units.get('M_w', '1/(m s)')}, and "
            f"Z_w M_q - M_w U_e = {margin:+.3g} 1/s^2 < 0 (Padfield's short-period stability condition), which gives "
            f"the {modes}: the "
            "pitching moment with angle of attack of the fuselage (fuselage_aero M) and of the rotor outweighs the "
            "horizontal tail's (its area, lift slope and arm); check them before trusting the longitudinal modes"]


TEETERING = ("teetering main rotor: its quasi-static control and damping derivatives are not validated. On a UH-1H "
             "in hover (no precone, no hub spring) the teeter follows the cyclic as two blades flapping on central "
             "hinges do (to 4 %) and the thrust tilts alike (X_θ1s to 1 %), yet M_θ1s is 2.92 against 4.39 1/s^2 "
             "and L_p -0.22 against -0.32 1/s for blades soft in plane (lag 1.5/rev); blades stiff in plane (lag "
             "6/rev) give 2.14 and +0.03, three of them 1.93 and +0.05, so the gap follows the in-plane stiffness, "
             "not the hub, and has not been checked against a measurement: compare the modes with heli floquet, "
             "which is exact for the model")
"""The measured reason a teetering main rotor's derivatives carry a warning."""


def stabilizer_bar_warning(d) -> list[str]:
    """A stabilizer bar is slow (its time constant is the body's, not the rotor's): the quasi-static
    rotor holds it in its periodic equilibrium, which is its response at zero frequency only."""
    from mbs.models.helicopter.stabilizer_bar import has_stabilizer_bar, time_constant

    if not has_stabilizer_bar(d):
        return []
    tau = time_constant(d["stabilizer_bar"], d["main_rotor"]["omega"], d["environment"]["rho"])
    return [f"stabilizer bar: its time constant {tau:.3g} s is the body's, not the rotor's, and the quasi-static "
            "rotor holds it in its periodic equilibrium, its response at zero frequency only: the damping and "
            "control derivatives through it are its steady ones, and the modes here miss the bar's lag; heli floquet "
            "carries the bar as states and gives the modes"]


def teetering_warning(d) -> list[str]:
    """:data:`TEETERING` for an aircraft whose main rotor is teetering, else nothing."""
    return [TEETERING] if d["main_rotor"]["hub_type"] == "teetering" else []


def in_pilot_controls(res: Derivatives, d) -> None:
    """Fill ``res.published`` (control derivatives per published control angle: the tail-rotor
    pitch with the aircraft's sign convention) and, with a rigging, ``res.pilot`` and
    ``res.B_pilot`` (per pilot position in SI: m, rad or fraction of travel)."""
    from mbs.aircraft import rigging

    conv, rig = rigging.conventions(d), rigging.rigging(d)
    blade = [c for c in rigging.BLADE if c in res.controls]
    cols = [res.controls.index(c) for c in blade]
    scale = dict(zip(rigging.BLADE, conv.scale()))
    for f in FORCES:
        for c in blade:
            res.published[f"{f}_{CONTROL_SYMBOLS[c]}"] = float(scale[c] * res.table[f"{f}_{CONTROL_SYMBOLS[c]}"])
    if rig is None or len(blade) < 4:
        return
    g = rig.matrix()
    res.B_pilot = res.B[:, cols] @ g
    dmean = np.array([[res.table[f"{f}_{CONTROL_SYMBOLS[c]}"] for c in rigging.BLADE] for f in FORCES]) @ g
    res.pilot_file_units = {p: d.meta["controls"][p]["unit"] for p in rigging.PILOT} if hasattr(d, "meta") else {}
    for i, f in enumerate(FORCES):
        for j, (p, si) in enumerate(zip(rigging.PILOT, rig.units)):
            res.pilot[f"{f}_{p}"] = float(dmean[i, j])
            res.pilot_units[f"{f}_{p}"] = pilot_unit(f, si)


def _flies_free(model) -> bool:
    """Whether ``model`` (a :class:`mbs.Model`) has a free fuselage."""
    return any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())


def _free_scenes(scenes) -> list[str]:
    """Names of the trimmable scenes with a free fuselage."""
    from mbs.analysis.trim import trimmable

    return sorted(n for n, s in scenes.all_scenes().items() if trimmable(s) and _flies_free(s.model()))


def linearise(sol, system, held_stepper: HeldStepper, radius: float, start: float | None = None) -> Derivatives:
    """:class:`Derivatives` at the periodic trim ``sol``."""
    start = time.perf_counter() if start is None else start
    rotor, b, c = at_trim(sol, system, held_stepper, radius)
    lay = rotor.lay
    held = rotor.solve(b, c, sol.x0[lay.rotor], derivatives=True)
    if not held.converged:
        raise RuntimeError(f"the rotor's periodic response with the fuselage held did not converge "
                           f"(max |scaled residual| {held.residual:.2e})")
    order = _controls(lay)
    dmean = np.hstack([held.dmean[:, :len(HELD)], held.dmean[:, len(HELD):][:, order]])
    controls = [lay.control_names[i] for i in order]
    a, bm = assemble(dmean, b, len(controls))
    table, units = derivative_table(dmean, b, controls)
    ref = dict(zip(("U_e", "V_e", "W_e", "P_e", "Q_e", "R_e", "Phi_e", "Theta_e"), map(float, b)))
    ref.update({c: float(sol.controls[c]) for c in controls})
    return Derivatives(sol.scene, sol.speed, a, bm, controls, ref, held.mean, flight_modes(a), held, rotor, sol,
                       table, units, time.perf_counter() - start, rotor.nfwd)


def write_matrices(res: Derivatives, path) -> str:
    """``A``, ``B``, state and control names, eigenvalues to ``path``: ``.mat`` (MATLAB, via
    :func:`scipy.io.savemat`) or ``.npz``."""
    from pathlib import Path

    path = Path(path)
    data = {"A": res.A, "B": res.B, "states": np.array(res.states, dtype=object),
            "controls": np.array(res.controls, dtype=object), "speed": res.speed,
            "eigenvalues": np.array([m.eigenvalue for m in res.modes]),
            "mode_names": np.array([m.name for m in res.modes], dtype=object)}
    if path.suffix.lower() not in (".mat", ".npz"):
        raise ValueError(f"unknown matrix file type {path.suffix!r}: use .mat (MATLAB) or .npz")
    write_matrix_file(path, data)
    return str(path)


def write_matrix_file(path, data: dict) -> None:
    """``data`` (name -> array) as a ``.mat`` (scipy's :func:`~scipy.io.savemat`) or ``.npz`` file
    ``path`` (by its suffix, any case), written atomically; object arrays of names as text."""
    from mbs import atomic

    with atomic.replacing(path) as tmp, open(tmp, "wb") as f:  # a file object: no suffix appended
        if str(path).lower().endswith(".mat"):
            from scipy.io import savemat

            savemat(f, data)
        else:
            np.savez(f, **{k: (v.astype(str) if getattr(v, "dtype", None) == object else v) for k, v in data.items()})
