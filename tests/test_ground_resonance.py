"""Ground resonance: the Floquet route against Coleman and Feingold's constant-coefficient
equations in multi-blade coordinates, written here from first principles, and the fan-plot sweep.

Linear equations (lag ``ζ_k`` positive against the rotation, blade ``k`` at ``ψ_k = Ω t + π (k-1)/2``;
fuselage lateral ``y`` (m) and roll ``φ`` (rad) about the gear axis on the ground; hub lateral
displacement ``y_h = y + h φ``). A blade on a lag hinge at offset ``e`` with mass ``m``, first
moment ``S`` and inertia ``I`` about the hinge, spring ``K`` and damper ``C``:

    I ζ_k'' + C ζ_k' + (K + e S Ω²) ζ_k - S cos ψ_k y_h'' = 0

(Lagrange's equation of the kinetic energy of the blade as a rigid body turning about the moving
hinge). The rotor's lateral force on the hub is ``-d²/dt² Σ (m y_h + S sin(ψ_k - ζ_k))``, which in
multi-blade coordinates ``ζ_k = ζ0 + ζ1c cos ψ_k + ζ1s sin ψ_k + ζd (-1)^(k-1)`` is
``-(N m y_h'' - N S / 2 ζ1c'')``; it acts at the hub, ``h`` above the roll axis. Projecting the lag
equations on ``cos ψ_k`` and ``sin ψ_k`` gives

    I (ζ1c'' + 2Ω ζ1s' - Ω² ζ1c) + C (ζ1c' + Ω ζ1s) + K_Ω ζ1c - S y_h'' = 0
    I (ζ1s'' - 2Ω ζ1c' - Ω² ζ1s) + C (ζ1s' - Ω ζ1c) + K_Ω ζ1s = 0

and collective and differential lag stay uncoupled. The rotor's roll inertia is constant for four
identical blades (Σ cos² ψ_k = 2); tilting the rotor plane does not enter the lag equations.
"""
import json
from functools import lru_cache

import numpy as np
import pytest
from scipy.optimize import brentq, linear_sum_assignment

from mbs.analysis import fanplot
from mbs.cli import main
from mbs.models import ground_resonance as gr

REDUCED_DAMPER = 50.0  # N m s/rad: the lag damper reduced to 0.4 % critical
UNDAMPED = {"lag_damping": 0.0, "lateral_damping": 0.0, "roll_damping": 0.0}


@lru_cache
def _model():
    return gr.build()


@lru_cache
def _data():
    return gr.load_data()


def _rotor_data(model):
    """Blade (mass, first moment S, inertia I about the lag hinge, offset e), blades' and hub's roll
    inertia about the hub centre (kg m²), hub mass and height (m) from the model's bodies."""
    blades = [b for name, b in model.bodies.items() if name.startswith("blade")]
    hub, b = model.bodies["main_hub"], blades[0]
    inertia_hinge = b.inertia + b.mass * (b.com @ b.com * np.eye(3) - np.outer(b.com, b.com))
    roll = 0.0
    for blade in blades:  # inertia about the hub frame's x axis, parallel axes
        c = blade.at + blade.frame @ b.com
        roll += (blade.frame @ b.inertia @ blade.frame.T)[0, 0] + b.mass * (c[1] ** 2 + c[2] ** 2)
    return dict(m=b.mass, S=b.mass * b.com[0], I=inertia_hinge[2, 2], e=np.linalg.norm(b.at), n=len(blades),
                roll=roll + hub.inertia[0, 0], hub_mass=hub.mass, h=-hub.at[2])


def mbc_matrices(omega: float, lag_damping: float, lateral_damping: float | None = None,
                 roll_damping: float | None = None):
    """``M q'' + D q' + K q = 0`` for ``q = (y, φ, ζ1c, ζ1s, ζ0, ζd)``; gear dampers (N s/m,
    N m s/rad) by default those of the data file."""
    d, model = _data(), _model()
    r, f, g = _rotor_data(model), model.bodies["fuselage"], d["landing_gear"]
    n, hc, h = r["n"], -f.com[2], r["h"]
    mr = r["hub_mass"] + n * r["m"]
    k_omega = d["rotor"]["lag_stiffness"] + r["e"] * r["S"] * omega**2
    big_m, damp, stiff = np.zeros((6, 6)), np.zeros((6, 6)), np.zeros((6, 6))
    big_m[:2, :2] = [[f.mass + mr, f.mass * hc + mr * h],
                     [f.mass * hc + mr * h, f.inertia[0, 0] + f.mass * hc**2 + r["roll"] + mr * h**2]]
    big_m[0, 2], big_m[1, 2] = -n * r["S"] / 2, -n * r["S"] / 2 * h
    big_m[2, :2] = -r["S"], -r["S"] * h
    big_m[2, 2] = big_m[3, 3] = big_m[4, 4] = big_m[5, 5] = r["I"]
    damp[0, 0] = g["lateral_damping"] if lateral_damping is None else lateral_damping
    damp[1, 1] = g["roll_damping"] if roll_damping is None else roll_damping
    damp[2:, 2:] = np.diag([lag_damping] * 4) + 2 * omega * r["I"] * np.array([[0, 1, 0, 0], [-1, 0, 0, 0],
                                                                            [0, 0, 0, 0], [0, 0, 0, 0]])
    stiff[0, 0], stiff[1, 1] = g["lateral_stiffness"], g["roll_stiffness"]
    cyclic = k_omega - r["I"] * omega**2
    stiff[2:, 2:] = [[cyclic, lag_damping * omega, 0, 0], [-lag_damping * omega, cyclic, 0, 0],
                     [0, 0, k_omega, 0], [0, 0, 0, k_omega]]
    return big_m, damp, stiff


def mbc_eigenvalues(omega: float, lag_damping: float, *gear_dampers) -> np.ndarray:
    """The 12 eigenvalues (1/s) of the constant-coefficient multi-blade system."""
    big_m, damp, stiff = mbc_matrices(omega, lag_damping, *gear_dampers)
    a = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.linalg.solve(big_m, stiff), -np.linalg.solve(big_m, damp)]])
    return np.linalg.eigvals(a)


def mbc_band(lag_damping: float, lo: float, hi: float, *gear_dampers) -> tuple[float, float]:
    """Edges of the unstable rotor-speed band (rad/s) of the multi-blade system inside ``(lo, hi)``:
    a multiplier over one revolution above ``1 + UNSTABLE`` in modulus (the sweep's criterion)."""
    def growth(om):
        return np.exp(mbc_eigenvalues(om, lag_damping, *gear_dampers).real.max() * 2 * np.pi / om) - 1 - fanplot.UNSTABLE

    grid = np.linspace(lo, hi, 301)
    unstable = grid[[growth(om) > 0 for om in grid]]
    step = grid[1] - grid[0]
    return (brentq(growth, unstable[0] - step, unstable[0], xtol=1e-10),
            brentq(growth, unstable[-1], unstable[-1] + step, xtol=1e-10))


def body_roll_frequency() -> float:
    """The fuselage mode on the gear with the rotor as a rigid mass (lag locked), the lower one, rad/s."""
    big_m, _, stiff = mbc_matrices(44.4, 0.0)
    return float(np.sqrt(np.linalg.eigvals(np.linalg.solve(big_m[:2, :2], stiff[:2, :2])).real.min()))


@pytest.fixture(scope="module")
def analysis():
    return fanplot.FanPlotAnalysis("ground-resonance", {"lag_damping": REDUCED_DAMPER}, steps_per_rev=400)


def _floquet_multipliers(res) -> np.ndarray:
    mu = [m.multiplier for m in res.modes]
    return np.array(mu + [np.conj(x) for x in mu if abs(x.imag) > 0])


@pytest.mark.parametrize("omega", [30.0, 43.0, 55.0])
def test_floquet_exponents_equal_the_multiblade_eigenvalues(analysis, omega):
    """Multipliers over one revolution ``exp(λ T)`` to 1e-6 relative; fixed-frame frequencies and
    damping of every mode equal the multi-blade eigenvalues (43 rad/s lies in the unstable band)."""
    point = analysis.at(omega=omega)
    assert point.status == "ok" and point.floquet.interval_revs == 1
    lam = mbc_eigenvalues(omega, REDUCED_DAMPER)
    expected, got = np.exp(lam * 2 * np.pi / omega), _floquet_multipliers(point.floquet)
    assert len(got) == len(expected) == 12
    rows, cols = linear_sum_assignment(np.abs(got[:, None] - expected[None, :]))
    assert np.max(np.abs(got[rows] - expected[cols]) / np.abs(expected[cols])) < 1e-6
    for m in point.floquet.modes:
        nearest = lam[np.argmin(np.abs(lam - m.exponent))]
        assert abs(m.exponent - nearest) < 1e-6 * abs(nearest)
    assert point.unstable == (lam.real.max() > 0)
    if point.unstable:  # the growing mode is the regressing lag, at Ω - ω_ζ in the fixed frame (< Ω)
        assert "regressing lag" in point.names[0] and point.floquet.modes[0].per_rev < 1


def regressing_lag_crossing() -> float:
    """Rotor speed (rad/s) where the undamped regressing lag in the fixed frame, ``Ω - ω_ζ(Ω)``
    with ``ω_ζ² = (K + e S Ω²) / I``, meets the body roll frequency: Coleman and Feingold's
    coalescence, the centre of the undamped instability band."""
    r, k = _rotor_data(_model()), _data()["rotor"]["lag_stiffness"]
    lag = lambda om: np.sqrt((k + r["e"] * r["S"] * om**2) / r["I"])  # noqa: E731
    return brentq(lambda om: om - lag(om) - body_roll_frequency(), 30.0, 60.0)


def test_unstable_band_of_the_sweep_matches_the_multiblade_system():
    """With the lag damper reduced, the sweep finds one unstable band around the coalescence of
    the regressing lag with the roll mode; its edges, refined on the Floquet growth rate, equal
    those of the damped multi-blade system within 1 % (RK4, 100 steps per revolution)."""
    ana = fanplot.FanPlotAnalysis("ground-resonance", {"lag_damping": REDUCED_DAMPER})
    points = fanplot.sweep(ana, "omega", np.linspace(30.0, 60.0, 16))
    bands = fanplot.unstable_bands(points, lambda om: ana.at(omega=om))
    expected = mbc_band(REDUCED_DAMPER, 30.0, 60.0)
    assert len(bands) == 1
    assert bands[0] == pytest.approx(expected, rel=1e-2)
    assert bands[0][0] < regressing_lag_crossing() < bands[0][1]
    assert all(p.unstable == (bands[0][0] < p.value < bands[0][1]) for p in points)


def test_undamped_band_is_the_coalescence_of_regressing_lag_and_roll_mode():
    """Every damper removed: the band is where the regressing lag and the roll mode coalesce
    (multi-blade eigenvalues, a double frequency at either edge). The Floquet sweep's edges equal
    them within 1 %, and the band is centred on the closed-form crossing ``Ω - ω_ζ(Ω) = ω_roll``
    within 1 %."""
    ana = fanplot.FanPlotAnalysis("ground-resonance", UNDAMPED)
    points = fanplot.sweep(ana, "omega", np.linspace(36.0, 48.0, 13))
    bands = fanplot.unstable_bands(points, lambda om: ana.at(omega=om), xtol=1e-4)
    expected = mbc_band(0.0, 36.0, 48.0, 0.0, 0.0)
    assert len(bands) == 1
    assert bands[0] == pytest.approx(expected, rel=1e-2)
    assert sum(bands[0]) / 2 == pytest.approx(regressing_lag_crossing(), rel=1e-2)


def test_the_nominal_lag_damper_removes_the_band():
    ana = fanplot.FanPlotAnalysis("ground-resonance")
    points = fanplot.sweep(ana, "omega", np.linspace(30.0, 60.0, 7))
    assert all(p.status == "ok" and not p.unstable for p in points)
    assert max(mbc_eigenvalues(om, gr.load_data()["rotor"]["lag_damping"]).real.max()
               for om in np.linspace(30, 60, 61)) < 0


def test_fan_plot_command_keeps_failed_points(tmp_path, capsys):
    """``omega = 2`` is outside the parameter's range: a row with its status, the sweep goes on;
    the last point (44 rad/s) is unstable, so the band runs to the end of the sweep."""
    args = ["floquet", "ground-resonance", "--sweep", "omega=2:44:4", "--set", f"lag_damping={REDUCED_DAMPER}",
            "--out", str(tmp_path), "--json", "--quiet"]
    assert main(args) == 0
    res = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert [p["status"].startswith("failed") for p in res["points"]] == [True, False, False, False]
    assert len(res["unstable_bands"]) == 1 and res["unstable_bands"][0][1] == 44.0
    csv = (tmp_path / "fanplot_ground-resonance.csv").read_text().splitlines()
    assert csv[0].startswith("parameter,value,omega_rad_s,mode,real_per_s")
    assert "outside its range" in csv[1] and sum(",unstable" in row for row in csv) >= 1
    assert (tmp_path / "fanplot_ground-resonance.png").stat().st_size > 10_000
    names = {m["name"] for p in res["points"] for m in p["modes"]}
    assert {"regressing lag", "advancing lag"} <= names


def test_slider_spring_damper_and_its_kinematics():
    """A mass on a tilted slider with spring and damper: acceleration ``-(k x + c v) / m`` along the
    axis, and the body moves along the axis (virtual machine, no compilation)."""
    import mbs

    m = mbs.Model("slider", gravity=(0.0, 0.0, 0.0))
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    m.add_body("mass", "world", mbs.Slider(tuple(axis), name="x", stiffness=400.0, damping=3.0), mass=2.0)
    system = mbs.build(m, "vm")
    x = system.x0(**{"mass.x": 0.1, "mass.x_rate": 0.5})
    assert system.rhs(x)[1] == pytest.approx(-(400.0 * 0.1 + 3.0 * 0.5) / 2.0, rel=1e-12)
    position = system.poses(x)[0]
    assert np.ravel(position)[:3] == pytest.approx(0.1 * axis, abs=1e-12)
