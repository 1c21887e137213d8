"""Periodic trim of a scene whose rotor speed is a state: steady flight at a given rotor speed.

The drive train's azimuth advances by ``2π`` per revolution instead of following the clock, so
the trim of :mod:`mbs.analysis.trim` takes one more equation and one more unknown:

* the azimuth starts at 0 and must advance by ``2π · revs`` (in the rotor's sense) over the
  shooting interval ``revs · 2π/Ω``: the period-mean rotor speed is the requested ``Ω``; the
  azimuth rate joins the periodic rotor states;
* the extra unknown is what holds that speed: the descent rate in a steady **autorotation**
  (zero drive torque, no engine: the climb rate ``W`` of the flight path is solved for), or a
  run-time parameter in powered flight (``drive_torque``, or the engines' ``governor_speed``).

Everything else is the trim of :mod:`mbs.analysis.shooting` (controls, attitude, body velocities
and rates, rotor states; the same residual scaling and the exact AD Jacobian of the discrete
period map); Newton with the backtracking line search of :mod:`mbs.analysis.newton`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs.analysis.newton import newton
from mbs.analysis.period import periodic_scene, scene_period
from mbs.analysis.shooting import TrimLayout, euler_angles, quaternion, residual_scales
from mbs.analysis.trim import ShootingProblem

AZIMUTH = "main_hub.azimuth"
CLIMB = "climb_rate"


@dataclass
class SpeedLayout:
    """The unknowns of a rotor-speed trim: the base layout's without the azimuth, plus ``extra``
    (:data:`CLIMB` or a parameter name)."""

    base: TrimLayout
    azimuth: int
    rotor: list[int]
    extra: str
    extra_param: int | None

    @classmethod
    def of(cls, info, extra: str) -> "SpeedLayout":
        base = TrimLayout.of(info)
        if not base.free:
            raise ValueError("a rotor-speed trim flies: the scene needs a free fuselage")
        if AZIMUTH not in info.state_names or "transmission.angle" in info.state_names:
            raise ValueError("a rotor-speed trim needs the rotor speed as a state on a rigid drive train "
                             "(drive_train = 'rigid')")
        az = info.state_names.index(AZIMUTH)
        names = [p["name"] for p in info.parameters]
        if extra != CLIMB and extra not in names:
            raise ValueError(f"the trim's extra unknown {extra!r} is neither the climb rate nor a parameter "
                             f"({', '.join(names)})")
        return cls(base, az, [i for i in base.rotor if i != az], extra,
                   None if extra == CLIMB else names.index(extra))

    @property
    def unknown_names(self) -> list[str]:
        b = self.base
        return [*b.control_names, "roll", "pitch", *(b.state_names[i] for i in b.body),
                *(b.state_names[i] for i in self.rotor), self.extra]

    @property
    def residual_names(self) -> list[str]:
        b = self.base
        return [*(b.state_names[i] for i in self.rotor), AZIMUTH, *(b.state_names[i] for i in b.body), "roll",
                "pitch", "heading", "fuselage.x", "fuselage.y", "fuselage.z"]

    def split(self, z):
        nc, nb, nr = len(self.base.controls), len(self.base.body), len(self.rotor)
        return z[:nc], z[nc:nc + 2], z[nc + 2:nc + 2 + nb], z[nc + 2 + nb:nc + 2 + nb + nr], z[-1]


def start_function(lay: SpeedLayout, nx: int, n_params: int) -> ca.Function:
    """``start(z, p_base) -> (x0, p, dx0/dz, dp/dz)``: the azimuth at 0."""
    z, pb = ca.SX.sym("z", len(lay.unknown_names)), ca.SX.sym("p_base", n_params)
    controls, attitude, body, rotor, extra = lay.split(z)
    x, p = [ca.SX(0)] * nx, [pb[i] for i in range(n_params)]
    for i, k in enumerate(lay.base.controls):
        p[k] = controls[i]
    if lay.extra_param is not None:
        p[lay.extra_param] = extra
    q = quaternion(attitude[0], attitude[1])
    for idx, values in ((lay.base.quaternion, q), (lay.base.body, body), (lay.rotor, rotor)):
        for i, k in enumerate(idx):
            x[k] = values[i]
    x, p = ca.vertcat(*x), ca.vertcat(*p)
    return ca.Function("start", [z, pb], [x, p, ca.jacobian(x, z), ca.jacobian(p, z)])


def residual_function(lay: SpeedLayout, nx: int, symmetry: np.ndarray, advance: float, duration: float,
                      speed: float, climb_rate: float) -> ca.Function:
    """``residual(x_end, z) -> (r, dr/dx_end, dr/dz)``: periodic rotor states, the azimuth's
    ``advance`` (rad), the body's periodicity and attitude, the flight path at ``speed`` (m/s)
    and the climb rate (the unknown, or ``climb_rate``) over ``duration`` (s)."""
    xe, z = ca.SX.sym("x_end", nx), ca.SX.sym("z", len(lay.unknown_names))
    _, attitude, body, rotor, extra = lay.split(z)
    climb = extra if lay.extra == CLIMB else climb_rate
    path = ca.vertcat(speed * duration, 0, -climb * duration)
    end_attitude = euler_angles(ca.vertcat(*[xe[k] for k in lay.base.quaternion]))
    r = ca.vertcat(ca.vertcat(*[symmetry[k] * xe[k] for k in lay.rotor]) - rotor, xe[lay.azimuth] - advance,
                   ca.vertcat(*[xe[k] for k in lay.base.body]) - body, end_attitude - ca.vertcat(attitude, 0),
                   ca.vertcat(*[xe[k] for k in lay.base.position]) - path)
    return ca.Function("residual", [xe, z], [r, ca.jacobian(r, xe), ca.jacobian(r, z)])


@dataclass
class SpeedTrim:
    """A rotor-speed trim: unknowns by name, the state at ``t = 0``, parameters, Newton's record;
    ``torque_balance``: the drive train's angular momentum gained over the period per period
    and per the hover torque scale (0 at a periodic solution); ``mean_torque``: the period mean
    of the aerodynamic torque on the drive train, main rotor plus gear ratio times tail rotor (N m)."""

    scene: str
    speed: float
    omega: float
    unknowns: dict[str, float]
    x0: np.ndarray
    params: np.ndarray
    converged: bool
    reason: str
    iterations: int
    residual: float
    residuals: list[float] = field(default_factory=list)
    mean_torque: float | None = None
    torque_balance: float | None = None
    wall_s: float = 0.0

    @property
    def climb_rate(self) -> float:
        return self.unknowns.get(CLIMB, 0.0)


class SpeedProblem(ShootingProblem):
    """Residual and Jacobian of a rotor-speed trim of ``system`` (its tangent ``stepper``): the
    shooting problem of :mod:`mbs.analysis.trim` with the azimuth's advance and the extra unknown."""

    def __init__(self, system, stepper, sc, speed: float, omega: float, extra: str, climb_rate: float,
                 steps_per_rev: int):
        info = system.info
        self.system, self.stepper, self.speed, self.omega = system, stepper, speed, omega
        self.radius = sc.aircraft.data["main_rotor"]["radius"]
        self.lay = SpeedLayout.of(info, extra)
        period = scene_period(periodic_scene(sc), system)  # a tail rotor repeating late: the nearest ratio's
        self.period = period
        self.h = 2 * np.pi / omega / steps_per_rev
        self.n = period.revs * steps_per_rev
        sense = 1.0 if sc.aircraft.data["main_rotor"]["rotation"] == "counter-clockwise" else -1.0
        self.p_base, self.path = system.params(), None
        self._start = start_function(self.lay, info.nx, len(self.p_base))
        residual = residual_function(self.lay, info.nx, period.symmetry(info.nx), sense * 2 * np.pi * period.revs,
                                     self.h * self.n, speed, climb_rate)
        self._residual = lambda x, z, _path: residual(x, z)  # the flight path is in the residual itself
        self.scale = residual_scales(self.lay.residual_names, omega, self.radius)
        self.nfwd = 0


def estimate(system, lay: SpeedLayout, sc, speed: float, extra_value: float) -> np.ndarray:
    """Starting unknowns: the closed-form level-flight estimate at ``speed`` with the rotor at its
    nominal speed and ``extra_value`` as the extra unknown; in autorotation the collective lowered
    by the descent's inflow, ``Δθ0 = (W/ΩR) / (2 (1/3 + μ²/2))``."""
    from mbs.analysis.trim import estimate as level

    d = sc.aircraft.data
    z_base = level(system, lay.base, speed, 0.0, sc.aircraft)
    nc, nb = len(lay.base.controls), len(lay.base.body)
    controls, attitude, body = z_base[:nc], z_base[nc:nc + 2], z_base[nc + 2:nc + 2 + nb]
    x = system.x0()
    rotor_all = dict(zip(lay.base.rotor, z_base[nc + 2 + nb:]))
    sense = 1.0 if d["main_rotor"]["rotation"] == "counter-clockwise" else -1.0
    rotor_all[lay.base.state_names.index("main_hub.azimuth_rate")] = sense * d["main_rotor"]["omega"]
    for i in lay.rotor:  # states the level estimate leaves at zero keep the scene's start (engines' states)
        if rotor_all.get(i, 0.0) == 0.0:
            rotor_all[i] = x[i]
    if lay.extra == CLIMB:
        tip, mu = d["main_rotor"]["omega"] * d["main_rotor"]["radius"], speed / (d["main_rotor"]["omega"]
                                                                               * d["main_rotor"]["radius"])
        collective = lay.base.control_names.index("collective")
        controls = controls.copy()
        controls[collective] += (extra_value / tip) / (2 * (1 / 3 + mu**2 / 2))
        body = body.copy()
        body[:3] += _turn_down(attitude, extra_value)
    return np.r_[controls, attitude, body, [rotor_all[i] for i in lay.rotor], extra_value]


def _turn_down(attitude, climb: float) -> np.ndarray:
    """Body-axis components of a climb velocity ``climb`` (m/s, up) at the attitude (roll, pitch)."""
    from mbs import _rotation as rot

    r = np.asarray(rot.quat_to_matrix(rot.euler_to_quat(attitude[0], attitude[1], 0.0)), dtype=float)
    return r.T @ np.array([0.0, 0.0, -climb])


def descent_estimate(sc, speed: float) -> float:
    """Climb rate (m/s, negative: descending) of an autorotation at ``speed`` by the energy
    method: the level-flight power of the closed-form estimate at that speed over the weight."""
    from mbs.models.helicopter import estimate_trim

    d = sc.aircraft.data
    e = estimate_trim(d, speed)
    weight = d["aircraft"]["mass"] * d["environment"]["g"]
    return -e.power / weight


def rotor_speed_trim(sc, speed: float, extra: str = CLIMB, climb_rate: float = 0.0, omega: float | None = None,
                     steps_per_rev: int | None = None, tol: float = 1e-10, max_iterations: int = 20,
                     system=None, stepper=None, progress=None) -> SpeedTrim:
    """Trim the scene ``sc`` (rotor speed a state, rigid drive train, free fuselage) at ``speed``
    (m/s) with the rotor turning at ``omega`` (rad/s, default nominal): in autorotation (``extra``
    :data:`CLIMB`, the descent rate solved for) or powered (``extra`` a parameter, at
    ``climb_rate`` m/s)."""
    from mbs.analysis.trim import evaluators

    start = time.perf_counter()
    if system is None or stepper is None:
        system, stepper = evaluators(sc)
    d = sc.aircraft.data
    omega = omega or d["main_rotor"]["omega"]
    prob = SpeedProblem(system, stepper, sc, speed, omega, extra, climb_rate, steps_per_rev or sc.steps_per_rev)
    guess = descent_estimate(sc, speed) if extra == CLIMB else float(system.params()[prob.lay.extra_param])
    res = newton(prob.residual, prob.jacobian, estimate(system, prob.lay, sc, speed, guess), tol, max_iterations,
                 progress=progress)
    out = SpeedTrim(sc.name, speed, omega, dict(zip(prob.lay.unknown_names, map(float, res.z))),
                    *prob.start(res.z)[:2], res.converged, res.reason, len(res.history),
                    float(np.abs(res.r).max()), res.residuals, wall_s=time.perf_counter() - start)
    if res.converged:
        out.mean_torque, out.torque_balance = _torque_figures(prob, res.z, d)
    return out


def _torque_figures(prob: SpeedProblem, z, d) -> tuple[float, float]:
    """Period mean of the rotors' aerodynamic torque on the drive train (N m), and the drive
    train's momentum gained over the period per period over the level-flight hover torque
    scale (dimensionless): the torque balance."""
    traj = prob.run(z, every=1)
    p = prob.start(z)[1]
    info = prob.system.info
    y = prob.system.history("outputs", traj, p)[1:]
    names = info.output_names
    gear = d["tail_rotor"]["gear_ratio"]
    torque = y[:, names.index("main_rotor.torque")]
    if "tail_rotor.torque" in names:
        torque = torque + gear * y[:, names.index("tail_rotor.torque")]
    x0, x1 = traj.x[0], traj.x[-1]
    momentum = _momentum(prob.system, x0, p), _momentum(prob.system, x1, p)
    duration = prob.h * prob.n
    scale = d["aircraft"]["mass"] * d["environment"]["g"] * d["main_rotor"]["radius"] * 0.05  # ~ the hover torque
    return float(torque.mean()), float((momentum[1] - momentum[0]) / duration / scale)


def _momentum(system, x, p) -> float:
    """The drive train's generalized momentum ``(J_uᵀ M V)_ψ`` (N m s): its angular momentum."""
    info = system.info
    v, ju, _ = system.kinematics(x, 0.0, p)
    mv = np.concatenate([np.r_[b["mass"] * v[6 * k:6 * k + 3], np.asarray(b["inertia"]) @ v[6 * k + 3:6 * k + 6]]
                         for k, b in enumerate(info.bodies)])
    return float(ju[:, info.v_names.index(AZIMUTH + "_rate")] @ mv)
