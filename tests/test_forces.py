"""Point forces and body torques act as Newton and Euler say (analytic accelerations)."""
import numpy as np

import mbs
from mbs import FreeJoint, Model
from mbs.forces import BodyTorque, PointForce

J = np.array([[2.0, 0.3, -0.2], [0.3, 3.0, 0.1], [-0.2, 0.1, 4.5]])


def _free_body(*forces) -> mbs.System:
    m = Model("pushed", gravity=(0, 0, 0))
    m.add_parameter("thrust", 5.0, "N")
    m.add_body("b", "world", FreeJoint(), mass=2.0, com=(0.1, 0, 0), inertia=J)
    for f in forces:
        m.add_force(f)
    return mbs.build(m, "vm")


def test_point_force_off_the_centre_of_mass_and_torque():
    f_body, point, tau = np.array([1.0, 2.0, -3.0]), np.array([0.5, -0.2, 0.3]), np.array([0.4, 0.0, -0.1])
    system = _free_body(PointForce("push", "b", f_body, point), BodyTorque("twist", "b", tau))
    q = np.array([np.cos(0.2), 0, np.sin(0.2), 0])  # rotated body: body and world frames differ
    x = system.x0(**{"b.qw": q[0], "b.qy": q[2]})
    xd = system.rhs(x)
    omega_dot = np.linalg.solve(J, tau + np.cross(point - [0.1, 0, 0], f_body))
    com_acc_body = f_body / 2.0
    # body-frame velocity of the body origin: a_origin = a_com - omega_dot x c (omega = 0)
    assert np.allclose(xd[-3:], omega_dot, rtol=1e-12, atol=1e-14)
    assert np.allclose(xd[7:10], com_acc_body - np.cross(omega_dot, [0.1, 0, 0]), rtol=1e-12, atol=1e-14)


def test_world_frame_force_from_a_parameter():
    system = _free_body(PointForce("lift", "b", (0.0, 0.0, "thrust"), (0.1, 0, 0), frame="world"))
    q = np.array([np.cos(0.3), np.sin(0.3), 0, 0])  # rolled
    x = system.x0(**{"b.qw": q[0], "b.qx": q[1]})
    _, rot = system.poses(x)
    for thrust in (5.0, -2.0):
        xd = system.rhs(x, p={"thrust": thrust})
        assert np.allclose(xd[7:10], rot[0].T @ [0, 0, thrust / 2.0], rtol=1e-12, atol=1e-14)
        assert np.allclose(xd[-3:], 0, atol=1e-14)
