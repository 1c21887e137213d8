"""The starts a flight page offers, computed when the page is written: the periodic trim at each
chosen speed (:func:`mbs.starts.periodic`, the same as ``heli simulate --start periodic:V``), the
periodic rotor response for a scene on a stand, or the scene's own start for a scene that cannot
be trimmed.
"""
from __future__ import annotations

import numpy as np

from mbs import inputs as inp
from mbs import starts

DEFAULT_SPEEDS = (0.0, 10.0, 20.0, 40.0, 60.0)
"""Trim speeds (m/s) of a page by default, besides the scene's own."""


def _entry(label: str, text: str, speed, x0: np.ndarray, controls: dict, info, names: list[str]) -> dict:
    found = inp.forward_speed_direction(info, x0)
    fs = None if found is None else {"v": list(found[0]), "direction": [float(c) for c in found[1]],
                                     "own": float(found[1] @ x0[found[0]])}
    return {"label": label, "start": text, "speed": speed, "x0": [float(v) for v in x0],
            "controls": [float(controls[n]) for n in names], "fs": fs}


def page_starts(sc, system, input_names: list[str], speeds=None, log=None) -> list[dict]:
    """The starts of ``sc`` (a :class:`mbs.scenes.Scene`) for ``system``: one entry per speed (m/s;
    ``speeds`` or :data:`DEFAULT_SPEEDS` and the scene's own, for a scene with a free fuselage),
    each with its state, its controls (rad, in the order of ``input_names``), the ``--start`` of
    ``heli simulate`` that gives it, and the direction of ``initial_forward_speed`` at its attitude."""
    from mbs.analysis.trim import trimmable

    info = system.info
    free = any(b["joint"] == "FreeJoint" for b in info.bodies)
    if not trimmable(sc):
        p = system.params()
        controls = {n: float(p[info.param_names.index(n)]) for n in input_names}
        return [_entry("the scene's own start (it cannot be trimmed)", "scene", None, system.x0(), controls, info,
                       input_names)]
    if not free:
        s = starts.periodic(sc, None, system=system)
        return [_entry("periodic rotor response at the scene's controls", "periodic", None, s.x0, s.controls, info,
                       input_names)]
    own = starts.periodic(sc, None, system=system)
    chosen = sorted({float(v) for v in (DEFAULT_SPEEDS if speeds is None else speeds)} - {own.speed})
    out = [_entry(f"periodic trim at {own.speed:g} m/s (the scene's)", "periodic", own.speed, own.x0, own.controls,
                  info, input_names)]
    for v in chosen:
        if log:
            log(f"trimming {sc.name} at {v:g} m/s ...")
        s = starts.periodic(sc, v, system=system)
        out.append(_entry(f"periodic trim at {v:g} m/s", f"periodic:{v:g}", v, s.x0, s.controls, info, input_names))
    return out
