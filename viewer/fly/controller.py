"""The hover-hold controller in the flight page: the controller FMU's own C (:mod:`fmu.controller`)
as WebAssembly, and what the page's worker needs to wire it as the co-simulation does
(:mod:`fmu.cosim`): the value references of the helicopter outputs it reads, its trim inputs and
outputs, and which of the page's inputs each output drives.

Modes: ``off``; ``hover`` (hover hold: the controller as designed, position and heading held where
it is engaged); ``attitude`` (attitude hold: the controller fed the trim's position and velocity,
so that only attitude and body rates feed back). The design is the hover trim's: the switch is
offered where the page's model is the one it was designed on.
"""
from __future__ import annotations

import hashlib

from fmu import controller as hh

OFFSET = ("fuselage.x", "fuselage.y", "fuselage.z", "fuselage.yaw")
"""Inputs held where the controller is engaged (hover hold keeps that position and heading)."""
TRANSLATION = ("fuselage.x", "fuselage.y", "fuselage.z", "fuselage.u", "fuselage.v", "fuselage.w")
"""Inputs that attitude hold feeds their trim values (no position or velocity feedback)."""
MODES = ("off", "attitude", "hover")


def _code(sc) -> str:
    from mbs.backends import build
    from mbs.backends.compiled import generate

    vm = build(sc.model(), "vm")
    return hashlib.sha256(generate(vm.functions, vm.info, "float64").encode()).hexdigest()


def applies(sc, aircraft=None) -> str | None:
    """Why the hover-hold controller cannot fly ``sc`` (None when it can): it needs the model of its
    design (the aircraft's hover scene)."""
    from mbs import scenes

    hover = scenes.get(hh.SCENE, aircraft)
    if sc.name != hover.name and _code(sc) != _code(hover):
        return (f"the hover-hold controller is designed on the {hh.SCENE} scene's model; scene {sc.name!r} has "
                "another model")
    return None


def page_controller(sc, vr: dict, input_names: list[str], aircraft=None, log=None) -> tuple[dict | None, bytes | None, str]:
    """(config, WebAssembly, note): the controller's part of the page config and its module, or
    (None, None, why not)."""
    why = applies(sc, aircraft)
    if why:
        return None, None, why
    from fmu.native import wasm

    path, _ = hh.ensure_controller_fmu(log=log, aircraft=aircraft)
    module, design = wasm.ensure_controller(path)
    config = {"input_vrs": [vr[n] for n in hh.INPUTS], "trim_in": [design["trim_inputs"][n] for n in hh.INPUTS],
              "trim_out": [design["trim_controls"][c] for c in hh.OUTPUTS],
              "output_of": [hh.OUTPUTS.index(n) if n in hh.OUTPUTS else -1 for n in input_names],
              "offset": [int(n in OFFSET) for n in hh.INPUTS],
              "velocity_or_position": [int(n in TRANSLATION) for n in hh.INPUTS],
              "note": ("stability augmentation: the hover-hold controller (LQR designed at the hover trim, the "
                       "controller FMU's C); attitude hold feeds back attitude and rates, hover hold also velocity, "
                       "position and heading (held where engaged); the pilot's inputs add to its outputs")}
    return config, module.read_bytes(), ""
