"""The pilot's controls and the blade angles: the aircraft's rigging and mixing.

A file's ``[controls]`` section gives each pilot control's travel (collective lever, longitudinal
and lateral stick, pedals; in inches, degrees or per cent) and each blade angle as an affine
function of them: ``blade = offset + G pilot`` (the mixing), then the swashplate phase turns the
cyclic pair. ``[conventions]`` says how published blade angles are stated: the tail-rotor pitch's
sign (``tail_collective_positive``), the radius of the collective (``collective_radius``) and the
cyclic's sign (``cyclic_pitch``: the model's θ1c, θ1s, or A1, B1 of θ = θ0 − A1 cos ψ − B1 sin ψ).

Blade angles here are the model's controls (rad): ``collective`` (at the blade root),
``longitudinal_cyclic`` θ1s, ``lateral_cyclic`` θ1c, ``tail_collective`` (positive against the
main rotor's torque). Pilot positions in SI: m, rad or a fraction of travel (% / 100).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mbs.aircraft import geometry as geo

PILOT = ("collective_lever", "longitudinal_stick", "lateral_stick", "pedals")
BLADE = ("collective", "longitudinal_cyclic", "lateral_cyclic", "tail_collective")


@dataclass(frozen=True)
class Conventions:
    """How published blade angles are stated. ``tail_sign``: published tail-rotor pitch times it is
    the model's ``tail_collective``; ``collective_offset`` (rad): published collective minus the
    model's root collective (``twist · collective_radius`` of a linearly twisted blade, negated);
    ``cyclic_sign``: published cyclic pitch (θ1s, θ1c or B1, A1) times it is the model's."""

    tail_sign: float = 1.0
    collective_offset: float = 0.0
    cyclic_sign: float = 1.0

    def to_model(self, published: dict) -> dict:
        """Model blade angles (rad) of published ones (``BLADE`` keys present are converted)."""
        out = dict(published)
        if "collective" in out:
            out["collective"] = out["collective"] - self.collective_offset
        return self._signs(out)

    def _signs(self, angles: dict) -> dict:
        """``angles`` with the tail-rotor pitch and the cyclic pair times their signs (each its own inverse)."""
        for key, sign in zip(BLADE[1:], self.scale()[1:]):
            if key in angles:
                angles[key] = sign * angles[key]
        return angles

    def to_published(self, model: dict) -> dict:
        """Published blade angles of the model's."""
        out = dict(model)
        if "collective" in out:
            out["collective"] = out["collective"] + self.collective_offset
        return self._signs(out)

    def scale(self) -> np.ndarray:
        """d(published)/d(model) of the blade angles in ``BLADE`` order (4,)."""
        return np.array([1.0, self.cyclic_sign, self.cyclic_sign, self.tail_sign])


def conventions(d) -> Conventions:
    """The :class:`Conventions` of the aircraft data ``d``."""
    c = d.get("conventions", {})
    positive = c.get("tail_collective_positive", "anti-torque")
    anti_torque = "starboard" if geo.main_sense(d) > 0 else "port"
    sign = 1.0 if positive in ("anti-torque", anti_torque) else -1.0
    cyclic = -1.0 if c.get("cyclic_pitch", "theta_1c, theta_1s") == "A1, B1" else 1.0
    return Conventions(sign, d["main_rotor"]["twist"] * c.get("collective_radius", 0.0), cyclic)


@dataclass(frozen=True)
class Rigging:
    """``blade = to_model(turn(offset + gains pilot))``: ``offset`` (4,) rad and ``gains`` (4, 4)
    in ``BLADE`` × ``PILOT`` order, published convention; ``phase`` rad; ``travel`` (4, 2) the
    pilot controls' ranges; ``units`` their SI units (m, rad, -)."""

    offset: np.ndarray
    gains: np.ndarray
    phase: float
    travel: np.ndarray
    units: tuple
    conventions: Conventions

    def _turn(self) -> np.ndarray:
        """The phase's turn of (θ1s, θ1c) as a (4, 4) matrix in ``BLADE`` order."""
        c, s = np.cos(self.phase), np.sin(self.phase)
        t = np.eye(4)
        t[1:3, 1:3] = [[c, -s], [s, c]]
        return t

    def matrix(self) -> np.ndarray:
        """d(model blade angles)/d(pilot positions) (4, 4)."""
        return self.conventions.scale()[:, None] * (self._turn() @ self.gains)

    def blade(self, pilot) -> dict[str, float]:
        """Model blade angles (rad) of pilot positions (dict by ``PILOT`` or (4,) in that order)."""
        x = np.array([pilot[k] for k in PILOT]) if isinstance(pilot, dict) else np.asarray(pilot, dtype=float)
        published = dict(zip(BLADE, self._turn() @ (self.offset + self.gains @ x)))
        return {k: float(v) for k, v in self.conventions.to_model(published).items()}

    def pilot(self, blade: dict) -> dict[str, float]:
        """Pilot positions of model blade angles (all four of ``BLADE``); ValueError when the mixing
        cannot be inverted."""
        published = self.conventions.to_published(blade)
        y = np.linalg.solve(self._turn(), np.array([published[k] for k in BLADE])) - self.offset
        try:
            return dict(zip(PILOT, map(float, np.linalg.solve(self.gains, y))))
        except np.linalg.LinAlgError:
            raise ValueError("controls: the mixing's gains (4 x 4) are singular, so blade angles do not give pilot "
                             "positions; give each pilot control a gain") from None

    def in_file_unit(self, name: str, value: float, unit: str) -> float:
        """A pilot position ``value`` (SI) of control ``name`` in ``unit`` (the file's)."""
        from mbs.aircraft.units import factor_to

        return value * factor_to(self.units[PILOT.index(name)], unit)

    def beyond_travel(self, pilot: dict, margin: float = 0.0) -> list[str]:
        """Pilot controls at or beyond a stop (within ``margin`` of the travel), one line each."""
        out = []
        for k, (low, high), unit in zip(PILOT, self.travel, self.units):
            span = high - low
            if pilot[k] <= low + margin * span or pilot[k] >= high - margin * span:
                where = "at or below its least" if pilot[k] <= low + margin * span else "at or beyond its largest"
                out.append(f"{k} = {_show(pilot[k], unit)} is {where} position (travel {_show(low, unit)} to "
                           f"{_show(high, unit)})")
        return out


def _show(x: float, unit: str) -> str:
    return {"m": f"{x / 0.0254:.3g} in", "rad": f"{np.degrees(x):.3g} deg"}.get(unit, f"{100 * x:.3g} %")


def rigging(d) -> Rigging | None:
    """The :class:`Rigging` of the aircraft data ``d``, None when it has no ``[controls]``."""
    c = d.get("controls", {})
    if "collective_lever" not in c:
        return None
    rows = np.array([c[k] for k in BLADE])
    units = tuple(d.meta["controls"][k]["unit"] for k in PILOT) if hasattr(d, "meta") else ("-",) * 4
    from mbs.aircraft.units import position_kind

    return Rigging(rows[:, 0], rows[:, 1:], c.get("phase", 0.0), np.array([c[k] for k in PILOT]),
                   tuple(position_kind(u) for u in units), conventions(d))
