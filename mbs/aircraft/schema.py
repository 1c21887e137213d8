"""What an aircraft file may and must hold: every entry with its SI unit, kind, bounds and meaning.

An entry is ``key = { value = ..., unit = "...", source = "...", note = "..." }`` in a
section. ``ENTRIES`` lists them; an entry with ``default`` may be left out (the default is
reported by ``heli aircraft check``); a :data:`DERIVED` entry is computed from the others
(:mod:`mbs.aircraft.derived`) and may appear in a file only with ``override = true``. Frames:
body axes at the aircraft's centre of gravity, x forward, y starboard, z down.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

DEG = math.pi / 180
AIRFRAME_AXES = ("body", "stability", "wind")


@dataclass(frozen=True)
class Entry:
    """One entry: SI ``unit`` ("-" a pure number, "1/rev" per revolution), ``kind`` (number,
    integer, choice, text, vector, table, airfoils: rows of r/R and a C81 file), ``low``/``high`` bounds (inclusive unless
    ``open_low``/``open_high``), ``choices``, ``length`` of a vector, ``columns`` (units) of
    a table, ``default`` (None: required), the meaning ``text``, and for a position from the CG
    the body ``axis`` (or axes) it lies along, so that it may be written as a station
    (:mod:`mbs.aircraft.stations`); a ``radial`` table's first column is r/R, or radial
    stations in a length unit that the reader divides by the rotor's radius."""

    unit: str
    text: str
    kind: str = "number"
    low: float = -math.inf
    high: float = math.inf
    open_low: bool = False
    open_high: bool = False
    default: object = None
    choices: tuple = ()
    length: int = 0
    columns: tuple = ()
    only_if: tuple = ()  # (key, value): the entry applies only when that entry of the section has that value
    replaces: str = ""  # the entries (space-separated) of the section this one gives instead (a table instead of numbers)
    axis: str = ""  # a position from the CG along these body axes ("x", "z", "xyz"): it may be given as stations
    radial: bool = False  # a table along the span: its first column r/R, or radial stations in a length unit
    optional_when: str = ""  # a rule of mbs.aircraft.reader.STAND_INS under which the entry may be left out


def num(unit, text, low=-math.inf, high=math.inf, **kw) -> Entry:
    return Entry(unit, text, "number", low, high, **kw)


def positive(unit, text, **kw) -> Entry:
    return Entry(unit, text, "number", 0.0, math.inf, open_low=True, **kw)


def count(text, low=1, high=64, **kw) -> Entry:
    return Entry("-", text, "integer", low, high, **kw)


def choice(text, *choices, **kw) -> Entry:
    return Entry("-", text, "choice", choices=choices, **kw)


def ratio(text, low=0.0, high=1.0, **kw) -> Entry:
    return Entry("-", text, "number", low, high, **kw)


def angle(text, limit_deg, **kw) -> Entry:
    return Entry("rad", text, "number", -limit_deg * DEG, limit_deg * DEG, **kw)


def _airfoil(what: str, cd2_default=None) -> dict[str, Entry]:
    return {
        "lift_slope": positive("1/rad", f"{what} section lift-curve slope"),
        "cd0": ratio(f"{what} profile drag coefficient at zero lift", 0.0, 0.5),
        "cd1": num("1/rad", f"{what} profile drag's linear term, as some reports fit the polar: c_d = cd0 + cd1 alpha "
                   "+ cd2 alpha^2", -1.0, 1.0, default=0.0),
        "cd2": num("1/rad^2", f"{what} profile drag rise: c_d = cd0 + cd1 alpha + cd2 alpha^2 (negative only as a "
                   "fit that stays positive to the stall)", -100.0, 100.0, default=cd2_default),
        "alpha_stall": num("rad", f"{what} stall angle: a guard that bounds the lift, not a stall model", 0.0,
                           math.pi / 2, open_low=True),
        "cd_stalled": num("-", f"{what} flat-plate drag coefficient beyond stall", 0.0, 3.0, default=1.8),
        "zero_lift_angle": angle(f"{what} section's zero-lift angle alpha_0 from the chord (a cambered section's, "
                                 "negative when it lifts at zero angle): c_L = a (alpha - alpha_0), the drag polar "
                                 "and the stall angle counted from the zero-lift line as well", 15, default=0.0),
    }


def _rotor(what: str) -> dict[str, Entry]:
    return {
        "radius": positive("m", f"{what} radius"),
        "diameter": num("m", f"{what} diameter as published; gives radius, half of it; given beside radius, a check "
                        "of it (within 0.5 %) (0: not given)",
                        0.0, math.inf, open_low=True, default=0.0, replaces="radius"),
        "chord": positive("m", f"{what} blade chord (constant)"),
        "twist": angle(f"{what} linear blade twist, tip minus axis: theta(r) = theta_root + twist r/R", 45),
        "root_cutout": ratio(f"{what} inner end of the aerodynamic blade, fraction of R", 0.0, 0.9),
        "blade_thickness": positive("m", f"{what} blade section thickness (inertia and display only)"),
        "hub_mass": positive("kg", f"{what} hub mass"),
        "kappa": num("-", f"{what} induced power factor on the uniform inflow", 1.0, 2.0),
        "elements": count(f"{what} blade elements per blade", 1, 200),
        "mach_dd": ratio(f"{what} drag-divergence Mach number of the section (with compressibility)", 0.3, 1.0),
        "mach_limit": ratio(f"{what} bound of the Mach number in the Prandtl-Glauert factor", 0.3, 0.95, default=0.8),
        **_airfoil(what),
        "chord_table": Entry("-, m", f"{what} chord along the span: rows r/R (or the radial station, a length), "
                             "chord (linear between stations, held beyond); replaces chord, which becomes the "
                             "thrust-weighted chord", "table", columns=("-", "m"), default=(), replaces="chord",
                             radial=True),
        "twist_table": Entry("-, rad", f"{what} twist along the span: rows r/R (or the radial station, a length), "
                             "twist angle added to the collective (the collective is the pitch where the table reads "
                             "0; linear between stations, held beyond); replaces twist, which becomes the "
                             "r^2-weighted straight line through it", "table", columns=("-", "rad"), default=(),
                             replaces="twist", radial=True),
        "tip_sweep": angle(f"{what} sweep of the blade tip: the quarter-chord line swept aft by this angle beyond "
                           "sweep_start (simple sweep theory: the air velocity normal to the swept line loads the "
                           "sections)", 45, default=0.0),
        "sweep_start": ratio(f"{what} where the tip sweep begins, fraction of R", 0.5, 1.0, default=1.0),
        "airfoils": Entry("-", f"{what} airfoil tables per radial segment: rows [r/R where the segment begins, C81 "
                          "file (path from this file)], the first at or inboard of root_cutout; each segment's "
                          "c_L, c_D, c_M against alpha (-180..180 deg) and Mach replace the analytic section above "
                          "(which the estimates still use)", "airfoils", default=()),
    }


POSITION = "m, rad or -"
"""The unit kinds a pilot control's position may have: a length (in, mm), an angle (deg) or a
fraction of its travel (%, -)."""


def _travel(what: str, positive: str) -> Entry:
    return Entry(POSITION, f"{what}: least and largest position, {positive} positive; a length (in), an angle (deg) "
                 "or a fraction (%)", "travel", length=2)


def _rig(what: str) -> Entry:
    return Entry("rad, rad/position (4)", f"{what} from the pilot's controls: [at zero position, per unit of the "
                 "collective lever, of the longitudinal stick, of the lateral stick, of the pedals], e.g. unit = "
                 "\"deg, deg/in, deg/in, deg/in, deg/in\" (each gain per its control's position unit)", "mixing",
                 length=5)


def _controls(prefix: str, what: str) -> dict[str, Entry]:
    return {f"{prefix}_min": angle(f"least {what} the control reaches", 60),
            f"{prefix}_max": angle(f"largest {what} the control reaches", 60)}


def _surface(what: str, arg: str = "alpha", flow: str = "downwash", optional_when: str = "") -> dict[str, Entry]:
    lift = ("positive to starboard for either sense of rotation: a counter-clockwise rotor's fin, lifting to starboard "
            "to unload its tail rotor, has positive incidence or a negative zero-lift angle, a clockwise rotor's "
            "the other signs" if flow == "sidewash" else "leading edge up positive")
    return {"area": positive("m^2", f"{what} area"), "incidence": angle(f"{what} incidence ({lift})", 30,
                                                                         optional_when=optional_when),
            "x": num("m", f"{what} aerodynamic centre, x (forward) from the CG", axis="x"),
            "y": num("m", f"{what} aerodynamic centre, y (starboard) from the CG: a surface to one side (a "
                     "stabiliser on the starboard side only); 0 on the centre line", axis="y", default=0.0),
            "z": num("m", f"{what} aerodynamic centre, z (down) from the CG", axis="z"),
            "chord": positive("m", f"{what} chord (display only)"), **_airfoil(what, cd2_default=0.0),
            "lift_slope": positive("1/rad", f"{what} lift-curve slope of the whole surface (3-D, with its aspect "
                                   "ratio); with aspect_ratio, the section's (2-D) slope, converted"),
            "aspect_ratio": num("-", f"{what} aspect ratio span^2/area: lift_slope is then the section's (2-D) "
                                "slope and the surface's is a / (sqrt(1 + k^2) + k), k = a / (pi A) (Helmbold)",
                                0.0, 30.0, open_low=True, default=0.0),
            "coefficient_table": Entry("rad, -, -", f"{what} lift and drag coefficients as published: rows angle of "
                                       "attack (within +-90 deg: flow from the trailing edge is folded onto it, as "
                                       "for the analytic section; or -180 to 180 deg, equal at both ends: reverse "
                                       "flow as printed), c_L, c_D; natural cubic splines through the rows, "
                                       "continued linearly beyond the first and last (a trim there warns); replaces "
                                       "lift_slope, cd0, cd1, cd2, alpha_stall, cd_stalled and zero_lift_angle",
                                       "table", columns=("rad", "-", "-"), default=(),
                                       replaces="lift_slope cd0 cd1 cd2 alpha_stall cd_stalled zero_lift_angle"),
            **_interference(what, arg, flow)}


def _wing() -> dict[str, Entry]:
    """A wing (an attack helicopter's stub wing, a compound's): a tail surface's entries without
    interference tables, in one panel on the centre line or two at a quarter of its span out."""
    keep = {k: e for k, e in _surface("wing").items() if not k.startswith("interference") and k not in (
        "q_ratio", "downwash", "chord", "y")}
    return {**keep, "span": num("m", "wing span tip to tip: two panels of half the area each, a quarter of the span "
                                "to port and to starboard of the centre line (their lift rolls the aircraft); 0: one "
                                "panel on the centre line", 0.0, default=0.0)}


def _interference(what: str, arg: str, flow: str) -> dict[str, Entry]:
    """Published interference at a tail surface: it replaces the main rotor's wake model there."""
    side = "to starboard" if flow == "sidewash" else "down"
    return {f"interference_{arg}": Entry("rad", f"fuselage {arg} breakpoints of {what} interference tables",
                                         "series", default=()),
            "q_ratio": Entry("-", f"{what} dynamic-pressure ratio q_surface/q against interference_{arg}", "curve",
                             default=()),
            flow: Entry("rad", f"{what} {flow} angle ({side}) against interference_{arg}", "curve", default=())}


def _stabilator() -> dict[str, Entry]:
    return {
        "airspeed": Entry("m/s", "airspeed breakpoints of the incidence schedule", "series"),
        "incidence": Entry("rad", "scheduled incidence at those airspeeds, leading edge up (trailing edge down) "
                           "positive", "curve"),
        "collective_gain": num("-", "incidence per collective (rad/rad) about collective_reference", default=0.0),
        "collective_reference": angle("collective at which the collective term is zero", 60, default=0.0),
        "pitch_rate_gain": num("s", "incidence per pitch rate (rad per rad/s, nose up positive)", default=0.0),
        "cyclic_gain": num("-", "incidence per longitudinal cyclic (rad per rad of the model's theta_1s, positive: "
                           "the disc tilts aft): an elevator linked to the cyclic stick", default=0.0),
        "incidence_min": angle("stop: least incidence (trailing edge up)", 90),
        "incidence_max": angle("stop: largest incidence (trailing edge down)", 90),
        "incidence_table": Entry("-, m/s, rad", "scheduled incidence against collective and airspeed as a report "
                                 "prints it: a first row [nan, airspeeds...], then rows [collective, incidences...]; the "
                                 "collective as the blades' (an angle) or as a fraction of the collective lever's travel "
                                 "(unit -, with [controls]); a tensor spline held beyond its ends; replaces airspeed and "
                                 "incidence", "schedule", default=(), replaces="airspeed incidence"),
    }


def _fuselage_tables() -> dict[str, Entry]:
    """Tables as a report prints them (:mod:`mbs.aircraft.airframe_data`, :mod:`mbs.aero.airframe_tables`)."""
    tables = ("model", "tables")
    out = {
        "axes": choice("axes of the tables: body (X, Y, Z, L, M, N), stability or wind (drag, side, lift, roll, "
                       "pitch, yaw; wind axes turned by alpha and beta from the body axes, stability by alpha only)",
                       *AIRFRAME_AXES, only_if=tables),
        "sideslip_positive": choice("the side the wind comes from at the tables' positive sideslip: starboard "
                                    "(beta = asin(v / V), the aircraft moving to starboard) or port (tables printed "
                                    "with the other sign: read at -beta)", "wind from starboard", "wind from port",
                                    default="wind from starboard", only_if=tables),
        "reference_point": Entry("m", "point the moments are about: x (forward), y (starboard), z (down) from the CG",
                                 "vector", length=3, default=(), only_if=tables, axis="xyz"),
        "reference_station": Entry("m", "point the moments are about as fuselage station (aft), butt line "
                                   "(starboard), water line (up); with cg_station", "vector", length=3, default=(),
                                   only_if=tables),
        "cg_station": Entry("m", "the CG as fuselage station, butt line, water line", "vector", length=3, default=(),
                            only_if=tables),
        "alpha": Entry("rad", "angle-of-attack breakpoints, atan2(w, u), increasing", "series", default=(),
                       only_if=tables),
        "beta": Entry("rad", "sideslip breakpoints, asin(v / V), increasing", "series", default=(), only_if=tables),
        "reference_speed": positive("m/s", "speed of tables given as loads (N, N m)", default=0.0, only_if=tables),
        "reference_area": positive("m^2", "area of tables given as coefficients (or in πR^2: of the main rotor's "
                                   "disc)", default=0.0, only_if=tables),
        "reference_length": positive("m", "length of moment tables given as coefficients (or in R: of the main "
                                     "rotor's radius)", default=0.0,
                                     only_if=tables),
    }
    for names in (("drag", "side", "lift", "roll", "pitch", "yaw"), ("X", "Y", "Z", "L", "M", "N")):
        for i, name in enumerate(names):
            unit = "m^3" if i >= 3 else "m^2"
            for arg, over in (("alpha", "alpha"), ("beta", "beta"), ("alpha_beta", "alpha (rows) and beta (columns)")):
                out[f"{name}_{arg}"] = Entry(unit, f"{name} against {over}: per dynamic pressure ({unit}), loads at "
                                             "reference_speed or coefficients (-); the parts of a component add up",
                                             "lookup", default=(), only_if=tables)
    return out


def _turboshaft() -> dict[str, Entry]:
    """The engines' entries (only with ``model = "turboshaft"`` or ``"piston"``)."""
    ts = ("model", ("turboshaft", "piston"))
    return {
        "count": count("number of engines", 1, 4, only_if=ts),
        "takeoff_power": positive("W", "each engine's take-off power rating at sea level, ISA", only_if=ts),
        "max_continuous_power": positive("W", "each engine's maximum continuous power at sea level, ISA", only_if=ts),
        "oei_power": positive("W", "an engine's one-engine-inoperative rating (the power the remaining engine may "
                              "give when another has failed), sea level, ISA (not needed with one engine)", only_if=ts,
                              optional_when="one engine"),
        "transmission_power": positive("W", "main gearbox limit on the engines' power together", only_if=ts),
        "lapse_temperature": num("-", "power available at altitude: rating times delta / theta^lapse_temperature "
                                 "(delta, theta: ambient pressure and temperature over sea level ISA)", 0.0, 4.0,
                                 only_if=("model", "turboshaft")),
        "full_throttle_power": positive("W", "a piston engine's full-throttle power at sea level, ISA, as its maker "
                                        "rates it (the O-360's 180 hp, not the helicopter's 'derated' figure, which "
                                        "is its take-off rating): each rating is available up to "
                                        "the altitude where this, lapsing as 1.132 sigma - 0.132 (Gagg and Ferrar), "
                                        "falls to it, and this lapsed above", only_if=("model", "piston")),
        "gas_generator_time_constant": positive("s", "lag of the gas generator's power behind the fuel flow",
                                                only_if=ts),
        "fuel_time_constant": positive("s", "lag of the metered fuel flow behind the governor's demand", only_if=ts),
        "governor_droop": num("-", "rotor speed drop (fraction of nominal) from zero to take-off power of every "
                              "engine, without anticipation: the governor's proportional gain is its inverse", 0.0,
                              0.5, open_low=True, only_if=ts),
        "anticipation": num("1/rad", "collective anticipation: fuel demand (fraction of take-off power) per rad of "
                            "collective above its least", 0.0, 50.0, only_if=ts),
        "governor_lead": num("s", "lead time constant of the governor's compensation (1 + lead s)/(1 + lag s) on the "
                             "speed error", 0.0, 10.0, only_if=ts),
        "governor_lag": positive("s", "lag time constant of the governor's compensation", only_if=ts),
    }


ENTRIES: dict[str, dict[str, Entry]] = {
    "aircraft": {
        "name": Entry("-", "name of the aircraft", "text"),
        "mass": positive("kg", "gross mass"),
        "inertia": choice("what Ixx, Iyy, Izz, Ixz are: the airframe's without the rotors, about its own centre of "
                          "mass (airframe), or the whole aircraft's with its rotors, about the CG (whole-aircraft: "
                          "the program subtracts the rotors' hubs and blades, averaged over a revolution)",
                          "airframe", "whole-aircraft", default="airframe"),
        "Ixx": positive("kg m^2", "roll moment of inertia (of what: see inertia)"),
        "Iyy": positive("kg m^2", "pitch moment of inertia (of what: see inertia)"),
        "Izz": positive("kg m^2", "yaw moment of inertia (of what: see inertia)"),
        "Ixz": num("kg m^2", "product of inertia: tensor [[Ixx, 0, -Ixz], [0, Iyy, 0], [-Ixz, 0, Izz]]", default=0.0),
        "cg_station": Entry("m", "the CG as fuselage station (aft), butt line (see conventions.butt_line_positive), "
                            "water line (up): with it, the positions from the CG (the hubs, the tail surfaces, the "
                            "fuselage tables' reference point) may be written as their stations, "
                            "{ station = ..., unit, source } instead of { value = ... }", "vector", length=3,
                            default=()),
    },
    "environment": {
        "rho": positive("kg/m^3", "air density", default=1.225),
        "g": positive("m/s^2", "gravitational acceleration", default=9.80665),
        "speed_of_sound": positive("m/s", "speed of sound (section Mach number)", default=340.3),
    },
    "main_rotor": {
        "n_blades": count("number of main-rotor blades", 2, 12),
        "hub_type": choice("flapping (each blade on its own flap and lag hinges: an articulated rotor, or the "
                           "equivalent hinges and springs of a hingeless one) or teetering (two blades on a seesaw "
                           "across the shaft, stiff in plane: no lag hinge; a Bell or Robinson rotor)", "flapping",
                           "teetering", default="flapping"),
        "seesaw_mass": positive("kg", "teetering hub: the yoke's mass, teetering with the blades (hub_mass is the "
                                "mast head's)", only_if=("hub_type", "teetering")),
        "seesaw_size": Entry("m", "teetering hub: the yoke as a box along the blades (inertia, display)", "vector",
                             0.0, math.inf, open_low=True, length=3, only_if=("hub_type", "teetering")),
        "coning_hinge_offset": num("m", "teetering hub with coning hinges (a Robinson's three-hinge rotor): each "
                                   "blade's coning hinge, a flap hinge on the yoke, this far from the rotor axis; "
                                   "the blades cone on it about the precone, free or on coning_stiffness (0: no "
                                   "coning hinges, the blades fixed to the yoke at the precone)", 0.0, default=0.0,
                                   only_if=("hub_type", "teetering")),
        "coning_stiffness": num("N m/rad", "spring of each coning hinge about the precone (0: free)", 0.0,
                                default=0.0, only_if=("hub_type", "teetering")),
        "undersling": num("m", "teetering hub: the blades' roots below the teeter hinge (an underslung hub puts "
                          "the coned blades' centre of mass at the hinge's height)", 0.0, default=0.0,
                          only_if=("hub_type", "teetering")),
        "rotation": choice("sense of rotation seen from above", "counter-clockwise", "clockwise"),
        "omega": positive("rad/s", "nominal main-rotor speed"),
        "tip_speed": num("m/s", "nominal main-rotor tip speed as published; gives omega, tip_speed / radius; given "
                         "beside omega, a check of it (within 0.5 %) (0: not given)", 0.0, math.inf, open_low=True, default=0.0, replaces="omega"),
        "omega_min": positive("rad/s", "least rotor speed the omega parameter accepts", default="0.5 omega"),
        "omega_max": positive("rad/s", "largest rotor speed the omega parameter accepts", default="1.2 omega"),
        "hub_x": num("m", "hub position x (forward) from the CG", axis="x"),
        "hub_z": num("m", "hub position z (down) from the CG; negative above it", axis="z"),
        "shaft_tilt": angle("forward tilt of the shaft", 30),
        "I_flap": positive("kg m^2", "blade moment of inertia about the flap hinge"),
        "lock_number": num("-", "Lock number as published, gamma = rho a c R^4 / I_flap at the file's density, "
                           "lift_slope, chord and radius; replaces I_flap, which is computed from it (0: not given)",
                           0.0, 100.0, open_low=True, default=0.0, replaces="I_flap"),
        "mass_table": Entry("-, kg/m", "blade mass per length along the span: rows r/R (or the radial station, a "
                            "length), mass per length (linear between stations, zero beyond), the last at r/R = 1; "
                            "replaces I_flap: the blade's mass, first moment and flap inertia are integrated from it "
                            "(outboard of the flap hinge)", "table", columns=("-", "kg/m"), default=(), replaces="I_flap", radial=True),
        "section_inertia_table": Entry("-, kg m, kg m, kg m", "section mass moments of inertia per length along the "
                                       "span (with mass_table): rows r/R (or the radial station), flap "
                                       "(about the chord), lag (about the normal), torsion (about the span); "
                                       "default: a box of the chord and blade_thickness", "table", columns=("-", "kg m", "kg m", "kg m"), default=(),
                                       radial=True),
        "flap_hinge_offset": num("m", "flap hinge (or equivalent hinge) distance from the rotor axis (0 on a "
                                 "teetering hub, whose blades start at the teeter hinge on the axis)", 0.0),
        "flap_stiffness": num("N m/rad", "flap spring (centre-spring equivalent of a hingeless rotor; on a teetering "
                              "hub the hub spring on the teeter angle)", 0.0),
        "delta3": angle("pitch-flap coupling angle of the flap hinge (or the teeter hinge): its axis skewed by delta3 "
                        "in the disc plane, so that flapping up by beta pitches the blade by -tan(delta3) beta (a "
                        "bearingless or hingeless rotor's kinematic coupling as published; with a [swashplate], its "
                        "own delta3 is the pitch horn's: give one of the two)", 70, default=0.0),
        "precone": angle("precone of the main-rotor blades: the rest angle of the flap spring (a hingeless or "
                         "bearingless rotor's built-in coning; nothing without flap_stiffness), built into the yoke "
                         "of a teetering hub", 20, default=0.0),
        "lag_frequency": positive("1/rev", "first rotating lag frequency", only_if=("hub_type", "flapping")),
        "lag_damping": num("N m s/rad", "lead-lag damper", 0.0, only_if=("hub_type", "flapping")),
        "hub_radius": positive("m", "hub radius (inertia of a solid disc, display)"),
        **_rotor("main-rotor"),
        **_controls("collective", "main-rotor collective pitch at the blade root"),
        **_controls("lateral_cyclic", "lateral cyclic pitch theta_1c"),
        **_controls("longitudinal_cyclic", "longitudinal cyclic pitch theta_1s"),
    },
    "tail_rotor": {
        "n_blades": count("number of tail-rotor blades (a fan-in-fin has up to 18: see duct_exit_ratio)", 2, 18),
        "duct_exit_ratio": num("-", "a fan-in-fin (Fenestron, fantail): its duct's exit area over the fan's disc "
                               "area, sigma_d (ideal momentum theory of a shrouded rotor: in hover the duct carries "
                               "(2 sigma_d - 1) times the fan's thrust, the power is T^1.5 / sqrt(4 sigma_d rho A); "
                               "the flow through the duct is axial: no translational lift); 0: an open rotor",
                               0.0, 2.0, default=0.0),
        "hub_type": choice("teetering (two blades on a seesaw), flapping (each blade on its own flap hinge: an "
                           "articulated rotor, or the equivalent hinge and spring of a hingeless or bearingless one) "
                           "or rigid (blades on pitch bearings only)", "teetering", "rigid", "flapping"),
        "upper_blade": choice("which way the upper tail-rotor blade moves: the tail rotor's sense of rotation, for "
                              "any number of blades (a fan-in-fin's too)", "aft", "forward"),
        "gear_ratio": positive("-", "tail-rotor speed per main-rotor speed"),
        "omega": num("rad/s", "nominal tail-rotor speed as published (rpm ...); replaces gear_ratio, which is "
                     "computed from it and main_rotor.omega (0: not given)", 0.0, math.inf, open_low=True,
                     default=0.0, replaces="gear_ratio"),
        "tip_speed": num("m/s", "nominal tail-rotor tip speed as published; gives gear_ratio, from it, the tail radius "
                         "and main_rotor.omega; given beside gear_ratio, a check of it (within 0.5 %) (0: not given)", 0.0, math.inf, open_low=True,
                         default=0.0, replaces="gear_ratio"),
        "hub_x": num("m", "tail-rotor hub x (forward) from the CG", axis="x"),
        "hub_y": num("m", "tail-rotor hub y (starboard) from the CG", axis="y"),
        "hub_z": num("m", "tail-rotor hub z (down) from the CG", axis="z"),
        "blade_mass": positive("kg", "tail-rotor blade mass"),
        "lock_number": num("-", "tail-rotor Lock number as published, gamma = rho a c R^4 / I_flap at the file's "
                           "density, lift_slope, chord and radius; replaces blade_mass, which is computed from it "
                           "(a uniform blade from the flap hinge: I_flap = blade_mass (R - e)^2 / 3) (0: not given)",
                           0.0, 100.0, open_low=True, default=0.0, replaces="blade_mass"),
        "hub_size": positive("m", "tail-rotor hub, a cube (inertia only)"),
        "seesaw_mass": positive("kg", "seesaw mass", only_if=("hub_type", "teetering")),
        "seesaw_size": Entry("m", "seesaw box along the blades (inertia, display)", "vector", 0.0, math.inf,
                             open_low=True, length=3, only_if=("hub_type", "teetering")),
        "teeter_stiffness": num("N m/rad", "teeter spring", 0.0, default=0.0, only_if=("hub_type", "teetering")),
        "delta3": angle("pitch-flap coupling angle of the flap or teeter hinge: its axis skewed by delta3 in the disc "
                        "plane, so that flapping up by beta pitches the blade by -tan(delta3) beta (a rigid hub does "
                        "not flap: 0 there)", 70, default=0.0),
        "cant": angle("cant of the tail-rotor shaft: the thrust axis turned about the body x axis so that the thrust "
                      "gains an upward component T sin(cant)", 60, default=0.0),
        "toe": angle("the tail-rotor shaft turned in the horizontal plane: the thrust axis turned about the body z "
                     "axis so that the thrust gains a forward component T cos(cant) sin(toe)", 45, default=0.0),
        "precone": angle("precone of the tail-rotor blades towards the thrust: built into the hub of a rigid or "
                         "teetering rotor; the rest angle of the flap spring of a flapping one", 20, default=0.0),
        "flap_hinge_offset": num("m", "flap hinge (or equivalent hinge) distance from the tail-rotor axis", 0.0,
                                 default=0.0, only_if=("hub_type", "flapping")),
        "flap_stiffness": num("N m/rad", "flap spring at each tail blade's hinge (the equivalent spring of a hingeless "
                              "or bearingless rotor)", 0.0, default=0.0, only_if=("hub_type", "flapping")),
        **_rotor("tail-rotor"),
        **_controls("collective", "tail-rotor collective pitch"),
    },
    "controls": {
        "collective_lever": _travel("collective lever", "up"),
        "longitudinal_stick": _travel("longitudinal cyclic stick", "forward"),
        "lateral_stick": _travel("lateral cyclic stick", "right"),
        "pedals": _travel("pedals", "right pedal forward"),
        "collective": _rig("main-rotor collective pitch (at conventions.collective_radius)"),
        "longitudinal_cyclic": _rig("longitudinal cyclic theta_1s (positive: the disc tilts aft)"),
        "lateral_cyclic": _rig("lateral cyclic theta_1c (positive: the disc tilts to the advancing side's left ... "
                               "as the model's lateral_cyclic)"),
        "tail_collective": _rig("tail-rotor collective pitch (sign of conventions.tail_collective_positive)"),
        "phase": angle("swashplate phase: the mixing's cyclic is turned by it in the sense of rotation, theta_1c = "
                       "c cos(phase) + s sin(phase), theta_1s = s cos(phase) - c sin(phase) of the mixing's (c, s)",
                       90, default=0.0),
    },
    "conventions": {
        "tail_collective_positive": choice("what a positive tail-rotor collective pitch does in this file's rigging "
                                           "and in published data of the aircraft: anti-torque (the model's "
                                           "tail_collective), or thrust to port or to starboard",
                                           "anti-torque", "port", "starboard", default="anti-torque"),
        "collective_radius": ratio("where published main-rotor collective pitch is measured, fraction of R (0: "
                                   "the blade root, the model's collective; 0.75 for theta_0.75)", 0.0, 1.0,
                                   default=0.0),
        "cyclic_pitch": choice("how this file's rigging and published data state cyclic pitch: the model's theta_1c, "
                               "theta_1s (pitch = theta_0 + theta_1c cos psi + theta_1s sin psi) or A1, B1 (pitch = "
                               "theta_0 - A1 cos psi - B1 sin psi, as NASA math-model reports print it; psi from the "
                               "tail in the sense of rotation in both): the mixing rows longitudinal_cyclic and "
                               "lateral_cyclic then give B1 and A1", "theta_1c, theta_1s", "A1, B1",
                               default="theta_1c, theta_1s"),
        "butt_line_positive": choice("the side to which butt lines count positive in this file's stations",
                                     "starboard", "port", default="starboard"),
        "fuselage_station_positive": choice("the way fuselage stations count positive in this file's stations "
                                            "(forward: a datum's x forward, as some simulation data give points)",
                                            "aft", "forward", default="aft"),
        "water_line_positive": choice("the way water lines count positive in this file's stations (down: a "
                                      "datum's z down)", "up", "down", default="up"),
        "stabilator_positive": choice("which way a positive stabilator incidence turns the surface in this file "
                                      "([stabilator] incidence, stops and gains): leading edge up (trailing edge "
                                      "down), the model's, or trailing edge up", "leading edge up",
                                      "trailing edge up", default="leading edge up"),
    },
    "lag_damper": {
        "hub_point": Entry("m", "the lag damper's end on the hub, in its blade's rotating frame at zero azimuth: "
                           "distance from the rotor axis along the blade, towards the blade's leading edge, up",
                           "vector", length=3),
        "blade_point": Entry("m", "its end on the blade (moving with flap, lag and pitch), at zero flap, lag and "
                             "pitch: distance from the rotor axis, towards the leading edge, up", "vector", length=3),
        "force_curve": Entry("m/s, N", "the damper's force against its rate of extension: rows of (rate, force), "
                             "the force resisting the motion (positive when extending); a natural cubic spline "
                             "through the rows, linear beyond the ends", "table", columns=("m/s", "N")),
        "stiffness": num("N/m", "the damper's stiffness along its line (an elastomeric damper), about its length at "
                         "zero flap, lag and pitch", 0.0, default=0.0),
    },
    "stabilizer_bar": {
        "mass": positive("kg", "stabilizer bar (flybar): its mass with paddles and weights"),
        "inertia": positive("kg m^2", "its moment of inertia about its teeter hinge (the bar's, paddles' and tip "
                            "weights')"),
        "height": num("m", "its teeter hinge above the main rotor's hub, along the shaft", default=0.0),
        "paddle_radius": positive("m", "distance from the rotor axis to each paddle's aerodynamic centre (or to the "
                                  "bar's tips without paddles: display)"),
        "paddle_area": num("m^2", "area of each of its two paddles (Hiller); 0: a Bell bar with dampers only", 0.0,
                           default=0.0),
        "paddle_lift_slope": num("1/rad", "the paddles' lift-curve slope (of the whole paddle, with its aspect ratio)",
                                 0.0, 2 * math.pi + 1e-9, default=0.0),
        "paddle_cd0": num("-", "the paddles' profile drag coefficient", 0.0, 1.0, default=0.01),
        "damping": num("N m s/rad", "damping on its teeter hinge (a Bell bar's dampers)", 0.0, default=0.0),
        "time_constant": num("s", "the bar's time constant in hover as published, 2 inertia / (the paddles' damping + "
                             "the hinge's): the hinge's damping is derived from it (0: give damping instead)", 0.0,
                             default=0.0),
        "paddle_gain": num("-", "paddle pitch per swashplate cyclic at the paddle's azimuth (rad/rad)", default=1.0),
        "hiller_gain": num("-", "the mixer: blade cyclic pitch per rad of the bar's teeter, at the blade 90 deg behind "
                           "the bar's end (rad/rad)"),
        "bell_gain": num("-", "the mixer: blade cyclic pitch per swashplate cyclic, the direct path (rad/rad; 0: the "
                         "blades follow the bar alone)", default=0.0),
    },
    "envelope": {
        "pitch_min": angle("least pitch attitude of the published flight envelope", 90),
        "pitch_max": angle("largest pitch attitude of the published flight envelope", 90),
        "roll_min": angle("least roll attitude (left bank) of the published flight envelope", 90),
        "roll_max": angle("largest roll attitude (right bank) of the published flight envelope", 90),
        "sideslip_min": angle("least sideslip of the published flight envelope", 90),
        "sideslip_max": angle("largest sideslip of the published flight envelope", 90),
    },
    "fuselage_aero": {
        "model": choice("Padfield's cubic polynomials in body axes about the CG, or tables as published",
                        "polynomials", "tables", default="polynomials"),
        "v_ref": positive("m/s", "speed at which the polynomials give the loads; loads scale with (V/v_ref)^2",
                          only_if=("model", "polynomials")),
        **{k: Entry(u, f"{k} {what}: coefficients of {arg}^0..3", "vector", length=4, only_if=("model", "polynomials"))
           for k, u, what, arg in (("X", "N", "force", "alpha"), ("Y", "N", "force", "beta"),
                                   ("Z", "N", "force", "alpha"), ("M", "N m", "moment", "alpha"),
                                   ("N", "N m", "moment", "beta"))},
        "angle_limit": num("rad", "angles of attack and sideslip are clipped here", 0.0, math.pi / 2, open_low=True,
                           only_if=("model", "polynomials")),
        **_fuselage_tables(),
    },
    "horizontal_tail": _surface("horizontal tail", optional_when="stabilator schedule"),
    "vertical_fin": _surface("fin", "beta", "sidewash"),
    "wing": _wing(),
    "stabilator": _stabilator(),
    "wake": {"width": positive("m", "edge smoothing of the main rotor's wake tube (tail wake, download), an "
                               "estimate that scales with the rotor (the Bo105's 0.25 m is 0.05 R): a tail at the "
                               "wake's edge has derivatives that follow it")},
    "download": {"panels": Entry("m, m, m, m^2, -", "fuselage panels in the wake: rows x, y, z (from the CG), plan "
                                 "area, drag coefficient in vertical flow", "table", columns=("m", "m", "m", "m^2", "-"))},
    "hub_drag": {"flat_plate_area": num("m^2", "drag area of the main-rotor hub and mast", 0.0)},
    "geometry": {
        "cabin": Entry("m", "display: cabin box length, width, height", "vector", 0.0, math.inf, open_low=True,
                       length=3, default="scaled"),
        "cabin_x": num("m", "display: cabin centre x", default="scaled"),
        "boom_radius": positive("m", "display: tail boom radius", default="scaled"),
        "hub_height": positive("m", "display: main hub height", default="scaled"),
        "tail_hub": Entry("m", "display: tail hub cylinder radius, length", "vector", 0.0, math.inf, open_low=True,
                          length=2, default="scaled"),
        "plate_thickness": positive("m", "display: tail surface thickness", default="scaled"),
    },
    "engine": {
        "transmission_efficiency": num("-", "main gearbox and tail-rotor drive together: engine power = rotors' "
                                       "shaft power / efficiency + accessory power", 0.5, 1.0, open_low=True),
        "accessory_power": num("W", "hydraulic pumps, generators, cooling fans driven by the gearbox", 0.0),
        "torque_reference": num("N m", "the torque a cockpit's torque gauge shows as 100 %, referred to the main-rotor "
                                "shaft (each engine's gauge of a twin: its engine's share); with it the output "
                                "engine.torque_fraction (0: none)", 0.0, default=0.0),
        "model": choice("the engines' dynamics: none (the power the rotors need, as it comes), turboshaft (gas "
                        "generator, fuel-flow lag, power limits and a rotor-speed governor, for scenes whose rotor "
                        "speed is a state) or piston (the same dynamics, the power lag the engine's own, with a "
                        "normally aspirated engine's lapse and derated ratings)", "none", "turboshaft", "piston",
                        default="none"),
        **{k: e for k, e in _turboshaft().items()},
    },
    "drive_train": {
        "transmission_inertia": positive("kg m^2", "polar inertia of the main gearbox, the shafts and the engines' "
                                         "power turbines, referred to the main-rotor shaft (each part's inertia times "
                                         "the square of its speed over the rotor's)"),
        "shaft_stiffness": positive("N m/rad", "torsional stiffness of the main-rotor shaft between the gearbox and "
                                    "the hub (scenes with a flexible drive train)"),
        "shaft_damping": num("N m s/rad", "torsional damping of the main-rotor shaft (flexible drive train)", 0.0),
    },
    "elastic_blade": {
        "torsion_frequency": positive("1/rev", "first rotating torsion frequency of the blade"),
        "structural_damping": ratio("structural damping ratio of each direction's first mode", 0.0, 0.5),
    },
    "swashplate": {
        "horn": choice("where the pitch horn sits: on the blade outboard of the flap and lag hinges (articulated "
                       "rotors: pitch-flap and pitch-lag coupling from the geometry) or on the feathering housing "
                       "inboard of the flexure (hingeless rotors: no kinematic coupling)", "blade", "housing"),
        "horn_arm": positive("m", "chordwise distance of the pitch link's upper ball from the feathering axis, on the "
                             "leading-edge side"),
        "horn_height": num("m", "height of the upper ball above the hinge plane at zero pitch"),
        "delta3": angle("pitch-flap coupling angle: the upper ball lies horn_arm tan(delta3) outboard of the flap "
                        "hinge line, so that flapping up by beta pitches the blade down by about tan(delta3) beta",
                        60, only_if=("horn", "blade")),
        "ball_radius": positive("m", "distance of the upper ball from the rotor axis (a horn on the housing)",
                                only_if=("horn", "housing")),
        "link_length": positive("m", "pitch link length between its balls"),
        "link_lean": angle("spanwise lean of the pitch link at neutral: its lower ball lies link_length sin(lean) "
                           "inboard of the upper one (pitch-lag coupling, about -tan(lean))", 45),
        "actuator_radius": positive("m", "distance of the actuators' balls on the non-rotating plate from the shaft"),
        "actuator_azimuths": Entry("rad", "azimuths of the three actuators in the rotor's azimuth frame (0 over the "
                                   "tail, counted in the sense of rotation)", "vector", -2 * math.pi, 2 * math.pi,
                                   length=3),
        "actuator_stroke": positive("m", "each actuator's travel either side of its neutral position"),
        "link_stiffness": positive("N/m", "axial stiffness of a pitch link with the control system behind it (scenes "
                                   "with elastic pitch links)"),
    },
}

OPTIONAL_SECTIONS = ("environment", "geometry", "elastic_blade", "swashplate", "stabilator", "controls",
                     "conventions", "envelope", "lag_damper", "drive_train", "wing", "horizontal_tail",
                     "stabilizer_bar")
"""Sections a file may leave out: ISA, display sizes scaled from the rotor, no elastic blades, no
swashplate mechanism (the blade pitch then only driven), no pilot-control rigging (the controls are
the blade angles), the model's own conventions, no drive-train data (the rotors then only at
constant speed), no wing, no horizontal tail (an S-51's; the check says so), no stabilizer bar."""

SURFACES = ("horizontal_tail", "vertical_fin", "wing")
"""The fixed lifting surfaces an aircraft file may give (the wing optional)."""


@dataclass(frozen=True)
class Derived:
    """A value computed from the other entries: SI ``unit``, its formula ``text``."""

    unit: str
    text: str


DERIVED: dict[str, dict[str, Derived]] = {
    "main_rotor": {
        "blade_mass": Derived("kg", "uniform blade from the flap hinge: 3 I_flap / (R - e)^2; with mass_table its "
                              "integral outboard of the flap hinge; given alone (override), the flap inertia of the "
                              "uniform blade of this mass"),
        "first_moment": Derived("kg m", "blade's first moment about the flap hinge: blade_mass (R - e) / 2 for the "
                                "uniform blade; with mass_table the integral of mass per length times (r - e)"),
        "lag_stiffness": Derived("N m/rad", "lag spring giving lag_frequency: (nu^2 - e S / I) I Omega^2, "
                                 "S the blade's first moment about the hinge, I = I_flap + m c^2 / 12 "
                                 "its lag inertia (a box of the chord c; with mass_table the integrated lag inertia)"),
        "tip_loss": Derived("-", "Prandtl's effective-radius factor B = 1 - sqrt(2 C_T) / N_b at the hover C_T "
                            "(Johnson, Helicopter Theory 3.5)"),
    },
    "tail_rotor": {
        "tip_loss": Derived("-", "B = 1 - sqrt(2 C_T) / N_b at the tail rotor's hover C_T (thrust balancing the "
                            "main rotor's hover torque)"),
    },
    "wake": {"core": Derived("-", "swirl core radius per R: the root cut-out (no torque inboard of it)")},
    "swashplate": {
        "ball_offset": Derived("m", "the upper ball's distance outboard of the flap hinge: horn_arm tan(delta3) on the "
                               "blade, ball_radius - flap_hinge_offset on the housing"),
        "plate_radius": Derived("m", "radius of the lower balls on the rotating plate: the upper ball's distance from "
                                "the axis in the plane, moved link_length sin(link_lean) inboard"),
        "phase": Derived("rad", "azimuth lead of a blade's lower ball over its feathering axis: "
                         "atan2(horn_arm, upper ball radius - link_length sin(link_lean))"),
        "plate_height": Derived("m", "height of the plate's lower balls at neutral above the hinge plane: "
                                "horn_height - link_length cos(link_lean)"),
    },
    "elastic_blade": {
        "flap_frequency": Derived("1/rev", "the rigid blade's first flap frequency, "
                                  "sqrt(1 + 3 e / (2 (R - e)) + K_beta / (I_flap Omega^2))"),
        "lag_frequency": Derived("1/rev", "main_rotor.lag_frequency"),
        "flap_stiffness": Derived("N m^2", "uniform EI whose continuous rotating blade has flap_frequency"),
        "lag_stiffness": Derived("N m^2", "uniform EI whose continuous rotating blade has lag_frequency"),
        "torsion_stiffness": Derived("N m^2", "uniform GJ whose continuous rotating blade has torsion_frequency"),
    },
}


FROM_TABLES: dict[str, dict[str, Derived]] = {
    section: {"chord": Derived("m", "thrust-weighted chord of chord_table, int c r^2 dr / int r^2 dr over the "
                               "aerodynamic blade (solidity, Lock number, estimates)"),
              "twist": Derived("rad", "slope of the r^2-weighted straight line through twist_table over the "
                               "aerodynamic blade (estimates, wake geometry)"),
              **({"I_flap": Derived("kg m^2", "integral of mass per length times (r - e)^2 plus the sections' flap "
                                    "inertia, outboard of the flap hinge, from mass_table; or rho a c R^4 / gamma "
                                    "from lock_number; or blade_mass (R - e)^2 / 3, a uniform blade, from "
                                    "blade_mass alone")}
                 if section == "main_rotor" else
                 {"blade_mass": Derived("kg", "uniform blade from the flap hinge (the axis unless the hub is "
                                        "flapping) of the Lock number: 3 rho a c R^4 / (gamma (R - e)^2)"),
                  "gear_ratio": Derived("-", "tail-rotor omega over main_rotor.omega")})}
    for section in ("main_rotor", "tail_rotor")
}
"""Plain entries that a distribution replaces, computed from it (:data:`Entry.replaces`)."""
