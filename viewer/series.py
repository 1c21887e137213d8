"""The time series a page shows beside the 3D view: hinge angles and pitch inputs (plot) and
the main-rotor azimuth (readout), taken from a :class:`viewer.motion.Recording`.

Hinge angles are the scene's plot panels (``Scene.plots``: coordinates or outputs), else the
coordinates called ``*.flap``, ``*.lag`` and ``*.teeter``. Pitch inputs are the parameters
whose names contain "collective" or "cyclic", and any other parameter that changes during
the run. With a swashplate: the blade pitch its links set (``blade<k>.pitch``) and its
actuators' displacements (``actuator<k>.displacement``). Rotor power: the outputs called
``*.power``, when the model has them; hub loads: the main rotor's force and moment on the
airframe (``main_rotor.hub.*``). Angles are shown in degrees, displacements in mm, power in
kW, loads in kN and kN m.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

CONTROL_WORDS = ("collective", "cyclic")
AZIMUTHS = ("main_rotor.azimuth", "azimuth", "main_hub.azimuth", "hub.azimuth")
HINGE = re.compile(r".+\.(flap|lag|teeter)$")
MAX_PLOT_ROWS = 5000


@dataclass
class Panel:
    """One plot panel: ``title`` (with its unit), series ``names`` and ``values`` (n, m) in
    the unit of the title (deg for angles)."""

    title: str
    names: list[str]
    values: np.ndarray


def plot_rows(rec, t0: float, t1: float, limit: int = MAX_PLOT_ROWS) -> np.ndarray:
    """Indices of the recorded rows in [t0, t1] s, every n-th so that at most ``limit`` remain
    (the last row always kept)."""
    rows = np.flatnonzero((rec.t >= t0 - 1e-12) & (rec.t <= t1 + 1e-12))
    stride = max(1, -(-len(rows) // limit))
    keep = rows[::stride]
    return keep if keep[-1] == rows[-1] else np.r_[keep, rows[-1]]


def signal(rec, name: str, rows: np.ndarray) -> np.ndarray:
    """Values (n,) of a state, parameter or output called ``name`` at the recorded ``rows``."""
    info = rec.info
    if name in info.state_names:
        return rec.x[rows, info.state_names.index(name)]
    if name in info.param_names:
        return np.array([rec.params_at(rec.t[r])[info.param_names.index(name)] for r in rows])
    if name in info.output_names:
        return outputs(rec, rows)[:, info.output_names.index(name)]
    raise ValueError(f"{name!r} is neither a state, a parameter nor an output of {info.name}")


def outputs(rec, rows: np.ndarray) -> np.ndarray:
    """Every output (n, ny) at the recorded ``rows``, evaluated once per row and kept on ``rec``."""
    cache = rec.__dict__.setdefault("_outputs", {})
    missing = [int(r) for r in rows if int(r) not in cache]
    for r in missing:
        cache[r] = rec.system.outputs(rec.x[r], rec.t[r], rec.params_at(rec.t[r]))
    return np.array([cache[int(r)] for r in rows])


def input_panels(rec) -> dict[str, list[str]]:
    """Panel title -> names: collective and cyclic pitch inputs apart (the cyclics are small),
    then the other parameters that change during the run."""
    names = rec.info.param_names
    varying = set() if rec.P is None else {n for j, n in enumerate(names) if np.ptp(rec.P[:, j]) > 0}
    shown = [n for n in names if n in varying or any(w in n for w in CONTROL_WORDS)]
    return {"collective pitch (rad)": [n for n in shown if "collective" in n],
            "cyclic pitch (rad)": [n for n in shown if "cyclic" in n],
            "other varying parameters": [n for n in shown if not any(w in n for w in CONTROL_WORDS)]}


def hinge_panels(rec) -> dict[str, list[str]]:
    """Panel title -> names: the scene's plot panels, else the flap, lag and teeter coordinates."""
    if rec.plots:
        return dict(rec.plots)
    out: dict[str, list[str]] = {}
    for name in rec.info.q_names:
        match = HINGE.match(name)
        if match:
            out.setdefault(f"{match.group(1)} (rad)", []).append(name)
    return out


def power_panels(rec) -> dict[str, list[str]]:
    """Panel title -> names: the rotors' aerodynamic shaft power and the engine power (W), if any."""
    return {"rotor and engine power (W)": [n for n in rec.info.output_names if n.endswith(".power")]}


def swashplate_panels(rec) -> dict[str, list[str]]:
    """Panel title -> names: the blade pitch the pitch links set and the swashplate actuators'
    displacements, when the model has a swashplate."""
    names = rec.info.output_names
    return {"blade pitch set by the pitch links (rad)": [n for n in names if re.fullmatch(r"blade\d+\.pitch", n)],
            "swashplate actuator displacements, up (m)": [n for n in names
                                                          if re.fullmatch(r"actuator\d+\.displacement", n)]}


def load_panels(rec) -> dict[str, list[str]]:
    """Panel title -> names: the main rotor's hub force and moment on the airframe (body axes),
    when the model has them."""
    names = rec.info.output_names
    return {title: [f"main_rotor.hub.{kind}_{c}" for c in "xyz"] for kind, title in
            (("force", "main-rotor hub force on the airframe, body axes (N)"),
             ("moment", "main-rotor hub moment on the airframe, body axes (N m)"))
            if f"main_rotor.hub.{kind}_x" in names}


UNITS = {"(rad)": ("(deg)", np.degrees), "(W)": ("(kW)", lambda w: w * 1e-3), "(N)": ("(kN)", lambda f: f * 1e-3),
         "(N m)": ("(kN m)", lambda m: m * 1e-3), "(m)": ("(mm)", lambda x: x * 1e3)}


def panels(rec, rows: np.ndarray) -> list[Panel]:
    """The plot: pitch inputs first (if any), the swashplate's actuators and blade pitch (if
    any), then the hinge-angle panels, rotor power and the main-rotor hub loads; angles in
    degrees, displacements in mm, power in kW, loads in kN and kN m."""
    groups = {**input_panels(rec), **swashplate_panels(rec), **hinge_panels(rec), **power_panels(rec),
              **load_panels(rec)}
    out = []
    for title, names in groups.items():
        if names:
            values = np.column_stack([signal(rec, n, rows) for n in names])
            for unit, (shown, convert) in UNITS.items():
                if title.endswith(unit):
                    title, values = title[:-len(unit)] + shown, convert(values)
            out.append(Panel(title, list(names), values))
    return out


def azimuth_name(info) -> str | None:
    """The main-rotor azimuth among the outputs or states, if the model has one."""
    return next((n for n in AZIMUTHS if n in info.output_names or n in info.state_names), None)


def azimuth(rec, times: np.ndarray) -> np.ndarray | None:
    """Main-rotor azimuth (rad, unwrapped) at ``times`` (s), or None without a main rotor."""
    name = azimuth_name(rec.info)
    if name is None:
        return None
    info = rec.info
    values = []
    for t in times:
        x = rec.state_at(float(t))
        if name in info.state_names:
            values.append(x[info.state_names.index(name)])
        else:
            values.append(rec.system.outputs(x, float(t), rec.params_at(float(t)))[info.output_names.index(name)])
    return np.unwrap(np.asarray(values, dtype=float))
