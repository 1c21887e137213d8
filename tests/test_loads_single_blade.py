"""A single blade on a flap hinge with a spring, in steady rotation and at rest: its root
shear and moments equal the closed forms (centrifugal force ``m Ω² r_cg``, spring moment
``k β``, the droop balance) to 1e-8.

The blade (mass ``m``, centre of mass at ``x_cg`` on its span axis, principal inertia ``J``
about it) hangs on a flap hinge at ``e`` from a vertical shaft turning at ``Ω``, then a lag
hinge; gravity ``g`` acts down the shaft. With ``A = Σ m ξ² = m x_cg² + (J_yy + J_zz - J_xx)/2``
and ``C = Σ m ζ² = (J_xx + J_yy - J_zz)/2``, the steady flap angle ``β`` (tip up) makes the
potential ``k β²/2 + m g x_cg sin β - Ω²/2 (2 e m x_cg cos β + A cos² β + C sin² β)``
stationary:

    k β = -m g x_cg cos β - Ω² sin β (e m x_cg + (A - C) cos β)

and the hub holds the blade with the force ``-m Ω² r_cg`` (radial, ``r_cg = e + x_cg cos β``)
and ``m g`` (up), and the moment ``k β`` about the flap axis (nothing about the others).
"""
import numpy as np
import pytest
from scipy.optimize import brentq

import mbs
from mbs import DrivenHinge, Hinge, Model, Serial
from mbs.loads.outputs import add_joint_loads

MASS, X_CG, E, K_FLAP, K_LAG, G = 30.0, 2.4, 0.3, 1.2e5, 2.0e5, 9.80665
J = np.diag([0.2, 55.0, 55.1])
A = MASS * X_CG**2 + (J[1, 1] + J[2, 2] - J[0, 0]) / 2
C = (J[0, 0] + J[1, 1] - J[2, 2]) / 2
TOL = 1e-8


def blade(omega: float):
    m = Model("flap-blade", gravity=(0, 0, -G))  # z up the shaft
    m.add_body("hub", "world", DrivenHinge((0, 0, 1), lambda t, p: omega * t, name="azimuth"), mass=20.0,
               inertia=np.diag([1.0, 1.0, 1.5]))
    m.add_body("blade", "hub", Serial(Hinge((0, -1, 0), name="flap", stiffness=K_FLAP),
                                      Hinge((0, 0, -1), name="lag", stiffness=K_LAG)),
               mass=MASS, com=(X_CG, 0, 0), inertia=J, at=(E, 0, 0))
    add_joint_loads(m, "blade", "blade.root")
    return mbs.build(m, "vm")


def steady_flap(omega: float) -> float:
    """The closed form's root ``β`` (rad)."""
    def moment(beta):
        return (K_FLAP * beta + MASS * G * X_CG * np.cos(beta)
                + omega**2 * np.sin(beta) * (E * MASS * X_CG + (A - C) * np.cos(beta)))
    return brentq(moment, -0.5, 0.5, xtol=1e-15)


def root_loads(system, beta: float, t: float = 0.37) -> tuple[np.ndarray, np.ndarray]:
    x = system.x0(**{"blade.flap": beta})
    assert np.abs(system.rhs(x, t)[system.info.nq:]).max() < 1e-9  # the closed form is the model's equilibrium
    y = system.outputs(x, t)
    return y[:3], y[3:]


@pytest.mark.parametrize("omega", [30.0, 44.4])
def test_steady_rotation_centrifugal_force_weight_and_spring_moment(omega):
    beta = steady_flap(omega)
    force, moment = root_loads(blade(omega), beta)
    c, s = np.cos(beta), np.sin(beta)
    radial, up = force[0] * c - force[2] * s, force[0] * s + force[2] * c  # blade axes -> hub axes
    centrifugal = MASS * omega**2 * (E + X_CG * c)
    assert -radial == pytest.approx(centrifugal, rel=TOL)
    assert up == pytest.approx(MASS * G, rel=TOL) and abs(force[1]) <= TOL * centrifugal
    assert moment[1] == pytest.approx(K_FLAP * beta, rel=TOL)
    droop_balance = -MASS * G * X_CG * c - omega**2 * s * (E * MASS * X_CG + (A - C) * c)
    assert moment[1] == pytest.approx(droop_balance, rel=TOL)
    assert abs(moment[0]) <= TOL * abs(moment[1]) and abs(moment[2]) <= TOL * abs(moment[1])


def test_at_rest_the_spring_holds_the_drooping_blade():
    """Ω = 0: the spring moment ``k β`` balances the weight's ``m g x_cg cos β`` (β < 0, tip down)."""
    beta = steady_flap(0.0)
    force, moment = root_loads(blade(0.0), beta)
    assert beta < 0
    assert moment[1] == pytest.approx(K_FLAP * beta, rel=TOL)
    assert moment[1] == pytest.approx(-MASS * G * X_CG * np.cos(beta), rel=TOL)
    assert force[0] * np.sin(beta) + force[2] * np.cos(beta) == pytest.approx(MASS * G, rel=TOL)
    assert abs(force[0] * np.cos(beta) - force[2] * np.sin(beta)) <= TOL * MASS * G
