"""Mode shapes of a blade: the shape functions of a flexible blade body.

Each direction's shapes are modes of the continuous blade clamped at its root, turning at a
reference speed ``omega`` (rad/s; 0: the cantilever's own modes), from the finite elements of
:func:`mbs.flexible.uniform_blade.beam_matrices` (cubic Hermite in bending, linear in torsion
and extension): smooth between the element nodes, with first and second derivatives, and
normalised so that the tip value is the blade length ``L`` (bending, extension: the modal
coordinate is then the tip deflection over ``L``, an angle in rad for small deflections) or
1 (torsion: the tip twist in rad). Span coordinates ``x`` (m) run from the root, ``0 <= x <= L``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh

from mbs.flexible.uniform_blade import BEAM_ELEMENTS, GAUSS, Blade, beam_matrices, element_shapes

DIRECTIONS = ("flap", "lag", "torsion", "axial")
"""The directions of a blade's modes: flap and lag bending, torsion and extension."""


@dataclass
class Shapes:
    """``count`` mode shapes of one ``direction`` of ``blade``: ``vectors`` (dofs, count) the
    element-node values (root dofs included, zero), ``frequencies`` (count,) rad/s at the
    reference speed ``omega`` (rad/s)."""

    blade: Blade
    direction: str
    omega: float
    vectors: np.ndarray
    frequencies: np.ndarray
    elements: int

    @property
    def count(self) -> int:
        return self.vectors.shape[1]

    @property
    def element_length(self) -> float:
        return self.blade.length / self.elements

    def _element(self, x: float) -> tuple[np.ndarray, float]:
        """The dof values (2 per_node, count) of the element holding ``x`` and ``x``'s place in it."""
        if not -1e-12 <= x <= self.blade.length * (1 + 1e-12):
            raise ValueError(f"span coordinate {x} m outside the blade (0 to {self.blade.length} m)")
        per_node = element_shapes(self.direction)[1]
        e = min(int(x / self.element_length), self.elements - 1)
        return self.vectors[per_node * e:per_node * (e + 2)], min(max(x / self.element_length - e, 0.0), 1.0)

    def values(self, x: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The shapes, their slopes (1/m) and curvatures (1/m²) at ``x`` (m), each (count,)."""
        dofs, xi = self._element(x)
        n, dn, ddn = element_shapes(self.direction)[0](np.array([xi]), self.element_length)
        return (n[:, 0] @ dofs, dn[:, 0] @ dofs, ddn[:, 0] @ dofs)

    def foreshortening(self, x: float) -> np.ndarray:
        """``G(x) = ∫_0^x φ_i' φ_j' dξ`` (count, count): a bending deflection ``Σ φ_i q_i``
        draws the section at ``x`` towards the root by ``q·G(x)·q / 2`` (m)."""
        whole = int(min(x / self.element_length, self.elements))
        out = sum((self._slope_products(e, 1.0) for e in range(whole)), np.zeros((self.count, self.count)))
        rest = x / self.element_length - whole
        return out + (self._slope_products(whole, rest) if rest > 1e-15 and whole < self.elements else 0.0)

    def _slope_products(self, e: int, upto: float) -> np.ndarray:
        """``∫ φ_i' φ_j'`` over element ``e`` from its start to the fraction ``upto`` of it."""
        per_node = element_shapes(self.direction)[1]
        dofs = self.vectors[per_node * e:per_node * (e + 2)]
        xi, w = (GAUSS[0] + 1) / 2 * upto, GAUSS[1] / 2 * upto * self.element_length
        slopes = element_shapes(self.direction)[0](xi, self.element_length)[1].T @ dofs  # (points, count)
        return slopes.T @ (slopes * w[:, None])

    def stiffness(self) -> np.ndarray:
        """Elastic stiffness ``∫ EI φ_i'' φ_j''`` (``GJ``, ``EA`` with first derivatives), (count, count),
        from the section data alone: the centrifugal stiffening comes from the kinematics."""
        k = beam_matrices(self.blade, 0.0, self.direction, self.elements)[0]
        v = self.vectors[element_shapes(self.direction)[1]:]
        return v.T @ k @ v


LINEAR_REFINEMENT = 4
"""Torsion and extension take this many times the elements of bending: linear elements
converge as h² (the third torsion frequency 0.2 % high with 48 of them, 0.014 % with 192)."""


def mode_shapes(blade: Blade, direction: str, count: int, omega: float = 0.0,
                elements: int = BEAM_ELEMENTS) -> Shapes:
    """The first ``count`` modes of ``direction`` of ``blade`` clamped at its root and turning
    at ``omega`` (rad/s), normalised at the tip (see the module), from ``elements`` finite
    elements (:data:`LINEAR_REFINEMENT` times as many in torsion and extension)."""
    if direction not in DIRECTIONS:
        raise ValueError(f"unknown mode direction {direction!r}; choose one of {', '.join(DIRECTIONS)}")
    if direction == "axial" and not np.isfinite(blade.axial_stiffness):
        raise ValueError("axial modes need the blade's axial stiffness EA (N); the blade is inextensible")
    per_node = element_shapes(direction)[1]
    elements *= LINEAR_REFINEMENT if per_node == 1 else 1
    if not 1 <= count <= per_node * elements:
        raise ValueError(f"{count} {direction} modes: choose 1 to {per_node * elements}")
    k, m = beam_matrices(blade, omega, direction, elements)
    lam, vec = eigh(k, m, subset_by_index=[0, count - 1])
    if lam[0] <= 0:
        raise ValueError(f"the blade's {direction} stiffness does not hold it at {omega} rad/s "
                         f"(first eigenvalue {lam[0]:.3g} 1/s²)")
    tip = vec[-per_node]  # displacement (not slope) at the tip node
    scale = (1.0 if direction == "torsion" else blade.length) / tip
    full = np.vstack([np.zeros((per_node, count)), vec * scale])
    return Shapes(blade, direction, omega, full, np.sqrt(lam), elements)
