"""SO(3) / SE(3) / quaternion maths, batched over a leading axis.

Conventions (see docs/algorithms/README.md and docs/algorithms/se3.md):

* poses are homogeneous 4×4 matrices ``T = [[R, p], [0, 1]]`` (R: orientation of the body in the world,
  p: position of the body origin in the world, metres);
* quaternions are scalar first ``(w, x, y, z)``, Hamilton product, active rotation;
* twists and displacement twists are ordered rotation first: ``(φ; ρ)`` or ``(ω; v)``.

Every formula is written once, as a numba kernel acting on a single element
(:mod:`framefree.core.se3_kernels`: the ``*_one`` functions, usable from other kernels). The
functions here validate their input, accept any leading batch shape ``(..., k)`` and loop over
it in compiled code.
"""

from __future__ import annotations

import math

import numpy as np

from .se3_kernels import (
    central_spatial_twists_kernel,
    continuity_inplace,
    interpolate_poses_kernel,
    matrix_from_quaternion_batch,
    pose_from_twist_batch,
    quaternion_from_matrix_batch,
    relative_twists_kernel,
    rotation_from_vector_batch,
    sclerp_batch,
    sign_flip_one,
    twist_from_pose_batch,
    vector_from_rotation_batch,
)

__all__ = [
    "NEAREST_SIGN",
    "REFERENCE_SIGN_THRESHOLD",
    "align_quaternion_sign",
    "central_spatial_twists",
    "hat",
    "interpolate_poses",
    "matrix_from_quaternion",
    "pose_from_twist",
    "poses_from_pq",
    "pq_from_poses",
    "quaternion_conjugate",
    "quaternion_continuity",
    "quaternion_from_matrix",
    "quaternion_multiply",
    "quaternion_sign",
    "relative_displacement_twists",
    "rotation_from_vector",
    "sclerp",
    "screw_axis",
    "transform_inverse",
    "twist_from_pose",
    "vector_from_rotation",
    "vee",
]

#: Sign-continuity threshold of the reference batch converter: Euclidean distance in R^4
#: (docs/algorithms/se3.md).
REFERENCE_SIGN_THRESHOLD = 0.5
#: Sign-continuity threshold that picks the nearer of ``q`` and ``-q`` (unit quaternions:
#: ``|q - ref| > √2`` exactly when ``q · ref < 0``).
NEAREST_SIGN = math.sqrt(2.0)


# --------------------------------------------------------------------------------------------------
# public, batched API
# --------------------------------------------------------------------------------------------------


def _flat(a: np.ndarray, tail: tuple[int, ...]) -> tuple[np.ndarray, tuple[int, ...]]:
    a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape[a.ndim - len(tail) :] != tail:
        raise ValueError(
            f"expected an array of shape (..., {', '.join(map(str, tail))}), got {a.shape}"
        )
    lead = a.shape[: a.ndim - len(tail)]
    return a.reshape((-1, *tail)), lead


def hat(v: np.ndarray) -> np.ndarray:
    """Skew-symmetric matrices ``[v]×``.

    Parameters
    ----------
    v : ndarray, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    v = np.asarray(v, dtype=np.float64)
    S = np.zeros((*v.shape[:-1], 3, 3))
    S[..., 0, 1] = -v[..., 2]
    S[..., 0, 2] = v[..., 1]
    S[..., 1, 0] = v[..., 2]
    S[..., 1, 2] = -v[..., 0]
    S[..., 2, 0] = -v[..., 1]
    S[..., 2, 1] = v[..., 0]
    return S


def vee(S: np.ndarray) -> np.ndarray:
    """Inverse of :func:`hat`: reads entries (3,2), (1,3), (2,1). Shape (..., 3, 3) → (..., 3)."""
    S = np.asarray(S, dtype=np.float64)
    return np.stack([S[..., 2, 1], S[..., 0, 2], S[..., 1, 0]], axis=-1)


def rotation_from_vector(phi: np.ndarray) -> np.ndarray:
    """SO(3) exponential. ``phi`` (..., 3) rotation vectors [rad] → (..., 3, 3) rotation matrices."""
    f, lead = _flat(phi, (3,))
    return rotation_from_vector_batch(f).reshape((*lead, 3, 3))


def vector_from_rotation(R: np.ndarray) -> np.ndarray:
    """SO(3) logarithm. ``R`` (..., 3, 3) → rotation vectors (..., 3), angle in [0, π]."""
    f, lead = _flat(R, (3, 3))
    return vector_from_rotation_batch(f).reshape((*lead, 3))


def pose_from_twist(xi: np.ndarray) -> np.ndarray:
    """SE(3) exponential. Displacement twists ``(phi, rho)`` (..., 6) → poses (..., 4, 4)."""
    f, lead = _flat(xi, (6,))
    return pose_from_twist_batch(f).reshape((*lead, 4, 4))


def twist_from_pose(T: np.ndarray) -> np.ndarray:
    """SE(3) logarithm. Poses (..., 4, 4) → displacement twists ``(phi, rho)`` (..., 6)."""
    f, lead = _flat(T, (4, 4))
    return twist_from_pose_batch(f).reshape((*lead, 6))


def transform_inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4)."""
    T = np.asarray(T, dtype=np.float64)
    Ti = np.zeros_like(T)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    Ti[..., :3, :3] = Rt
    Ti[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3])
    Ti[..., 3, 3] = 1.0
    return Ti


def matrix_from_quaternion(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of quaternions (..., 4) ``(w, x, y, z)`` (normalized first)."""
    f, lead = _flat(q, (4,))
    return matrix_from_quaternion_batch(f).reshape((*lead, 3, 3))


def quaternion_from_matrix(R: np.ndarray, continuous: bool = True) -> np.ndarray:
    """Quaternions (..., 4) of rotation matrices (..., 3, 3), reference algorithm (docs/algorithms/se3.md).

    With ``continuous=True`` and a sequence (leading axis = time), signs are made continuous:
    a quaternion farther than 0.5 from its predecessor is negated.
    """
    f, lead = _flat(R, (3, 3))
    q = quaternion_from_matrix_batch(f)
    if continuous and len(lead) == 1:
        continuity_inplace(q, REFERENCE_SIGN_THRESHOLD)
    return q.reshape((*lead, 4))


def quaternion_continuity(q: np.ndarray, threshold: float = REFERENCE_SIGN_THRESHOLD) -> np.ndarray:
    """Copy of a quaternion sequence (N, 4) with sign flips removed (docs/algorithms/se3.md)."""
    q = np.array(q, dtype=np.float64, copy=True)
    if q.ndim != 2 or q.shape[1] != 4:
        raise ValueError(f"expected quaternions of shape (N, 4), got {q.shape}")
    continuity_inplace(q, threshold)
    return q


def quaternion_sign(q: np.ndarray, ref: np.ndarray, threshold: float = NEAREST_SIGN) -> float:
    """``-1.0`` when quaternion ``q`` (4,) must be negated to stay continuous with ``ref`` (4,), else 1.0.

    The rule is :func:`sign_flip_one`; the default threshold keeps the nearer of ``q`` and ``-q``.
    """
    q = np.ascontiguousarray(q, dtype=np.float64)
    ref = np.ascontiguousarray(ref, dtype=np.float64)
    return -1.0 if sign_flip_one(q, ref, float(threshold)) else 1.0


def align_quaternion_sign(
    q: np.ndarray, ref: np.ndarray, threshold: float = NEAREST_SIGN
) -> np.ndarray:
    """``q`` or ``-q`` (4,), whichever the sign-continuity rule keeps next to ``ref`` (4,)."""
    return quaternion_sign(q, ref, threshold) * np.asarray(q, dtype=np.float64)


def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product ``a ⊗ b`` of quaternions (..., 4), scalar first."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    w = a[..., 0] * b[..., 0] - np.sum(a[..., 1:] * b[..., 1:], axis=-1)
    v = a[..., :1] * b[..., 1:] + b[..., :1] * a[..., 1:] + np.cross(a[..., 1:], b[..., 1:])
    return np.concatenate([w[..., None], v], axis=-1)


def quaternion_conjugate(q: np.ndarray) -> np.ndarray:
    """Conjugate ``(w, -x, -y, -z)`` of quaternions (..., 4)."""
    q = np.asarray(q, dtype=np.float64)
    return np.concatenate([q[..., :1], -q[..., 1:]], axis=-1)


def poses_from_pq(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Poses (..., 4, 4) from positions (..., 3) [m] and quaternions (..., 4) ``(w, x, y, z)``."""
    p = np.asarray(p, dtype=np.float64)
    R = matrix_from_quaternion(q)
    T = np.zeros((*p.shape[:-1], 4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def pq_from_poses(T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions (N, 3) and sign-continuous quaternions (N, 4) of a pose sequence (N, 4, 4)."""
    T = np.asarray(T, dtype=np.float64)
    return T[..., :3, 3].copy(), quaternion_from_matrix(T[..., :3, :3], continuous=True)


def sclerp(A: np.ndarray, B: np.ndarray, alpha: np.ndarray | float) -> np.ndarray:
    """Screw linear interpolation between poses ``A`` and ``B`` (..., 4, 4).

    ``alpha = 0`` gives ``A``, ``alpha = 1`` gives ``B``; the path is the constant-body-twist screw
    motion ``A exp(alpha log(A^-1 B))``.
    """
    fa, lead = _flat(A, (4, 4))
    fb, leadb = _flat(B, (4, 4))
    if lead != leadb:
        fa, fb = (x.reshape(-1, 4, 4) for x in np.broadcast_arrays(np.asarray(A), np.asarray(B)))
        lead = np.broadcast_shapes(np.shape(A), np.shape(B))[:-2]
    al = np.broadcast_to(np.asarray(alpha, dtype=np.float64), lead).reshape(-1)
    out = sclerp_batch(
        np.ascontiguousarray(fa), np.ascontiguousarray(fb), np.ascontiguousarray(al)
    )
    return out.reshape((*lead, 4, 4))


def interpolate_poses(x: np.ndarray, T: np.ndarray, xq: np.ndarray) -> np.ndarray:
    """ScLERP poses ``T`` (n, 4, 4) given at non-decreasing knots ``x`` (n,) at query values ``xq``.

    ``xq`` must be non-decreasing and inside ``[x[0], x[-1]]``. Equal knots (a standstill) return
    the left pose, as the reference ``interpT`` does.

    Returns
    -------
    ndarray, shape (len(xq), 4, 4)
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    xq = np.ascontiguousarray(xq, dtype=np.float64)
    T = np.ascontiguousarray(T, dtype=np.float64)
    if x.ndim != 1 or T.shape != (x.shape[0], 4, 4) or x.shape[0] < 2:
        raise ValueError("interpolate_poses needs at least two knots and one pose per knot")
    if xq.size and (xq[0] < x[0] or xq[-1] > x[-1]):
        raise ValueError(
            f"query range [{xq[0]}, {xq[-1]}] lies outside the knot range [{x[0]}, {x[-1]}]"
        )
    return interpolate_poses_kernel(x, T, xq)


def relative_displacement_twists(T: np.ndarray) -> np.ndarray:
    """Body-frame displacement twists ``log(T_k^-1 T_{k+1})`` (N-1, 6) of a pose sequence (N, 4, 4)."""
    return relative_twists_kernel(np.ascontiguousarray(T, dtype=np.float64))


def central_spatial_twists(T: np.ndarray, ds: float) -> np.ndarray:
    """Spatial twists (N, 6) from central differences ``log(T_{k+1} T_{k-1}^-1) / (2 ds)``.

    The first and last twists are one-sided differences still divided by ``2 ds`` (reference
    quirk, docs/algorithms/se3.md).
    """
    return central_spatial_twists_kernel(np.ascontiguousarray(T, dtype=np.float64), float(ds))


def screw_axis(twist: np.ndarray, ref_point: np.ndarray | None = None):
    """Instantaneous screw axis of twists ``(ω, v_r)`` (..., 6) referred to point ``r``
    (docs/algorithms/se3.md).

    Parameters
    ----------
    twist : ndarray, shape (..., 6)
        Rotation first; ``v`` is the velocity of the point ``ref_point``.
    ref_point : ndarray, shape (..., 3), optional
        The reference point ``r`` of the twist (default: the origin).

    Returns
    -------
    direction : ndarray, shape (..., 3)
        Unit axis direction (NaN where ``ω = 0``: the axis is undefined for pure translation).
    point : ndarray, shape (..., 3)
        The point of the axis closest to ``r``.
    pitch : ndarray, shape (...)
        ``ω·v / |ω|^2`` [m/rad].
    """
    twist = np.asarray(twist, dtype=np.float64)
    w, v = twist[..., :3], twist[..., 3:]
    r = np.zeros_like(w) if ref_point is None else np.broadcast_to(ref_point, w.shape)
    nw2 = np.sum(w * w, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        direction = w / np.sqrt(nw2)[..., None]
        point = r + np.cross(w, v) / nw2[..., None]
        pitch = np.sum(w * v, axis=-1) / nw2
    return direction, point, pitch
