"""Periodic trim by shooting with the AD monodromy: quadratic convergence, a periodic
solution, the hover collective of blade-element-momentum theory, hover to 70 m/s, the CLI."""
import json

import numpy as np
import pytest

from mbs import scenes
from mbs.analysis.monodromy import TangentStepper
from mbs.analysis.trim import periodic_solution, trim
from mbs.cli import main
from mbs.aircraft import load as load_aircraft
from mbs.models.helicopter import estimate_trim, with_aero

QUADRATIC_C = 10.0  # r_{k+1} <= C r_k^2 + FLOOR once r_k < 1e-4 (measured C: 0.2 .. 7)
FLOOR = 1e-13  # round-off level of the scaled residual (measured 1e-16 .. 2e-15)


@pytest.fixture(scope="module")
def trims():
    """Trims of the forward-flight model by speed (m/s), computed on first use and shared."""
    sc = scenes.get("forward-flight")
    system, stepper, cache = sc.system("compiled"), TangentStepper(sc.model(), "rk4"), {}

    def get(speed: float):
        if speed not in cache:
            cache[speed] = trim("forward-flight", speed=speed, system=system, stepper=stepper)
        return cache[speed]
    get.system, get.stepper = system, stepper
    return get


@pytest.mark.parametrize("speed", [0.0, 10.0, 30.0, 50.0, 70.0])
def test_trim_converges_from_the_estimate(trims, speed):
    res = trims(speed)
    assert res.converged, res.reason
    assert np.abs(res.residual).max() <= 1e-10 and res.iterations <= 8
    assert res.n_jacobian == res.iterations and res.nfwd > 0 and res.nfev > 0 and res.wall_s > 0
    ranges = {q["name"]: (q["low"], q["high"]) for q in trims.system.info.parameters}
    for name, value in res.controls.items():
        assert ranges[name][0] <= value <= ranges[name][1], name


def test_where_newton_from_the_estimate_fails_continuation_in_speed_trims(trims):
    """Climbing at 10 m/s at 60 m/s, Newton from the closed-form estimate (level flight's
    collective) needs more than 4 iterations; with at most 4 per solve it fails, and the
    continuation 10, 20, ... 60 m/s, each solve from the last, converges."""
    res = trim("forward-flight", speed=60.0, climb_rate=10.0, system=trims.system, stepper=trims.stepper,
               max_iterations=4)
    assert res.converged and "continuation in speed over 6 steps" in res.reason, res.reason
    assert np.abs(res.residual).max() <= 1e-10 and res.n_jacobian > res.iterations


@pytest.mark.parametrize("speed", [0.0, 30.0, 70.0])
def test_residual_converges_quadratically(trims, speed):
    r = trims(speed).residuals
    asymptotic = [(a, b) for a, b in zip(r[:-1], r[1:]) if a < 1e-4]
    assert asymptotic and all(b <= QUADRATIC_C * a * a + FLOOR for a, b in asymptotic), r
    assert r[-1] <= 1e-10


@pytest.mark.parametrize("speed", [0.0, 30.0])
def test_a_run_from_the_trim_returns_after_one_period(trims, speed):
    """The model's own driver, from the trimmed state: after the half period (2 revolutions)
    the state is ``S x0`` (teeter reversed), after the period (4 revolutions) ``x0``, for every
    rotor state and the fuselage velocities and rates, to 1e-9 (scaled per radius and rev)."""
    res, system = trims(speed), trims.system
    n = res.period.revs * res.steps_per_rev
    x = system.run(res.x0, 0.0, res.period.revolution / res.steps_per_rev, 2 * n, every=n, p=res.params).x
    names = res.state_names
    keep = [i for i, k in enumerate(names) if k not in ("fuselage.x", "fuselage.y", "fuselage.z")]
    scale = _scales(names, 44.4, 4.91)[keep]
    s = res.period.symmetry(len(names))
    assert np.abs((s * x[1] - x[0])[keep] / scale).max() <= 1e-9
    assert np.abs((x[2] - x[0])[keep] / scale).max() <= 1e-9
    assert np.abs(x[2][:3] - [res.speed * 2 * res.period.duration, 0, 0]).max() < 1e-8


def _scales(names, omega, radius):
    from mbs.analysis.shooting import residual_scales

    return residual_scales(names, omega, radius)


def test_hover_collective_matches_blade_element_momentum_theory():
    """The paper's aerodynamics (every switch off): strip theory on the model's own strips (8
    from the 0.2 R cut-out, linear twist, κ v uniform inflow from momentum theory at the trim's
    mean thrust): within 2 %; and the closed-form estimate (no cut-out) too."""
    res, d = periodic_solution(with_aero(scenes.get("forward-flight"), "none"), speed=0.0), load_aircraft().data
    mr, rho = d["main_rotor"], d["environment"]["rho"]
    big_r, omega, thrust = mr["radius"], mr["omega"], res.thrust
    v = np.sqrt(thrust / (2 * rho * np.pi * big_r**2))
    r0 = mr["root_cutout"] * big_r
    dr = (big_r - r0) / mr["elements"]
    r = r0 + dr * (np.arange(mr["elements"]) + 0.5)
    k = mr["n_blades"] * 0.5 * rho * mr["chord"] * dr * mr["lift_slope"] * (omega * r) ** 2
    theta0 = (thrust - np.sum(k * (mr["twist"] * r / big_r - mr["kappa"] * v / (omega * r)))) / np.sum(k)
    assert res.controls["collective"] == pytest.approx(theta0, rel=0.02)
    assert res.controls["collective"] == pytest.approx(estimate_trim(d, 0.0).collective, rel=0.02)
    assert thrust == pytest.approx(d["aircraft"]["mass"] * d["environment"]["g"], rel=0.01)


def test_heli_trim_reports_and_writes_to_a_user_path(tmp_path, capsys):
    path = tmp_path / "trims.toml"
    assert main(["trim", "forward-flight", "--speed", "30", "--quiet", "--json", "--write", str(path)]) == 0
    captured = capsys.readouterr()
    res, out = json.loads(captured.out), captured.err.splitlines()  # --json: the report on stderr
    assert res["converged"] and res["max_abs_residual"] <= 1e-10 and res["period"]["full_revs"] == 4
    assert set(res["controls"]) == {"collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective"}
    assert res["controls_deg"]["collective"] == pytest.approx(np.degrees(res["controls"]["collective"]))
    assert res["power"] == pytest.approx(res["outputs"]["main_rotor.power"]) and res["power"] > 1e5
    assert res["torque"] * 44.4 == pytest.approx(res["power"], rel=1e-12)
    assert {"main_rotor.inflow_ratio", "tail_rotor.torque", "tail_rotor.power"} <= set(res["outputs"])
    assert any(line.startswith("converged") for line in out) and any("iteration 1" in line for line in out)
    assert '["forward-flight at 30 m/s, MBB Bo105, ' in path.read_text() and res["key"] in path.read_text()


def test_heli_trim_exits_non_zero_when_not_converged(capsys):
    assert main(["trim", "forward-flight", "--speed", "50", "--iterations", "1", "--quiet"]) == 1
    out = capsys.readouterr().out
    assert "NOT CONVERGED: no convergence in 1 iterations" in out
    # the controls printed are labelled as the last iterate, not a trim (a new user's Bell 206 read them as one)
    assert out.index("NOT A TRIM: the values below are the last Newton iterate") < out.index("  collective ")


def test_a_trim_failing_against_a_control_stop_names_the_stop(tmp_path, capsys):
    """The Bo105 with its lateral-cyclic stop at 0.02 rad (the 10 m/s trim needs 0.032 rad; the
    closed-form estimate, 0, is inside the range): the failed trim names the control, its stop and
    the aircraft entry, and the step that left the range."""
    from mbs import aircraft

    text = aircraft.resolve("bo105").read_text()
    line = next(x for x in text.splitlines() if x.startswith("lateral_cyclic_max = "))
    path = tmp_path / "stop.toml"
    path.write_text(text.replace(line, 'lateral_cyclic_max = { value = 0.02, unit = "rad", source = "EST" }'))
    assert main(["trim", "--aircraft", str(path), "--speed", "10", "--quiet"]) == 1
    out = capsys.readouterr().out
    assert "at its high stop 0.02 rad (main_rotor.lateral_cyclic_max)" in out, out
    assert "the smallest step could not be run: parameter 'lateral_cyclic' =" in out


def test_heli_trim_names_the_trimmable_scenes(capsys):
    assert main(["trim", "single-blade"]) == 2
    err = capsys.readouterr().err
    assert "cannot be trimmed" in err and "forward-flight, forward-flight-actuators, forward-flight-swashplate, " \
        "ground-run, hover" in err


def test_clamped_ground_run_trims_its_periodic_rotor_response():
    res = trim("ground-run")
    assert res.converged and res.controls == {} and np.abs(res.residual).max() <= 1e-10


def test_line_search_rescues_newton_where_full_steps_diverge():
    """``atan(z) = 0`` from z = 3: full Newton steps diverge (|z| > 1.39 overshoots), halved
    steps converge, then full steps finish quadratically; trials beyond |z| > 10 fail as a run
    that cannot be evaluated and are halved too."""
    from mbs.analysis.newton import Failure, newton

    def residual(z):
        if abs(z[0]) > 10:
            raise Failure("outside the range")
        return np.arctan(z)

    res = newton(residual, lambda z: np.array([[1 / (1 + z[0] ** 2)]]), np.array([3.0]), tol=1e-14)
    assert res.converged and abs(res.z[0]) < 1e-14
    assert res.history[0].step < 1 and res.history[-1].step == 1
    assert res.n_jacobian == len(res.history) and res.n_residual > res.n_jacobian
