"""The hinge-angle panels of a helicopter scene's plot (``hinge_angles.png``): flap and lag of
the main-rotor blades, the tail rotor's teeter or flap, the rotor speed on a drive train; for a
scene's config (:func:`config_plots`) and, for another aircraft, from its data (:func:`plots`).
"""
from __future__ import annotations

from mbs.models.helicopter.config import Config, config_of


def config_plots(cfg: Config, n_blades: int) -> dict:
    """The hinge-angle panels of a scene of ``cfg`` on a rotor of ``n_blades`` (panel title ->
    coordinates or outputs)."""
    blades = range(cfg.blade_count(n_blades))
    panels = {"main-rotor flap (rad)": [f"blade{k + 1}.flap" for k in blades],
              "main-rotor lag (rad)": [f"blade{k + 1}.lag" for k in blades]}
    if cfg.tail_rotor:
        panels["tail-rotor seesaw (rad)"] = ["seesaw.teeter"]
    if cfg.drive_train:
        panels["rotor speed (rad/s)"] = ["main_rotor.speed"]
    return panels


def plots(scene) -> dict:
    """The hinge-angle panels of a helicopter scene (:class:`mbs.scenes.Scene`) for its aircraft
    (a teetering main rotor's teeter in place of its blades' flap and lag; the tail's teeter only if
    it teeters, the tail blades' flap if they flap)."""
    data, cfg = scene.aircraft.data, config_of(scene)
    panels = config_plots(cfg, data["main_rotor"]["n_blades"])
    if data["main_rotor"]["hub_type"] == "teetering":
        panels.pop("main-rotor lag (rad)")
        panels["main-rotor flap (rad)"] = ["main_seesaw.teeter"]
    tr = data["tail_rotor"]
    if tr["hub_type"] != "teetering":
        panels.pop("tail-rotor seesaw (rad)", None)
    if tr["hub_type"] == "flapping" and cfg.tail_rotor:
        panels["tail-rotor flap (rad)"] = [f"tail_blade{k + 1}.flap" for k in range(tr["n_blades"])]
    return panels
