"""What a trim's airframe aerodynamics should tell its user: a tail surface in more wake than a
rotor can make, a surface at its stall, a stabilator at its stop, fuselage tables used beyond
their breakpoints.

:func:`airframe_warnings` reads the period means of a trim's outputs and states (names as the
model's: ``horizontal_tail.downwash``, ``fin.sidewash``, ``main_rotor.inflow``,
``horizontal_tail.alpha``, ``stabilator.incidence_unlimited``, ``fuselage.u`` ...; SI, rad) with
the aircraft data, and returns one sentence per finding.
"""
from __future__ import annotations

import numpy as np

from mbs.aero.empennage import CLAMP_SMOOTHING
from mbs.aircraft.airframe_data import has_horizontal_tail

WAKE_MARGIN = 0.02
"""A surface's wake may exceed the fully developed 2 v0 by this share before it is reported."""


WINGS = (("wing", "wing"), ("wing1", "wing (port panel)"), ("wing2", "wing (starboard panel)"))
"""A wing's outputs' names and what a warning calls them."""

EDGE = (0.1, 0.9)
"""A surface whose immersion in the wake is between these is at the wake's edge."""


def airframe_warnings(values: dict, d) -> list[str]:
    """Warnings (one line each) about the airframe at a trim: ``values`` the period means of its
    outputs and states by name (SI), ``d`` the aircraft data."""
    return (_wake(values) + _edge(values, d) + _stall(values, d) + _stops(values, d) + _table_range(values, d)
            + _fin_against_the_tail_rotor(values, d) + _duct_in_cross_flow(values, d) + _paddles_reversed(values, d)
            + _beyond_schedule(values, d) + _blade_stall(values, d))


STALLED = 0.01
"""Share of a rotor's blade dynamic pressure (over the period) beyond the stall angle from which
a trim warns (the Bo105 at 80 m/s: 0.12 %)."""


def _blade_stall(values: dict, d) -> list[str]:
    """Rotor blades beyond their analytic section's stall angle over more than :data:`STALLED` of
    their dynamic pressure over the period: the lift there is only bounded, so the trim is past the
    model."""
    out = []
    for name in ("main_rotor", "tail_rotor"):
        share = values.get(f"{name}.stalled_share")
        if share is not None and share > STALLED:
            out.append(f"{name.replace('_', ' ')}: {100 * share:.1f} % of its blades' dynamic pressure over the "
                       f"revolution is beyond the stall angle {np.degrees(d[name]['alpha_stall']):.1f} deg "
                       f"({name}.alpha_stall; the retreating blade at speed, or a high collective): the analytic "
                       "section bounds the lift there and models no stall, so this trim is past the model's validity; "
                       "give airfoil tables to model it")
    return out


def _beyond_schedule(values: dict, d) -> list[str]:
    """A trim flown beyond a stabilator schedule's airspeeds or collectives, where it is held."""
    from mbs.aircraft.airframe_data import has_stabilator, schedule_collective

    if not has_stabilator(d):
        return []
    st, out = d["stabilator"], []
    table = st.get("incidence_table")
    airspeeds = table["airspeed"] if table else st["airspeed"]
    speed = _speed(values)
    if speed is not None and len(airspeeds) > 1 and not airspeeds[0] <= speed <= airspeeds[-1]:
        out.append(f"stabilator: airspeed {speed:.4g} m/s beyond its schedule's {airspeeds[0]:.4g} to "
                   f"{airspeeds[-1]:.4g} m/s, where the schedule is held at its end: give it over the speeds flown")
    collective = values.get("collective")
    if table and collective is not None:
        rows = schedule_collective(d)
        if not rows[0] <= collective <= rows[-1]:
            out.append(f"stabilator: collective {np.degrees(collective):.4g} deg beyond its incidence_table's "
                       f"{np.degrees(rows[0]):.4g} to {np.degrees(rows[-1]):.4g} deg, where the table is held at its "
                       "end row: give it over the collectives flown (check its unit)")
    return out


PADDLE_ADVANCE = 0.5
"""The stabilizer bar's paddle advance ratio ``V / (Ω r)`` beyond which a trim warns: the retreating
paddle's air comes at it from well aft of its leading edge (reverse flow from 1)."""


def _paddles_reversed(values: dict, d) -> list[str]:
    """A stabilizer bar's paddles at an advance ratio of their own past :data:`PADDLE_ADVANCE`."""
    bar, speed = d.get("stabilizer_bar") or {}, _speed(values)
    if not bar.get("paddle_area") or speed is None:
        return []
    mu = speed / (d["main_rotor"]["omega"] * bar["paddle_radius"])
    if mu <= PADDLE_ADVANCE:
        return []
    return [f"stabilizer bar: its paddles' advance ratio V / (Omega r) = {mu:.2f} (at {bar['paddle_radius']:.3g} m from "
            f"the axis, beyond {PADDLE_ADVANCE:g}): the retreating paddle's air comes from far aft of its leading edge"
            + (" and from behind it (reverse flow), where its section is a flat plate's" if mu > 1 else "")
            + ", and the bar's tilt follows the speed strongly: check the paddles' radius and the speed range"]


def _duct_in_cross_flow(values: dict, d) -> list[str]:
    """A fan in a duct whose cross-flow (the flight speed) exceeds the flow through it: the duct
    model is axial momentum theory (docs/tail-rotor.md), past what it covers."""
    speed, inflow = _speed(values), values.get("tail_rotor.inflow")
    if not d.get("tail_rotor", {}).get("duct_exit_ratio") or speed is None or inflow is None or speed <= abs(inflow):
        return []
    return [f"tail rotor: its fan in a duct meets {speed:.3g} m/s of cross-flow, more than the {abs(inflow):.3g} m/s "
            "through it; the duct model is axial (the duct keeps its hover share of the thrust, "
            f"{values.get('tail_rotor.duct_thrust', float('nan')):.4g} N here, with no momentum drag or shielding of "
            "the blades in cross-flow), so the tail's thrust, power and control power here are not validated"]


FIN_LOAD = 0.25
"""A fin pushing the tail the torque's way with more than this share of the tail rotor's thrust,
in forward flight, is warned of (a fin's incidence or camber of the wrong sign for the rotation)."""
FORWARD = 20.0
"""m/s: the speed from which a fin carries the load its incidence is set for."""


def _fin_against_the_tail_rotor(values: dict, d) -> list[str]:
    """A fin whose side force adds to the main rotor's torque reaction in forward flight, so that
    the tail rotor carries more than the torque: its incidence or zero-lift angle likely signed
    for the other sense of rotation (positive lift is to starboard for either)."""
    from mbs.aero.sections import section_force, turn
    from mbs.models.helicopter.aero import airfoil

    thrust = values.get("tail_rotor.thrust")
    if thrust is None or "fuselage.u" not in values or _speed(values) < FORWARD:
        return []
    fin = d["vertical_fin"]
    w_c, w_n = _section_air(values, d, "vertical_fin")
    f_c, f_n = section_force(w_c, w_n, airfoil(fin), d["environment"]["rho"], fin["area"], flat_plate=True)
    side = float(turn(float(f_c), float(f_n), -fin["incidence"])[1])  # N, to starboard
    anti_torque = 1.0 if d["main_rotor"]["rotation"] == "counter-clockwise" else -1.0  # the tail rotor's push
    if side * anti_torque >= 0 or abs(side) < FIN_LOAD * abs(thrust):
        return []
    way = "port" if side < 0 else "starboard"
    return [f"fin: its side force, {abs(side):.4g} N to {way}, pushes the tail the way the "
            f"{d['main_rotor']['rotation']} main rotor's torque does, {abs(side) / abs(thrust):.2g} of the tail "
            "rotor's thrust, which must carry it: a fin is usually set to unload the tail rotor in forward flight; "
            "check the sign of vertical_fin.incidence (and zero_lift_angle): positive lift is to starboard for "
            "either sense of rotation"]


def _edge(values: dict, d) -> list[str]:
    """A tail surface at the wake's edge, where its load follows the edge's smoothing."""
    width = d.get("wake", {}).get("width")
    out = []
    for key, what in (("horizontal_tail", "horizontal tail"), ("fin", "fin"), *WINGS):
        share = values.get(f"{key}.wake_immersion")
        if share is not None and width is not None and EDGE[0] < share < EDGE[1]:
            out.append(f"{what}: at the edge of the main rotor's wake (immersion {share:.2f}; the edge is smoothed "
                       f"over wake.width = {width:.3g} m): its load changes steeply as the wake moves, so this trim and "
                       "the derivatives in u, w, q and the controls follow wake.width, an estimate: compare with "
                       "another width, or give the surface's interference tables")
    return out


def trim_warnings(trim, d) -> list[str]:
    """:func:`airframe_warnings` of a :class:`mbs.analysis.trim.Trim` (its controls by name too)."""
    return airframe_warnings({**dict(trim.state), **dict(trim.output_means), **dict(trim.controls)}, d)


def _wake(values: dict) -> list[str]:
    v0 = values.get("main_rotor.inflow")
    out = []
    for key, what in (("horizontal_tail.downwash", "horizontal tail"), ("fin.sidewash", "fin")):
        if key in values and v0 is not None and abs(values[key]) > 2 * abs(v0) * (1 + WAKE_MARGIN):
            out.append(f"{what}: {abs(values[key]):.3g} m/s of main-rotor wake, more than the fully developed wake's "
                       f"2 v0 = {2 * abs(v0):.3g} m/s: the wake model is past its validity here (check the surface's "
                       "position and the wake data)")
    return out


STILL_AIR = 1.0
"""m/s: a surface (a tail out of the wake in hover) or a fuselage in slower air than this carries no
load worth a warning (dynamic pressure under 0.6 Pa), and its angles mean nothing (a hover's
fuselage: -179 deg of round-off at 1e-7 m/s)."""


def _stall(values: dict, d) -> list[str]:
    out = []
    surfaces = ((("horizontal_tail", "horizontal_tail", "horizontal tail"),) if has_horizontal_tail(d) else ()) + (
        ("vertical_fin", "fin", "fin"), *(("wing", key, what) for key, what in WINGS if f"{key}.alpha" in values))
    for section, key, what in surfaces:
        alpha, speed = _estimated_flow(values, d, section) if section != "wing" else (None, _speed(values))
        alpha = values.get(f"{key}.alpha", alpha)
        if speed is not None and speed < STILL_AIR:
            continue
        table = d[section].get("coefficient_table")
        if table and alpha is not None and not table[0][0] <= alpha <= table[-1][0]:
            out.append(f"{what}: angle of attack {np.degrees(alpha):+.1f} deg beyond its coefficient table "
                       f"[{np.degrees(table[0][0]):.4g}, {np.degrees(table[-1][0]):.4g}] deg "
                       f"({section}.coefficient_table); the table is continued linearly there: give it over the "
                       "range flown")
            continue
        if table:
            continue  # the table models the stall
        stall, zero = d[section]["alpha_stall"], d[section].get("zero_lift_angle", 0.0)
        if alpha is not None and abs(alpha - zero) >= stall:
            line = f" from its zero-lift angle {np.degrees(zero):+.1f} deg" if zero else ""
            out.append(f"{what}: angle of attack {np.degrees(alpha):+.1f} deg at or beyond its stall angle "
                       f"{np.degrees(stall):.1f} deg{line} ({section}.alpha_stall): its lift is only bounded there "
                       "(a flat plate's from 60 deg), its stall not modelled")
    return out


def _stops(values: dict, d) -> list[str]:
    raw = values.get("stabilator.incidence_unlimited")
    if raw is None:
        return []
    st = d["stabilator"]
    for stop, name, beyond in ((st["incidence_max"], "incidence_max", raw > st["incidence_max"] - CLAMP_SMOOTHING),
                               (st["incidence_min"], "incidence_min", raw < st["incidence_min"] + CLAMP_SMOOTHING)):
        if beyond:
            return [f"stabilator: at its stop {np.degrees(stop):+.1f} deg (stabilator.{name}); the schedule asks for "
                    f"{np.degrees(raw):+.1f} deg"]
    return []


def _table_range(values: dict, d) -> list[str]:
    """Fuselage tables used beyond their breakpoints (continued linearly there)."""
    fa = d["fuselage_aero"]
    if fa["model"] != "tables" or "fuselage.u" not in values or "fuselage.w" not in values:
        return []
    u, v, w = values["fuselage.u"], values.get("fuselage.v", 0.0), values["fuselage.w"]
    speed = np.sqrt(u * u + v * v + w * w)
    if speed < STILL_AIR:  # the angles of round-off, and loads of nothing
        return []
    from mbs.aircraft.airframe_data import beta_sign

    angles = {"alpha": np.arctan2(w, u), "beta": beta_sign(fa) * np.arcsin(v / speed)}  # the tables' own
    out = []
    for name, angle in angles.items():
        grid = fa[name]
        if len(grid) and not grid[0] <= angle <= grid[-1]:
            out.append(f"fuselage tables: {name} {np.degrees(angle):+.1f} deg beyond the breakpoints "
                       f"[{np.degrees(grid[0]):.4g}, {np.degrees(grid[-1]):.4g}] deg (fuselage_aero.{name}); the tables "
                       "are continued linearly there: give them over the range flown")
    return out + _own_range(fa, angles)


def _own_range(fa: dict, angles: dict) -> list[str]:
    """Tables on their own angles (a curve digitised at its own points, a table on its own grid)
    used beyond them."""
    from mbs.aircraft.airframe_data import given

    out = []
    for key, table in given(fa).items():
        own = table.get("breakpoints")
        if own is None:
            continue
        names = key.partition("_")[2].split("_")
        for name, grid in zip(names, own if isinstance(own, tuple) else (own,)):
            if not grid[0] <= angles[name] <= grid[-1]:
                out.append(f"fuselage tables: {name} {np.degrees(angles[name]):+.1f} deg beyond fuselage_aero.{key}'s "
                           f"own angles [{np.degrees(grid[0]):.4g}, {np.degrees(grid[-1]):.4g}] deg; the table is "
                           "continued linearly there: give it over the range flown")
    return out


def _speed(values: dict) -> float | None:
    """The trim's air speed (m/s) at the CG, None without the fuselage's velocity."""
    if "fuselage.u" not in values:
        return None
    return float(np.hypot(np.hypot(values["fuselage.u"], values.get("fuselage.v", 0.0)), values.get("fuselage.w", 0.0)))


def _section_air(values: dict, d, section: str) -> tuple:
    """The air (m/s) at a fixed surface in its section axes, ``(w_c, w_n)`` after its incidence,
    from the trim's body velocity and the wake at it (rates zero in a trim); None without the
    velocity."""
    if "fuselage.u" not in values or "fuselage.w" not in values:
        return None
    air = -np.array([values["fuselage.u"], values.get("fuselage.v", 0.0), values["fuselage.w"]])
    if section == "horizontal_tail":
        air[2] += values.get("horizontal_tail.downwash", 0.0)
        w_c, w_n = air[0], -air[2]
    else:
        air[1] += values.get("fin.sidewash", 0.0)
        w_c, w_n = air[0], air[1]
    inc = d[section]["incidence"]
    return np.cos(inc) * w_c + np.sin(inc) * w_n, -np.sin(inc) * w_c + np.cos(inc) * w_n


def _estimated_flow(values: dict, d, section: str) -> tuple:
    """Angle of attack (rad) and speed (m/s) of the air at a fixed surface
    (:func:`_section_air`); (None, None) without the velocity."""
    air = _section_air(values, d, section)
    if air is None:
        return None, None
    w_c, w_n = air
    return 0.5 * np.arctan2(-2 * w_n * w_c, w_c**2 - w_n**2), float(np.hypot(w_c, w_n))
