"""Values an aircraft file does not state: defaults of optional entries and derived values.

Each derived value has one formula here (its text in :data:`mbs.aircraft.schema.DERIVED`);
a file replaces one only with ``override = true``. Units SI, angles in rad.
"""
from __future__ import annotations

import math

from mbs.aircraft.blade import Distribution, equivalent_chord, equivalent_twist
from mbs.aircraft.schema import DERIVED, ENTRIES

BO105_RADIUS = 4.91  # m: the display geometry of an aircraft that gives none is the Bo105's scaled by R
BO105_GEOMETRY = {"cabin": [3.6, 1.5, 1.4], "cabin_x": 0.3, "boom_radius": 0.18, "hub_height": 0.25,
                  "tail_hub": [0.06, 0.15], "plate_thickness": 0.05}


def fill_defaults(values: dict, meta: dict) -> None:
    """Put the default of every optional entry that is absent into ``values`` (origin "default")."""
    for section, entries in ENTRIES.items():
        given = values.setdefault(section, {})
        for key, spec in entries.items():
            if key in given or spec.default is None:
                continue
            given[key] = spec.default if spec.kind in ("choice", "text") else _default(section, key, spec.default, values)
            meta.setdefault(section, {})[key] = {"unit": spec.unit, "source": "default", "origin": "default",
                                                 "note": f"default ({spec.default})"}


def _default(section: str, key: str, default, values: dict):
    if default == "scaled":
        scale = values["main_rotor"]["radius"] / BO105_RADIUS
        base = BO105_GEOMETRY[key]
        return [scale * b for b in base] if isinstance(base, list) else scale * base
    if isinstance(default, str) and " " in default:  # "<factor> omega"
        factor, _, name = default.partition(" ")
        return float(factor) * values[section][name]
    return default


def blade_mass(mr: dict) -> float:
    """kg: a uniform blade from the flap hinge with the file's flap inertia."""
    return 3 * mr["I_flap"] / (mr["radius"] - mr["flap_hinge_offset"]) ** 2


def lag_inertia(mr: dict) -> float:
    """kg m²: the model's blade (a uniform box of the blade's chord, or integrated from its mass
    table) about its lag hinge."""
    if mr.get("mass_table"):
        return Distribution(mr).lag_inertia
    return mr["I_flap"] + mr["blade_mass"] * mr["chord"] ** 2 / 12


def lag_stiffness(mr: dict) -> float:
    """N m/rad: the lag spring that gives ``lag_frequency`` with the hinge offset's own
    stiffening, ``ν² = K / (I Ω²) + e S / I`` (S the blade's first moment about the hinge)."""
    e, inertia = mr["flap_hinge_offset"], lag_inertia(mr)
    return (mr["lag_frequency"] ** 2 - e * mr["first_moment"] / inertia) * inertia * mr["omega"] ** 2


def flap_frequency(mr: dict) -> float:
    """1/rev: first flap frequency of the rigid blade with its hinge offset and spring,
    ``ν² = 1 + e S / I + K / (I Ω²)`` (``e S / I = 1.5 e / (R − e)`` for the uniform blade)."""
    from mbs.aircraft.mass import is_uniform_blade

    if mr.get("hub_type") == "teetering":
        return teeter_frequency(mr)
    e, span = mr["flap_hinge_offset"], mr["radius"] - mr["flap_hinge_offset"]
    offset = 1.5 * e / span if is_uniform_blade(mr) else e * mr["first_moment"] / mr["I_flap"]
    return math.sqrt(1 + offset + mr["flap_stiffness"] / (mr["I_flap"] * mr["omega"] ** 2))


def teeter_frequency(mr: dict) -> float:
    """1/rev: teeter frequency of the two blades on one seesaw with its spring ``K``, their points at
    ``z = r sin(precone) − undersling`` from the hinge: ``ν² = (c² I − Z) / (c² I + Z) + K / (2 (c² I
    + Z) Ω²)``, ``Z = m u² − 2 u s S + s² I`` (per blade: mass ``m``, first moment ``S`` and
    inertia ``I`` about the axis; ``s, c`` of the precone; the blades' thickness neglected): 1/rev
    with the blades in the hinge's plane, less as their centre of mass lies off it."""
    s, c, u = math.sin(mr["precone"]), math.cos(mr["precone"]), mr.get("undersling", 0.0)
    inertia = mr["I_flap"]
    off = mr["blade_mass"] * u**2 - 2 * u * s * mr["first_moment"] + s**2 * inertia
    teeter = c**2 * inertia + off
    return math.sqrt((c**2 * inertia - off) / teeter + mr["flap_stiffness"] / (2 * teeter * mr["omega"] ** 2))


def tail_flap_frequency(tr: dict, omega: float, pitch: float = 0.0) -> float:
    """1/rev: flap frequency of a flapping tail rotor's blade, the model's rigid box (mass m,
    span L = R - e from the hinge, chord c, thickness t) on its hinge at offset e with spring
    K, skewed by δ3, at ``pitch`` (rad), the shaft turning at ``gear_ratio omega`` (rad/s).

    Energy of the 1-DOF blade in the rotating frame: ``J β̇²/2`` and the centrifugal potential
    ``-Ω²/2 ∫|P (h + R(β) ρ)|² dm`` (``P`` the projection on the disc plane, ``h`` the hinge,
    ``ρ`` a point from it); with ``A = [â]×`` of the hinge axis ``â`` and ``Σ = ∫ρρᵀ dm`` its
    stiffness is ``-Ω² (tr(AᵀPAΣ) + tr(PA²Σ) + m hᵀPA²c)`` and ``J = tr Σ - âᵀΣâ``; for δ3 = 0 at
    zero pitch ``ν² = (e S + m L²/3 - m t²/12) / (m L²/3 + m t²/12) + K / (J Ω²)``, ``S = m L/2``."""
    import numpy as np

    e, span, m = tr["flap_hinge_offset"], tr["radius"] - tr["flap_hinge_offset"], tr["blade_mass"]
    d3, rate = tr["delta3"], tr["gear_ratio"] * omega
    axis = np.array([-math.sin(d3), -math.cos(d3), 0.0])
    turn = np.array([[1.0, 0, 0], [0, math.cos(pitch), -math.sin(pitch)], [0, math.sin(pitch), math.cos(pitch)]])
    sigma = turn @ (m * np.diag([span**2 / 3, tr["chord"] ** 2 / 12, tr["blade_thickness"] ** 2 / 12])) @ turn.T
    a = np.cross(axis, np.eye(3)).T  # a @ v = axis x v
    p, hinge, first = np.diag([1.0, 1.0, 0.0]), np.array([e, 0.0, 0.0]), m * np.array([span / 2, 0.0, 0.0])
    stiffness = -rate**2 * (np.trace(a.T @ p @ a @ sigma) + np.trace(p @ a @ a @ sigma) + hinge @ p @ a @ a @ first)
    inertia = np.trace(sigma) - axis @ sigma @ axis
    return math.sqrt((stiffness + tr["flap_stiffness"]) / inertia) / rate


def tip_loss(thrust_coefficient: float, n_blades: int) -> float:
    """Prandtl's effective-radius factor ``B = 1 - sqrt(2 C_T) / N_b``."""
    return 1 - math.sqrt(2 * max(thrust_coefficient, 0.0)) / n_blades


def complete(values: dict) -> list[str]:
    """Compute every derived value that the file does not override, in place; returns the
    problems (a derived value outside what the model accepts)."""
    from mbs.aircraft import performance

    mr, tr = values["main_rotor"], values["tail_rotor"]
    _distributions(values)
    _set(mr, "blade_mass", lambda: blade_mass(mr))
    _set(mr, "first_moment", lambda: mr["blade_mass"] * (mr["radius"] - mr["flap_hinge_offset"]) / 2)
    if mr["hub_type"] == "flapping":
        _set(mr, "lag_stiffness", lambda: lag_stiffness(mr))
    hover = performance.hover(values)
    _set(mr, "tip_loss", lambda: tip_loss(hover.main.thrust_coefficient, mr["n_blades"]))
    _set(tr, "tip_loss", lambda: tip_loss(hover.tail.thrust_coefficient, tr["n_blades"]))
    _set(values.setdefault("wake", {}), "core", lambda: mr["root_cutout"])
    if "elastic_blade" in values and values["elastic_blade"] and mr["hub_type"] == "flapping":
        try:
            _elastic(values)
        except ValueError as exc:  # a frequency no uniform blade of this rotor has: the entry's problem
            return [str(exc)]
    if values.get("swashplate"):
        _swashplate(values["swashplate"], mr["flap_hinge_offset"])
    return _problems(values)


def _distributions(values: dict) -> None:
    """The numbers that distributions along the span replace (:data:`mbs.aircraft.schema.FROM_TABLES`)
    and, from a mass table, the blade's mass and first moment."""
    for name in ("main_rotor", "tail_rotor"):
        sec = values[name]
        if sec.get("chord_table"):
            _set(sec, "chord", lambda: equivalent_chord(sec["chord_table"], sec["root_cutout"]))
        if sec.get("twist_table"):
            _set(sec, "twist", lambda: equivalent_twist(sec["twist_table"], sec["root_cutout"]))
    tr = values["tail_rotor"]
    if tr.get("omega"):
        _set(tr, "gear_ratio", lambda: tr["omega"] / values["main_rotor"]["omega"])
    if tr.get("lock_number"):
        from mbs.aircraft.mass import tail_hinge

        rho, span = values["environment"]["rho"], tr["radius"] - tail_hinge(tr)
        _set(tr, "blade_mass", lambda: 3 * rho * tr["lift_slope"] * tr["chord"] * tr["radius"] ** 4
             / (tr["lock_number"] * span**2))
    mr = values["main_rotor"]
    if mr.get("lock_number") and not mr.get("mass_table"):
        rho = values["environment"]["rho"]
        _set(mr, "I_flap", lambda: rho * mr["lift_slope"] * mr["chord"] * mr["radius"] ** 4 / mr["lock_number"])
    if "I_flap" not in mr and "blade_mass" in mr and not mr.get("mass_table"):  # a report's blade weight alone
        _set(mr, "I_flap", lambda: mr["blade_mass"] * (mr["radius"] - mr["flap_hinge_offset"]) ** 2 / 3)
    if mr.get("mass_table"):
        blade = Distribution(mr)
        _set(mr, "I_flap", lambda: blade.flap_inertia)
        _set(mr, "blade_mass", lambda: blade.mass)
        _set(mr, "first_moment", lambda: blade.first_moment)


def _set(section: dict, key: str, compute) -> None:
    if key not in section:
        section[key] = compute()


def _elastic(values: dict) -> None:
    mr, eb = values["main_rotor"], values["elastic_blade"]
    _set(eb, "flap_frequency", lambda: flap_frequency(mr))
    _set(eb, "lag_frequency", lambda: mr["lag_frequency"])
    todo = {k: eb[f"{k}_frequency"] for k in ("flap", "lag", "torsion") if f"{k}_stiffness" not in eb}
    if todo:  # the continuous blade's finite elements (scipy) only when a stiffness is to be found
        from mbs.flexible.uniform_blade import blade_from_data, calibrate

        trial = blade_from_data(values, flap=1.0, lag=1.0, torsion=1.0)
        eb.update({f"{k}_stiffness": v for k, v in calibrate(trial, mr["omega"], todo).items()})


def _swashplate(sp: dict, hinge_offset: float) -> None:
    """The pitch link's geometry at neutral (zero pitch, flap, lag and actuator travel)."""
    if sp["horn"] == "blade":
        _set(sp, "ball_offset", lambda: sp["horn_arm"] * math.tan(sp["delta3"]))
    else:
        _set(sp, "ball_offset", lambda: sp["ball_radius"] - hinge_offset)
    inward = hinge_offset + sp["ball_offset"] - sp["link_length"] * math.sin(sp["link_lean"])
    _set(sp, "plate_radius", lambda: math.hypot(inward, sp["horn_arm"]))
    _set(sp, "phase", lambda: math.atan2(sp["horn_arm"], inward))
    _set(sp, "plate_height", lambda: sp["horn_height"] - sp["link_length"] * math.cos(sp["link_lean"]))


def _problems(values: dict) -> list[str]:
    mr, out = values["main_rotor"], []
    if mr["hub_type"] == "flapping" and mr["lag_stiffness"] < 0:
        own = math.sqrt(max(mr["lag_frequency"] ** 2 - mr["lag_stiffness"] / (lag_inertia(mr) * mr["omega"] ** 2), 0))
        out.append(f"main_rotor.lag_frequency: {mr['lag_frequency']:g}/rev is below the {own:.3g}/rev the hinge "
                   "offset alone gives; no lag spring can lower it")
    for section in ("main_rotor", "tail_rotor"):
        b = values[section]["tip_loss"]
        if not 0.5 < b <= 1.0:
            out.append(f"{section}.tip_loss: B = {b:.4g} outside (0.5, 1]: {DERIVED[section]['tip_loss'].text}")
    return out
