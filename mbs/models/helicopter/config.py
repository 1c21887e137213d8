"""What a helicopter scene builds (:class:`Config`) and the rotor-aerodynamics switches."""
from __future__ import annotations

from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Config:
    """What a scene builds.

    fuselage: "free" (6 DOF), "clamped" (fixed to the world) or "none" (hub on the world).
    rotors: "driven" (hubs at constant speed, swashplate pitch) or "free" (every driven joint
    replaced by a free hinge; speeds from the initial condition). blades: main-rotor blades
    built, the first ``blades`` of the aircraft's (None: all of them; their azimuths are
    always the aircraft's ``2 pi k / n_blades``). speed: initial forward speed, m/s.

    Rotor aerodynamics switches (README, "Simplifications"): inflow "uniform" (one state per
    rotor) or "pitt-peters" (three states on the main rotor); tip_loss (effective blade radius
    B R on both rotors); compressibility (Prandtl-Glauert lift slope and drag divergence on
    both rotors); tail_wake (the main rotor's wake on the horizontal tail and fin); download
    (the wake's vertical drag on the fuselage); hub_drag (drag of the main-rotor hub). All off:
    the model of the paper's scenes. blade_segments: main-rotor blades as elastic chains of
    that many segments (:mod:`mbs.models.elastic_blade`); blade_modes: main-rotor blades as
    flexible bodies with that many modes per direction (one count, or flap, lag, torsion
    counts; :mod:`mbs.models.modal_blade`); both 0: rigid blades. swashplate: None (the
    blade pitch driven by the pitch inputs), "pitch" (the swashplate and pitch links of the
    aircraft's ``[swashplate]`` set the pitch, the pilot pitch inputs mixed into the plate) or
    "actuators" (the same, the three actuator displacements the controls); loop_solver: how the
    pitch links' loops are solved, "closed-form" or "newton"; pitch_link: "rigid" (the pitch solved
    from each link's loop) or "elastic" (the pitch a state, each link a spring of the aircraft's
    link_stiffness) (:mod:`mbs.models.helicopter.swashplate`).

    The air (:mod:`mbs.models.helicopter.environment`): atmosphere "file" (the aircraft file's
    density and speed of sound) or "isa" (the ISA at the run-time parameters ``altitude``, m,
    and ``temperature_offset``, K, whose defaults are ``altitude`` and ``temperature_offset``);
    wind: None (still air) or the defaults (north, east, down; m/s) of the steady-wind
    parameters ``wind_north``, ``wind_east``, ``wind_down``.

    The rotors' speed (:mod:`mbs.drivetrain`): drive_train None (hubs at the constant speed
    ``omega``), "rigid" (the rotor speed a state: main and tail rotors and the transmission on one
    rigid drive train) or "flexible" (the main shaft a torsion spring between transmission and
    hub); with a drive train, the run-time parameter ``drive_torque`` (N m) drives it, or with
    engines (True) the aircraft's turboshafts and their governor (:mod:`mbs.drivetrain.engine`);
    failure_time: the default of every engine's run-time failure time (s; None: never).

    ground_effect: the main rotor's induced inflow reduced near the ground (Cheeseman and Bennett,
    :mod:`mbs.aero.ground`), the ground plane at the world's ``z`` = the run-time parameter
    ``height`` (m below the world's origin, where the aircraft starts), whose default is ``height``.
    turbulence: None, "dryden" or "von-karman" (MIL-F-8785C, :mod:`mbs.environment.turbulence`);
    gust: a discrete 1 − cosine gust (:mod:`mbs.environment.gust`); both need a free fuselage;
    turbulence_intensity: the default of the run-time ``turbulence_intensity`` (W20, m/s; None:
    moderate, 15.4 m/s). payload: None, or the default of the run-time ``payload`` (kg): weight
    added at the centre of gravity (a free fuselage; its inertia stays the file's: for trims
    and performance at another mass). cg_shift: the run-time ``cg_x``, ``cg_y`` (m): the weight
    acting that far from the file's CG (for trims at another CG position).
    """

    fuselage: str = "free"
    rotors: str = "driven"
    blades: int | None = None
    tail_rotor: bool = True
    rotor_aero: bool = True
    airframe_aero: bool = True
    dampers: bool = True
    shaft_tilt: bool = True
    pitch_hinge: bool = True
    speed: float = 10.0
    elements: int | None = None
    trim: str | None = None  # key of the aircraft's stored trims giving defaults
    inflow: str = "uniform"
    tip_loss: bool = False
    compressibility: bool = False
    tail_wake: bool = False
    download: bool = False
    hub_drag: bool = False
    blade_segments: int = 0
    blade_modes: int | tuple = 0
    swashplate: str | None = None
    loop_solver: str = "closed-form"
    pitch_link: str = "rigid"
    atmosphere: str = "file"
    altitude: float = 0.0
    temperature_offset: float = 0.0
    wind: tuple | None = None
    drive_train: str | None = None
    engines: bool = False
    failure_time: float | None = None
    ground_effect: bool = False
    height: float | None = None
    turbulence: str | None = None
    gust: bool = False
    turbulence_intensity: float | None = None
    payload: float | None = None
    cg_shift: bool = False

    def __post_init__(self):
        from mbs.drivetrain import train
        from mbs.models.helicopter import environment
        from mbs.models.helicopter.swashplate import check
        environment.check(self)
        train.check(self)
        if self.blade_segments and self.blade_modes:
            raise ValueError(f"blade_segments = {self.blade_segments} and blade_modes = {self.blade_modes!r}: an "
                             "elastic blade is either a chain of segments or a modal blade; give one of them")
        check(self)
        needs_rotor = [n for n in ("tail_wake", "download", "tip_loss", "compressibility") if getattr(self, n)]
        needs_rotor += ["inflow"] if self.inflow != "uniform" else []
        if needs_rotor and not self.rotor_aero:
            raise ValueError(f"{needs_rotor[0]} needs the main rotor's aerodynamics, which this scene does not model")
        needs_airframe = [n for n in ("tail_wake", "download", "hub_drag") if getattr(self, n)]
        if needs_airframe and not (self.airframe_aero and self.fuselage == "free"):
            raise ValueError(f"{needs_airframe[0]} acts on the airframe's aerodynamics, which this scene does not model")

    def blade_count(self, n_blades: int) -> int:
        """Main-rotor blades built on a rotor of ``n_blades``; ValueError when asked for more."""
        if self.blades is None:
            return n_blades
        if not 1 <= self.blades <= n_blades:
            raise ValueError(f"blades = {self.blades}: the aircraft's main rotor has {n_blades} blades; build "
                             f"1 to {n_blades} of them (change main_rotor.n_blades in the aircraft file for more)")
        return self.blades


AERO_SWITCHES = {"pitt-peters": ("inflow", "pitt-peters", "uniform"), "tip-loss": ("tip_loss", True, False),
                 "compressibility": ("compressibility", True, False), "tail-wake": ("tail_wake", True, False),
                 "download": ("download", True, False), "hub-drag": ("hub_drag", True, False)}
"""Aerodynamics switches: name -> (Config field, value when on, value when off)."""

FULL = {field: on for field, on, _ in AERO_SWITCHES.values()}
NONE = {field: off for field, _, off in AERO_SWITCHES.values()}


def applicable_switches(cfg: Config) -> list[str]:
    """The switches that apply to a scene configured by ``cfg`` (its rotors and airframe)."""
    def applies(name: str) -> bool:
        field, on, _ = AERO_SWITCHES[name]
        try:
            replace(cfg, **{**NONE, field: on})
        except ValueError:
            return False
        return True
    return [n for n in AERO_SWITCHES if applies(n)]


def aero_switches(scene) -> list[str]:
    """The aerodynamics switches that are on in ``scene``."""
    cfg = replace(config_of(scene), **{k: v for k, v in scene.options.items() if k in NONE})
    return [n for n, (field, on, _) in AERO_SWITCHES.items() if getattr(cfg, field) == on]


def with_aero(scene, switches: str):
    """``scene`` with exactly the aerodynamics switches named in ``switches`` on: comma-separated
    names of :data:`AERO_SWITCHES`, "full" (every switch that applies to the scene) or "none"
    (the paper's model: uniform inflow, no tip loss, compressibility, wake on the airframe,
    download or hub drag)."""
    ok = applicable_switches(config_of(scene))
    if not ok:
        raise ValueError(f"scene {scene.name!r} models no rotor or airframe aerodynamics: no switch applies")
    words = [n.strip() for n in switches.split(",") if n.strip()]
    if not words:
        raise ValueError("no switch named: give comma-separated switches, full or none")
    if len(words) > 1 and ({"full", "none"} & set(words)):
        raise ValueError(f"{next(w for w in words if w in ('full', 'none'))!r} stands alone: give full, none, or "
                         "comma-separated switches")
    twice = sorted({w for w in words if words.count(w) > 1})
    if twice:
        raise ValueError(f"switch {twice[0]!r} is named twice; name each switch once")
    names = ok if words == ["full"] else [] if words == ["none"] else words
    for n in names:
        if n not in AERO_SWITCHES:
            raise ValueError(f"unknown aerodynamics switch {n!r}; known: {', '.join(AERO_SWITCHES)}, full, none")
        if n not in ok:
            raise ValueError(f"aerodynamics switch {n!r} does not apply to scene {scene.name!r}, which models "
                             f"{'only ' + ', '.join(ok) if ok else 'no rotor or airframe aerodynamics'}")
    options = {**NONE, **{AERO_SWITCHES[n][0]: AERO_SWITCHES[n][1] for n in names}}
    return replace(scene, options={**scene.options, **options})


def config_of(scene) -> Config:
    """The :class:`Config` of a helicopter scene; ValueError for other scenes."""
    cfg = getattr(scene.builder, "config", None)
    if cfg is None:
        raise ValueError(f"scene {scene.name!r} is not a helicopter scene: it has no aerodynamics switches")
    return cfg
