"""Trim of a free-flying helicopter: controls and attitude for steady, level, straight flight.

Unknowns ``z``: the four controls (collective, lateral and longitudinal cyclic, tail-rotor
collective, rad), roll and pitch attitude (rad); the flight path is level along world x at
the given speed with zero sideslip and heading. Residual: the fuselage's mean accelerations
(``u', v', w'`` in m/s², ``p', q', r'`` in rad/s²) over ``average_revs`` revolutions, after
``settle_revs`` revolutions from the trial state. Newton steps with a finite-difference
Jacobian of this residual; between iterations the rotor states (flap, lag, inflow) are carried
over from the previous run at a whole revolution, so they converge to the periodic response.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from mbs import _rotation as rot

CONTROLS = ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective")
FUSELAGE_RATES = ("u", "v", "w", "p", "q", "r")


@dataclass
class Trim:
    """Result of :func:`trim`: controls (rad), attitude (rad), the trimmed state and figures."""

    scene: str
    speed: float
    controls: dict[str, float]
    roll: float
    pitch: float
    state: dict[str, float]
    residual: np.ndarray
    iterations: int
    wall_s: float
    history: list = field(default_factory=list)

    def summary(self) -> dict:
        return {"scene": self.scene, "speed": self.speed, "controls": self.controls, "roll": self.roll,
                "pitch": self.pitch, "max_abs_residual": float(np.abs(self.residual).max()),
                "residual": self.residual.tolist(), "iterations": self.iterations, "wall_s": self.wall_s}


class _Problem:
    """Maps the unknowns to initial states and runs the residual simulations."""

    def __init__(self, system, speed: float, steps_per_rev: int, settle: int, average: int):
        self.system, self.speed = system, speed
        names = system.info.state_names
        self.vel = [names.index(f"fuselage.{k}") for k in FUSELAGE_RATES]
        self.quat = names.index("fuselage.qw")
        self.pos = [names.index(f"fuselage.{k}") for k in "xyz"]
        self.period = 2 * np.pi / system.params()[system.info.param_names.index("omega")]
        self.n, self.settle, self.average = steps_per_rev, settle, average

    def state(self, z: np.ndarray, rotor: np.ndarray) -> np.ndarray:
        x = rotor.copy()
        q = rot.euler_to_quat(z[4], z[5], 0.0)
        x[self.quat:self.quat + 4] = q
        x[self.vel[:3]] = _matrix(q).T @ np.array([self.speed, 0.0, 0.0])
        x[self.vel[3:]] = 0.0
        x[self.pos] = 0.0
        return x

    def residual(self, z: np.ndarray, rotor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p = self.system.params(dict(zip(CONTROLS, z[:4])))
        h = self.period / self.n
        traj = self.system.run(self.state(z, rotor), 0.0, h, (self.settle + self.average) * self.n,
                               every=self.n, p=p)
        if not traj.ok:
            raise RuntimeError(f"trim: the trial run failed ({traj.message})")
        x = traj.x
        acc = (x[self.settle + self.average][self.vel] - x[self.settle][self.vel]) / (self.average * self.period)
        return acc, x[1]


def _matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def trim(scene: str = "forward-flight", system=None, speed: float | None = None, iterations: int = 10,
         steps_per_rev: int = 100, settle_revs: int = 1, average_revs: int = 2, progress=None) -> Trim:
    """Trim ``scene`` (a free-flying helicopter with the four controls) at ``speed`` (m/s).

    Starts from the scene's defaults (its stored trim or the closed-form estimate).
    """
    from mbs import scenes

    sc = scenes.get(scene)
    system = system or sc.system("compiled")
    if speed is None:
        velocity = system.x0()[[system.info.state_names.index(f"fuselage.{k}") for k in "uvw"]]
        speed = round(float(np.linalg.norm(velocity)), 6)
    prob = _Problem(system, speed, steps_per_rev, settle_revs, average_revs)
    x0 = system.x0()
    p0 = system.params()
    z = np.r_[[p0[system.info.param_names.index(c)] for c in CONTROLS], rot.quat_to_euler(x0[prob.quat:prob.quat + 4])[:2]]
    rotor, start, history = x0, time.perf_counter(), []
    for it in range(iterations):
        r, rotor_next = prob.residual(z, rotor)
        history.append(float(np.abs(r).max()))
        z = z - np.linalg.solve(_jacobian(prob, z, rotor, r), r)
        rotor = rotor_next
        if progress:
            progress(it + 1, iterations)
    r, _ = prob.residual(z, rotor)
    state = prob.state(z, rotor)
    return Trim(scene, speed, dict(zip(CONTROLS, map(float, z[:4]))), float(z[4]), float(z[5]),
                dict(zip(system.info.state_names, map(float, state))), r, iterations,
                time.perf_counter() - start, history + [float(np.abs(r).max())])


def _jacobian(prob: _Problem, z, rotor, r, dz: float = 1e-4) -> np.ndarray:
    cols = []
    for j in range(len(z)):
        zz = z.copy()
        zz[j] += dz
        cols.append((prob.residual(zz, rotor)[0] - r) / dz)
    return np.column_stack(cols)
