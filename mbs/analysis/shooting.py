"""The periodic-trim equations: unknowns, initial state, residual, and their AD Jacobians.

Unknowns ``z`` of a free-flying model (world: x north, y east, z down; body axes x forward,
y starboard, z down):

* the controls (rad), in the model's order (``collective``, ``lateral_cyclic``,
  ``longitudinal_cyclic``, ``tail_collective`` for the Bo105);
* roll and pitch (rad) at ``t = 0``; the heading is 0: with zero sideslip (the default) the
  aircraft points along the flight path (north) at the start of the period; with a given bank
  (:attr:`FlightPath.bank`) the roll is that bank and the unknown in its place is the sideslip
  ``β`` of the track (the track starts at heading ``β``, to starboard of the nose for ``β > 0``);
* the fuselage's body-axis velocities ``u, v, w`` (m/s) and rates ``p, q, r`` (rad/s) at
  ``t = 0``;
* every rotor state at ``t = 0``: flap, lag, teeter (rad), their rates (rad/s), inflows (m/s).

The initial position is the origin; the azimuths are not states (the hubs are driven), they
advance by ``2π`` per revolution with time. Residual after the shooting interval ``τ``
(:class:`mbs.analysis.period.RotorPeriod`):

* rotor states ``S x(τ) - x(0)`` (``S`` reverses the teeter when ``τ`` is half the period);
* fuselage velocities and rates ``x(τ) - x(0)``;
* attitude: roll, pitch and heading at ``τ`` minus those at 0 (rad), the heading's less the
  turn ``ψ̇ τ`` of a turning flight;
* flight path: the position at ``τ`` minus the flight path's (m): speed ``V`` along the track,
  climb rate ``W`` (up positive), along a circle of radius ``V/ψ̇`` when turning (:class:`FlightPath`).

For a model whose fuselage is clamped (or absent) the unknowns are the rotor states and the
residual their periodicity; the controls stay as given. The maps ``z -> (x(0), p)`` and
``(x(τ), z) -> r`` are small CasADi functions; their Jacobians come from AD.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

BODY_RATES = ("u", "v", "w", "p", "q", "r")
ATTITUDE = ("roll", "pitch")


@dataclass(frozen=True)
class FlightPath:
    """The flight a trim holds: ``speed`` V (m/s, along the track), ``climb_rate`` W (m/s, up),
    ``turn_rate`` ψ̇ (rad/s, the heading's rate, positive turning right) and the attitude
    constraint: ``bank`` None for zero sideslip (the roll a trim unknown), or the roll angle (rad,
    right wing down positive) with the track's sideslip a trim unknown (``bank = 0``: zero bank)."""

    speed: float = 0.0
    climb_rate: float = 0.0
    turn_rate: float = 0.0
    bank: float | None = None

    @property
    def constraint(self) -> str:
        return "zero sideslip" if self.bank is None else "zero bank" if self.bank == 0 else "given bank"

    def chord(self, duration: float) -> np.ndarray:
        """Where the aircraft is after ``duration`` (s) from the origin, in axes of the track at
        the start (x along it, y to its right, z down), m (3,)."""
        turn = self.turn_rate * duration
        along, across = (1.0, 0.0) if turn == 0 else (np.sin(turn) / turn, (1 - np.cos(turn)) / turn)
        return np.array([self.speed * duration * along, self.speed * duration * across, -self.climb_rate * duration])


@dataclass
class TrimLayout:
    """Where the unknowns live in the state (indices into ``x``) and parameters (into ``p``)."""

    state_names: list[str]
    free: bool
    position: list[int]
    quaternion: list[int]
    body: list[int]
    rotor: list[int]
    controls: list[int]
    control_names: list[str]
    sideslip: bool = False  # the first attitude unknown is the track's sideslip (roll given), not the roll

    @classmethod
    def of(cls, info, sideslip: bool = False) -> "TrimLayout":
        """The layout of a model described by ``info`` (:class:`mbs.backends.info.ModelInfo`);
        ``sideslip``: the roll is given and the track's sideslip is an unknown in its place."""
        names = info.state_names
        free = "fuselage.qw" in names
        idx = lambda keys: [names.index(f"fuselage.{k}") for k in keys] if free else []  # noqa: E731
        fuselage = set(idx("xyz") + idx(("qw", "qx", "qy", "qz")) + idx(BODY_RATES))
        controls = [i for i, q in enumerate(info.parameters) if _flight_control(q)] if free else []
        return cls(names, free, idx("xyz"), idx(("qw", "qx", "qy", "qz")), idx(BODY_RATES),
                   [i for i in range(len(names)) if i not in fuselage], controls,
                   [info.parameters[i]["name"] for i in controls], sideslip and free)

    @property
    def unknown_names(self) -> list[str]:
        attitude = ("sideslip", "pitch") if self.sideslip else ATTITUDE
        body = [*attitude, *(self.state_names[i] for i in self.body)] if self.free else []
        return [*self.control_names, *body, *(self.state_names[i] for i in self.rotor)]

    @property
    def residual_names(self) -> list[str]:
        rotor = [self.state_names[i] for i in self.rotor]
        if not self.free:
            return rotor
        return [*rotor, *(self.state_names[i] for i in self.body), "roll", "pitch", "heading",
                "fuselage.x", "fuselage.y", "fuselage.z"]

    def split(self, z):
        """``(controls, attitude (roll, pitch), body velocities and rates, rotor states)`` of ``z``."""
        nc, nb = len(self.controls), len(self.body)
        na = 2 if self.free else 0
        return z[:nc], z[nc:nc + na], z[nc + na:nc + na + nb], z[nc + na + nb:]


def _flight_control(q: dict) -> bool:
    """A pilot's flight control (pitch of the blades or the swashplate), which a trim solves for; an
    engine's throttle is an input the trim holds."""
    return bool(q.get("control")) and not q["name"].endswith("_throttle")


def quaternion(roll, pitch):
    """Unit quaternion (w, x, y, z) of roll and pitch (rad) at zero heading (SX or numbers)."""
    cr, sr, cp, sp = ca.cos(roll / 2), ca.sin(roll / 2), ca.cos(pitch / 2), ca.sin(pitch / 2)
    return ca.vertcat(cr * cp, sr * cp, cr * sp, -sr * sp)


def euler_angles(q):
    """Roll, pitch, heading (rad) of a quaternion (w, x, y, z), not necessarily unit (SX)."""
    w, x, y, z = (q[i] / ca.norm_2(q) for i in range(4))
    return ca.vertcat(ca.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)),
                      ca.asin(2 * (w * y - z * x)),
                      ca.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))


def start_function(lay: TrimLayout, nx: int, n_params: int, bank: float = 0.0) -> ca.Function:
    """``start(z, p_base) -> (x0 (nx,), p (np,), dx0/dz, dp/dz)``: the initial state and
    parameters of the unknowns, and their Jacobians (AD); ``bank`` (rad) the roll when the
    layout's first attitude unknown is the sideslip."""
    z, pb = ca.SX.sym("z", len(lay.unknown_names)), ca.SX.sym("p_base", n_params)
    controls, attitude, body, rotor = lay.split(z)
    x = [ca.SX(0)] * nx
    p = [pb[i] for i in range(n_params)]
    for i, k in enumerate(lay.controls):
        p[k] = controls[i]
    q = quaternion(bank if lay.sideslip else attitude[0], attitude[1]) if lay.free else []
    for idx, values in ((lay.quaternion, q), (lay.body, body), (lay.rotor, rotor)):
        for i, k in enumerate(idx):
            x[k] = values[i]
    x, p = ca.vertcat(*x), ca.vertcat(*p)
    return ca.Function("start", [z, pb], [x, p, ca.jacobian(x, z), ca.jacobian(p, z)],
                       ["z", "p_base"], ["x0", "p", "dx0_dz", "dp_dz"])


def residual_function(lay: TrimLayout, nx: int, symmetry: np.ndarray, turn: float = 0.0,
                      bank: float = 0.0, source=None) -> ca.Function:
    """``residual(x_end, z, path) -> (r, dr/dx_end, dr/dz)``; ``path`` (3,) is the end of the
    interval in the axes of the track at its start (:meth:`FlightPath.chord`, m), ``symmetry``
    (nx,) the signs of ``S`` and ``source`` (nx,) the states it exchanges (``(S x)[k] =
    symmetry[k] x[source[k]]``; None: none), ``turn`` the heading's change over the interval
    (rad), ``bank`` the roll (rad) when the layout's first attitude unknown is the track's
    sideslip (which then turns ``path`` from the nose's heading)."""
    xe, z, path = ca.SX.sym("x_end", nx), ca.SX.sym("z", len(lay.unknown_names)), ca.SX.sym("path", 3)
    _, attitude, body, rotor = lay.split(z)
    source = range(nx) if source is None else source
    r = [ca.vertcat(*[symmetry[k] * xe[source[k]] for k in lay.rotor]) - rotor]
    if lay.free:
        end_attitude = euler_angles(ca.vertcat(*[xe[k] for k in lay.quaternion]))
        start = ca.vertcat(bank, attitude[1]) if lay.sideslip else attitude
        change = end_attitude - ca.vertcat(start, turn)
        if turn:  # the heading wraps at ±π
            change[2] = ca.atan2(ca.sin(change[2]), ca.cos(change[2]))
        target = path
        if lay.sideslip:
            c, s = ca.cos(attitude[0]), ca.sin(attitude[0])
            target = ca.vertcat(c * path[0] - s * path[1], s * path[0] + c * path[1], path[2])
        r += [ca.vertcat(*[xe[k] for k in lay.body]) - body,
              change, ca.vertcat(*[xe[k] for k in lay.position]) - target]
    r = ca.vertcat(*r)
    return ca.Function("residual", [xe, z, path], [r, ca.jacobian(r, xe), ca.jacobian(r, z)],
                       ["x_end", "z", "path"], ["r", "dr_dx", "dr_dz"])


def residual_scales(names: list[str], omega: float, radius: float) -> np.ndarray:
    """Scale of each residual: lengths ``R`` (m), speeds ``ΩR`` (m/s), rates ``Ω`` (rad/s),
    angles 1 rad; dividing by it makes the residual per rotor radius and revolution."""
    def scale(name: str) -> float:
        key = name.rsplit(".", 1)[-1]
        if name.startswith("fuselage.") and key in "xyz":
            return radius
        if key in ("u", "v", "w") or key.startswith("inflow"):
            return abs(omega) * radius
        if key in ("p", "q", "r") or key.endswith("_rate"):
            return abs(omega)
        return 1.0
    return np.array([scale(n) for n in names])
