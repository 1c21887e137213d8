"""Wind, discrete gusts and continuous turbulence after MIL-F-8785C (:mod:`mbs.environment`):
intensities and scale lengths against height, spectra, the transport delay along the aircraft and
reproducibility from a seed."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.signal import welch

from mbs import scenes
from mbs.environment import turbulence as tb
from mbs.models.helicopter.air_options import with_environment

FT, KT = tb.FT, tb.KT


@pytest.mark.parametrize("h_ft, w20_kt", [(50.0, 30.0), (300.0, 15.0), (1000.0, 45.0)])
def test_low_altitude_intensities_and_scale_lengths_are_the_specifications(h_ft, w20_kt):
    """MIL-F-8785C below 1000 ft: σ_w = 0.1 W20, σ_u = σ_v = σ_w / (0.177 + 0.000823 h)^0.4,
    L_w = h, L_u = L_v = h / (0.177 + 0.000823 h)^1.2 (ft)."""
    base = 0.177 + 0.000823 * h_ft
    sigma_w = 0.1 * w20_kt * KT
    assert tb.intensities(h_ft * FT, w20_kt * KT) == pytest.approx(
        (sigma_w / base**0.4, sigma_w / base**0.4, sigma_w), rel=1e-12)
    assert tb.scale_lengths(h_ft * FT) == pytest.approx((h_ft / base**1.2 * FT,) * 2 + (h_ft * FT,), rel=1e-12)


def test_medium_and_high_altitude_intensities_follow_the_exceedance_table():
    """At and above 2000 ft: the table (moderate at 5000 ft lies between 7.4 ft/s at 3750 ft and 6.7 at
    7500 ft); L = 1750 ft (Dryden), 2500 ft (von Kármán); between 1000 and 2000 ft linear in h."""
    moderate = 7.4 + (5000 - 3750) / (7500 - 3750) * (6.7 - 7.4)
    assert tb.intensities(5000 * FT, 30 * KT) == pytest.approx((moderate * FT,) * 3, rel=1e-12)
    severe = 13.0 + (2000 - 1750) / (3750 - 1750) * (16.0 - 13.0)
    assert tb.intensities(2000 * FT, 45 * KT)[2] == pytest.approx(severe * FT, rel=1e-12)
    assert tb.scale_lengths(9000 * FT, "dryden") == pytest.approx((1750 * FT,) * 3)
    assert tb.scale_lengths(9000 * FT, "von-karman") == pytest.approx((2500 * FT,) * 3)
    low, high = tb.intensities(1000 * FT, 30 * KT), tb.intensities(2000 * FT, 30 * KT)
    assert tb.intensities(1500 * FT, 30 * KT) == pytest.approx(tuple((a + b) / 2 for a, b in zip(low, high)))
    assert tb.intensities(3000 * FT, 0.0) == (0.0, 0.0, 0.0)


def _record(form: str, height: float, seed: int, spacing: float, n: int):
    sigma, length = tb.intensities(height, tb.W20_MODERATE), tb.scale_lengths(height, form)
    xi = spacing * np.arange(n)
    return np.array(tb.field(form, xi, sigma, length, tb.phases(float(seed)))), sigma, length


@pytest.mark.parametrize("form", tb.FORMS)
def test_the_field_has_the_specified_intensity(form):
    """RMS of each component over a record of 1000 of its longest scale lengths: σ within 2 %."""
    u, sigma, length = _record(form, 15.0, 7, 1.0, int(1000 * max(tb.scale_lengths(15.0, form))))
    assert np.sqrt(np.mean(u**2, axis=1)) == pytest.approx(np.array(sigma), rel=0.02)


@pytest.mark.parametrize("form", tb.FORMS)
@pytest.mark.parametrize("component", [0, 2])
def test_welch_spectra_match_the_specification_within_10_percent(form, component):
    """Welch's estimate of the field sampled along the flight path every 0.1 m (the step of a
    100-per-revolution RK4 run at 70 m/s) or 1 m for the long scale length, integrated over half-decade bands of LΩ from 10^-0.5 to 100 (the
    part of the lines' band that Welch resolves with segments of 314 L; each band holds three
    lines), against the specification's spectrum over the same bands (times 1/captured: the lines
    carry all of σ²): within 10 %."""
    height = 15.0
    length = tb.scale_lengths(height, form)[component]
    spacing = min(1.0, length / 30)  # the lines' highest LΩ = 80 well below Nyquist's π L/spacing
    segment = int(314 * length / spacing)
    u, sigma, _ = _record(form, height, 3, spacing, 24 * segment)
    omega, psd = welch(u[component], fs=2 * np.pi / spacing, nperseg=segment)  # one-sided, per rad/m
    x = omega * length
    comp, worst = "uvw"[component], []
    edges = np.geomspace(10**-0.5, 100.0, 6)
    for a, b in zip(edges[:-1], edges[1:]):
        inside = (x >= a) & (x < b)
        measured = np.trapezoid(psd[inside], omega[inside]) if inside.sum() > 1 else psd[inside].sum()
        grid = np.geomspace(a, b, 400)
        spec = sigma[component] ** 2 * np.trapezoid(tb.spectrum(form, comp, grid), grid) / tb.captured(form, comp)
        worst.append(abs(measured / spec - 1))
        assert measured == pytest.approx(spec, rel=0.10), (a, b)
    print(f"{form} {comp}: largest band error {max(worst):.2e}")


@pytest.fixture(scope="module")
def turbulent():
    sc = with_environment(scenes.get("forward-flight"), turbulence="dryden", gust=True)
    return sc, sc.system("compiled")


def test_the_tail_rotor_meets_the_air_the_main_rotor_met_a_transport_delay_before(turbulent):
    """The tail rotor's hub 6.0 m behind the main rotor's: the turbulence and the gust it sees with
    the aircraft at north X are those the main rotor saw at X − 6.0 m, to 1e-12."""
    sc, system = turbulent
    d = sc.aircraft.data
    gap = d["main_rotor"]["hub_x"] - d["tail_rotor"]["hub_x"]
    names = system.info.output_names
    p = system.params({"gust_down": 5.0, "gust_start": 2.0, "gust_length": 8.0})
    x = system.x0()
    i = system.info.state_names.index("fuselage.x")
    for t in (0.0, 0.7):
        ahead, behind = x.copy(), x.copy()
        ahead[i], behind[i] = 3.0, 3.0 + gap
        y_main = system.outputs(ahead, t, p)
        y_tail = system.outputs(behind, t, p)
        for axis in ("north", "east", "down"):
            assert y_tail[names.index(f"turbulence.tail_{axis}")] == pytest.approx(
                y_main[names.index(f"turbulence.{axis}")], abs=1e-12)
        assert y_main[names.index("turbulence.down")] != y_tail[names.index("turbulence.down")]


def test_a_discrete_gust_has_the_one_minus_cosine_shape():
    from mbs.environment.gust import shape
    import casadi as ca

    d, hold = 8.0, 3.0
    for s, want in ((-1.0, 0.0), (2.0, 0.5 * (1 - np.cos(np.pi * 2 / d))), (d, 1.0), (d + 2, 1.0),
                    (d + hold + 2, 0.5 * (1 + np.cos(np.pi * 2 / d))), (2 * d + hold + 1, 0.0)):
        assert float(shape(ca.DM(s), d, hold)) == pytest.approx(want, abs=1e-15)


def test_the_same_seed_gives_bit_identical_runs_on_one_and_on_two_dask_workers(tmp_path):
    from mbs.sweep import simulate_sweep

    seeds = {"turbulence_seed": np.array([1.0, 2.0, 3.0])}
    options = {"revs": 4.0, "environment": {"turbulence": "dryden"}}
    tables = [simulate_sweep("forward-flight", seeds, options=options, workers=w).to_pydict() for w in (1, 2)]
    columns = [c for c in tables[0] if c not in ("wall_s",)]
    order = [np.argsort(t["turbulence_seed"]) for t in tables]
    for c in columns:
        a, b = (np.asarray(t[c])[o] for t, o in zip(tables, order))
        assert a.tolist() == b.tolist(), c
    down = np.asarray(tables[0]["turbulence.down.max"])
    assert len(set(down.tolist())) == 3  # different seeds, different turbulence


@pytest.mark.parametrize("options, words", [
    (dict(turbulence="dryden"), "needs a free fuselage"),
    (dict(turbulence="kolmogorov"), "choose None or one of dryden, von-karman"),
])
def test_turbulence_is_refused_where_it_cannot_work(options, words):
    sc = scenes.get("ground-run") if "needs" in words else scenes.get("hover")
    with pytest.raises(ValueError, match=words):
        replace(sc.builder.config, **options)
