"""Closed-form hover figures of an aircraft's rotors: momentum theory with the profile power of
the blade element (Johnson, *Helicopter Theory*, 2.6 and 5.1; Padfield, *Helicopter Flight
Dynamics*, 3.2.1). They give the derived tip-loss factors and the figures of ``heli aircraft
check``; the model's own trim is the accurate answer. SI units.
"""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class RotorHover:
    """One rotor in hover: thrust (N, of the blades), solidity, thrust coefficient, induced velocity
    (m/s), induced and profile power (W), shaft torque (N m), tip speed (m/s), disc loading
    (N/m², of the whole thrust) and, for a fan-in-fin, its duct's thrust (N)."""

    thrust: float
    solidity: float
    thrust_coefficient: float
    induced_velocity: float
    induced_power: float
    profile_power: float
    torque: float
    tip_speed: float
    disc_loading: float
    duct_thrust: float = 0.0

    @property
    def power(self) -> float:
        return self.induced_power + self.profile_power

    @property
    def blade_loading(self) -> float:
        """C_T / σ."""
        return self.thrust_coefficient / self.solidity


@dataclass(frozen=True)
class Hover:
    main: RotorHover
    tail: RotorHover

    @property
    def power(self) -> float:
        return self.main.power + self.tail.power


def profile_drag(sec: dict, alpha):
    """The analytic section's drag polar ``cd0 + cd1 α + cd2 α²`` of the rotor or surface section
    ``sec`` at the angle ``alpha`` (rad, a float or an array; attached flow)."""
    return sec["cd0"] + sec.get("cd1", 0.0) * alpha + sec.get("cd2", 0.0) * alpha**2


def rotor_hover(sec: dict, thrust: float, omega: float, rho: float) -> RotorHover:
    """Hover of the rotor of section ``sec`` at ``thrust`` (N) and rotor speed ``omega`` (rad/s):
    ``v_i = sqrt(T / (2 ρ A))``, ``P_i = κ T v_i``, ``P_0 = ρ A (Ω R)³ σ δ / 8`` with the profile
    drag ``δ = c_d0 + c_d1 ᾱ + c_d2 ᾱ²`` at the mean angle ``ᾱ = 6 C_T / (σ a)`` of the blades'
    ``C_T``. A fan-in-fin (``duct_exit_ratio`` σ_d > 0) shares ``thrust`` with its duct: the blades
    carry ``T / (2 σ_d)`` at ``v_i = sqrt(σ_d T / (ρ A))`` (:func:`mbs.aero.inflow.ducted_fan_thrust`)."""
    radius, ducted = sec["radius"], sec.get("duct_exit_ratio", 0.0)
    area, tip = math.pi * radius**2, omega * radius
    sigma = sec["n_blades"] * sec["chord"] / (math.pi * radius)
    blades = thrust / (2 * ducted) if ducted else thrust
    ct = blades / (rho * area * tip**2)
    v_i = math.sqrt(abs(thrust) * (ducted / (rho * area) if ducted else 1 / (2 * rho * area)))
    delta = profile_drag(sec, 6 * ct / (sigma * sec["lift_slope"]))
    profile = rho * area * tip**3 * sigma * delta / 8
    induced = sec["kappa"] * abs(blades) * v_i
    return RotorHover(blades, sigma, ct, v_i, induced, profile, (induced + profile) / omega, tip, thrust / area,
                      thrust - blades)


def hover(values: dict) -> Hover:
    """Both rotors in hover: the main rotor carries the weight; the tail rotor's thrust balances
    the main rotor's torque about the main-rotor shaft."""
    mr, tr, env = values["main_rotor"], values["tail_rotor"], values["environment"]
    weight = values["aircraft"]["mass"] * env["g"]
    main = rotor_hover(mr, weight, mr["omega"], env["rho"])
    arm = abs(mr["hub_x"] - tr["hub_x"])  # a side force: only the x distance is a lever
    side = main.torque / arm
    thrust = side if tr["cant"] == 0.0 and tr["toe"] == 0.0 else side / (math.cos(tr["cant"]) * math.cos(tr["toe"]))
    tail = rotor_hover(tr, thrust, tr["gear_ratio"] * mr["omega"], env["rho"])
    return Hover(main, tail)


def lock_number(mr: dict, rho: float) -> float:
    """γ = ρ a c R⁴ / I_flap."""
    return rho * mr["lift_slope"] * mr["chord"] * mr["radius"] ** 4 / mr["I_flap"]
