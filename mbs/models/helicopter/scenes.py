"""The helicopter scenes: each a :class:`Config` of what to build, for any aircraft.

They are registered with the packaged Bo105; ``scene.with_aircraft(aircraft)`` (``heli ...
--aircraft FILE``) gives the same scene of another aircraft.
"""
from __future__ import annotations

from dataclasses import replace

from mbs import aircraft as ac
from mbs.models.helicopter.build import build
from mbs.models.helicopter.config import FULL, Config
from mbs.models.helicopter.panels import config_plots
from mbs.scenes import Scene, register


def _builder(cfg: Config, name: str):
    def make(aircraft=None, **options):
        aircraft = aircraft or ac.load()
        return build(replace(cfg, **options), aircraft, name=f"{aircraft.key}-{name}")
    make.config = cfg
    return make


SCENE_CONFIGS = {
    "structural": (Config(rotors="free", rotor_aero=False, airframe_aero=False, dampers=False),
                   "the paper's conservative case: free fuselage, free hubs spinning from the initial "
                   "condition, free pitch hinges, no aerodynamics, no dampers", True),
    "forward-flight": (Config(speed=10.0, trim="forward-flight", **FULL),
                       "the paper's aeromechanic case: free flight at 10 m/s with blade-element rotors (Pitt-Peters "
                       "inflow, tip loss, compressibility), lag dampers, fuselage, hub and empennage loads in the rotor's "
                       "wake; heli simulate starts it from its periodic trim (stored per aircraft file, or trimmed and "
                       "stored on first use)", False),
    "hover": (Config(speed=0.0, trim="hover", **FULL), "as forward-flight, at zero speed", False),
    "ground-run": (Config(fuselage="clamped", airframe_aero=False, speed=0.0, trim="hover",
                          **{k: v for k, v in FULL.items() if k not in ("tail_wake", "download", "hub_drag")}),
                   "fuselage clamped to the ground, both rotors with aerodynamics (Pitt-Peters inflow, tip loss, "
                   "compressibility) and dampers, hover controls (a stored hover trim's, else the closed-form "
                   "estimate's)", False),
    "single-blade": (Config(fuselage="none", blades=1, tail_rotor=False, rotor_aero=False, airframe_aero=False,
                            dampers=False, shaft_tilt=False, pitch_hinge=False),
                     "hub clamped and driven (vertical shaft), one blade on flap and lag hinges with springs, "
                     "no aerodynamics: for frequency checks", False),
    "forward-flight-swashplate": (Config(speed=10.0, trim="forward-flight", swashplate="pitch", **FULL),
                                  "as forward-flight, the blade pitch set by the swashplate and pitch links (local "
                                  "loops solved in the generated code) from the pilot pitch inputs; pitch-link and "
                                  "actuator loads as outputs", False),
    "forward-flight-actuators": (Config(speed=10.0, trim="forward-flight", swashplate="actuators", **FULL),
                                 "as forward-flight-swashplate, the three swashplate actuator displacements (m) "
                                 "the controls", False),
    "single-blade-aero": (Config(fuselage="none", blades=1, tail_rotor=False, airframe_aero=False, dampers=False,
                                 shaft_tilt=False, speed=0.0),
                          "hub clamped and driven (vertical shaft), one blade on flap, lag and driven pitch "
                          "hinges with blade-element aerodynamics and uniform dynamic inflow, in hover: for the "
                          "Lock-number check of the flap mode", False),
}

DRIVE_TRAIN_CONFIGS = {
    "engine-failure": (Config(speed=0.0, trim="hover", drive_train="rigid", engines=True, failure_time=1.0, **FULL),
                       "as hover, the rotor speed a state: main and tail rotors and the transmission on one drive "
                       "train driven by the aircraft's engines and their governor (the Bo105's two turboshafts); "
                       "every engine fails at 1 s (the run-time engine<k>_failure_time; one for one engine "
                       "inoperative), pilot inputs held or from --inputs; started from its governed trim"),
    "engine-failure-cruise": (Config(speed=50.0, drive_train="rigid", engines=True, failure_time=1.0, **FULL),
                              "as engine-failure, at 50 m/s"),
    "hover-engines": (Config(speed=0.0, trim="hover", drive_train="rigid", engines=True, atmosphere="isa",
                             wind=(0.0, 0.0, 0.0), turbulence="dryden", turbulence_intensity=0.0, gust=True, **FULL),
                      "as hover, the rotor speed a state on the drive train with the aircraft's engines and their "
                      "governor (the Bo105's two turboshafts), in the ISA (altitude, temperature offset), a steady wind, Dryden turbulence (calm "
                      "by default: turbulence_intensity 0) and a discrete gust (none by default): the FMU's scene "
                      "for engine failures and turbulence"),
    "autorotation": (Config(speed=30.0, drive_train="rigid", **FULL),
                     "free flight at 30 m/s, the rotor speed a state, no engine (free-wheeling drive train: "
                     "drive_torque 0): the steady autorotation that 'heli autorotation' trims"),
}

ELASTIC_ROTOR = Config(fuselage="none", tail_rotor=False, airframe_aero=False, shaft_tilt=False, speed=0.0,
                       trim="hover", blade_segments=8)
ELASTIC_TEXT = ("hub clamped and driven (vertical shaft), the main rotor's blades elastic, 8 segments each on flap, "
                "lag and torsion hinges with springs (the aircraft's first blade frequencies: 1.117, 0.68 and 3.7/rev "
                "for the Bo105), blade-element aerodynamics with uniform dynamic inflow, hover controls (as ground-run); RK4 at 300 "
                "steps per revolution (at 200 the step check finds the tip segments' lag rates 3 % off)")

ELASTIC_ROTOR_MODAL = replace(ELASTIC_ROTOR, blade_segments=0, blade_modes=(2, 2, 2))
MODAL_TEXT = ("as elastic-rotor, the blades flexible bodies with modal coordinates: 2 flap, 2 lag and 2 torsion modes "
              "each (the blade's own rotating modes: 1.117, 3.33, 0.68, 4.16, 3.7 and 10.7/rev for the Bo105), the "
              "centrifugal stiffening from the kinematics; RK4 at 120 steps per revolution (the step check finds the "
              "second torsion mode 1.2 % off at 100)")


def _register() -> None:
    bo105 = ac.load()
    n = bo105.data["main_rotor"]["n_blades"]
    for name, (cfg, text, conservative) in SCENE_CONFIGS.items():
        register(Scene(name, text, _builder(cfg, name), omega=bo105.omega, conservative=conservative,
                       plots=config_plots(cfg, n), aircraft=bo105))
    for name, (cfg, text) in DRIVE_TRAIN_CONFIGS.items():
        register(Scene(name, text, _builder(cfg, name), omega=bo105.omega, plots=config_plots(cfg, n),
                       aircraft=bo105))
    register(Scene("elastic-rotor", ELASTIC_TEXT, _builder(ELASTIC_ROTOR, "elastic-rotor"), omega=bo105.omega,
                   steps_per_rev=300, plots=config_plots(ELASTIC_ROTOR, n), aircraft=bo105))
    register(Scene("elastic-rotor-modal", MODAL_TEXT, _builder(ELASTIC_ROTOR_MODAL, "elastic-rotor-modal"),
                   omega=bo105.omega, steps_per_rev=120, plots=config_plots(ELASTIC_ROTOR_MODAL, n), aircraft=bo105))


_register()
