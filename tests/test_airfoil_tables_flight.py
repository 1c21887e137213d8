"""Trims and Floquet with airfoil tables on: a table sampled from the analytic section trims as
the analytic section does, and a forward-flight trim and its Floquet analysis converge with C81
tables on both rotors as they do without."""
from __future__ import annotations

import numpy as np
import pytest

from mbs import aircraft, scenes
from mbs.aero import Airfoil
from mbs.aero.tables import AirfoilSegment, TableAirfoil
from mbs.aero.tables.sample import analytic_c81, angles, with_sampled_tables
from mbs.aircraft._aircraft import Aircraft, Data
from mbs.analysis.floquet import floquet
from mbs.analysis.trim import trim
from mbs.models.helicopter.config import with_aero

CONSISTENCY_STEP = 0.25  # deg, the sampled table's spacing within ±30 deg


def _sampled(step: float) -> Aircraft:
    """The Bo105 with both rotors' analytic sections sampled into tables at full precision (no
    Mach dependence: the scenes here have compressibility off)."""
    craft = aircraft.load()
    data = Data({s: dict(v) for s, v in craft.data.items()})
    data.meta = craft.data.meta
    for section in ("main_rotor", "tail_rotor"):
        sec = data[section]
        c81 = analytic_c81(Airfoil(sec["lift_slope"], sec["cd0"], sec["cd2"], sec["alpha_stall"], sec["cd_stalled"]),
                           alpha_deg=angles(step), name=section)
        sec["airfoils"] = (AirfoilSegment(0.0, "sampled", c81, TableAirfoil.from_c81(c81), ""),)
    return Aircraft("bo105_sampled", craft.name, craft.path, data, "sampled")


@pytest.mark.parametrize("scene", ["hover", "forward-flight"])
def test_a_table_sampled_from_the_analytic_section_trims_as_the_analytic_section(scene):
    """Consistency of the whole path (full-circle angle, table, interpolant, element loads): the
    trims agree to 1e-8 rad in every control and attitude (measured 3.4e-9 rad in hover, 2.7e-9 rad
    at 10 m/s, both in 3 Newton iterations like the analytic section's)."""
    base = with_aero(scenes.get(scene), "none")
    ours = trim(with_aero(scenes.get(scene).with_aircraft(_sampled(CONSISTENCY_STEP)), "none"))
    ref = trim(base)
    assert ours.converged and ref.converged, (ours.reason, ref.reason)
    diffs = {k: ours.controls[k] - ref.controls[k] for k in ref.controls}
    diffs.update(roll=ours.roll - ref.roll, pitch=ours.pitch - ref.pitch)
    print(f"{scene}: trim differences (rad) {diffs}; iterations {ours.iterations} / {ref.iterations}")
    assert max(abs(v) for v in diffs.values()) <= 1e-8, diffs
    assert ours.iterations <= ref.iterations


def test_forward_flight_trim_and_floquet_converge_with_c81_tables_on_both_rotors(tmp_path):
    """C81 files (91 angles x 12 Mach numbers, 4 decimals, sampled from the analytic sections with
    their compressibility) in the forward-flight scene with every aerodynamics switch on: the
    trim converges in no more Newton iterations than the analytic scene's plus one, to its
    tolerance, and Floquet finds the same modes (frequencies and decay rates within 5 % or
    0.02 1/s)."""
    craft = with_sampled_tables(aircraft.load(), tmp_path)
    tables = scenes.get("forward-flight").with_aircraft(craft)
    base = scenes.get("forward-flight")
    ours, ref = floquet(tables), floquet(base)
    t, r = ours.trim, ref.trim
    print(f"trim iterations {t.iterations} (analytic {r.iterations}); residual {np.abs(t.residual).max():.2e} "
          f"(analytic {np.abs(r.residual).max():.2e}); controls {t.controls} (analytic {r.controls})")
    assert t.converged and t.iterations <= r.iterations + 1 and np.abs(t.residual).max() <= 1e-10
    assert len(ours.modes) == len(ref.modes)
    for a, b in zip(sorted(ours.modes, key=lambda m: abs(m.exponent)), sorted(ref.modes, key=lambda m: abs(m.exponent))):
        print(f"  {a.exponent:.4f} vs {b.exponent:.4f}")
        assert abs(a.exponent.imag - b.exponent.imag) <= max(0.05 * abs(b.exponent.imag), 0.02)
        assert abs(a.exponent.real - b.exponent.real) <= max(0.05 * abs(b.exponent.real), 0.02)
