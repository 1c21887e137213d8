"""Floquet analysis at the periodic solution: the single blade's exponents against the closed
forms, and the Bo105 in hover (neutral heading, rotor modes named and placed)."""
import json

import numpy as np
import pytest

import mbs
from mbs import scenes
from mbs.analysis import flap_lag_frequencies
from mbs.analysis.floquet import analyse, floquet
from mbs.analysis.monodromy import TangentStepper
from mbs.analysis.trim import periodic_solution
from mbs.cli import main
from mbs.models import bo105


def _closed_form(system):
    b, mr = system.info.bodies[system.info.body_names.index("blade1")], bo105.load_data()["main_rotor"]
    return flap_lag_frequencies(b["mass"], b["com"], b["inertia"], mr["flap_hinge_offset"], mr["flap_stiffness"],
                                mr["lag_stiffness"], mr["omega"])


def _single_blade_modes(gravity: bool):
    sc = scenes.get("single-blade")
    model = sc.model()
    if not gravity:
        model.gravity = np.zeros(3)
    system, stepper = mbs.build(model, "compiled"), TangentStepper(model, "rk4")
    sol = periodic_solution(sc, steps_per_rev=200, system=system, stepper=stepper)
    return {m.name: m for m in analyse(sol, system, stepper).modes}, _closed_form(system)


def test_single_blade_exponents_equal_the_closed_forms():
    """Without gravity the periodic solution is the undeflected blade, about which the closed
    forms linearise: frequencies to 1e-6 (measured 1e-8, 2e-9), no damping (RK4 at 200 steps
    per revolution: |Re λ| < 1e-7 |λ|). With gravity the blade droops by 1.2 mrad and the
    frequencies move by 3e-6."""
    modes, (nu_flap, nu_lag) = _single_blade_modes(gravity=False)
    assert set(modes) == {"flap", "lag"}
    assert modes["flap"].per_rev == pytest.approx(nu_flap, rel=1e-6)
    assert modes["lag"].per_rev == pytest.approx(nu_lag, rel=1e-6)
    for m in modes.values():
        assert abs(m.exponent.real) < 1e-7 * abs(m.exponent) and abs(abs(m.multiplier) - 1) < 1e-6
    drooped, _ = _single_blade_modes(gravity=True)
    assert drooped["flap"].per_rev == pytest.approx(nu_flap, rel=1e-5)
    assert drooped["lag"].per_rev == pytest.approx(nu_lag, rel=1e-5)


def test_hover_modes(capsys):
    """Hover trim: the heading mode is neutral, the lag modes sit near the blade's 0.68/rev
    with the damper's few per cent, the flap modes near 1/rev are well damped (Lock number 5),
    the teeter near the tail rotor's 1/rev (5.25/rev of the main rotor)."""
    assert main(["floquet", "hover", "--json"]) == 0
    res = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    modes = res["modes"]
    assert min(abs(np.hypot(*m["multiplier"]) - 1) for m in modes) < 1e-9  # heading
    lag = [m for m in modes if m["name"] == "lag"]
    flap = [m for m in modes if m["name"] == "flap" and m["per_rev"] > 0.5]
    teeter = [m for m in modes if m["name"] == "tail rotor" and m["per_rev"] > 1]
    assert len(lag) == 4 and all(0.6 < m["per_rev"] < 0.85 and 0.02 < m["damping_ratio"] < 0.1 for m in lag)
    assert flap and all(0.9 < m["per_rev"] < 1.3 and m["damping_ratio"] > 0.1 for m in flap)
    assert len(teeter) == 1 and teeter[0]["per_rev"] == pytest.approx(5.25, rel=0.02)
    assert res["period_revs"] == 4 and res["interval_revs"] == 2


def test_floquet_rejects_scenes_without_a_periodic_solution():
    with pytest.raises(ValueError, match="no periodic solution"):
        floquet("structural")
