"""The air options of a helicopter scene: the scene in the ISA, a wind, turbulence, a gust or
ground effect (:func:`with_environment`, the commands' ``--altitude``, ``--temperature-offset``,
``--wind`` ...), and those options as ``run.json`` records them and a scene from that record.
The air itself is built by :mod:`mbs.models.helicopter.environment`.
"""
from __future__ import annotations

from dataclasses import replace

from mbs.models.helicopter.config import Config, config_of


def with_environment(scene, altitude: float | None = None, temperature_offset: float | None = None,
                     wind=None, turbulence: str | None = None, gust: bool = False, ground_effect: bool = False):
    """``scene`` in the ISA at ``altitude`` (m) and ``temperature_offset`` (K) (either given:
    the ISA, the other 0), in a steady ``wind`` (north, east, down; m/s), in ``turbulence``
    ("dryden" or "von-karman"), with a discrete ``gust``, in ``ground_effect``; ValueError naming
    the value when the scene cannot have it."""
    cfg, options = config_of(scene), dict(scene.options)
    if altitude is not None or temperature_offset is not None:
        options.update(atmosphere="isa", altitude=float(altitude or 0.0),
                       temperature_offset=float(temperature_offset or 0.0))
    if wind is not None:
        options["wind"] = tuple(float(w) for w in wind)
    options.update({k: v for k, v in (("turbulence", turbulence), ("gust", gust), ("ground_effect", ground_effect))
                    if v})
    replace(cfg, **{k: v for k, v in options.items() if hasattr(cfg, k)})  # checked before anything is built
    return replace(scene, options=options)


def environment_record(scene) -> dict:
    """The scene's air options as ``run.json`` records them (empty for the file's still air)."""
    keys = ("atmosphere", "altitude", "temperature_offset", "wind", "turbulence", "gust", "ground_effect", "height",
            "payload", "cg_shift")
    base = getattr(scene.builder, "config", Config())
    cfg = {k: scene.options.get(k, getattr(base, k)) for k in keys}
    return {} if cfg == {k: getattr(Config(), k) for k in keys} else cfg


def environment_of_record(scene, record: dict):
    """``scene`` with the air options of a ``run.json`` record (:func:`environment_record`)."""
    if not record:
        return scene
    wind = record.get("wind")
    return replace(scene, options={**scene.options, **record, "wind": None if wind is None else tuple(wind)})
