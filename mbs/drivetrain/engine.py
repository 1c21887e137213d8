"""Turboshaft engines and their rotor-speed governor, as flight simulation models them.

After G.D. Padfield, *Helicopter Flight Dynamics*, 2nd ed., §3.2.7: the engine's torque lags
the fuel flow, and a governor meters the fuel from the rotor speed's error through a lead-lag
compensation, with droop and collective anticipation. Per engine ``k`` (powers as fractions of
the take-off rating ``P_TO``, speeds of the transmission referred to the main rotor):

* governor (one for all engines): speed error ``e = (Ω_ref − Ω)/Ω_ref`` through
  ``(1 + τ_lead s)/(1 + τ_lag s)``, demand ``d = e_c / droop + K_θ (θ0 − θ0_min)``;
* limits: ``d_k`` held within ``[0, throttle_k · L_k]``, ``L_k`` the
  rating in force over ``P_TO``: take-off power, its share of the gearbox limit while every
  engine runs, the one-engine-inoperative rating once another has failed; every rating lapses
  with the air as ``δ / θ^n`` (``n`` the file's ``lapse_temperature``); a piston engine's
  ratings, derated below its full-throttle power ``P_FT``, hold to the altitude where ``P_FT``
  lapsing as ``1.132 σ − 0.132`` (Gagg and Ferrar's law of a normally aspirated engine, ``σ =
  δ/θ``) falls to them, then follow it;
* fuel flow ``τ_f ẇ_k = d_k − w_k`` (zero demand after the engine's failure time: a flame-out);
* gas generator ``τ_g ε̇_k = w_k − ε_k``; shaft power ``P_k = ε_k P_TO``.

The rotors get ``η (Σ P_k − P_acc)`` (the file's transmission efficiency and accessory power,
as :class:`mbs.loads.engine.Engine` states them) as a torque on the transmission's coordinate,
power over its speed (floored smoothly at 5 % of ``Ω_ref`` so a stopped rotor takes a finite
torque). States ``governor.lead`` and ``engine<k>.fuel``, ``engine<k>.power`` (fractions);
run-time parameters ``governor_speed`` (rad/s, ``Ω_ref``), ``engine<k>_throttle`` (a control,
0 to 1) and ``engine<k>_failure_time`` (s; the default, 1e6 s, is never).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from mbs.forces import ForceElement

NEVER = 1e6  # s: the default failure time (no failure in any run of the scenes)
SPEED_FLOOR = 0.05  # of the governed speed: the smooth floor of the speed dividing the power


@dataclass(frozen=True)
class Turboshaft:
    """The engines of an aircraft file's ``[engine]`` section (SI; see :mod:`mbs.aircraft.schema`)."""

    count: int
    takeoff_power: float
    max_continuous_power: float
    oei_power: float
    transmission_power: float
    lapse_temperature: float
    gas_generator_time_constant: float
    fuel_time_constant: float
    governor_droop: float
    anticipation: float
    governor_lead: float
    governor_lag: float
    efficiency: float
    accessory_power: float
    kind: str = "turboshaft"  # or "piston"
    full_throttle_power: float = 0.0  # W: a piston engine's at sea level, ISA

    @classmethod
    def of(cls, d) -> "Turboshaft":
        """From the aircraft data ``d``; ValueError when it has no turboshaft engines."""
        e = d["engine"]
        if e.get("model") not in ("turboshaft", "piston"):
            raise ValueError("the aircraft file's [engine] has no engine model (model = \"turboshaft\" or "
                             "\"piston\" with its ratings, time constants and governor): a scene with engines needs it")
        keys = [k for k in cls.__dataclass_fields__ if k not in ("efficiency", "accessory_power", "kind",
                                                                  "lapse_temperature", "full_throttle_power")]
        return cls(**{k: e[k] for k in keys}, lapse_temperature=e.get("lapse_temperature", 0.0),
                   efficiency=e["transmission_efficiency"], accessory_power=e["accessory_power"], kind=e["model"],
                   full_throttle_power=e.get("full_throttle_power", 0.0))

    def lapse(self, delta, theta):
        """A turboshaft's power available at the air's pressure ratio ``delta`` and temperature
        ratio ``theta`` over the sea-level rating."""
        return delta / theta**self.lapse_temperature

    def available(self, rating, delta, theta):
        """The power (W) a ``rating`` (W, sea level ISA) gives in the air of ``delta`` and ``theta``:
        a turboshaft's lapsed, a piston engine's held to its full-throttle power's lapse."""
        if self.kind != "piston":
            return rating * self.lapse(delta, theta)
        full = self.full_throttle_power * (1.132 * delta / theta - 0.132)
        return 0.5 * (rating + full - ca.fabs(rating - full)) if isinstance(full, (ca.SX, ca.MX)) \
            else min(rating, full)


def names(k: int) -> tuple[str, str]:
    """State names of engine ``k`` (1-based): fuel flow and power (fractions of take-off power)."""
    return f"engine{k}.fuel", f"engine{k}.power"


def add_parameters(m, eng: Turboshaft, omega: float, failure_time: float | None = None) -> None:
    """The governor's reference speed (rad/s), each engine's throttle (a control) and failure time
    (default ``failure_time`` s, else never)."""
    if failure_time is not None and not 0 <= failure_time < NEVER:
        raise ValueError(f"failure_time = {failure_time} s must lie in [0, {NEVER:g}) s")
    m.add_parameter("governor_speed", omega, "rad/s", "rotor speed the governor holds (at zero load; it droops "
                    "below it under load)", low=0.5 * omega, high=1.2 * omega)
    for k in range(1, eng.count + 1):
        m.add_parameter(f"engine{k}_throttle", 1.0, "1", f"engine {k}'s power lever: 1 flight (governed up to the "
                        "rating in force), 0 fuel off; between, a proportionally lower power limit", control=True,
                        low=0.0, high=1.0)
        m.add_parameter(f"engine{k}_failure_time", NEVER if failure_time is None else failure_time, "s", f"time at which engine {k} fails (fuel cut, it spools "
                        f"down); {NEVER:g} s: never", low=0.0, high=NEVER)


class Engines(ForceElement):
    """The turboshafts' dynamics and their torque on the transmission's ``coordinate``, driving
    the rotors in their ``sense``; ``collective_min`` (rad) the anticipation's zero."""

    def __init__(self, eng: Turboshaft, coordinate: str, sense: int, collective_min: float, air_ratios):
        self.name, self.eng, self.coordinate, self.sense = "turboshaft engines", eng, coordinate, sense
        self.collective_min, self.air_ratios = collective_min, air_ratios
        self.states = ["governor.lead"] + [n for k in range(1, eng.count + 1) for n in names(k)]

    def speed(self, state):
        """The transmission's speed (rad/s, in the rotors' sense)."""
        return self.sense * state.v(self.coordinate + "_rate")

    def demand(self, state):
        """The governor's demand (fraction of take-off power, every engine) before the limits."""
        eng, p = self.eng, state.p
        error = (p["governor_speed"] - self.speed(state)) / p["governor_speed"]
        ratio = eng.governor_lead / eng.governor_lag
        compensated = ratio * error + state.z("governor.lead")
        return compensated / eng.governor_droop + eng.anticipation * (p["collective"] - self.collective_min), error

    def limits(self, state) -> list:
        """Each engine's power limit (fraction of take-off power) with its throttle."""
        eng, p, t = self.eng, state.p, state.t
        delta, theta = self.air_ratios(state)
        failed = [t >= p[f"engine{k}_failure_time"] for k in range(1, eng.count + 1)]
        running = sum(1 - f for f in failed)
        all_run = eng.available(eng.takeoff_power, delta, theta)
        shared = eng.transmission_power / eng.count
        normal = ca.fmin(all_run, shared) / eng.takeoff_power
        oei = eng.available(eng.oei_power, delta, theta) / eng.takeoff_power
        rating = ca.if_else(running < eng.count, oei, normal)
        return [p[f"engine{k}_throttle"] * rating * (1 - failed[k - 1]) for k in range(1, eng.count + 1)]

    def apply(self, state, loads):
        eng = self.eng
        demand, error = self.demand(state)
        loads.set_rate("governor.lead", ((1 - eng.governor_lead / eng.governor_lag) * error
                                         - state.z("governor.lead")) / eng.governor_lag)
        total = 0
        for k, limit in enumerate(self.limits(state), start=1):
            fuel, power = names(k)
            command = ca.fmin(ca.fmax(demand, 0), limit)
            loads.set_rate(fuel, (command - state.z(fuel)) / eng.fuel_time_constant)
            loads.set_rate(power, (state.z(fuel) - state.z(power)) / eng.gas_generator_time_constant)
            total = total + state.z(power)
        shaft = eng.efficiency * (eng.takeoff_power * total - eng.accessory_power)
        floor = SPEED_FLOOR * state.p["governor_speed"]
        omega = self.speed(state)
        torque = shaft * omega / (omega**2 + floor**2)
        state.signals["engines.torque"] = torque
        loads.add_generalized(self.coordinate + "_rate", self.sense * torque)



def add_outputs(m, element: Engines) -> None:
    """Per engine its power (W), torque at rotor speed (N m) and margins to each rating (W);
    the torque the engines put on the transmission and the governor's demand."""
    eng = element.eng
    for k in range(1, eng.count + 1):
        _, power = names(k)
        m.add_output(f"engine{k}.power", lambda s, z=power: eng.takeoff_power * s.z(z), "W",
                     f"engine {k}'s shaft power")
        m.add_output(f"engine{k}.torque", lambda s, z=power: eng.takeoff_power * s.z(z) / element.speed(s), "N m",
                     f"engine {k}'s torque referred to the rotor speed")
        for what, rating in (("takeoff", eng.takeoff_power), ("max_continuous", eng.max_continuous_power),
                             ("oei", eng.oei_power)):
            m.add_output(f"engine{k}.{what}_margin",
                         lambda s, z=power, r=rating, k=k: (1 - (s.t >= s.p[f"engine{k}_failure_time"]))
                         * (eng.available(r, *element.air_ratios(s)) - eng.takeoff_power * s.z(z)),
                         "W", f"engine {k}'s {what.replace('_', ' ')} rating at the air's conditions minus its power "
                         "(none once the engine has failed: it has no rating left)")
    m.add_output("engines.torque", lambda s: s.signals["engines.torque"], "N m",
                 "the engines' torque on the transmission (after the accessories and transmission losses)")
    m.add_output("governor.demand", lambda s: element.demand(s)[0], "1",
                 "the governor's fuel demand before the limits, fraction of an engine's take-off power")
