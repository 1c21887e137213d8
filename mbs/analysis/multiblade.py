"""Multi-blade coordinates (Coleman's transform) of per-blade rotor coordinates, and fixed-frame
names of rotor modes.

For ``N >= 3`` identical blades at azimuths ``ψ_k = Ω t + 2π (k - 1) / N`` (blade 1 over the tail
at ``t = 0``, the model's convention) a per-blade coordinate ``β_k`` (``bladeK.lag``,
``bladeK.flap`` and their rates) becomes

    β0  = 1/N Σ β_k                      collective
    βnc = 2/N Σ β_k cos nψ_k,  βns = 2/N Σ β_k sin nψ_k     cyclic, 1 <= n < N/2
    βd  = 1/N Σ β_k (-1)^(k-1)           differential (N even)

The rates are transformed by the same matrix ``B(t)``: since ``B' B⁻¹`` is constant, this differs
from the multi-blade state ``(Bβ, (Bβ)')`` by a constant matrix, so an isotropic rotor's
equations are time-invariant in either. In these coordinates a Floquet mode's periodic part is
constant, which fixes its frequency in the fixed frame (:func:`transform` is the ``frame`` of
:func:`mbs.analysis.floquet.analyse`).
"""
from __future__ import annotations

import re
from typing import Callable

import numpy as np

BLADE = re.compile(r"^blade(\d+)(?:_(\d+))?\.(.+)$")
"""A per-blade coordinate: ``blade<k>.<dof>``, or ``blade<k>_<segment>.<dof>`` on the segments
of an elastic blade (:mod:`mbs.models.elastic_blade`)."""


def dof_of(key: str) -> str:
    """The coordinate (``flap``, ``lag_rate``, ...) of a :func:`blade_groups` key."""
    return key.split("#", 1)[0]


def blade_groups(names: list[str]) -> dict[str, list[int]]:
    """Per-blade coordinates: key (``lag``, ``lag_rate``, ...; ``lag#2`` on segment 2 of an
    elastic blade) -> indices into ``names`` by blade number, for keys present on every blade
    of a rotor with at least 3 blades."""
    found: dict[str, dict[int, int]] = {}
    for i, name in enumerate(names):
        m = BLADE.match(name)
        if m:
            key = m.group(3) + (f"#{m.group(2)}" if m.group(2) else "")
            found.setdefault(key, {})[int(m.group(1))] = i
    groups = {s: [idx[k] for k in sorted(idx)] for s, idx in found.items()}
    return {s: g for s, g in groups.items() if len(g) >= 3 and sorted(found[s]) == list(range(1, len(g) + 1))}


def component_names(n_blades: int) -> list[str]:
    """Names of the multi-blade components in the order of :func:`coleman_matrix`'s rows."""
    cyclic = [f"{n}{cs}" for n in range(1, (n_blades - 1) // 2 + 1) for cs in "cs"]
    return ["0", *cyclic, *(["d"] if n_blades % 2 == 0 else [])]


def coleman_matrix(n_blades: int, psi1: float) -> np.ndarray:
    """``B`` (N, N): multi-blade components from per-blade values, blade 1 at azimuth ``psi1`` (rad)."""
    psi = psi1 + 2 * np.pi * np.arange(n_blades) / n_blades
    rows = [np.full(n_blades, 1.0 / n_blades)]
    for n in range(1, (n_blades - 1) // 2 + 1):
        rows += [2.0 / n_blades * np.cos(n * psi), 2.0 / n_blades * np.sin(n * psi)]
    if n_blades % 2 == 0:
        rows.append((-1.0) ** np.arange(n_blades) / n_blades)
    return np.array(rows)


TEETERING = {"main_seesaw.teeter": 0.0, "stabilizer_bar.teeter": np.pi / 2}
"""Two-ended bodies teetering on the main hub, with the azimuth (rad, from blade 1 in the sense of
rotation) of the end their positive teeter lifts: a teetering main rotor's yoke, a stabilizer bar."""


def transform(names: list[str], omega: float) -> Callable[[np.ndarray], np.ndarray]:
    """``frame(t) -> (m, ny, ny)``: the identity on every coordinate except the per-blade ones,
    which become multi-blade components in the same slots (collective in blade 1's, ...), and a
    teetering body's teeter ``β`` and rate, which become the tilt of its plane in the fixed frame,
    ``a = β cos ψ - β'/Ω sin ψ`` and ``b = β sin ψ + β'/Ω cos ψ`` (exact for a tilt ``β = a cos ψ +
    b sin ψ`` held in space, ``ψ`` its lifted end's azimuth) in the teeter's and the rate's slots."""
    groups = blade_groups(names)
    rate = abs(omega)
    bodies = [(names.index(k), names.index(f"{k}_rate"), phase) for k, phase in TEETERING.items()
              if k in names and f"{k}_rate" in names]

    def frame(t) -> np.ndarray:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.tile(np.eye(len(names)), (len(t), 1, 1))
        for idx in groups.values():
            out[:, np.array(idx)[:, None], idx] = [coleman_matrix(len(idx), omega * tk) for tk in t]
        for i, j, phase in bodies:
            c, s = np.cos(rate * t + phase), np.sin(rate * t + phase)
            out[:, i, i], out[:, i, j], out[:, j, i], out[:, j, j] = c, -s / rate, s, c / rate
        return out
    return frame


def mode_name(vector: np.ndarray, names: list[str], frequency: float, omega: float,
              groups: dict[str, str], threshold: float = 0.25) -> str:
    """Fixed-frame name of a mode from its eigenvector in multi-blade coordinates at ``t = 0``
    (``vector`` (ny,), the mode ``∝ exp(+i frequency t)``, frequency and ``omega`` in rad/s).

    groups: coordinate name -> group (``body``, ``lag``, ``flap``, ...), e.g.
    :func:`mbs.analysis.floquet.group_of`; the blade groups split into collective, regressing,
    advancing and differential. The name joins the parts above ``threshold`` of the energy, body first."""
    energy = _energies(vector, names, frequency, omega, groups)
    total = sum(energy.values()) or 1.0
    return " + ".join(sorted((k for k, w in energy.items() if w >= threshold * total), key=_rank))


KINDS = ("regressing", "advancing", "collective", "differential")


def _rank(part: str) -> tuple[int, str]:
    """Order of the parts in a name: fixed-frame groups (body) first, then the rotor's by kind."""
    kind = part.split(" ", 1)[0]
    return (1 + KINDS.index(kind) if kind in KINDS else 0, part)


def _energies(vector, names, frequency, omega, groups) -> dict[str, float]:
    """Energy of the eigenvector by named part (coordinates only, not rates; a teetering body's rate
    slot holds the second component of its tilt, :func:`transform`)."""
    out: dict[str, float] = {}
    blades = blade_groups(names)
    in_blades = {i for idx in blades.values() for i in idx}
    for i, name in enumerate(names):
        if i not in in_blades and (not name.endswith("_rate") or name.removesuffix("_rate") in TEETERING):
            out[groups[name]] = out.get(groups[name], 0.0) + abs(vector[i]) ** 2
    for key, idx in blades.items():
        if not dof_of(key).endswith("_rate"):
            for part, w in _blade_parts(vector[idx], dof_of(key), frequency, omega).items():
                out[part] = out.get(part, 0.0) + w
    return out


def _blade_parts(v: np.ndarray, dof: str, frequency: float, omega: float) -> dict[str, float]:
    """Energy of the collective, cyclic (regressing or advancing, by whirl) and differential
    components ``v`` (N,) of one blade coordinate ``dof``."""
    comps = component_names(len(v))
    out = {f"collective {dof}": abs(v[0]) ** 2}
    if comps[-1] == "d":
        out[f"differential {dof}"] = abs(v[-1]) ** 2
    for n in range(1, (len(v) - 1) // 2 + 1):
        c, s = v[2 * n - 1], v[2 * n]
        forward = abs(c + 1j * s) >= abs(c - 1j * s)
        whirl = frequency if forward else -frequency
        kind = "advancing" if whirl > n * omega else "regressing"
        key = f"{kind} {dof}" if n == 1 else f"{kind} {dof} ({n}/rev)"
        out[key] = out.get(key, 0.0) + abs(c) ** 2 + abs(s) ** 2
    return out
