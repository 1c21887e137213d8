"""Extra first-order states (e.g. induced inflow) integrate next to the joint coordinates."""
import numpy as np

import mbs
from mbs import Hinge, Model, UserForce


def test_first_order_lag_state_matches_exponential():
    m = Model("lag-state", gravity=(0, 0, 0))
    m.add_body("a", "world", Hinge((0, 0, 1)), mass=1.0, com=(1, 0, 0), inertia=np.eye(3) * 0.1)
    m.add_state("z", 2.0, "m/s")
    m.add_force(UserForce("decay", lambda s, loads: loads.set_rate("z", -3.0 * s.z("z"))))
    for backend in ("vm", "compiled"):
        system = mbs.build(m, backend)
        assert system.info.state_names[-1] == "z" and system.info.nx == 3
        traj = system.run(system.x0(), 0.0, 1e-3, 1000)
        assert abs(traj.column("z")[-1] - 2.0 * np.exp(-3.0)) < 1e-10
