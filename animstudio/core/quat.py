"""Quaternion helpers. Order is **wxyz** everywhere (docs/conventions.md); arrays broadcast over leading axes."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def identity(shape: tuple[int, ...] = ()) -> F64:
    """Identity quaternions of the given leading shape, ``shape + (4,)``."""
    q = np.zeros((*shape, 4))
    q[..., 0] = 1.0
    return q


def from_axis_angle(axis: ArrayLike, angle_rad: ArrayLike) -> F64:
    """Rotation by ``angle_rad`` (right-handed) about unit ``axis``; broadcasts."""
    axis_a = np.asarray(axis, dtype=np.float64)
    half = 0.5 * np.asarray(angle_rad, dtype=np.float64)
    s = np.sin(half)[..., None]
    return np.concatenate([np.cos(half)[..., None], axis_a * s], axis=-1)


def about_x(angle_rad: ArrayLike) -> F64:
    return from_axis_angle((1.0, 0.0, 0.0), angle_rad)


def about_y(angle_rad: ArrayLike) -> F64:
    return from_axis_angle((0.0, 1.0, 0.0), angle_rad)


def about_z(angle_rad: ArrayLike) -> F64:
    return from_axis_angle((0.0, 0.0, 1.0), angle_rad)


def multiply(a: ArrayLike, b: ArrayLike) -> F64:
    """Hamilton product ``a * b`` (apply ``b`` first, then ``a``)."""
    a_ = np.asarray(a, dtype=np.float64)
    b_ = np.asarray(b, dtype=np.float64)
    aw, ax, ay, az = np.moveaxis(a_, -1, 0)
    bw, bx, by, bz = np.moveaxis(b_, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def normalize(q: ArrayLike) -> F64:
    q_ = np.asarray(q, dtype=np.float64)
    return q_ / np.linalg.norm(q_, axis=-1, keepdims=True)


def conjugate(q: ArrayLike) -> F64:
    q_ = np.array(q, dtype=np.float64)
    q_[..., 1:] *= -1.0
    return q_


def to_matrix(q: ArrayLike) -> F64:
    """Rotation matrices ``(..., 3, 3)`` acting on column vectors."""
    w, x, y, z = np.moveaxis(normalize(q), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def from_matrix(m: ArrayLike) -> F64:
    """Quaternion (w >= 0) from rotation matrices ``(..., 3, 3)`` (Shepperd's method, stable for all angles)."""
    m_ = np.asarray(m, dtype=np.float64)
    shape = m_.shape[:-2]
    m2 = m_.reshape(-1, 3, 3)
    out = np.empty((m2.shape[0], 4))
    tr = m2[:, 0, 0] + m2[:, 1, 1] + m2[:, 2, 2]
    diag = np.stack([tr, m2[:, 0, 0], m2[:, 1, 1], m2[:, 2, 2]], axis=-1)
    best = np.argmax(diag, axis=-1)
    for k in range(4):
        sel = best == k
        if not np.any(sel):
            continue
        r = m2[sel]
        if k == 0:
            s = np.sqrt(1.0 + tr[sel]) * 2
            q = [
                0.25 * s,
                (r[:, 2, 1] - r[:, 1, 2]) / s,
                (r[:, 0, 2] - r[:, 2, 0]) / s,
                (r[:, 1, 0] - r[:, 0, 1]) / s,
            ]
        elif k == 1:
            s = np.sqrt(1.0 + r[:, 0, 0] - r[:, 1, 1] - r[:, 2, 2]) * 2
            q = [
                (r[:, 2, 1] - r[:, 1, 2]) / s,
                0.25 * s,
                (r[:, 0, 1] + r[:, 1, 0]) / s,
                (r[:, 0, 2] + r[:, 2, 0]) / s,
            ]
        elif k == 2:
            s = np.sqrt(1.0 + r[:, 1, 1] - r[:, 0, 0] - r[:, 2, 2]) * 2
            q = [
                (r[:, 0, 2] - r[:, 2, 0]) / s,
                (r[:, 0, 1] + r[:, 1, 0]) / s,
                0.25 * s,
                (r[:, 1, 2] + r[:, 2, 1]) / s,
            ]
        else:
            s = np.sqrt(1.0 + r[:, 2, 2] - r[:, 0, 0] - r[:, 1, 1]) * 2
            q = [
                (r[:, 1, 0] - r[:, 0, 1]) / s,
                (r[:, 0, 2] + r[:, 2, 0]) / s,
                (r[:, 1, 2] + r[:, 2, 1]) / s,
                0.25 * s,
            ]
        out[sel] = np.stack(q, axis=-1)
    out *= np.where(out[:, :1] < 0, -1.0, 1.0)
    return out.reshape(*shape, 4)


def rotate(q: ArrayLike, v: ArrayLike) -> F64:
    """Rotate vectors ``v (..., 3)`` by quaternions ``q (..., 4)``."""
    return np.einsum("...ij,...j->...i", to_matrix(q), np.asarray(v, dtype=np.float64))


def slerp(q0: ArrayLike, q1: ArrayLike, t: ArrayLike) -> F64:
    """Spherical linear interpolation along the shorter arc; ``t`` broadcasts against the leading axes."""
    a = normalize(q0)
    b = normalize(q1)
    t_ = np.asarray(t, dtype=np.float64)[..., None]
    dot = np.sum(a * b, axis=-1, keepdims=True)
    b = np.where(dot < 0, -b, b)
    dot = np.abs(dot)
    close = dot > 0.9995  # nearly parallel: lerp is exact to float precision and avoids 0/0
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    sin_theta = np.where(close, 1.0, np.sin(theta))
    wa = np.where(close, 1.0 - t_, np.sin((1.0 - t_) * theta) / sin_theta)
    wb = np.where(close, t_, np.sin(t_ * theta) / sin_theta)
    return normalize(wa * a + wb * b)
