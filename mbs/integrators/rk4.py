"""Classical fourth-order Runge-Kutta method (the paper's integrator)."""
from mbs.integrators._tableau import ButcherTableau

RK4 = ButcherTableau(
    name="rk4",
    a=((0, 0, 0, 0), (0.5, 0, 0, 0), (0, 0.5, 0, 0), (0, 0, 1.0, 0)),
    b=(1 / 6, 1 / 3, 1 / 3, 1 / 6),
    c=(0, 0.5, 0.5, 1.0),
    order=4,
)
