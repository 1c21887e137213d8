"""Rotor loads at the periodic trim: one whole period of every loads output, their means and
their harmonics per revolution.

The periodic solution (:func:`mbs.analysis.trim.periodic_solution`: a trim for a free
fuselage, the periodic rotor response otherwise) is run over the model's whole period
(``full_revs`` main-rotor revolutions, :mod:`mbs.analysis.period`), the model's outputs are
recorded at every step, and :func:`mbs.analysis.signals.periodic_spectrum` gives their exact
Fourier amplitudes: integer orders are harmonics of the main-rotor speed; with a tail rotor
(5.25 times faster) the airframe also carries orders of a quarter revolution (its 2/rev is
10.5/rev of the main rotor).

Hub loads (fixed frame) of ``N_b`` identical blades contain only the orders 0, ``N_b``,
``2 N_b`` … of what the rotor itself makes: the rotor is a filter. Blade loads are in the
rotating frame and contain every harmonic.
"""
from __future__ import annotations

import re
import time
from dataclasses import dataclass

import numpy as np

from mbs.analysis.signals import periodic_spectrum
from mbs.loads.outputs import COMPONENTS

STATION = re.compile(r"^(blade\d+)\.(root|station(\d+))\.moment_y$")
"""A blade station's flap-bending output: the root (``bladeK.root``) or segment ``j``'s joint."""


@dataclass
class RotorLoads:
    """The loads over one whole period of a periodic solution.

    t: (n,) s, equally spaced over ``revs`` main-rotor revolutions of ``revolution`` s;
    names: the outputs; values: (n, ny) in their units; orders: (m,) per main-rotor revolution;
    amplitudes: (m, ny) complex Fourier amplitudes (``A_0`` the mean; phase at azimuth 0);
    n_blades: main-rotor blades; gear: tail-rotor speed per main-rotor speed (None without);
    tail_blades: tail-rotor blades;
    stations: blade-station output prefix (``blade1.root``, ``blade1.station2`` …) -> radius (m).
    """

    scene: str
    speed: float
    revolution: float
    revs: int
    t: np.ndarray
    names: list[str]
    values: np.ndarray
    orders: np.ndarray
    amplitudes: np.ndarray
    n_blades: int
    gear: float | None
    stations: dict[str, float]
    thrust: float | None
    trim_reason: str
    wall_s: float
    tail_blades: int = 2
    aircraft: str | None = None

    @property
    def title(self) -> str:
        """``hover of the MBB Bo105 at 0 m/s``: scene, aircraft and speed."""
        return f"{self.scene}" + (f" of the {self.aircraft}" if self.aircraft else "") + f" at {self.speed:g} m/s"

    def column(self, name: str) -> int:
        if name not in self.names:
            raise KeyError(f"no output {name!r} in the loads of {self.scene}")
        return self.names.index(name)

    def mean(self, name: str) -> float:
        """Period mean of the output ``name``."""
        return float(self.amplitudes[0, self.column(name)].real)

    def harmonic(self, name: str, order: float) -> float:
        """Amplitude of the output ``name`` at ``order`` per main-rotor revolution (0: |mean|)."""
        k = np.flatnonzero(np.isclose(self.orders, order, atol=1e-9))
        if not k.size:
            per_rev = len(self.t) // self.revs
            raise ValueError(f"order {order:g}/rev is not resolved by {self.revs} revolutions of {len(self.t)} samples "
                             f"({per_rev} per revolution resolve orders below {per_rev / 2:g}/rev): give "
                             f"--steps-per-rev {steps_resolving(order)} or more")
        return float(abs(self.amplitudes[k[0], self.column(name)]))

    def largest(self, name: str, keep) -> tuple[float, float]:
        """The order (per revolution) and amplitude of the largest content of ``name`` among
        the orders > 0 for which ``keep(order)`` holds; (None, 0) when there are none."""
        mask = np.array([o > 0 and keep(o) for o in self.orders])
        if not mask.any():
            return None, 0.0
        a = np.abs(self.amplitudes[mask, self.column(name)])
        return float(self.orders[mask][np.argmax(a)]), float(a.max())

    def hub_rows(self, rotor: str = "main_rotor") -> list[dict]:
        """Per hub-load component of ``rotor``: mean, the ``N_b`` and ``2 N_b`` harmonics of the
        rotor's own speed, the largest other harmonic of it (``other``) and the largest content
        at orders that are no harmonic of it (``fractional``: the other rotor's, through the
        airframe). Orders per main-rotor revolution."""
        nb, ratio = (self.n_blades, 1.0) if rotor == "main_rotor" else (self.tail_blades, self.gear or 1.0)
        rows = []
        for c in COMPONENTS:
            name = f"{rotor}.hub.{c}"
            if name in self.names:
                rows.append({"output": name, "mean": self.mean(name),
                             **{f"{m * nb}/rev": self.harmonic(name, m * nb * ratio) for m in (1, 2)},
                             **dict(zip(("other_order", "other"), self.largest(name, lambda o: _other(o, nb, ratio)))),
                             **dict(zip(("fractional_order", "fractional"),
                                        self.largest(name, lambda o: not _integer(o / ratio))))})
        return rows

    def blade_rows(self, harmonics: int = 4) -> list[dict]:
        """Blade 1's root loads (rotating frame): mean and the first ``harmonics`` harmonics."""
        return [{"output": n, "mean": self.mean(n),
                 **{f"{k}/rev": self.harmonic(n, k) for k in range(1, harmonics + 1)}}
                for n in (f"blade1.root.{c}" for c in (*COMPONENTS, "pitch_torque")) if n in self.names]

    def power_rows(self) -> list[dict]:
        """Mean aerodynamic and shaft powers of the rotors and the engine power (W)."""
        keys = ("main_rotor.power", "main_rotor.shaft_power", "tail_rotor.power", "tail_rotor.shaft_power",
                "engine.power")
        return [{"output": k, "mean": self.mean(k), f"{self.n_blades}/rev": self.harmonic(k, self.n_blades)}
                for k in keys if k in self.names]

    def span_rows(self, blade: str = "blade1") -> list[dict]:
        """Per station of ``blade`` (root out): radius, mean and 1/rev of the flap and lag
        bending and torsion moments (N m)."""
        rows = []
        for prefix, radius in sorted(self.stations.items(), key=lambda kv: kv[1]):
            if prefix.split(".")[0] == blade:
                row = {"station": prefix, "radius": radius}
                for what, c in (("flap", "moment_y"), ("lag", "moment_z"), ("torsion", "moment_x")):
                    row[f"{what}_mean"] = self.mean(f"{prefix}.{c}")
                    row[f"{what}_1/rev"] = self.harmonic(f"{prefix}.{c}", 1)
                rows.append(row)
        return rows

    def summary(self) -> dict:
        """Plain-data form (JSON)."""
        rotors = [r for r in ("main_rotor", "tail_rotor") if f"{r}.hub.force_x" in self.names]
        return {"scene": self.scene, "speed": self.speed, "revolution_s": self.revolution, "revs": self.revs,
                "samples": len(self.t), "n_blades": self.n_blades, "thrust": self.thrust,
                "hub": {r: self.hub_rows(r) for r in rotors}, "blade_root": self.blade_rows(),
                "power": self.power_rows(), "span": self.span_rows() if len(self.stations) > self.n_blades else [],
                "means": {n: self.mean(n) for n in self.names}, "trim": self.trim_reason, "wall_s": self.wall_s}


def _integer(x: float) -> bool:
    return abs(x - round(x)) < 1e-9


def _other(order: float, nb: int, ratio: float) -> bool:
    """An integer harmonic of the rotor (speed ``ratio``) that is not a multiple of ``nb``."""
    k = order / ratio
    return _integer(k) and round(k) % nb != 0


def radii(info, hub: str = "main_hub") -> dict[str, float]:
    """Per body below ``hub``: the distance (m) of its joint from the hub's axis with every
    joint at zero (the undeformed rotor), from the bodies' placements."""
    bodies = {b["name"]: b for b in info.bodies}
    place = {hub: (np.zeros(3), np.eye(3))}
    for b in info.bodies:
        if b["parent"] in place and b["name"] not in place:
            p, r = place[b["parent"]]
            place[b["name"]] = (p + r @ np.array(b["at"]), r @ np.array(bodies[b["name"]]["frame"]))
    return {n: float(np.hypot(*p[:2])) for n, (p, _) in place.items() if n != hub}


def stations(info, data=None) -> dict[str, float]:
    """Blade-station output prefix -> radius (m) of its joint on the undeformed rotor (a modal
    blade's stations from the aircraft ``data``: :func:`mbs.models.modal_blade.station_radii`)."""
    r = radii(info) if "main_hub" in info.body_names else {}
    out = {}
    for name in info.output_names:
        m = STATION.match(name)
        if m and r:
            body = m.group(1) if m.group(2) == "root" else f"{m.group(1)}_{m.group(3)}"
            out[name.rsplit(".", 1)[0]] = r[body] if body in r else _modal_radius(data, int(m.group(3)))
    return out


def _modal_radius(data, j: int) -> float:
    from mbs.models.modal_blade import station_radii

    if data is None:
        raise ValueError(f"the radius of a modal blade's station {j} needs the aircraft data")
    return station_radii(data)[j]


def check_scene(scene):
    """The scene (a name or :class:`mbs.scenes.Scene`) if it has loads outputs and a periodic
    solution; ValueError saying which it lacks otherwise (symbolic only: before any compiling)."""
    from mbs import scenes
    from mbs.analysis.period import periodic_scene
    from mbs.analysis.trim import trimmable

    sc = scenes.get(scene) if isinstance(scene, str) else scene
    model = sc.model()
    if not any(STATION.match(n) or ".hub." in n for n in model.outputs):
        raise ValueError(f"scene {sc.name!r} declares no rotor loads outputs (hub or blade root loads; "
                         "mbs.loads.add_joint_loads declares them)")
    free = any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())
    if not trimmable(sc) and (free or "omega" not in model.parameters):
        raise ValueError(f"scene {sc.name!r} has no periodic solution for its loads: they need driven rotors "
                         "and either a trimmable scene or a fuselage that is not free")
    return periodic_scene(sc)


def steps_resolving(order: float) -> int:
    """The fewest steps per revolution (a multiple of 10) whose samples resolve ``order`` per
    revolution (more than two samples per cycle)."""
    return int(np.ceil((2 * order + 1) / 10) * 10)


def highest_order(sc) -> tuple[float, str]:
    """The highest order (per main-rotor revolution) the loads of the scene ``sc`` report, twice
    the blade passage of its main rotor or of its tail rotor, and which it is (words)."""
    from mbs.models.helicopter.config import config_of

    if sc.aircraft is None:
        return 0.0, "no rotor"
    d, cfg = sc.aircraft.data, config_of(sc)
    nb = cfg.blade_count(int(d["main_rotor"]["n_blades"]))
    tr = d["tail_rotor"]
    tail = 2 * tr["n_blades"] * tr["gear_ratio"] if cfg.tail_rotor else 0.0
    if tail > 2 * nb:
        return float(tail), (f"twice the blade passage of the tail rotor: {tr['n_blades']:g} blades at "
                             f"{tr['gear_ratio']:g} times the rotor speed")
    return float(2 * nb), f"twice the blade passage of the main rotor's {nb} blades"


def rotor_loads(scene="forward-flight", speed: float | None = None, steps_per_rev: int | None = None,
                backend: str = "compiled", system=None, stepper=None, progress=None) -> RotorLoads:
    """The loads of ``scene`` (a name or :class:`mbs.scenes.Scene`) at its periodic solution
    at ``speed`` (m/s; default the scene's). ``system``/``stepper`` reuse built evaluators.
    Raises ValueError when the scene has no periodic solution or it does not converge."""
    from mbs.analysis.trim import evaluators, periodic_solution

    start = time.perf_counter()
    sc = check_scene(scene)
    if system is None or stepper is None:
        system, stepper = evaluators(sc, "rk4", backend)
    sol = periodic_solution(sc, speed, steps_per_rev=steps_per_rev, system=system, stepper=stepper,
                            progress=progress)
    if not sol.converged:
        raise ValueError(f"{sc.name} at {sol.speed:g} m/s: no periodic solution ({sol.reason})")
    return _record(sc, sol, system, start)


def _record(sc, sol, system, start: float) -> RotorLoads:
    """Run the periodic solution ``sol`` over its whole period and analyse its outputs."""
    info, per = system.info, sol.period
    n = per.full_revs * sol.steps_per_rev
    traj = system.run(sol.x0, 0.0, per.revolution / sol.steps_per_rev, n, every=1, p=sol.params)
    if not traj.ok:
        raise ValueError(f"{sc.name} at {sol.speed:g} m/s: the run over the period failed: {traj.message}")
    values = system.history("outputs", traj, sol.params)[1:]
    orders, amplitudes = periodic_spectrum(traj.t[1:], values, per.revolution)
    gear = _gear(sc, info)
    n_blades = sum(1 for b in info.bodies if re.fullmatch(r"blade\d+", b["name"]))
    tail_blades = sum(1 for b in info.bodies if re.fullmatch(r"tail_blade\d+", b["name"]))
    return RotorLoads(sc.name, sol.speed, per.revolution, per.full_revs, traj.t[1:], info.output_names, values,
                      orders, amplitudes, n_blades, gear, stations(info, sc.aircraft.data if sc.aircraft else None),
                      sol.thrust, _reason(sol), time.perf_counter() - start, tail_blades,
                      sc.aircraft.name if sc.aircraft else None)


def _reason(sol) -> str:
    """How the periodic solution converged and, when the tail rotor turns at a nearby ratio, which."""
    gear = sol.period.gear
    return sol.reason if gear is None or gear.exact else f"{sol.reason}; approximation: {gear.text()}"



def _gear(sc, info) -> float | None:
    """The tail rotor's speed per main-rotor speed, from the scene's aircraft (None without a tail rotor)."""
    if "tail_rotor.azimuth" not in info.output_names or sc.aircraft is None:
        return None
    return float(sc.aircraft.data["tail_rotor"]["gear_ratio"])
