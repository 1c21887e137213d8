"""Analytic solutions: pendulum period, torque-free rigid body, steady precession of a top."""
import numpy as np

import mbs
from mbs import FreeJoint, Hinge, Model, Serial

G = 9.81


def _crossing_period(t, y) -> float:
    """Mean period from upward zero crossings (linear interpolation)."""
    i = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(np.mean(np.diff(tc)))


def test_small_angle_pendulum_period():
    m, l, ic = 2.0, 0.8, 0.05
    model = Model("pendulum", gravity=(0, 0, G))
    model.add_body("rod", "world", Hinge(axis=(0, 1, 0)), mass=m, com=(0, 0, l),
                   inertia=np.diag([ic, ic, 0.01]))
    system = mbs.build(model, "vm")
    period = 2 * np.pi * np.sqrt((ic + m * l**2) / (m * G * l))
    x0 = system.x0(**{"rod.angle": 1e-4})
    traj = system.run(x0, 0.0, period / 400, 400 * 5)
    measured = _crossing_period(traj.t, traj.column("rod.angle"))
    assert abs(measured / period - 1) < 1e-6


def test_torque_free_asymmetric_body_keeps_energy_and_momentum():
    j = np.array([[2.0, 0.3, -0.2], [0.3, 3.0, 0.1], [-0.2, 0.1, 4.5]])
    model = Model("tumbling", gravity=(0, 0, 0))
    model.add_body("body", "world", FreeJoint(), mass=3.0, inertia=j)
    system = mbs.build(model, "vm")
    x0 = system.x0(**{"body.u": 0.4, "body.p": 0.3, "body.q": 2.0, "body.r": 0.5})
    traj = system.run(x0, 0.0, 1e-3, 5000, every=50)

    def momentum(x):
        _, rot = system.poses(x)
        return rot[0] @ j @ x[-3:]

    e = np.array([system.energy(x)[-1] for x in traj.x])
    lw = np.array([momentum(x) for x in traj.x])
    assert np.abs(traj.x[-1][-3:] - x0[-3:]).max() > 0.1  # it really tumbles
    assert np.abs(e / e[0] - 1).max() < 1e-9
    assert np.abs(lw - lw[0]).max() < 1e-9 * np.linalg.norm(lw[0])


def test_heavy_symmetric_top_keeps_steady_precession():
    m, l, i1c, i3 = 1.0, 0.1, 0.005, 0.008
    i1 = i1c + m * l**2
    theta, precession = 0.3, 2.0
    omega3 = (m * G * l / precession + i1 * precession * np.cos(theta)) / i3
    model = Model("top", gravity=(0, 0, -G))
    euler_zxz = Serial(Hinge((0, 0, 1), name="precession"), Hinge((1, 0, 0), name="nutation"),
                       Hinge((0, 0, 1), name="spin"))
    model.add_body("top", "world", euler_zxz, mass=m, com=(0, 0, l), inertia=np.diag([i1c, i1c, i3]))
    system = mbs.build(model, "vm")
    x0 = system.x0(**{"top.nutation": theta, "top.precession_rate": precession,
                      "top.spin_rate": omega3 - precession * np.cos(theta)})
    traj = system.run(x0, 0.0, 2e-4, 10000, every=100)
    assert np.abs(traj.column("top.nutation") - theta).max() < 1e-7
    assert np.abs(traj.column("top.precession_rate") / precession - 1).max() < 1e-7
    assert abs(traj.column("top.precession")[-1] - precession * traj.t[-1]) < 1e-6
