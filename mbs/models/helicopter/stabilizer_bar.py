"""A stabilizer bar (flybar): a teetering bar on the main-rotor hub, 90 deg ahead of blade 1 in
the sense of rotation, with aerofoil paddles at its ends (Hiller) and dampers on its hinge (Bell).

The bar is a body on the hub (``stabilizer_bar.teeter``, end A up positive: the end 90 deg ahead
of blade 1). Its paddles are pitched by the swashplate's cyclic at their own azimuth, times
``paddle_gain``. The blades' pitch is the mixer's, a dependent coordinate of the bar's teeter:

    θ_k = θ0 + bell_gain (θ1c cos ψ_k + θ1s sin ψ_k) + hiller_gain cos(ψ_k - ψ_1) β_bar

so a bar tilted back (its end A, over the advancing side, low ahead of it) gives the blades the
cyclic that tilts their disc back too: the rotor follows the bar, which holds its plane in space
as a gyroscope and is brought round by its paddles' lift (time constant ``2 I / (ρ a S Ω r³)``
for two paddles of area ``S`` at radius ``r``, :func:`time_constant`). The paddles fly in the
free stream and the hub's motion (no main-rotor inflow: a teetering bar's two ends share it).
Units SI, angles in rad.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aero.empennage import TailSurface
from mbs.aero.sections import Airfoil
from mbs.aircraft import geometry as geo
from mbs.aircraft import mass
from mbs.joints import Hinge

BAR = "stabilizer_bar"
PADDLE_STALL = 0.25  # rad: the paddles' stall angle (a thin flat aerofoil's, about 14 deg)
CD_STALLED = 1.2  # the paddles' drag coefficient beyond their stall (a flat plate's)
AXIAL = mass.BAR_AXIAL


def has_stabilizer_bar(d) -> bool:
    """Whether the aircraft data ``d`` give a ``[stabilizer_bar]``."""
    return "hiller_gain" in (d.get("stabilizer_bar") or {})


def aero_damping(bar: dict, omega: float, rho: float) -> float:
    """The paddles' damping of the teeter, ``ρ a S Ω r³`` (N m s/rad): both paddles' lift per
    teeter rate at their radius, in hover (the free stream's ``Ω r`` over them)."""
    return rho * bar["paddle_lift_slope"] * bar["paddle_area"] * omega * bar["paddle_radius"] ** 3


def hinge_damping(bar: dict, omega: float, rho: float) -> float:
    """The damping on the bar's hinge (N m s/rad): the file's, or from its published time constant
    ``τ`` the rest of ``2 I / τ`` after the paddles' (negative when they alone damp it faster)."""
    if not bar["time_constant"]:
        return bar["damping"]
    return 2 * bar["inertia"] / bar["time_constant"] - aero_damping(bar, omega, rho)


def time_constant(bar: dict, omega: float, rho: float) -> float:
    """The bar's response time (s) to cyclic or to the hub's tilt in hover: ``2 I / (c_a + c)``,
    the decay of its 1/rev teeter in the rotating frame under the paddles' damping ``c_a``
    (:func:`aero_damping`) and its hinge's ``c`` (:func:`hinge_damping`)."""
    damping = aero_damping(bar, omega, rho) + hinge_damping(bar, omega, rho)
    return 2 * bar["inertia"] / damping if damping > 0 else np.inf


def cyclic_gain(bar: dict, omega: float, rho: float) -> float:
    """Blade cyclic per swashplate cyclic in steady hover (rad/rad): the direct path and the
    bar's, which tilts by ``paddle_gain`` times the cyclic, less the share its hinge's damping takes
    (the 1/rev teeter at resonance: tilt = paddle_gain c_a / (c_a + c) per rad)."""
    aero, hinge = aero_damping(bar, omega, rho), hinge_damping(bar, omega, rho)
    share = aero / (aero + hinge) if aero + hinge > 0 else 0.0
    return bar["bell_gain"] + bar["hiller_gain"] * bar["paddle_gain"] * share


def mixer(d, psi0: float, azimuth):
    """The pitch law of the blade at ``psi0`` (rad from blade 1, in the sense of rotation):
    ``fn(q, t, p)``, ``azimuth(q, t, p)`` the hub's azimuth in the sense of rotation (rad)."""
    bar = d["stabilizer_bar"]

    def pitch(q, t, p):
        psi = azimuth(q, t, p) + psi0
        cyclic = p["lateral_cyclic"] * ca.cos(psi) + p["longitudinal_cyclic"] * ca.sin(psi)
        return p["collective"] + bar["bell_gain"] * cyclic + bar["hiller_gain"] * np.cos(psi0) * q[f"{BAR}.teeter"]
    return pitch


def add_stabilizer_bar(m, d, cfg, sense: int) -> None:
    """The bar on ``main_hub`` 90 deg ahead of blade 1, and its paddles when the scene has rotor
    aerodynamics."""
    bar = d["stabilizer_bar"]
    frame = geo.rz(sense * np.pi / 2)
    span = 2 * bar["paddle_radius"]
    part = mass.stabilizer_bar(d)
    damping = hinge_damping(bar, d["main_rotor"]["omega"], d["environment"]["rho"]) if cfg.dampers else 0.0
    m.add_body(BAR, "main_hub", Hinge((0, -1, 0), name="teeter", damping=damping),
               mass=part.mass, com=part.com, inertia=part.inertia, frame=frame,
               at=np.array([0.0, 0.0, bar["height"]]),
               shape={"kind": "box", "size": [span, 0.2 * bar["paddle_radius"], 0.02 * span], "color": "#50565e"})
    if cfg.rotor_aero and bar["paddle_area"] > 0:
        section = Airfoil(bar["paddle_lift_slope"], bar["paddle_cd0"], 0.0, PADDLE_STALL, CD_STALLED, 0.0)
        for end, side in (("A", 1.0), ("B", -1.0)):
            m.add_force(Paddle(f"{BAR} paddle {end}", BAR, (side * bar["paddle_radius"], 0.0, 0.0),
                               (0.0, side * sense, 0.0), (0.0, 0.0, 1.0), 0.0, bar["paddle_area"], section,
                               d["environment"]["rho"], azimuth=np.pi / 2 if side > 0 else 3 * np.pi / 2,
                               gain=bar["paddle_gain"], hub=hub_azimuth(cfg, sense)))


def add_stabilizer_bar_outputs(m, d, cfg) -> None:
    """Each blade's pitch as the mixer sets it, and each paddle's incidence (rad)."""
    if not cfg.pitch_hinge:
        return
    for k in range(cfg.blade_count(d["main_rotor"]["n_blades"])):
        m.add_output(f"blade{k + 1}.pitch", lambda s, k=k: s.q(f"blade{k + 1}.pitch"), "rad",
                     f"blade {k + 1}'s pitch as the stabilizer bar's mixer sets it, nose up")
    if cfg.rotor_aero and d["stabilizer_bar"]["paddle_area"] > 0:
        for end in "AB":
            m.add_output(f"{BAR}.paddle_{end}_pitch", lambda s, e=end: s.signals[f"{BAR} paddle {e}.incidence"], "rad",
                         f"paddle {end}'s pitch (the swashplate's cyclic at its azimuth times paddle_gain)")


def hub_azimuth(cfg, sense: int):
    """``fn(q, t, p)``: the main hub's azimuth (rad) in the sense of rotation: its coordinate when
    it is a state (a drive train, free rotors), else ``Ω t``."""
    if cfg.rotors == "driven" and not cfg.drive_train:
        return lambda q, t, p: p["omega"] * t
    return lambda q, t, p: sense * q["main_hub.azimuth"]


class Paddle(TailSurface):
    """A paddle of the bar: a tail-surface section whose incidence is the swashplate's cyclic at its
    azimuth (``azimuth`` rad from blade 1 in the sense of rotation) times ``gain``; ``hub`` the
    hub's azimuth (:func:`hub_azimuth`). Signal ``<name>.incidence`` (rad)."""

    def __init__(self, *args, azimuth: float, gain: float, hub, **kw):
        super().__init__(*args, **kw)
        self.azimuth, self.gain, self.hub = azimuth, gain, hub

    def _incidence(self, state, m):
        psi = self.hub(_Coordinates(state), state.t, state.p) + self.azimuth
        incidence = self.gain * (state.p["lateral_cyclic"] * ca.cos(psi) + state.p["longitudinal_cyclic"] * ca.sin(psi))
        state.signals[f"{self.name}.incidence"] = incidence
        return incidence


class _Coordinates:
    """``q[name]`` of a force element's state, as a dependent coordinate's law reads it."""

    def __init__(self, state):
        self.state = state

    def __getitem__(self, name: str):
        return self.state.q(name)
