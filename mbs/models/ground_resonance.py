"""Ground resonance of a Bo105-like helicopter: the fuselage on its landing gear and a rotor with
lag hinges, and nothing else (no aerodynamics, no flap, no gravity).

Tree::

    world -lateral slider, roll hinge-> fuselage -driven hinge-> main_hub -lag-> blade1..4

The fuselage moves sideways on the gear's lateral spring-damper and rolls about an axis on the
ground (roll spring-damper); the hub, ``hub_height`` above that axis, turns at the run-time rotor
speed ``omega`` (rad/s); each blade is a uniform box on a lag hinge at ``lag_hinge_offset`` with a
spring (constant of the generated code) and a damper. The damper constants are run-time
parameters, ``lag_damping`` (N m s/rad, every blade), ``lateral_damping`` (N s/m) and
``roll_damping`` (N m s/rad) of the gear, so a fan plot with a damper reduced or removed needs no
rebuild. Gravity is left out: on the gear it only softens the roll spring by ``m g h`` (3 %).

Frames as in :mod:`mbs.models.helicopter`: fuselage x forward, y starboard, z down; hub x aft,
z up, blade ``k`` at azimuth ``ψ_k = Ω t + 2π (k - 1) / N`` from the tail, rotor
counter-clockwise from above; positive lag is lagging (against the rotation). Numbers from
``ground_resonance.toml`` (sources there; the gear and lag-hinge values are estimates).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from mbs.forces import UserForce
from mbs.joints import DrivenHinge, Hinge, Serial, Slider
from mbs.aircraft import Data
from mbs.scenes import Scene, register
from mbs.tree import Model

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DATA_FILE = Path(__file__).with_name("ground_resonance.toml")
HUB_FRAME = np.array([[-1.0, 0, 0], [0, 1.0, 0], [0, 0, -1.0]])  # columns: hub x aft, y starboard, z up


def load_data(path: Path = DATA_FILE) -> Data:
    """The scene's parameters (``data[section][key]``, SI as written; unit, source and note in
    ``data.meta``)."""
    raw = tomllib.loads(Path(path).read_text())
    data = Data({sec: {k: e["value"] for k, e in entries.items()} for sec, entries in raw.items()})
    data.meta = {sec: {k: {f: e.get(f, "") for f in ("unit", "source", "note")} for k, e in entries.items()}
                 for sec, entries in raw.items()}
    return data


def hub_height(d: Data) -> float:
    """Hub above the gear roll axis, m."""
    return d["fuselage"]["cg_height"] + d["fuselage"]["hub_above_cg"]


def fuselage_mass(d: Data) -> float:
    """Aircraft mass minus hub and blades, kg."""
    r = d["rotor"]
    return d["fuselage"]["aircraft_mass"] - r["hub_mass"] - r["n_blades"] * r["blade_mass"]


def blade_body(d: Data) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) from the lag hinge (m) and inertia (3, 3) about it (kg m²)
    of a uniform box from the lag hinge to the tip: x span, y chord, z thickness."""
    r = d["rotor"]
    span, m = r["radius"] - r["lag_hinge_offset"], r["blade_mass"]
    inertia = m / 12 * np.diag([r["chord"] ** 2 + r["blade_thickness"] ** 2, span**2 + r["blade_thickness"] ** 2,
                                span**2 + r["chord"] ** 2])
    return m, np.array([span / 2, 0.0, 0.0]), inertia


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _add_parameters(m: Model, d: Data) -> None:
    r, g = d["rotor"], d["landing_gear"]
    m.add_parameter("omega", r["omega"], "rad/s", "rotor speed", low=r["omega_min"], high=r["omega_max"])
    m.add_parameter("lag_damping", r["lag_damping"], "N m s/rad", "lag damper constant, every blade",
                    low=0.0, high=r["lag_damping_max"])
    m.add_parameter("lateral_damping", g["lateral_damping"], "N s/m", "landing-gear lateral damper",
                    low=0.0, high=g["lateral_damping_max"])
    m.add_parameter("roll_damping", g["roll_damping"], "N m s/rad", "landing-gear roll damper",
                    low=0.0, high=g["roll_damping_max"])


def _add_fuselage(m: Model, d: Data) -> None:
    f, g = d["fuselage"], d["landing_gear"]
    joint = Serial(Slider((0, 1, 0), name="lateral", stiffness=g["lateral_stiffness"]),
                   Hinge((1, 0, 0), name="roll", stiffness=g["roll_stiffness"]))
    m.add_body("fuselage", "world", joint, mass=fuselage_mass(d), com=(0.0, 0.0, -f["cg_height"]),
               inertia=np.diag([f["Ixx"], f["Iyy"], f["Izz"]]),
               shape={"kind": "box", "size": [3.6, 1.5, 1.4], "offset": [0.3, 0, -f["cg_height"]]})


def _add_rotor(m: Model, d: Data) -> None:
    r = d["rotor"]
    n, e, rh = int(r["n_blades"]), r["lag_hinge_offset"], r["hub_radius"]
    m.add_body("main_hub", "fuselage", DrivenHinge((0, 0, 1), lambda t, p: p["omega"] * t, name="azimuth"),
               mass=r["hub_mass"], inertia=r["hub_mass"] / 4 * np.diag([rh**2, rh**2, 2 * rh**2]),
               at=(0.0, 0.0, -hub_height(d)), frame=HUB_FRAME,
               shape={"kind": "cylinder", "radius": rh, "length": 0.25, "axis": [0, 0, 1], "color": "#50565e"})
    mass, com, inertia = blade_body(d)
    for k in range(n):
        psi0 = 2 * np.pi * k / n
        m.add_body(f"blade{k + 1}", "main_hub", Hinge((0, 0, -1), name="lag", stiffness=r["lag_stiffness"]),
                   mass=mass, com=com, inertia=inertia, at=e * _rz(psi0)[:, 0], frame=_rz(psi0),
                   shape={"kind": "box", "size": [2 * com[0], r["chord"], r["blade_thickness"]],
                          "offset": com.tolist(), "color": ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e"][k % 4]})


def _dampers(n: int) -> UserForce:
    """Linear dampers whose constants are run-time parameters: lag moment ``-lag_damping ζ'``
    (N m) on every blade, gear force ``-lateral_damping y'`` (N) and moment ``-roll_damping φ'`` (N m)."""
    rates = {f"blade{k + 1}.lag_rate": "lag_damping" for k in range(n)}
    rates.update({"fuselage.lateral_rate": "lateral_damping", "fuselage.roll_rate": "roll_damping"})

    def apply(state, loads) -> None:
        for rate, constant in rates.items():
            loads.add_generalized(rate, -state.p[constant] * state.v(rate))
    return UserForce("dampers", apply)


def build(data: Data | None = None) -> Model:
    """The ground-resonance model (6 DOF: lateral, roll, four lags)."""
    d = data or load_data()
    m = Model("ground-resonance", gravity=(0.0, 0.0, 0.0))
    _add_parameters(m, d)
    _add_fuselage(m, d)
    _add_rotor(m, d)
    m.add_force(_dampers(int(d["rotor"]["n_blades"])))
    m.add_output("main_rotor.azimuth", lambda s: s.p["omega"] * s.t, "rad", "azimuth of blade 1 from the tail")
    m.set_initial(**{"fuselage.roll": 0.01})
    return m


register(Scene("ground-resonance", "ground resonance: fuselage on landing-gear springs and dampers in lateral "
               "translation and roll, hub at constant speed, 4 blades on offset lag hinges with springs and "
               "dampers (damper constants are run-time parameters); no aerodynamics, no gravity (Bo105-like, gear and hinge data estimated)",
               build, omega=load_data()["rotor"]["omega"],
               plots={"fuselage roll (rad)": ["fuselage.roll"],
                      "lag (rad)": [f"blade{k}.lag" for k in range(1, 5)]}))
