"""Controls and attitudes for steady level flight from momentum and blade-element theory."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mbs.aero import momentum_inflow
from mbs.aircraft.derived import flap_frequency
from mbs.aircraft.performance import profile_drag
from mbs.models.helicopter.frames import main_sense
from mbs.models.helicopter.stabilizer_bar import cyclic_gain, has_stabilizer_bar


@dataclass
class TrimEstimate:
    """Controls and attitudes for steady level flight from momentum and blade-element theory.

    Angles in rad: collective (at the root, r = 0), cyclics (the swashplate's: with a stabilizer
    bar, the blades' over its hover gain; Padfield: θ1s > 0 tilts the disc
    back, θ1c > 0 towards ψ = 180° + 90°; both in the azimuth ψ counted in the rotor's sense of
    rotation), tail collective, fuselage pitch and roll, coning, flapping relative to the
    shaft; inflow velocities in m/s; tail-rotor thrust in N.
    """

    speed: float
    collective: float
    lateral_cyclic: float
    longitudinal_cyclic: float
    tail_collective: float
    pitch: float
    roll: float
    coning: float
    a1s: float
    inflow_main: float
    inflow_tail: float
    tail_thrust: float
    power: float = 0.0  # W: the main rotor's shaft power (its torque times the rotor speed)


def _fuselage_drag(d, speed: float) -> float:
    """Fuselage drag (N) at zero angle of attack and sideslip."""
    from mbs.aircraft.airframe_data import drag_area

    return drag_area(d) * 0.5 * d["environment"]["rho"] * speed**2


def estimate_trim(d, speed: float) -> TrimEstimate:
    """Classical closed-form estimates (uniform inflow, linear twist, small angles) for the
    aircraft data ``d`` at ``speed`` (m/s)."""
    mr, tr, env = d["main_rotor"], d["tail_rotor"], d["environment"]
    weight = d["aircraft"]["mass"] * env["g"]
    rho, big_r, omega = env["rho"], mr["radius"], mr["omega"]
    tip, area = omega * big_r, np.pi * big_r**2
    sigma = mr["n_blades"] * mr["chord"] / (np.pi * big_r)
    drag = _fuselage_drag(d, speed)
    drag += 0.5 * rho * d["hub_drag"]["flat_plate_area"] * speed**2
    tilt = drag / weight
    ct, mu = weight / (rho * area * tip**2), speed / tip
    lam_i = momentum_inflow(weight, rho, big_r, speed, speed * tilt) / tip
    lam = mu * tilt + mr["kappa"] * lam_i
    theta0 = (2 * ct / (sigma * mr["lift_slope"]) - mr["twist"] / 4 * (1 + mu**2) + lam / 2) / (1 / 3 + mu**2 / 2) \
        + mr.get("zero_lift_angle", 0.0)
    lock = rho * mr["lift_slope"] * mr["chord"] * big_r**4 / mr["I_flap"]
    nu2 = flap_frequency(mr) ** 2
    coning = lock / (8 * nu2) * (theta0 * (1 + mu**2) + 0.8 * mr["twist"] * (1 + 5 / 6 * mu**2) - 4 / 3 * lam) \
        + mr["flap_stiffness"] * mr.get("precone", 0.0) / (mr["I_flap"] * omega**2 * nu2)
    blowback = 2 * mu * (4 / 3 * theta0 + mr["twist"] - lam) / (1 - mu**2 / 2)
    e = mr["flap_hinge_offset"]
    hub_spring = mr["flap_stiffness"] + e * mr["blade_mass"] * (big_r - e) / 2 * omega**2  # per blade, N m/rad
    springs = mr["flap_stiffness"] / 2 if mr.get("hub_type") == "teetering" else mr["n_blades"] / 2 * hub_spring
    hub_moment_tilt = weight * -mr["hub_x"] / (springs - weight * mr["hub_z"])
    cl_mean = 6 * ct / sigma
    delta = profile_drag(mr, cl_mean / mr["lift_slope"])
    torque = rho * area * tip**2 * big_r * (ct * lam + sigma * delta / 8 * (1 + 3 * mu**2))
    side = torque / (mr["hub_x"] - tr["hub_x"])
    t_thrust = side if tr["cant"] == 0.0 and tr["toe"] == 0.0 else side / (np.cos(tr["cant"]) * np.cos(tr["toe"]))
    theta_t, v_tail = _tail_collective(d, t_thrust, speed)
    roll = -main_sense(d) * side / weight  # the main rotor leans against the tail rotor's side force
    gain = cyclic_gain(d["stabilizer_bar"], omega, rho) if has_stabilizer_bar(d) else 1.0
    return TrimEstimate(speed, theta0, 0.0, (hub_moment_tilt - blowback) / gain, theta_t,
                        mr["shaft_tilt"] - (tilt + hub_moment_tilt), roll, coning,
                        hub_moment_tilt, lam_i * tip, v_tail, t_thrust, torque * omega)


def _tail_collective(d, thrust: float, speed: float) -> tuple[float, float]:
    tr, rho = d["tail_rotor"], d["environment"]["rho"]
    omega_t = tr["gear_ratio"] * d["main_rotor"]["omega"]
    tip = omega_t * tr["radius"]
    sigma = tr["n_blades"] * tr["chord"] / (np.pi * tr["radius"])
    ducted = tr.get("duct_exit_ratio", 0.0)
    if ducted:  # the fan's share and inflow of the axial-flow duct (mbs.aero.inflow.ducted_fan_thrust)
        v = float(np.sqrt(abs(thrust) * ducted / (rho * np.pi * tr["radius"] ** 2)))
        thrust = thrust / (2 * ducted)
    else:
        v = momentum_inflow(thrust, rho, tr["radius"], speed)
    ct, mu = thrust / (rho * np.pi * tr["radius"] ** 2 * tip**2), speed / tip
    theta = (2 * ct / (sigma * tr["lift_slope"]) + tr["kappa"] * v / tip / 2) / (1 / 3 + mu**2 / 2)
    return theta + tr.get("zero_lift_angle", 0.0), v


def flap_start(d, blades: int, coning: float, a1s: float, omega: float) -> dict[str, float]:
    """Start values of the main rotor's flap coordinates for the flapping ``β_k = β0 − a1s cos ψ_k``
    (rad; ψ_k the blade's azimuth at t = 0): per blade on a flapping hub (the first ``blades``),
    the seesaw's teeter (blade 1's, less the precone) on a teetering one."""
    mr = d["main_rotor"]
    if mr.get("hub_type") == "teetering":
        return {"main_seesaw.teeter": -a1s, "main_seesaw.teeter_rate": 0.0}
    out = {}
    for k, psi in enumerate(2 * np.pi * np.arange(mr["n_blades"]) / mr["n_blades"]):
        if k < blades:
            out.update({f"blade{k + 1}.flap": coning - a1s * np.cos(psi),
                        f"blade{k + 1}.flap_rate": a1s * omega * np.sin(psi)})
    return out

