"""Rigid transforms for the viewer (numpy only): absolute poses to parent-relative node
transforms and back, rotation angles and three.js quaternions.

Transforms are 4x4 homogeneous matrices ``[[R, r], [0, 1]]`` mapping child-frame
coordinates to parent-frame coordinates (m). Parent indices: ``-1`` is the world.
"""
from __future__ import annotations

import numpy as np


def homogeneous(origins: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """Transforms (..., 4, 4) from origins (..., 3) in m and rotations (..., 3, 3)."""
    origins, rotations = np.asarray(origins, dtype=float), np.asarray(rotations, dtype=float)
    out = np.zeros(origins.shape[:-1] + (4, 4))
    out[..., :3, :3] = rotations
    out[..., :3, 3] = origins
    out[..., 3, 3] = 1.0
    return out


def inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4)."""
    R, r = T[..., :3, :3], T[..., :3, 3]
    Rt = np.swapaxes(R, -1, -2)
    return homogeneous(-np.einsum("...ij,...j->...i", Rt, r), Rt)


def relative(absolute: np.ndarray, parents: list[int]) -> np.ndarray:
    """Parent-relative transforms (..., nb, 4, 4) of absolute body transforms (..., nb, 4, 4)."""
    out = absolute.copy()
    for i, p in enumerate(parents):
        if p >= 0:
            out[..., i, :, :] = inverse(absolute[..., p, :, :]) @ absolute[..., i, :, :]
    return out


def compose(local: np.ndarray, parents: list[int]) -> np.ndarray:
    """Absolute transforms (..., nb, 4, 4) from parent-relative ones; parents come first."""
    out = local.copy()
    for i, p in enumerate(parents):
        if p >= i:
            raise ValueError(f"body {i} has parent {p}: parents must precede their children")
        if p >= 0:
            out[..., i, :, :] = out[..., p, :, :] @ local[..., i, :, :]
    return out


def rotation_angle(Ra: np.ndarray, Rb: np.ndarray) -> np.ndarray:
    """Angle (rad, in [0, pi]) of the rotation ``Ra^T Rb``; shapes (..., 3, 3)."""
    D = np.swapaxes(Ra, -1, -2) @ Rb
    c = (np.trace(D, axis1=-2, axis2=-1) - 1.0) / 2.0
    v = np.stack([D[..., 2, 1] - D[..., 1, 2], D[..., 0, 2] - D[..., 2, 0], D[..., 1, 0] - D[..., 0, 1]], -1)
    return np.arctan2(np.linalg.norm(v, axis=-1) / 2.0, c)


def quaternions_xyzw(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4) in three.js order ``(x, y, z, w)`` of rotations (..., 3, 3).

    Along the first axis the sign is chosen so that neighbours have a non-negative dot
    product (a sequence of keys then describes the shortest turns between them).
    """
    R = np.asarray(R, dtype=float)
    m = R.reshape(-1, 3, 3)
    K = np.empty((len(m), 4, 4))  # Bar-Itzhack: the eigenvector of the largest eigenvalue
    K[:, 0, 0] = m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2]
    K[:, 1, 1] = m[:, 1, 1] - m[:, 0, 0] - m[:, 2, 2]
    K[:, 2, 2] = m[:, 2, 2] - m[:, 0, 0] - m[:, 1, 1]
    K[:, 3, 3] = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    K[:, 0, 1] = K[:, 1, 0] = m[:, 0, 1] + m[:, 1, 0]
    K[:, 0, 2] = K[:, 2, 0] = m[:, 0, 2] + m[:, 2, 0]
    K[:, 1, 2] = K[:, 2, 1] = m[:, 1, 2] + m[:, 2, 1]
    K[:, 0, 3] = K[:, 3, 0] = m[:, 2, 1] - m[:, 1, 2]
    K[:, 1, 3] = K[:, 3, 1] = m[:, 0, 2] - m[:, 2, 0]
    K[:, 2, 3] = K[:, 3, 2] = m[:, 1, 0] - m[:, 0, 1]
    _, vecs = np.linalg.eigh(K / 3.0)
    q = vecs[:, :, -1].reshape(R.shape[:-2] + (4,))
    q = q * np.where(q[..., 3:] < 0, -1.0, 1.0)
    if q.ndim >= 2:
        signs = np.cumprod(np.where(np.sum(q[1:] * q[:-1], axis=-1) < 0, -1.0, 1.0), axis=0)
        q[1:] *= signs[..., None]
    return q


def rotations_xyzw(q: np.ndarray) -> np.ndarray:
    """Rotations (..., 3, 3) of unit quaternions (..., 4) in three.js order ``(x, y, z, w)``."""
    x, y, z, w = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    rows = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return np.moveaxis(np.array(rows), (0, 1), (-2, -1))


def key_angles(local: np.ndarray) -> np.ndarray:
    """Rotation (rad) of every node relative to its parent between consecutive keys:
    ``local`` (k, nb, 4, 4) -> (k - 1, nb)."""
    return rotation_angle(local[:-1, :, :3, :3], local[1:, :, :3, :3])


def rotation_x(angle: float) -> np.ndarray:
    """Transform (4, 4) rotating by ``angle`` (rad) about x."""
    c, s = np.cos(angle), np.sin(angle)
    return homogeneous(np.zeros(3), np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]]))


def align_y(axis) -> np.ndarray:
    """A rotation (3, 3) taking the y axis onto the unit vector along ``axis``."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    y = np.array([0.0, 1.0, 0.0])
    v, c = np.cross(y, a), float(np.dot(y, a))
    if c < -1 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k / (1 + c)
