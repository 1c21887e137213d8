"""Scenes: named test cases that build only the bodies and forces they need.

A scene is data plus one builder call. ``SCENES`` is the registry; the helicopter scenes
register themselves from :mod:`mbs.models.helicopter.scenes` (with the packaged Bo105; any
aircraft through :meth:`Scene.with_aircraft`) and the generic demonstration scenes from
:mod:`mbs.models.demo`.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field, replace
from typing import Any, Callable

import numpy as np

SCENES: dict[str, "Scene"] = {}
_PROVIDERS = ("mbs.models.demo", "mbs.models.helicopter.scenes", "mbs.models.ground_resonance")


@dataclass
class Scene:
    """A test case.

    builder: ``builder(**options) -> Model``. omega: main-rotor speed in rad/s, setting the
    revolution used by ``--revs`` and ``--steps-per-rev`` (taken from the parameter
    ``omega`` when the model has one). conservative: no energy sources or sinks, so the
    total energy is an accuracy check. plots: panel title -> coordinates or outputs shown
    in ``hinge_angles.png``. aircraft: the :class:`mbs.aircraft.Aircraft` of a helicopter
    scene (None for the others).
    """

    name: str
    description: str
    builder: Callable
    omega: float
    conservative: bool = False
    steps_per_rev: int = 100
    plots: dict[str, list[str]] = field(default_factory=dict)
    options: dict = field(default_factory=dict)
    aircraft: Any = None

    def model(self, **options):
        extra = {"aircraft": self.aircraft} if self.aircraft is not None else {}
        return self.builder(**extra, **{**self.options, **options})

    def with_aircraft(self, aircraft) -> "Scene":
        """This helicopter scene of another aircraft: an :class:`mbs.aircraft.Aircraft`, a
        packaged aircraft's name or a file path (loaded and checked)."""
        from mbs import aircraft as ac
        from mbs.models.helicopter.panels import plots

        if self.aircraft is None:
            raise ValueError(f"scene {self.name!r} is not a helicopter scene: an aircraft file applies to "
                             f"{', '.join(n for n, s in all_scenes().items() if s.aircraft is not None)}")
        craft = aircraft if isinstance(aircraft, ac.Aircraft) else ac.load(aircraft)
        scene = replace(self, aircraft=craft, omega=craft.omega)
        return replace(scene, plots=plots(scene))

    def system(self, backend: str = "compiled", dtype: str = "float64", **options):
        from mbs.backends import build

        return build(self.model(**options), backend, dtype)

    def revolution(self, system=None, p=None) -> float:
        """Main-rotor revolution period (s) for the given parameters."""
        omega = self.omega
        if system is not None and "omega" in system.info.param_names:
            omega = system.params(p)[system.info.param_names.index("omega")]
        return 2 * np.pi / abs(omega)


def register(scene: Scene) -> Scene:
    if scene.name in SCENES:
        raise ValueError(f"duplicate scene name {scene.name!r}")
    SCENES[scene.name] = scene
    return scene


def _load() -> None:
    for module in _PROVIDERS:
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name != module:
                raise


def all_scenes() -> dict[str, Scene]:
    _load()
    return dict(SCENES)


def get(name: str, aircraft=None) -> Scene:
    """The scene called ``name`` (of ``aircraft`` when given: see :meth:`Scene.with_aircraft`);
    ValueError listing the known ones otherwise."""
    scenes = all_scenes()
    if name not in scenes:
        raise ValueError(f"unknown scene {name!r}; known scenes: {', '.join(sorted(scenes))}")
    return scenes[name] if aircraft is None else scenes[name].with_aircraft(aircraft)
