"""Tables sampled from the analytic section (:class:`mbs.aero.sections.Airfoil`), with or without
its compressibility corrections: a C81 file to start from, and the check that a table
reproducing the analytic section flies as the analytic section does.

The analytic section folds reverse flow onto ±90° (the angle between the flow and the chord
line); over the full circle its coefficients are those at the folded angle, ``sin²α`` the same.
"""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np

from mbs.aero.compressibility import Compressibility
from mbs.aero.sections import Airfoil, ZeroLiftShift
from mbs.aero.tables.c81 import C81, CoefficientTable

ATTACHED_STEP = 1.0  # deg, the table's spacing within ±ATTACHED
ATTACHED = 30.0  # deg
COARSE_STEP = 10.0  # deg, the spacing beyond
MACH = (0.0, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85, 0.9, 1.0)


def angles(step: float = ATTACHED_STEP, attached: float = ATTACHED, coarse: float = COARSE_STEP) -> np.ndarray:
    """Angles of attack (deg) over -180..180: every ``step`` within ±``attached``, every ``coarse`` beyond."""
    inner = np.arange(-attached, attached + step / 2, step)
    outer = np.arange(attached + coarse, 180 + coarse / 2, coarse)
    return np.concatenate([-outer[::-1], inner, outer])


def _folded(alpha_deg: np.ndarray) -> np.ndarray:
    a = np.radians(alpha_deg)
    return np.where(a > np.pi / 2, a - np.pi, np.where(a < -np.pi / 2, a + np.pi, a))


def analytic_c81(airfoil: Airfoil, alpha_deg=None, mach=(0.0,), compressibility: Compressibility | None = None,
                 name: str = "analytic section") -> C81:
    """C81 tables of ``airfoil`` at ``alpha_deg`` (default :func:`angles`) and ``mach`` (its
    Prandtl–Glauert lift and drag rise when ``compressibility`` is given; none otherwise), ``c_M``
    zero."""
    alpha_deg = angles() if alpha_deg is None else np.asarray(alpha_deg, float)
    mach = np.asarray(mach, float)
    a, m = ca.SX.sym("a"), ca.SX.sym("m")
    cl, cd = airfoil.coefficients_of(a, ca.sin(a) ** 2)
    if compressibility is not None:
        cl, cd = compressibility.glauert_factor(m) * cl, cd + compressibility.drag_rise(m)
    f = ca.Function("f", [a, m], [cl, cd])
    grid_a, grid_m = np.meshgrid(_folded(alpha_deg), mach, indexing="ij")
    cl_v, cd_v = (np.array(v).reshape(grid_a.shape, order="F")
                  for v in f(grid_a.ravel(order="F")[None, :], grid_m.ravel(order="F")[None, :]))
    return C81(name, Path(f"{name}.c81"), CoefficientTable(alpha_deg, mach, cl_v),
               CoefficientTable(alpha_deg, mach, cd_v), CoefficientTable(alpha_deg, mach, 0 * cl_v))


TABLE_SOURCE = "sampled from the analytic section and its compressibility corrections"


def with_sampled_tables(aircraft, folder: Path):
    """``aircraft`` (an :class:`mbs.aircraft.Aircraft`) with both rotors' sections given as C81
    files sampled from their analytic sections with compressibility (:data:`MACH`), written with
    a copy of the aircraft file into ``folder``: the aircraft that ``heli bench speed`` flies with
    tables on, and a starting point for a file of one's own."""
    from mbs.aero.tables.c81 import COEFFICIENTS, format_c81
    from mbs.aircraft import load

    d, text = aircraft.data, aircraft.path.read_text()
    folder.mkdir(parents=True, exist_ok=True)
    for section in ("main_rotor", "tail_rotor"):
        sec = d[section]
        section_airfoil = Airfoil(sec["lift_slope"], sec["cd0"], sec["cd2"], sec["alpha_stall"], sec["cd_stalled"],
                                  sec["cd1"])
        if sec.get("zero_lift_angle"):
            section_airfoil = ZeroLiftShift(section_airfoil, sec["zero_lift_angle"])
        comp = Compressibility(d["environment"]["speed_of_sound"], sec["mach_dd"], sec["mach_limit"])
        c81 = analytic_c81(section_airfoil, mach=MACH, compressibility=comp, name=f"{aircraft.key} {section}")
        (folder / f"{section}.c81").write_text(format_c81(c81.name, {c: c81.table(c) for c in COEFFICIENTS}))
        entry = (f'airfoils = {{ value = [[0.0, "{section}.c81"]], unit = "-", source = "{TABLE_SOURCE}" }}\n')
        text = text.replace(f"[{section}]\n", f"[{section}]\n{entry}", 1)
    path = folder / aircraft.path.name
    path.write_text(text)
    return load(path)
