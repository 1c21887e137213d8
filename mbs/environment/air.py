"""What the aerodynamics reads of the air: its density, its speed of sound and its velocity.

:class:`Air` belongs to a model (``Model.air``; None: still air with the aircraft file's
density and speed of sound, the default). Force elements never read it directly: they ask the
symbolic state (:class:`mbs.forces.State`), which is the one hook of every aerodynamic element:

* ``state.density(rho)``: the air density (kg/m³), ``rho`` (the file's, a number) unless the
  scene asks for the ISA, whose density then follows the run-time parameters ``altitude`` (m)
  and ``temperature_offset`` (K);
* ``state.speed_of_sound(a)``: likewise (m/s);
* ``state.air_velocity(position)``: the air's velocity (3,) (m/s, world axes: x north, y east,
  z down) at the world point ``position`` (m): steady wind, gusts and turbulence as the scene
  models them, or None in still air. An element computes its velocity through the air as
  ``through_air(state, velocity, position)``.

In still air at the file's values each call returns what the element had before (the same
number, the same symbol), so a scene without these options generates the same code.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from mbs.environment import atmosphere as isa

ISA_PARAMETERS = ("altitude", "temperature_offset")
WIND_PARAMETERS = ("wind_north", "wind_east", "wind_down")


def through_air(state, velocity, position):
    """``velocity`` (3,) (m/s, world) of a point at ``position`` relative to the air there:
    the same expression in still air."""
    air = state.air_velocity(position)
    return velocity if air is None else velocity - air


@dataclass
class Air:
    """The air of a model: ``isa`` (density and speed of sound from the ISA at the run-time
    parameters ``altitude`` and ``temperature_offset``, else the aircraft file's ``rho`` and
    ``speed_of_sound``), ``wind`` (a steady wind from the parameters ``wind_north``,
    ``wind_east``, ``wind_down``, m/s, world axes: the air's own velocity) and further motions
    (``motions``: objects with ``velocity(state, position) -> SX (3,)``, e.g. gusts and
    turbulence, summed)."""

    isa: bool = False
    wind: bool = False
    motions: list = field(default_factory=list)

    @property
    def moves(self) -> bool:
        return self.wind or bool(self.motions)

    def add_parameters(self, model, altitude: float = 0.0, offset: float = 0.0) -> None:
        """Declare this air's run-time parameters on ``model`` (defaults: ``altitude`` m,
        ``offset`` K)."""
        if self.isa:
            isa.check(altitude, offset)
            model.add_parameter("altitude", altitude, "m", "pressure altitude of the ISA (density, speed of sound)",
                                low=isa.ALTITUDE_RANGE[0], high=isa.ALTITUDE_RANGE[1])
            model.add_parameter("temperature_offset", offset, "K", "air temperature minus the ISA's at the altitude "
                                "(ISA + 20: 20)", low=isa.OFFSET_RANGE[0], high=isa.OFFSET_RANGE[1])
        if self.wind:
            for name, what in zip(WIND_PARAMETERS, ("north", "east", "down")):
                model.add_parameter(name, 0.0, "m/s", f"steady wind: the air's velocity towards {what} (world axes)",
                                    low=-60.0, high=60.0)
        for motion in self.motions:
            motion.add_parameters(model)

    def density(self, state, default: float):
        """kg/m³: the ISA's at the state's parameters, else ``default``."""
        if not self.isa:
            return default
        return _cached(state, "air.density", lambda: isa.density(state.p["altitude"], state.p["temperature_offset"]))

    def speed_of_sound(self, state, default: float):
        """m/s: the ISA's at the state's parameters, else ``default``."""
        if not self.isa:
            return default
        return _cached(state, "air.speed_of_sound",
                       lambda: isa.speed_of_sound(state.p["altitude"], state.p["temperature_offset"]))

    def velocity(self, state, position):
        """The air's velocity (3,) (m/s, world) at ``position`` (3,) (m, world); None when still."""
        if not self.moves:
            return None
        out = _cached(state, "air.wind", lambda: _wind(state)) if self.wind else 0
        for motion in self.motions:
            out = out + motion.velocity(state, position)
        return out


def _wind(state):
    import casadi as ca

    return ca.vertcat(*[state.p[n] for n in WIND_PARAMETERS])


def _cached(state, key: str, make):
    """One expression per state for ``key`` (every element reads the same symbols)."""
    if key not in state.signals:
        state.signals[key] = make()
    return state.signals[key]
