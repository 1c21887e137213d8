"""Rotation algebra on CasADi SX symbols (and plain floats).

Conventions used throughout the package:

* rotation matrices map body-frame components to parent-frame components;
* quaternions are Hamilton quaternions stored scalar first, ``(w, x, y, z)``;
* angles are in radians, right-handed about the given axis.
"""
from __future__ import annotations

import casadi as ca
import numpy as np


def skew(a) -> ca.SX:
    """Cross-product matrix ``[a]x`` with ``[a]x b = a x b``; ``a`` of shape (3,)."""
    return ca.vertcat(
        ca.horzcat(0, -a[2], a[1]),
        ca.horzcat(a[2], 0, -a[0]),
        ca.horzcat(-a[1], a[0], 0),
    )


def axis_angle(axis: np.ndarray, angle) -> ca.SX:
    """Rotation by ``angle`` (rad) about the constant unit ``axis`` (Rodrigues)."""
    k = skew(ca.DM(axis))
    return ca.SX.eye(3) + ca.sin(angle) * k + (1 - ca.cos(angle)) * ca.mtimes(k, k)


def quat_to_matrix(q) -> ca.SX:
    """Rotation matrix of quaternion ``q = (w, x, y, z)``; ``q`` need not be unit."""
    w, x, y, z = (q[i] / ca.norm_2(q) for i in range(4))
    return ca.vertcat(
        ca.horzcat(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        ca.horzcat(2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        ca.horzcat(2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    )


def quat_rate(q, omega_body) -> ca.SX:
    """Time derivative ``q' = q (x) (0, omega) / 2`` for a body-frame angular velocity."""
    w, x, y, z = (q[i] for i in range(4))
    p, r, s = (omega_body[i] for i in range(3))
    return 0.5 * ca.vertcat(
        -x * p - y * r - z * s,
        w * p + y * s - z * r,
        w * r - x * s + z * p,
        w * s + x * r - y * p,
    )


def matrix_to_quat(m: np.ndarray) -> np.ndarray:
    """Unit quaternion ``(w, x, y, z)`` of a numeric rotation matrix (shape (3, 3))."""
    m = np.asarray(m, dtype=float)
    tr = np.trace(m)
    if tr > 0:
        s = 2.0 * np.sqrt(1.0 + tr)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0] * 4
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q) * np.sign(q[0] or 1.0)


def euler_to_quat(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Quaternion of aerospace Euler angles (yaw-pitch-roll, z-y-x sequence), rad."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return np.array([
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ])


def quat_to_euler(q: np.ndarray) -> np.ndarray:
    """Aerospace Euler angles (roll, pitch, yaw) in rad of quaternions ``q`` (..., 4)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], axis=-1)
